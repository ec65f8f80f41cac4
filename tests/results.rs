//! The typed results: every committed results/fits file reads as its type, and a file
//! that is malformed, another study's or of another layout is a typed error naming the
//! file — never taken for "absent", never a default.

mod common;

use ndfbench::results::{self, alpha_me::AlphaMe, filters::Filters, leadr_grids::LeadrGrids};
use ndfbench::results::{ltc, smith_lambda::SmithLambda};
use std::path::Path;

#[test]
fn every_committed_result_reads_as_its_type() {
    let r = Path::new("results");
    let sl: SmithLambda = results::require(r).unwrap();
    // the generated constants carry these numbers: the typed read gives them exactly
    assert!(sl.held_out.ours.max_dg1 > 0.0 && sl.held_out.ours.max_dg1 < sl.spec.tolerance.max_rel);
    let am: AlphaMe = results::require(r).unwrap();
    assert_eq!(am.ours.coefficients.len(), 7);
    let lg: LeadrGrids = results::require(r).unwrap();
    assert!(lg.fitted_h_n5 > 0.2 && lg.fitted_h_n5 < 2.2);
    let f: Filters = results::require(r).unwrap();
    assert!(f.fitted("vMF α² + c/κ", "GGX").is_some());
    assert!(!f.summary.is_empty() && !f.survey.rows.is_empty());
    let _: results::render::Render = results::require(r).unwrap();
    let t: results::tensor::Tensor = results::require(r).unwrap();
    assert!(t.rows.iter().all(|x| x.mean_rel_error <= x.max_rel_error));
    let a: results::ltc_aniso::Aniso = results::require(r).unwrap();
    assert_eq!(a.cells.len(), a.grid.cells());
    let g: ltc::Ggx = results::require(r).unwrap();
    assert_eq!(g.table.len(), g.grid.n);
    assert!(!g.polygons.is_empty() && !g.pipeline.levels.is_empty());
    for name in [
        "ltc-ggx",
        "ltc-sheen",
        "ltc-sheen-neubelt",
        "ltc-diffuse",
        "ltc-diffuse-engines",
    ] {
        let s: ltc::Summary = results::require_named(r, name).unwrap();
        assert_eq!(s.held_out.cells, 4096, "{name}");
        assert_eq!(ltc::table(r, name).unwrap().n, 64, "{name}");
    }
    assert!(results::costs::read(r).unwrap().is_some());
}

#[test]
fn a_wrong_result_file_is_a_typed_error_naming_it() {
    let d = common::scratch("results", "wrong");
    std::fs::create_dir_all(d.join("fits")).unwrap();
    let file = d.join("fits/smith-lambda.json");
    // absent: None, not an error
    assert!(results::read::<SmithLambda>(&d).unwrap().is_none());
    let missing = results::require::<SmithLambda>(&d).unwrap_err().to_string();
    assert!(
        missing.contains("smith-lambda.json") && missing.contains("regen --only smith-lambda"),
        "{missing}"
    );
    let leadr = std::fs::read_to_string("results/fits/leadr-grids.json").unwrap();
    let ours = std::fs::read_to_string("results/fits/smith-lambda.json").unwrap();
    for (body, needle) in [
        ("{", "not a well-formed result"),
        ("[]", "names no spec"),
        // another study's file under this name
        (leadr.as_str(), "written by the study \"leadr-grids\""),
        // an older layout: a field renamed
        (
            &ours.replacen("\"max_dg1\"", "\"max_delta_g1\"", 1),
            "not a smith-lambda result",
        ),
        // a number that is not one
        (
            &ours.replacen("\"iterations\": ", "\"iterations\": -", 1),
            "not a smith-lambda result",
        ),
    ] {
        std::fs::write(&file, body).unwrap();
        let e = results::read::<SmithLambda>(&d).unwrap_err().to_string();
        assert!(
            e.contains("smith-lambda.json") && e.contains(needle),
            "{needle}: {e}"
        );
    }
    // a mean over no cases is written as null (serde_json's NaN): it reads back as NaN,
    // not as an error (the quick preset leaves some alignment cells empty)
    let filters = std::fs::read_to_string("results/fits/filters.json").unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&filters).unwrap();
    v["survey"]["alignment"][0]["tan_cost_aligned"][0] =
        serde_json::json!({"error": null, "value": null});
    let emptied = serde_json::to_string_pretty(&v).unwrap();
    std::fs::write(d.join("fits/filters.json"), &emptied).unwrap();
    let f: Filters = results::require(&d).unwrap();
    assert!(f
        .survey
        .alignment
        .iter()
        .any(|a| a.tan_cost_aligned.0.value.is_nan() && a.tan_cost_aligned.0.error.is_nan()));
    // a variant table is read as its study's file; another study's is not
    let sheen = std::fs::read_to_string("results/fits/ltc-sheen.json").unwrap();
    std::fs::write(d.join("fits/ltc-sheen-neubelt.json"), &sheen).unwrap();
    assert!(ltc::table(&d, "ltc-sheen-neubelt").is_ok());
    std::fs::write(d.join("fits/ltc-ggx.json"), &sheen).unwrap();
    let e = ltc::table(&d, "ltc-ggx").unwrap_err().to_string();
    assert!(e.contains("written by the study \"ltc-sheen\""), "{e}");
    // a table cell that is not a number
    let broken = sheen.replacen(
        "\"table\": [\n    [\n      [\n",
        "\"table\": [\n    [\n      [\n null,",
        1,
    );
    assert_ne!(broken, sheen);
    std::fs::write(d.join("fits/ltc-sheen.json"), broken).unwrap();
    assert!(ltc::table(&d, "ltc-sheen").is_err());
    let _ = std::fs::remove_dir_all(&d);
}

/// Every file under results/ (hidden entries such as the set manifests left out), as
/// `/`-separated paths relative to results/.
fn result_files() -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![Path::new("results").to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if e.file_name().to_string_lossy().starts_with('.') {
                continue;
            }
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix("results").unwrap();
                out.push(rel.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn the_index_of_results_holds_to_the_folder_and_its_readme_is_current() {
    use ndfbench::results::index::{entry, matches, readme, OUTPUTS};
    let files = result_files();
    // every file is listed, every entry names a file that exists
    let unlisted: Vec<&String> = files.iter().filter(|f| entry(f).is_none()).collect();
    assert!(
        unlisted.is_empty(),
        "results/ files missing from src/results/index.rs: {unlisted:?}"
    );
    let empty: Vec<&str> = OUTPUTS
        .iter()
        .filter(|o| !files.iter().any(|f| matches(o.path, f)))
        .map(|o| o.path)
        .collect();
    assert!(
        empty.is_empty(),
        "index entries with no file in results/: {empty:?}"
    );
    // a file that says which command wrote it says its entry's command
    let mut claims = 0;
    for f in &files {
        let Ok(text) = std::fs::read_to_string(Path::new("results").join(f)) else {
            continue;
        };
        let head: String = text.chars().take(4000).collect();
        let said = if f.ends_with(".json") {
            serde_json::from_str::<serde_json::Value>(&text)
                .ok()
                .and_then(|v| {
                    v.get("command")
                        .and_then(|c| c.as_str())
                        .map(str::to_string)
                })
        } else {
            ["@generated by `", "Written by `"].iter().find_map(|k| {
                let at = head.find(k)? + k.len();
                Some(head[at..].split('`').next()?.to_string())
            })
        };
        if let Some(said) = said {
            claims += 1;
            // the same command, or it with its arguments left off (down to the subcommand)
            let full = entry(f).unwrap().by.command();
            let same = said == full
                || (full.starts_with(&format!("{said} ")) && said.split(' ').count() >= 4);
            assert!(
                same,
                "results/{f} says it was written by `{said}`; its index entry says `{full}`"
            );
        }
    }
    assert!(
        claims >= 30,
        "only {claims} files say which command wrote them"
    );
    let committed = std::fs::read_to_string("results/README.md").unwrap_or_default();
    assert!(
        committed == readme(),
        "results/README.md is stale: run `cargo run --release -- results-readme`"
    );
}

/// Every measured figure the README and docs/ quote — a number with %, ×, or a unit of
/// time, a range's two ends each — appears as such in a file of results/: the docs quote
/// what results/ generates and nothing else, so a rerun that changes a figure leaves no
/// stale copy behind in prose.
#[test]
fn the_docs_quote_only_figures_results_generate() {
    let mut generated = String::new();
    for f in result_files() {
        if [".md", ".json", ".svg"].iter().any(|x| f.ends_with(x)) {
            generated.push_str(&std::fs::read_to_string(Path::new("results").join(&f)).unwrap());
        }
    }
    let units = ["%", "×", "ms", "µs", "ns", "s", "min", "minutes"];
    let mut docs = vec!["README.md".to_string()];
    for e in std::fs::read_dir("docs").unwrap().flatten() {
        docs.push(e.path().display().to_string());
    }
    let mut missing = Vec::new();
    for d in docs.iter().filter(|d| d.ends_with(".md")) {
        let text = std::fs::read_to_string(d).unwrap();
        let chars: Vec<char> = text.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            let starts = chars[i].is_ascii_digit()
                && (i == 0 || !(chars[i - 1].is_alphanumeric() || ".,_".contains(chars[i - 1])));
            if !starts {
                i += 1;
                continue;
            }
            // a number, and a range's second end after – or -
            let mut nums = Vec::new();
            let mut j = i;
            loop {
                let s = j;
                while j < chars.len() && (chars[j].is_ascii_digit() || chars[j] == '.') {
                    j += 1;
                }
                let n: String = chars[s..j].iter().collect();
                nums.push(n.trim_end_matches('.').to_string());
                if j + 1 < chars.len() && "–-".contains(chars[j]) && chars[j + 1].is_ascii_digit()
                {
                    j += 1;
                    continue;
                }
                break;
            }
            let rest: String = chars[j..chars.len().min(j + 9)].iter().collect();
            let spaced = rest.starts_with(' ');
            let after = rest.trim_start();
            let unit = units.iter().copied().find(|u| {
                after.starts_with(u) && !after[u.len()..].starts_with(|c: char| c.is_alphanumeric())
            });
            if let Some(u) = unit {
                for n in &nums {
                    let forms = [format!("{n} {u}"), format!("{n}{u}")];
                    if !forms.iter().any(|f| generated.contains(f.as_str())) {
                        let sep = if spaced { " " } else { "" };
                        missing.push(format!("{d}: {n}{sep}{u}"));
                    }
                }
            }
            i = j.max(i + 1);
        }
    }
    assert!(
        missing.is_empty(),
        "figures quoted in the docs that no file of results/ generates: {missing:?}"
    );
}

/// The files of results/ that may hold wall clock, and why: the main job's profile and
/// criterion's times, and seed 002 at the paper's scale, whose comparison with the paper's
/// Table 2 is one of time.
const TIMED: &[&str] = &[
    "performance.md",
    "main-job-before.json",
    "tensor-scale.md",
    "fits/tensor-scale.json",
];

/// A result is the same on every machine and at every thread count: no file outside
/// [`TIMED`] states a thread count, "wall-clock", or a JSON field of seconds.
#[test]
fn results_hold_no_wall_clock_or_thread_count_outside_the_profile() {
    let mut found = Vec::new();
    for rel in result_files() {
        if TIMED.contains(&rel.as_str()) || !(rel.ends_with(".md") || rel.ends_with(".json")) {
            continue;
        }
        let text = std::fs::read_to_string(Path::new("results").join(&rel)).unwrap();
        let threads = text
            .match_indices(" threads")
            .any(|(at, _)| text[..at].ends_with(|c: char| c.is_ascii_digit()));
        let wall = text.contains("wall-clock on") || text.contains("\"seconds\"");
        if threads || wall {
            found.push(rel);
        }
    }
    assert!(
        found.is_empty(),
        "results that depend on the machine or the thread count: {found:?}"
    );
    for t in TIMED {
        assert!(
            Path::new("results").join(t).exists(),
            "{t} is listed but gone"
        );
    }
}

/// The studies that refit the published GGX table (optimisers, work) read it by index: a
/// file whose held-out cells or table do not match its grid is a typed error naming the
/// file, never an out-of-bounds panic or a comparison over a silently shorter zip.
#[test]
fn the_studies_refitting_the_ggx_table_refuse_it_in_the_wrong_shape() {
    for name in ["ltc-ggx-optimisers", "ltc-work"] {
        refuses_a_published_table_of_the_wrong_shape(name);
    }
}

fn refuses_a_published_table_of_the_wrong_shape(name: &str) {
    use ndfbench::fit::spec::FitSpec;
    let committed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("results/fits/ltc-ggx.json").unwrap())
            .unwrap();
    let path = format!("fits/{name}.toml");
    let spec = FitSpec::parse(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    let breaks: [(&str, fn(&mut serde_json::Value)); 3] = [
        ("short held-out column", |v| {
            v["held_out_cells"]["l2"][3].as_array_mut().unwrap().pop();
        }),
        ("grid side", |v| v["grid"]["n"] = 63.into()),
        ("negative figure", |v| {
            v["held_out_cells"]["l2"][0][0] = serde_json::json!([-1.0, 0.0])
        }),
    ];
    for (what, brk) in breaks {
        let d = common::scratch("results", &format!("{name}-{}", what.replace(' ', "-")));
        std::fs::create_dir_all(d.join("fits")).unwrap();
        let mut v = committed.clone();
        brk(&mut v);
        std::fs::write(
            d.join("fits/ltc-ggx.json"),
            serde_json::to_string(&v).unwrap(),
        )
        .unwrap();
        match common::compute_study(&spec, &d, ndfbench::integrate::Preset::Quick) {
            Err(e) => assert!(
                e.to_string().contains("ltc-ggx.json"),
                "{name}, {what}: {e}"
            ),
            Ok(_) => panic!("{name}, {what}: a broken published table was accepted"),
        }
        let _ = std::fs::remove_dir_all(&d);
    }
}

/// The held-out judge's tolerance study, on four cells of each published table: its
/// reference figures agree with the figures the table's own study published for the same
/// cells (judged by `ltc::held::judge_table`, at the table spec's tolerance) within the two
/// bars; a looser tolerance never costs more evaluations; the table's tolerance is the one
/// its spec names.
#[test]
fn the_judge_tolerance_study_agrees_with_the_published_figures() {
    use ndfbench::fit::spec::FitSpec;
    let spec = FitSpec::parse(
        "name = \"ltc-judge-tolerance\"\nseed = 0\ntolerance = { max_rel = 1.0 }\n[params]\nevery = 32\nrels = [5e-4, 2e-3, 1e-2]\nl1_rels = [2e-3, 1e-2, 5e-2]\naniso_every = 500\n",
        "test",
    )
    .unwrap();
    let computed = common::compute_study(
        &spec,
        Path::new("results"),
        ndfbench::integrate::Preset::Default,
    )
    .unwrap();
    let mut set = ndfbench::io::Outputs::new();
    let d = common::scratch("results", "judge-tolerance");
    computed.render(&mut set, &d).unwrap();
    let out: serde_json::Value =
        serde_json::from_slice(set.get(&d.join("fits/ltc-judge-tolerance.json")).unwrap()).unwrap();
    for c in out["tables"].as_array().unwrap() {
        let name = c["table"].as_str().unwrap();
        let published: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(format!("results/fits/{name}.json")).unwrap(),
        )
        .unwrap();
        let fits: toml::Value =
            toml::from_str(&std::fs::read_to_string(format!("fits/{name}.toml")).unwrap()).unwrap();
        assert_eq!(
            c["chosen_rel"].as_f64(),
            fits["params"]["held_out_rel"].as_float(),
            "{name}"
        );
        assert_eq!(
            c["chosen_l1_rel"].as_f64(),
            fits["params"]["held_out_l1_rel"].as_float(),
            "{name}"
        );
        let pts = c["points"].as_array().unwrap();
        let evals: Vec<f64> = pts
            .iter()
            .map(|p| p["evals_per_cell"].as_f64().unwrap())
            .collect();
        if name == "ltc-aniso" {
            // the anisotropic table publishes no per-cell figures: its curve is checked on
            // itself, every L1 point within both bars of the reference's mean L1, and on
            // its work
            let g = &published["grid"];
            let side = |k: &str| g[k].as_u64().unwrap();
            // α_x > α_y at every φ, and the diagonal up to φ = π/4 (its other cells mirror)
            let (n_r, n_phi) = (side("n_r"), side("n_phi"));
            let fitted = side("n_t") * (n_phi * n_r * (n_r - 1) / 2 + n_r * (n_phi + 1) / 2);
            assert_eq!(
                c["cells"].as_u64(),
                Some(fitted.div_ceil(500)),
                "{name}: every 500th of the fitted cells"
            );
            let reference = &pts[0]["l1_mean"];
            let (rv, re) = (
                reference["value"].as_f64().unwrap(),
                reference["error"].as_f64().unwrap(),
            );
            for p in c["l1_points"].as_array().unwrap() {
                let m = &p["l1_mean"];
                let (mv, me) = (m["value"].as_f64().unwrap(), m["error"].as_f64().unwrap());
                assert!(
                    (mv - rv).abs() <= me + re,
                    "{name}: L1 {mv} ± {me} against {rv} ± {re}"
                );
            }
            assert!(evals.windows(2).all(|w| w[1] <= w[0]), "{name}: {evals:?}");
            continue;
        }
        assert_eq!(c["cells"], 4, "{name}");
        // the mean of the same four cells' published relative L2 and its bar
        let cells = &published["held_out_cells"]["l2"];
        let (mut v, mut e) = (0.0, 0.0);
        for j in [0, 32] {
            for i in [0, 32] {
                v += cells[j][i][0].as_f64().unwrap() / 4.0;
                e += cells[j][i][1].as_f64().unwrap() / 4.0;
            }
        }
        let r = &pts[0]["l2_mean"];
        let (rv, re) = (r["value"].as_f64().unwrap(), r["error"].as_f64().unwrap());
        assert!(
            (rv - v).abs() <= re + e,
            "{name}: {rv} ± {re} against the published {v} ± {e}"
        );
        assert!(evals.windows(2).all(|w| w[1] <= w[0]), "{name}: {evals:?}");
        assert!(
            evals[2] < evals[0],
            "{name}: a looser tolerance saved nothing: {evals:?}"
        );
        // the L1 curve: the published relative L1 of the same cells within both bars, at
        // each L1 tolerance, and less work as the L1's tolerance loosens
        let l1 = &published["held_out_cells"]["l1"];
        let (mut v1, mut e1) = (0.0, 0.0);
        for j in [0, 32] {
            for i in [0, 32] {
                v1 += l1[j][i][0].as_f64().unwrap() / 4.0;
                e1 += l1[j][i][1].as_f64().unwrap() / 4.0;
            }
        }
        let l1_pts = c["l1_points"].as_array().unwrap();
        assert_eq!(l1_pts.len(), 3, "{name}");
        for p in l1_pts {
            let m = &p["l1_mean"];
            let (mv, me) = (m["value"].as_f64().unwrap(), m["error"].as_f64().unwrap());
            assert!(
                (mv - v1).abs() <= me + e1,
                "{name}: L1 {mv} ± {me} against the published {v1} ± {e1}"
            );
        }
        let l1_evals: Vec<f64> = l1_pts
            .iter()
            .map(|p| p["evals_per_cell"].as_f64().unwrap())
            .collect();
        assert!(
            l1_evals.windows(2).all(|w| w[1] <= w[0]) && l1_evals[2] < l1_evals[0],
            "{name}: {l1_evals:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A tolerance out of its range in a table's spec, or a curve whose tolerances do not
/// increase, is a typed error naming the key before any work.
#[test]
fn held_out_tolerances_out_of_range_are_refused() {
    use ndfbench::fit::spec::FitSpec;
    let cases = [
        (
            "ltc-ggx",
            "held_out_rel = 2e-3",
            "held_out_rel = 0.0",
            "held_out_rel",
        ),
        (
            "ltc-sheen",
            "held_out_rel = 2e-3",
            "held_out_rel = nan",
            "held_out_rel",
        ),
        (
            "ltc-diffuse",
            "held_out_rel = 2e-3",
            "held_out_rel = 0.5",
            "held_out_rel",
        ),
        (
            "ltc-ggx",
            "held_out_l1_rel = 1e-2",
            "held_out_l1_rel = -1e-2",
            "held_out_l1_rel",
        ),
        (
            "ltc-sheen",
            "held_out_l1_rel = 1e-2",
            "held_out_l1_rel = 1.0",
            "held_out_l1_rel",
        ),
        (
            "ltc-aniso",
            "held_out_l1_rel = 1e-2",
            "held_out_l1_rel = 0.0",
            "held_out_l1_rel",
        ),
        (
            "ltc-judge-tolerance",
            "rels = [1e-4,",
            "rels = [1e-3, 1e-4,",
            "rels",
        ),
        (
            "ltc-judge-tolerance",
            "l1_rels = [2e-3,",
            "l1_rels = [2e-2, 2e-3,",
            "l1_rels",
        ),
    ];
    for (name, from, to, key) in cases {
        let text = std::fs::read_to_string(format!("fits/{name}.toml")).unwrap();
        assert!(
            text.contains(from),
            "{name}: the spec no longer holds '{from}'"
        );
        let spec = FitSpec::parse(&text.replacen(from, to, 1), name).unwrap();
        match common::compute_study(
            &spec,
            Path::new("results"),
            ndfbench::integrate::Preset::Default,
        ) {
            Err(e) => assert!(e.to_string().contains(key), "{name}: {e}"),
            Ok(_) => panic!("{name}: '{to}' was accepted"),
        }
    }
}

/// The stored comparison with the shipped table was made against the published GGX table
/// (the same fingerprint), and the GGX report says so: a table judged to another
/// tolerance is the same table, a refitted one is not.
#[test]
fn the_stored_comparison_is_of_the_published_table() {
    let cmp: ndfbench::results::compare::LtcCompare =
        serde_json::from_str(&std::fs::read_to_string("results/ltc-compare.json").unwrap())
            .unwrap();
    let t = ltc::table(Path::new("results"), "ltc-ggx").unwrap();
    assert_eq!(
        cmp.ours_table_fingerprint.as_deref(),
        Some(t.fingerprint().as_str())
    );
    let md = std::fs::read_to_string("results/ltc-ggx.md").unwrap();
    assert!(
        !md.contains("STALE"),
        "results/ltc-ggx.md calls the comparison stale"
    );
    // a different table has a different fingerprint
    let mut other = t.clone();
    other.cells[5][2] = f64::from_bits(other.cells[5][2].to_bits() ^ 1);
    assert_ne!(other.fingerprint(), t.fingerprint());
}

/// results/performance.md's compact section quotes the compact study's current figures:
/// each family's full-table row carries results/fits/ltc-compact.json's mean held-out
/// errors at the cells and the squares. The section is written by `bench-report`
/// (`--compact-only` after the study alone), from criterion's times and that file; a
/// study rerun without it leaves the page quoting the previous run.
#[test]
fn the_performance_page_quotes_the_current_compact_study() {
    use ndfbench::results::ltc_compact::LtcCompact;
    let Some(file) = ndfbench::results::read::<LtcCompact>(Path::new("results")).unwrap() else {
        panic!("results/fits/ltc-compact.json absent");
    };
    let md = std::fs::read_to_string("results/performance.md").unwrap();
    let head = "\n## Compact LTC tables: texture-free against the texture";
    let start = md
        .find(head)
        .expect("performance.md has the compact section");
    let section = &md[start..];
    let section = &section[..section[head.len()..]
        .find("\n## ")
        .map_or(section.len(), |k| head.len() + k)];
    for f in &file.families {
        let want = format!(
            "| {} | lookup: full table (binary16) | {} |",
            f.table, f.full_coefficients
        );
        let row = section
            .lines()
            .find(|l| l.starts_with(&want))
            .unwrap_or_else(|| panic!("performance.md's compact section has no row {want}"));
        let err = format!(
            "{} / {}",
            f.full.cells.mean.pct(2),
            f.full.squares.mean.pct(2)
        );
        assert!(
            row.trim_end().trim_end_matches('|').trim_end().ends_with(&err),
            "performance.md quotes {} for {}'s full table, results/fits/ltc-compact.json has {err} (bench-report --compact-only)",
            row.rsplit('|').nth(1).unwrap_or("").trim(),
            f.table
        );
    }
}

/// The compact study was run on the tables results/ holds now: each family records the
/// fingerprint of the table it was fitted to, and it is the published table's. A table
/// refitted without rerunning the study (on request, 30 min) would leave the series, and
/// the shaders, three.js drop-ins and Rust twins written from them, describing the old
/// table.
#[test]
fn the_compact_study_is_of_the_published_tables() {
    use ndfbench::results::ltc_compact::LtcCompact;
    let results = Path::new("results");
    let file = ndfbench::results::read::<LtcCompact>(results)
        .unwrap()
        .expect("results/fits/ltc-compact.json");
    assert!(!file.families.is_empty());
    for f in &file.families {
        let now = ltc::table(results, &f.table).unwrap().fingerprint();
        assert_eq!(
            f.table_fingerprint.as_deref(),
            Some(now.as_str()),
            "results/fits/ltc-compact.json's {} family was fitted to another table than results/fits/{}.json (regen --only ltc-compact)",
            f.table,
            f.table
        );
    }
}

/// The optimisers study (on request) ran on the published GGX table: its floor and route
/// comparison index that table's cells, so a refit without rerunning it leaves them
/// describing another table.
#[test]
fn the_optimisers_study_is_of_the_published_table() {
    let results = Path::new("results");
    let o = results::read::<ltc::Optimisers>(results)
        .unwrap()
        .expect("results/fits/ltc-ggx-optimisers.json");
    let now = ltc::table(results, "ltc-ggx").unwrap().fingerprint();
    assert_eq!(
        o.table_fingerprint.as_deref(),
        Some(now.as_str()),
        "results/fits/ltc-ggx-optimisers.json was computed on another table than results/fits/ltc-ggx.json (regen --only ltc-ggx-optimisers)"
    );
}

/// The render study shaded its LTC methods with the published GGX table: the SHA-256 it
/// records is that of results/fits/ltc-ggx.json's binary16 table, packed here as every
/// texture ships it (per texel k = i + n·j: (a, b), (c, d), (norm, fresnel) as binary16
/// pairs in little-endian u32, the first in the low bits). A refit without rerunning
/// `regen --only render` fails here, not only in its pictures.
#[test]
fn the_render_study_shaded_with_the_published_table() {
    let text = std::fs::read_to_string("results/fits/ltc-ggx.json").unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let t = v["table_f16"].as_array().unwrap();
    let n = t.len();
    let mut bytes = Vec::new();
    for k in 0..n * n {
        let (i, j) = (k % n, k / n);
        let c = &t[j][i];
        let h = |q: usize| half::f16::from_f64(c[q].as_f64().unwrap()).to_bits() as u32;
        for w in [h(0) | h(1) << 16, h(2) | h(3) << 16, h(4) | h(5) << 16] {
            bytes.extend_from_slice(&w.to_le_bytes());
        }
    }
    let now = ndfbench::io::sha256_hex(&bytes);
    let r = results::read::<ndfbench::results::render::Render>(Path::new("results"))
        .unwrap()
        .expect("results/fits/render.json");
    assert_eq!(
        r.ltc_table_sha256.as_deref(),
        Some(now.as_str()),
        "results/fits/render.json was rendered with another GGX LTC table than results/fits/ltc-ggx.json's (regen --only render)"
    );
}

/// The JSON text of a table file's part its readers read (spec, preset, grid, layout,
/// the stored tables), keys sorted.
fn table_part(text: &str) -> Vec<u8> {
    let v: serde_json::Value = serde_json::from_str(text).unwrap();
    let keys = [
        "cells",
        "grid",
        "layout",
        "preset",
        "spec",
        "table",
        "table_f16",
    ];
    let part: std::collections::BTreeMap<&str, &serde_json::Value> = keys
        .iter()
        .filter_map(|k| v.get(*k).map(|x| (*k, x)))
        .collect();
    serde_json::to_vec(&part).unwrap()
}

/// The judge-tolerance study (on request) ran on the published tables: each curve records
/// the SHA-256 of its table file's table part (its cells and its spec's tolerances), and it
/// is the file's now, so a refit without rerunning the study fails here, not only in its
/// report.
#[test]
fn the_judge_tolerance_study_is_of_the_published_tables() {
    let results = Path::new("results");
    let j = results::read::<ltc::JudgeTolerance>(results)
        .unwrap()
        .expect("results/fits/ltc-judge-tolerance.json");
    assert!(!j.tables.is_empty());
    for c in &j.tables {
        let text = std::fs::read_to_string(format!("results/fits/{}.json", c.table)).unwrap();
        // FIPS 180-4's SHA-256 (lower-case hex) of what the judge reads: the spec, the
        // preset, the grid and the stored tables, one JSON object with sorted keys
        let now = ndfbench::io::sha256_hex(&table_part(&text));
        assert_eq!(
            c.table_sha256.as_deref(),
            Some(now.as_str()),
            "results/fits/ltc-judge-tolerance.json's {} curve was judged on another file than results/fits/{}.json (regen --only ltc-judge-tolerance)",
            c.table,
            c.table
        );
    }
}

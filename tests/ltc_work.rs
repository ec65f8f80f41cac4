//! The LTC tables' accuracy-against-work study (`regen --only ltc-work`, on request): its
//! pipeline is each published table's, its rule behaves on a route whose answer is known,
//! a fixed-node route evaluates fewer targets, and the committed file is of the committed
//! tables.

mod common;

use ndfbench::ltc::fit as ltc_fit;
use ndfbench::results::{self, ltc};
use std::path::Path;

/// The mean held-out relative L2 of a published table's cells, as its file holds them.
fn published_mean(results: &Path, name: &str) -> f64 {
    let (p, _) = ltc::published(results, name).unwrap();
    let c: Vec<f64> = p
        .held_out_cells
        .l2
        .iter()
        .flatten()
        .flatten()
        .map(|c| c[0])
        .collect();
    c.iter().sum::<f64>() / c.len() as f64
}

/// At the quick preset, in a scratch results folder: the GGX and sheen studies publish
/// their 8×8 tables, then the work study refits them. For each table, its route with the
/// published settings and nodes goes through fit, bilinear pass, storage and judge on the
/// work study's own code path, and must give the table study's published held-out figures
/// bit for bit (the GGX table on moving samples, the sheen tables on fixed nodes in every
/// stage). The reference route (moving samples) at the published offset is the first draw:
/// the same mean, and against every envelope that holds that draw no cell above it;
/// against the one without it, exactly what the draw does.
#[test]
fn each_published_route_refitted_is_its_published_table() {
    let d = common::scratch("ltc-work", "quick");
    let out = common::regen_in(
        Path::new("fits"),
        &d,
        &["--only", "ltc-work", "--preset", "quick", "--no-cache"],
    )
    .output()
    .unwrap();
    common::assert_success(&out);
    let w = results::read::<ltc::LtcWork>(&d)
        .unwrap()
        .expect("ltc-work.json");
    let names: Vec<&str> = w.tables.iter().map(|t| t.table.as_str()).collect();
    assert_eq!(names, ["ltc-ggx", "ltc-sheen", "ltc-sheen-neubelt"]);
    for t in &w.tables {
        let (p, fingerprint) = ltc::published(&d, &t.table).unwrap();
        assert_eq!(t.table_fingerprint, fingerprint, "{}", t.table);
        let route = p.route(&t.table).unwrap();
        // the published table's own figures
        let mean = published_mean(&d, &t.table);
        assert_eq!(t.published_nodes, route.nodes, "{}", t.table);
        // the quick routes at the published settings, by their nodes
        let at = |nodes: ltc_fit::Nodes| {
            t.routes
                .iter()
                .find(|(r, _)| {
                    (r.samples, r.max_iters) == (route.samples, route.max_iters)
                        && r.nodes() == nodes
                })
                .unwrap_or_else(|| {
                    panic!("fits/ltc-work.toml's quick routes hold the published route on {nodes:?} nodes")
                })
        };
        // the published table: the first draw where it is on moving samples, else the route
        // on its nodes
        let published = match route.nodes {
            ltc_fit::Nodes::Moving => &t.draws[0],
            n => &at(n).0,
        };
        assert_eq!(published.mean.value, mean, "{}", t.table);
        let (same, v) = at(ltc_fit::Nodes::Moving);
        let bits = |f: ndfbench::integrate::Figure<ndfbench::integrate::Quad>| {
            (f.value.to_bits(), f.error.to_bits())
        };
        assert_eq!(bits(same.mean), bits(t.draws[0].mean), "{}", t.table);
        assert_eq!(v.candidate[0], v.reference[0], "{}", t.table);
        for e in &v.candidate[1..] {
            assert_eq!(e.above, 0, "{}: {v:?}", t.table);
        }
        assert!(v.no_worse, "{}", t.table);
        // the same settings on fixed nodes: another table, whose cubic-stage trials
        // evaluate no target — a moving-sample trial evaluates one per LTC-half sample, so
        // over ~100 trials a cell's target evaluations fall well below the published route's
        let (fixed, _) = at(ltc_fit::Nodes::Fixed);
        assert_ne!(fixed.mean.value, same.mean.value, "{}", t.table);
        let evals = |r: &ltc::WorkRow| r.target_evals_per_cell.expect("counted");
        let fewer = |a: &ltc::WorkRow, b: &ltc::WorkRow| {
            let (a, b) = (evals(a), evals(b));
            assert!(
                a < 0.7 * b,
                "{}: {a} vs {b} target evaluations per cell",
                t.table
            );
        };
        fewer(fixed, same);
        // fixed nodes in every stage: the L2 polish's trials evaluate no target either, so
        // of the fixed route's evaluations (the polish's ≤ half-cap trials on moving
        // samples, one per LTC-half sample) few remain
        let (all, va) = at(ltc_fit::Nodes::FixedAll);
        assert!(all.fixed_nodes, "{}", t.table);
        // ... and is no worse than the published route's draws by the study's rule: the
        // polish's checks (ltc::polish) redo on moving samples the head-on sheen cells its
        // nodes cannot see (without them: ~94-101 points above, bound ~23-52)
        assert!(va.no_worse, "{}: {va:?}", t.table);
        assert_ne!(all.mean.value, fixed.mean.value, "{}", t.table);
        fewer(all, fixed);
        // the refitted draws did real work, and each is another table; the first is
        // refitted unless it is the published table
        let refitted = usize::from(route.nodes == ltc_fit::Nodes::Moving);
        for r in &t.draws[refitted..] {
            assert!(r.work_per_cell.is_some_and(|x| x > 0.0), "{}", t.table);
        }
        for r in &t.draws[1..] {
            assert_ne!(r.mean.value, t.draws[0].mean.value, "{}", t.table);
        }
        // every refitted table is judged between cells (the published one in its study)
        assert_eq!(
            t.draws[0].between_l2.is_none(),
            refitted == 1,
            "{}",
            t.table
        );
        for r in t.draws[refitted..]
            .iter()
            .chain(t.routes.iter().map(|(r, _)| r))
        {
            let b = r
                .between_l2
                .expect("a refitted table's figure between cells");
            assert!(
                b.value.is_finite() && b.value > 0.0 && b.error >= 0.0,
                "{}: {b:?}",
                t.table
            );
        }
        // the published route refitted is the published table: between cells too, where
        // the table's own study keeps the figure in its file (the GGX table)
        if t.table == "ltc-ggx" {
            let (g, _) = ltc::published_ggx(&d).unwrap();
            let b = same.between_l2.expect("judged between cells");
            assert_eq!(
                (b.value.to_bits(), b.error.to_bits()),
                (
                    g.between.mean_l2.value.to_bits(),
                    g.between.mean_l2.error.to_bits()
                )
            );
            // every square judged: no s.e., and the integrals' own mean bar kept beside it
            assert_eq!(
                same.between_bar.map(f64::to_bits),
                Some(g.between.judged.l2.mean.error.to_bits())
            );
            assert!(same.between_bar.is_some_and(|q| q > 0.0));
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// The committed work study ran on the committed tables: a refit without rerunning it
/// leaves it describing other tables.
#[test]
fn the_work_study_is_of_the_published_tables() {
    let r = Path::new("results");
    let w = results::read::<ltc::LtcWork>(r)
        .unwrap()
        .expect("results/fits/ltc-work.json");
    for t in &w.tables {
        assert_eq!(
            t.table_fingerprint,
            ltc::table(r, &t.table).unwrap().fingerprint(),
            "results/fits/ltc-work.json was computed on another table than results/fits/{}.json (regen --only ltc-work)",
            t.table
        );
    }
}

/// A table's spec chooses its cubic stage's nodes: at the quick preset, the GGX spec with
/// `nodes = "fixed"` fits another table than the committed spec's moving samples (its
/// report says how), and an unknown value is refused before anything runs. The work study
/// then judges the table fitted on fixed nodes as a route: its first draw is the reference
/// fitter refitted at the published offset, which is the moving-sample table bit for bit,
/// and the fixed route at the published settings is the published table.
#[test]
fn the_nodes_key_chooses_the_route_and_the_work_study_judges_a_fixed_table_as_a_route() {
    let d = common::scratch("ltc-work-nodes", "quick");
    let fits = d.join("fits-in");
    common::copy_dir(Path::new("fits"), &fits);
    let spec = fits.join("ltc-ggx.toml");
    let text = std::fs::read_to_string(&spec).unwrap();
    assert!(
        !text.contains("\nnodes ="),
        "fits/ltc-ggx.toml sets no nodes key"
    );
    let with =
        |value: &str| text.replace("\n[params]\n", &format!("\n[params]\nnodes = {value}\n"));
    let run = |args: &[&str]| common::regen_in(&fits, &d, args).output().unwrap();
    let fit_ggx = || run(&["--only", "ltc-ggx", "--preset", "quick", "--no-cache"]);
    // an unknown value: refused, naming the file
    std::fs::write(&spec, with("\"frozen\"")).unwrap();
    let out = fit_ggx();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("ltc-ggx") && err.contains("nodes"), "{err}");
    // the committed spec (moving samples), then fixed nodes
    std::fs::write(&spec, &text).unwrap();
    common::assert_success(&fit_ggx());
    let moving = ltc::table(&d, "ltc-ggx").unwrap();
    let moving_mean = published_mean(&d, "ltc-ggx");
    let md = std::fs::read_to_string(d.join("ltc-ggx.md")).unwrap();
    assert!(!md.contains("fixed nodes"), "the moving route's report");
    std::fs::write(&spec, with("\"fixed\"")).unwrap();
    common::assert_success(&fit_ggx());
    let fixed = ltc::table(&d, "ltc-ggx").unwrap();
    assert_ne!(fixed.fingerprint(), moving.fingerprint());
    let md = std::fs::read_to_string(d.join("ltc-ggx.md")).unwrap();
    assert!(
        md.contains("the trials measured on fixed nodes"),
        "the fixed route's report"
    );
    // the work study: the reference refitted, the published table a route
    let fixed_mean = published_mean(&d, "ltc-ggx");
    common::assert_success(&run(&[
        "--only",
        "ltc-work",
        "--preset",
        "quick",
        "--no-cache",
    ]));
    let w = results::read::<ltc::LtcWork>(&d)
        .unwrap()
        .expect("ltc-work.json");
    let g = &w.tables[0];
    assert_eq!(g.table, "ltc-ggx");
    assert_eq!(g.published_nodes, ltc_fit::Nodes::Fixed);
    assert_eq!(g.table_fingerprint, fixed.fingerprint());
    assert_eq!(g.draws[0].mean.value, moving_mean);
    assert!(g.draws[0].work_per_cell.is_some_and(|x| x > 0.0));
    let (r, _) = g
        .routes
        .iter()
        .find(|(r, _)| {
            r.nodes() == ltc_fit::Nodes::Fixed
                && r.samples == g.draws[0].samples
                && r.max_iters == g.draws[0].max_iters
        })
        .expect("the fixed route at the published settings");
    assert_eq!(r.mean.value, fixed_mean);
    assert_ne!(fixed_mean, moving_mean);
    let md = std::fs::read_to_string(d.join("ltc-work.md")).unwrap();
    assert!(md.contains("(the published table)"), "{md}");
    // a plan without the published table's route is refused before any fit: the table
    // would go unjudged (exit 2, one line naming the file and the nodes)
    let plan = fits.join("ltc-work.toml");
    let plan_text = std::fs::read_to_string(&plan).unwrap();
    let quick_fixed = "  { samples = 1.0, max_iters = 1.0, nodes = \"fixed\" },\n";
    let k = plan_text
        .rfind(quick_fixed)
        .expect("the quick plan's fixed route");
    let mut without = plan_text.clone();
    without.replace_range(k..k + quick_fixed.len(), "");
    std::fs::write(&plan, without).unwrap();
    let out = run(&["--only", "ltc-work", "--preset", "quick", "--no-cache"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let last = err.trim_end().lines().last().unwrap_or_default();
    assert!(
        last.contains("results/fits/ltc-ggx.json")
            && last.contains("\"fixed\"")
            && last.contains("unjudged"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

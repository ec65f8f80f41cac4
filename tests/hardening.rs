//! The binary driven through every class of bad or extreme input: bad fit specs, extreme
//! `eval` arguments over the whole f64 range, malformed scenes, broken and non-normal
//! PNGs, output sets with an obstacle in the way, killed runs, and the inputs that are not
//! what they claim (empty selections, tables with nothing to compare, partial criterion
//! output). Each must give exit status 2, one line naming the input and no files — or a
//! finite, correct value — and never a panic.

mod common;

use ndfbench::cli::{AlphaMethod, EvalArgs, LambdaArg, MapName, NdfArg, Quantity};
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::bin;

fn scratch(name: &str) -> PathBuf {
    common::scratch("hard", name)
}

/// Every file under `dir` (recursively), as paths relative to it.
fn files_under(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    out.sort();
    out
}

/// No panic, exit status 2, and a single "error: …" line (stage lines may precede it)
/// that contains every one of `needles`.
#[track_caller]
fn assert_typed_error(out: &Output, what: &str, needles: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{what}: panicked\n{err}");
    assert_eq!(out.status.code(), Some(2), "{what}: exit status\n{err}");
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(errors.len(), 1, "{what}: not one error line\n{err}");
    let line = errors[0];
    assert_eq!(
        err.lines().last(),
        Some(line),
        "{what}: the error is not the last line\n{err}"
    );
    assert!(
        line.len() < 600,
        "{what}: message too long ({} chars)",
        line.len()
    );
    for n in needles {
        assert!(
            line.contains(n),
            "{what}: message does not name {n:?}: {line}"
        );
    }
}

const ALPHA_ME_SPEC: &str = include_str!("../fits/multiscale-alpha-me.toml");
const LTC_SPEC: &str = include_str!("../fits/ltc-ggx.toml");

/// `spec` with `from` replaced by `to`; `from` must occur, so that an edit of the spec
/// cannot silently turn a bad-input case into a valid one.
fn edit(spec: &str, from: &str, to: &str) -> String {
    assert!(spec.contains(from), "the spec no longer contains {from:?}");
    spec.replace(from, to)
}
const LAMBDA_SPEC: &str = include_str!("../fits/smith-lambda.toml");
const TENSOR_SCALE_SPEC: &str = include_str!("../fits/tensor-scale.toml");

#[test]
fn bad_fit_specs_are_refused_before_anything_is_written() {
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "points 2^64 − 1",
            edit(
                ALPHA_ME_SPEC,
                "training_points = 600",
                "training_points = 18446744073709551615",
            ),
            "line",
        ),
        (
            "points 1e9",
            edit(
                ALPHA_ME_SPEC,
                "training_points = 600",
                "training_points = 1000000000",
            ),
            "training_points",
        ),
        (
            "points as a float",
            edit(
                ALPHA_ME_SPEC,
                "training_points = 600",
                "training_points = 1e9",
            ),
            "[params]",
        ),
        (
            "terms 0",
            edit(ALPHA_ME_SPEC, "terms = 7", "terms = 0"),
            "terms",
        ),
        (
            "terms_large 0",
            edit(ALPHA_ME_SPEC, "terms_large = 8", "terms_large = 0"),
            "terms_large",
        ),
        (
            "table_entries 0",
            edit(ALPHA_ME_SPEC, "table_entries = 256", "table_entries = 0"),
            "table_entries",
        ),
        (
            "alpha_min 1e-300",
            edit(ALPHA_ME_SPEC, "alpha_min = 1e-4", "alpha_min = 1e-300"),
            "alpha_min",
        ),
        (
            "alpha_max ∞",
            edit(ALPHA_ME_SPEC, "alpha_max = 1e2", "alpha_max = inf"),
            "alpha_max",
        ),
        (
            "nan tolerance",
            edit(ALPHA_ME_SPEC, "max_rel = 1e-3", "max_rel = nan"),
            "tolerance.max_rel",
        ),
        (
            "huge iteration cap",
            edit(
                ALPHA_ME_SPEC,
                "refit_max_iters = 20000",
                "refit_max_iters = 100000000000",
            ),
            "refit_max_iters",
        ),
        (
            "unknown key in the header",
            format!("bogus_key = 1\n{ALPHA_ME_SPEC}"),
            "bogus_key",
        ),
        (
            "unknown key in [params]",
            edit(ALPHA_ME_SPEC, "[params]\n", "[params]\nbogus_key = 1\n"),
            "bogus_key",
        ),
        (
            "a key missing from [params]",
            edit(ALPHA_ME_SPEC, "table_entries = 256", ""),
            "table_entries",
        ),
        ("malformed TOML", "name = [".to_string(), "line"),
        (
            "nesting 100 000 deep",
            format!("a = {}{}\n", "[".repeat(100_000), "]".repeat(100_000)),
            "recursion",
        ),
        (
            "absurd name",
            edit(
                ALPHA_ME_SPEC,
                "name = \"multiscale-alpha-me\"",
                &format!("name = \"{}\"", "x".repeat(10_000)),
            ),
            "name",
        ),
        (
            "ltc alpha_min 1e-300",
            edit(LTC_SPEC, "alpha_min = 1e-5", "alpha_min = 1e-300"),
            "alpha_min",
        ),
        (
            "ltc samples",
            edit(LTC_SPEC, "samples = 24", "samples = 900000"),
            "samples",
        ),
        (
            "a bad value only in the precise preset's table",
            edit(
                LTC_SPEC,
                "[precise]\nsamples = 32",
                "[precise]\nsamples = 0",
            ),
            "[precise]",
        ),
        (
            // 2048 / 48 is no whole region: a region size derived from the spec
            "regions that do not divide the map",
            edit(TENSOR_SCALE_SPEC, "regions = 8", "regions = 48"),
            "regions",
        ),
        (
            "lambda points",
            edit(LAMBDA_SPEC, "points = 600", "points = 500000"),
            "points",
        ),
    ];
    for (what, text, needle) in cases {
        let d = scratch("spec");
        let fits = d.join("fits");
        std::fs::create_dir_all(&fits).unwrap();
        std::fs::write(fits.join("spec.toml"), &text).unwrap();
        let results = d.join("results");
        let out = common::regen_in(&fits, &results, &["--preset", "quick"])
            .output()
            .unwrap();
        assert_typed_error(&out, what, &[needle, "spec.toml"]);
        assert!(
            files_under(&results).is_empty(),
            "{what}: wrote {:?}",
            files_under(&results)
        );
        // the same validation on the eval paths that read the spec
        if text.contains("multiscale-alpha-me") {
            for args in [
                vec!["eval", "alpha-me", "--b", "0.5", "--method", "ours"],
                vec![
                    "eval",
                    "filter",
                    "--filter",
                    "seed000-moment",
                    "--alpha",
                    "0.5",
                    "--b",
                    "0.3",
                ],
            ] {
                let out = bin().args(&args).arg("--fits").arg(&fits).output().unwrap();
                assert_typed_error(&out, &format!("{what} via {args:?}"), &[needle]);
            }
        }
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn an_oversized_spec_file_is_refused_unread() {
    let d = scratch("bigspec");
    let fits = d.join("fits");
    std::fs::create_dir_all(&fits).unwrap();
    let mut text = ALPHA_ME_SPEC.to_string();
    text.push_str(&"# padding\n".repeat(200_000));
    std::fs::write(fits.join("big.toml"), &text).unwrap();
    let out = bin()
        .args(["regen"])
        .arg("--fits")
        .arg(&fits)
        .arg("--results")
        .arg(d.join("r"))
        .output()
        .unwrap();
    assert_typed_error(&out, "2 MB spec", &["limit"]);
    let _ = std::fs::remove_dir_all(&d);
}

/// Run `eval` and return its JSON, asserting it succeeded without a silent NaN.
#[track_caller]
fn eval_ok(args: &[&str]) -> serde_json::Value {
    let out = bin().arg("eval").args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{args:?}: {err}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_no_silent_nan(&v, &format!("{args:?}"));
    v
}

#[track_caller]
fn assert_no_silent_nan(v: &serde_json::Value, what: &str) {
    if v["value"].is_null() {
        assert_eq!(
            v["infinite"].as_bool(),
            Some(true),
            "{what}: null value, not infinite: {v}"
        );
    } else {
        assert!(
            v["value"].as_f64().is_some_and(f64::is_finite),
            "{what}: {v}"
        );
    }
    if let Some(f) = v["model"].get("f32") {
        assert!(f.as_f64().is_some_and(f64::is_finite), "{what}: f32 {f}");
    }
}

#[test]
fn extreme_eval_inputs_give_correct_values() {
    // the audit's examples, with independent references
    // ‖b̄‖ = 0.5 ↦ α = 1.815 (exact inverse of the closed form; the fit was 0.353 before)
    let v = eval_ok(&["alpha-me", "--b", "0.5", "--method", "ours"]);
    let a = v["value"].as_f64().unwrap();
    assert!((a / 1.8148 - 1.0).abs() < 1e-3, "{a}");
    // … and its round trip through the closed form (seed 000 Eq 4)
    let back = eval_ok(&["mrl", "--alpha", &a.to_string()])["value"]
        .as_f64()
        .unwrap();
    assert!((back - 0.5).abs() < 1e-3, "{back}");
    assert_eq!(v["model"]["inside_domain"].as_bool(), Some(true));
    // --b 0.3 ↦ 3.94 (was 0.0134); inside the fit domain [1e-4, 1e2] by its input
    let v = eval_ok(&["alpha-me", "--b", "0.3", "--method", "ours"]);
    assert!(
        (v["value"].as_f64().unwrap() / 3.94 - 1.0).abs() < 2e-3,
        "{v}"
    );
    // far outside the domain, judged from the input
    let v = eval_ok(&["alpha-me", "--one-minus-b", "1e-300", "--method", "ours"]);
    assert_eq!(v["model"]["inside_domain"].as_bool(), Some(false));
    // seed-000 moment filter: f32 form agrees with the f64 reference (5.04)
    let v = eval_ok(&[
        "filter",
        "--filter",
        "seed000-moment",
        "--alpha",
        "0.5",
        "--b",
        "0.3",
    ]);
    let (f64v, f32v) = (
        v["value"].as_f64().unwrap(),
        v["model"]["f32"].as_f64().unwrap(),
    );
    assert!((f64v / 5.04 - 1.0).abs() < 2e-3, "{f64v}");
    assert!((f32v / f64v - 1.0).abs() < 1e-3, "{f32v} vs {f64v}");
    // mrl at α = 1e155 and 1e300: ≈ π/(2α) (the large-α series)
    for a in [1e155f64, 1e300] {
        let v = eval_ok(&["mrl", "--alpha", &format!("{a:e}")]);
        let b = v["value"].as_f64().unwrap();
        assert!(
            (b * 2.0 * a / std::f64::consts::PI - 1.0).abs() < 1e-12,
            "{b}"
        );
    }
    // Newton inverse at y = 1e-300: the small-α series α²(ln(2/α) − 1) = y
    let v = eval_ok(&["alpha-me", "--one-minus-b", "1e-300", "--method", "newton"]);
    let a = v["value"].as_f64().unwrap();
    let y = a * a * ((2.0 / a).ln() - 1.0);
    assert!((y / 1e-300 - 1.0).abs() < 1e-12, "α {a}: y {y}");
    // toksvig / vMF at ‖μ‖ → 0: f64 finite; f32 absent (input below f32) or finite
    for f in ["toksvig-2", "vmf-2", "toksvig-1", "vmf-1", "vmf-half"] {
        for b in ["1e-300", "1e-30", "1e-45"] {
            let v = eval_ok(&["filter", "--filter", f, "--alpha", "0.5", "--b", b]);
            let bb: f64 = b.parse().unwrap();
            // α′ ~ √(c/r) as r → 0 (c ≤ 2 over (1 + r)(3 − r²) ≥ 1)
            let val = v["value"].as_f64().unwrap();
            assert!(
                val > 0.5 / bb.sqrt() * 0.3 && val < 2.0 / bb.sqrt(),
                "{f} {b}: {val}"
            );
        }
    }
    // Toksvig BP at huge and tiny α
    for a in ["1e300", "1e-300", "1e-160"] {
        let v = eval_ok(&[
            "filter",
            "--filter",
            "toksvig-bp",
            "--alpha",
            a,
            "--b",
            "0.5",
        ]);
        assert!(v["value"].as_f64().unwrap() > 0.0);
    }
    // ν below the horizon: signed everywhere (−∞ along −n, negative at (1, 0, −0.1))
    let v = eval_ok(&["nu", "--alpha", "0.5", "--o", "0,0,-1"]);
    assert!(
        v["value"].is_null() && v["sign"].as_i64() == Some(-1),
        "{v}"
    );
    let v = eval_ok(&["nu", "--alpha", "0.5", "--o", "1,0,-0.1"]);
    assert!(v["value"].as_f64().unwrap() < 0.0);
    // overall α at tiny roughness returns (bounded work) with the closed form
    let v = eval_ok(&["overall-alpha", "--alpha-mi", "1e-8", "--alpha-me", "1e-8"]);
    let m = v["value"].as_f64().unwrap();
    // ρ = ρ_me ρ_mi ⇒ y ≈ 2y(1e-8) ⇒ α ≈ 1e-8·√2 (1 + O(1/ln α))
    assert!(m > 1.3e-8 && m < 1.5e-8, "{m}");
}

#[test]
fn extreme_eval_inputs_that_cannot_be_answered_are_typed_errors() {
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (
            vec!["d", "--alpha", "1e-81", "--m", "0,0,1"],
            vec!["roughness", "1e-81"],
        ),
        (
            vec!["d", "--alpha", "1e-300", "--m", "0,0,1"],
            vec!["roughness", "1e-300"],
        ),
        (
            vec!["d", "--alpha", "1e300", "--m", "0,0,1"],
            vec!["roughness"],
        ),
        (
            vec!["d", "--matrix", "1e-200,0,1e-200", "--m", "0,0,1"],
            vec!["roughness"],
        ),
        (
            vec![
                "jacobian",
                "--map",
                "half-vector",
                "--w",
                "0,0,1",
                "--o",
                "0,0,-1",
            ],
            vec!["half-vector"],
        ),
        (
            vec![
                "filter",
                "--filter",
                "lean",
                "--alpha",
                "0.1",
                "--cov",
                "1e300,1e300,0",
            ],
            vec!["roughness"],
        ),
        (vec!["alpha-me", "--b", "1.5"], vec!["--b"]),
        (
            vec!["alpha-me", "--one-minus-b", "0"],
            vec!["--one-minus-b"],
        ),
        (vec!["mrl", "--alpha", "nan"], vec!["roughness"]),
        (vec!["d", "--alpha", "abc", "--m", "0,0,1"], vec!["--alpha"]),
        (
            vec!["overall-alpha", "--alpha-mi", "1e300", "--alpha-me", "0.1"],
            vec!["roughness"],
        ),
    ];
    for (args, needles) in cases {
        let out = bin().arg("eval").args(&args).output().unwrap();
        assert_typed_error(&out, &format!("{args:?}"), &needles);
        assert!(
            !String::from_utf8_lossy(&out.stderr).contains("NotSpd"),
            "{args:?}"
        );
    }
}

/// An f64 anywhere in the full range: ±1e-300 … ±1e300 log-uniform, subnormals, zero,
/// the largest finite numbers, ∞ and NaN.
fn extreme() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => (-300.0f64..300.0).prop_map(|e| 10f64.powf(e)),
        2 => (-300.0f64..300.0).prop_map(|e| -(10f64.powf(e))),
        1 => (1u64..(1u64 << 52)).prop_map(f64::from_bits),
        1 => Just(0.0f64),
        1 => Just(f64::MAX),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NAN),
        2 => -1.0f64..1.0,
    ]
}

/// A cosine with its extremes: uniform, within 1e-16 of 0 (grazing) or of ±1 (the pole).
fn cosine() -> impl Strategy<Value = f64> {
    prop_oneof![
        2 => -1.0f64..1.0,
        1 => (-16.0f64..0.0, any::<bool>()).prop_map(|(e, s)| if s { 10f64.powf(e) } else { -(10f64.powf(e)) }),
        1 => (-16.0f64..0.0, any::<bool>()).prop_map(|(e, s)| if s { 1.0 - 10f64.powf(e) } else { 10f64.powf(e) - 1.0 }),
    ]
}

/// A direction: mostly a unit vector with an extreme cosine, sometimes three extremes.
fn direction() -> impl Strategy<Value = [f64; 3]> {
    prop_oneof![
        3 => (cosine(), 0.0f64..std::f64::consts::TAU).prop_map(|(c, p)| {
            let s = (1.0 - c * c).max(0.0).sqrt();
            [s * p.cos(), s * p.sin(), c]
        }),
        1 => (extreme(), extreme(), extreme()).prop_map(|(a, b, c)| [a, b, c]),
    ]
}

/// A roughness: mostly log-uniform over the supported range and beyond, sometimes extreme.
fn roughness() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => (-80.0f64..80.0).prop_map(|e| 10f64.powf(e)),
        1 => extreme(),
    ]
}

fn list(v: &[f64]) -> Option<String> {
    Some(
        v.iter()
            .map(|x| format!("{x:e}"))
            .collect::<Vec<_>>()
            .join(","),
    )
}

fn args_for(q: Quantity) -> EvalArgs {
    EvalArgs {
        quantity: q,
        ndf: NdfArg::Ggx,
        alpha: None,
        alpha_xy: None,
        matrix: None,
        mean: None,
        lambda: LambdaArg::Exact,
        o: None,
        i: None,
        m: None,
        slope: None,
        map: None,
        w: None,
        b: None,
        one_minus_b: None,
        method: AlphaMethod::Newton,
        alpha_mi: None,
        alpha_me: None,
        filter: None,
        cov: None,
        dn_u: None,
        dn_v: None,
        du: None,
        dv: None,
    }
}

const QUANTITIES: [Quantity; 14] = [
    Quantity::D,
    Quantity::P22,
    Quantity::Lambda,
    Quantity::Nu,
    Quantity::G1,
    Quantity::G2Correlated,
    Quantity::G2Separable,
    Quantity::VndfPdf,
    Quantity::Jacobian,
    Quantity::Mrl,
    Quantity::AlphaMe,
    Quantity::OverallAlpha,
    Quantity::Filter,
    Quantity::D,
];

/// Every footprint filter of the registry, by key (the refitted ones read results/).
fn filter_key(i: usize) -> String {
    let all: Vec<_> = ndfbench::filters::registry::Filter::all().collect();
    all[i % all.len()].key().to_string()
}

const MAPS: [MapName; 5] = [
    MapName::NormalToSlope,
    MapName::Reflection,
    MapName::HalfVector,
    MapName::SlopeParallel,
    MapName::ProjectedDisk,
];

proptest! {
    #![proptest_config(common::config(10_000))]

    /// Every `eval` quantity over the full f64 range: a finite value (or a documented ±∞
    /// flagged as such), an f32 form that is a number where it is given, or a typed error
    /// with a one-line message. Never NaN, never a panic. (`overall-alpha` pairs inside
    /// the quadrature domain take ~1 s each and are covered by the tests above.)
    #[test]
    fn every_eval_quantity_is_finite_or_a_typed_error(
        qi in 0usize..QUANTITIES.len(),
        fi in 0usize..ndfbench::filters::registry::Filter::all().count(),
        mi in 0usize..MAPS.len(),
        beck in any::<bool>(),
        rough_kind in 0u8..3,
        x in proptest::collection::vec(extreme(), 12),
        r in proptest::collection::vec(roughness(), 3),
        d in proptest::collection::vec(direction(), 3),
        method in 0u8..4,
    ) {
        let q = QUANTITIES[qi];
        let mut a = args_for(q);
        a.ndf = if beck { NdfArg::Beckmann } else { NdfArg::Ggx };
        match rough_kind {
            0 => a.alpha = Some(r[0].abs()),
            1 => a.alpha_xy = list(&[r[0].abs(), r[1].abs()]),
            _ => a.matrix = list(&[r[0].abs(), r[1] * x[1].clamp(-1.0, 1.0).abs().sqrt() * r[0].abs().sqrt() * r[2].abs().sqrt() / r[1].abs().max(1e-300), r[2].abs()]),
        }
        if q == Quantity::Filter || q == Quantity::Mrl {
            a.alpha = Some(r[0].abs());
            a.alpha_xy = None;
            a.matrix = None;
        }
        if x[2] > 0.5 {
            a.mean = list(&[x[3].clamp(-1e3, 1e3), x[4].clamp(-1e3, 1e3)]);
        }
        a.o = list(&d[0]);
        a.i = list(&d[1]);
        a.m = list(&d[2]);
        a.w = list(&d[1]);
        a.slope = list(&[x[9], x[10]]);
        a.map = Some(MAPS[mi]);
        a.b = Some(x[9].abs().min(1.0));
        a.filter = Some(filter_key(fi));
        a.cov = list(&[x[9].abs(), x[10].abs(), x[11] * 1e-3]);
        a.dn_u = list(&[x[3], x[4], x[5]]);
        a.dn_v = list(&[x[6], x[7], x[8]]);
        a.du = list(&[x[9], x[10]]);
        a.dv = list(&[x[11], x[9]]);
        if q == Quantity::AlphaMe {
            a.method = [AlphaMethod::Newton, AlphaMethod::Ours, AlphaMethod::Table, AlphaMethod::Paper][method as usize];
            if x[11] > 0.0 {
                a.b = None;
                a.one_minus_b = Some(x[10].abs());
            }
        }
        if q == Quantity::OverallAlpha {
            let (mi, me) = (r[0].abs(), r[1].abs());
            let inside = |v: f64| (1e-3..=3.0).contains(&v);
            if inside(mi) && inside(me) {
                return Ok(());
            }
            a.alpha_mi = Some(mi);
            a.alpha_me = Some(me);
        }
        match ndfbench::cli::eval(&a, Path::new("fits"), Path::new("results")) {
            Ok(text) => {
                let v: serde_json::Value = serde_json::from_str(&text).unwrap();
                if v["value"].is_null() {
                    prop_assert_eq!(v["infinite"].as_bool(), Some(true), "{:?}: {}", q, v);
                } else {
                    prop_assert!(v["value"].as_f64().is_some_and(f64::is_finite), "{:?}: {}", q, v);
                }
                if let Some(f) = v["model"].get("f32") {
                    prop_assert!(f.as_f64().is_some_and(f64::is_finite), "{:?}: f32 {}", q, f);
                }
            }
            Err(e) => {
                let m = e.to_string();
                prop_assert!(!m.contains('\n') && m.len() < 600, "{:?}: {}", q, m);
            }
        }
    }
}

#[test]
fn malformed_scenes_write_nothing() {
    let good = include_str!("scenes/forward-ggx.toml");
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "newline in the name",
            good.replace(
                "name = \"forward-ggx\"",
                "name = \"x\\nfn evil() -> f32 { return 1.0; }\"",
            ),
            "name",
        ),
        (
            "path in the name",
            good.replace("name = \"forward-ggx\"", "name = \"../escape\""),
            "name",
        ),
        (
            "long name",
            good.replace(
                "name = \"forward-ggx\"",
                &format!("name = \"{}\"", "a".repeat(65)),
            ),
            "name",
        ),
        (
            "unknown key",
            format!("{good}\nshadows = true\n"),
            "shadows",
        ),
        (
            "bad value",
            good.replace("ndf = \"ggx\"", "ndf = \"phong\""),
            "ndf",
        ),
        (
            "nan budget",
            good.replace("error_budget = 0.25", "error_budget = nan"),
            "error_budget",
        ),
        ("not TOML", "name = ".to_string(), "scene"),
    ];
    for (what, text, needle) in cases {
        let d = scratch("scene");
        let f = d.join("s.toml");
        std::fs::write(&f, text).unwrap();
        let out_dir = d.join("out");
        let out = bin()
            .arg("scene")
            .arg(&f)
            .arg("--out")
            .arg(&out_dir)
            .output()
            .unwrap();
        assert_typed_error(&out, what, &[needle]);
        assert!(
            !out_dir.exists(),
            "{what}: wrote {:?}",
            files_under(&out_dir)
        );
        let _ = std::fs::remove_dir_all(&d);
    }
}

/// CRC-32 (IEEE) of a PNG chunk's type and data.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

fn png(path: &Path, w: u32, h: u32, px: impl Fn(u32, u32) -> [u8; 3]) {
    let mut img = image::RgbImage::new(w, h);
    for y in 0..h {
        for x in 0..w {
            img.put_pixel(x, y, image::Rgb(px(x, y)));
        }
    }
    img.save(path).unwrap();
}

#[test]
fn broken_and_non_normal_pngs_write_nothing() {
    let d = scratch("png");
    let cases: Vec<(&str, PathBuf, &str)> = {
        let garbage = d.join("garbage.png");
        std::fs::write(&garbage, b"\x89PNG\r\n\x1a\nthis is not a png at all").unwrap();
        let truncated = d.join("truncated.png");
        png(&truncated, 16, 16, |_, _| [128, 128, 255]);
        let bytes = std::fs::read(&truncated).unwrap();
        std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
        let grey = d.join("grey.png");
        png(&grey, 16, 16, |_, _| [128, 128, 128]);
        let half = d.join("half-grey.png");
        png(&half, 16, 16, |x, _| {
            if x < 8 {
                [128, 128, 255]
            } else {
                [128, 128, 128]
            }
        });
        let npot = d.join("npot.png");
        png(&npot, 12, 16, |_, _| [128, 128, 255]);
        let below = d.join("below.png");
        png(&below, 16, 16, |_, _| [128, 128, 0]);
        // a header that declares 65536² texels over a few bytes of data: refused before
        // anything is allocated
        let huge = d.join("huge.png");
        {
            let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
            let chunk = |bytes: &mut Vec<u8>, t: &[u8], data: &[u8]| {
                bytes.extend((data.len() as u32).to_be_bytes());
                let mut td = t.to_vec();
                td.extend(data);
                bytes.extend(&td);
                bytes.extend(crc32(&td).to_be_bytes());
            };
            let mut ihdr = Vec::new();
            ihdr.extend(65536u32.to_be_bytes());
            ihdr.extend(65536u32.to_be_bytes());
            ihdr.extend([8, 2, 0, 0, 0]);
            chunk(&mut bytes, b"IHDR", &ihdr);
            chunk(&mut bytes, b"IEND", &[]);
            std::fs::write(&huge, bytes).unwrap();
        }
        let luma = d.join("luma.png");
        image::GrayImage::from_pixel(16, 16, image::Luma([128]))
            .save(&luma)
            .unwrap();
        vec![
            ("garbage", garbage, "garbage.png"),
            ("truncated", truncated, "truncated.png"),
            ("grey RGB(128,128,128)", grey, "not a normal map"),
            ("half grey", half, "50.0 %"),
            ("not a power of two", npot, "powers of two"),
            ("below the horizon", below, "upper-hemisphere"),
            ("uniform luma", luma, "luma.png"),
            ("65536² declared", huge, "huge.png"),
        ]
    };
    for (what, input, needle) in cases {
        for extra in [vec!["--alpha", "0.1"], vec!["--study"], vec!["--rank", "4"]] {
            let out_dir = d.join("out");
            let out = bin()
                .arg("prefilter")
                .arg("--input")
                .arg(&input)
                .args(&extra)
                .args(["--preset", "quick", "--out"])
                .arg(&out_dir)
                .output()
                .unwrap();
            assert_typed_error(&out, &format!("{what} {extra:?}"), &[needle]);
            assert!(
                !out_dir.exists(),
                "{what}: wrote {:?}",
                files_under(&out_dir)
            );
        }
    }
    // a genuine map passes the same check (flat normals, exact unit length)
    let flat = d.join("flat.png");
    png(&flat, 16, 16, |_, _| [128, 128, 255]);
    assert!(ndfbench::filters::footprint::NormalMap::from_png(&flat).is_ok());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn an_obstacle_in_the_last_write_leaves_no_partial_set() {
    // prefilter --rank writes tensor-flakes.json, .md and -rank.svg: a directory where the
    // JSON goes must stop the whole set
    let d = scratch("obstacle");
    let out_dir = d.join("out");
    std::fs::create_dir_all(out_dir.join("tensor-flakes.json")).unwrap();
    let run = || {
        bin()
            .args([
                "prefilter",
                "--generator",
                "flakes",
                "--rank",
                "4",
                "--preset",
                "quick",
            ])
            .arg("--out")
            .arg(&out_dir)
            .output()
            .unwrap()
    };
    let out = run();
    assert_typed_error(&out, "directory in the way", &["tensor-flakes.json"]);
    assert!(
        files_under(&out_dir).is_empty(),
        "{:?}",
        files_under(&out_dir)
    );
    // without the obstacle the same command publishes the set with its manifest
    std::fs::remove_dir_all(out_dir.join("tensor-flakes.json")).unwrap();
    let out = run();
    common::assert_success(&out);
    assert!(ndfbench::io::set_is_complete(
        &out_dir.join(".manifest.json")
    ));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn killed_runs_leave_complete_sets_or_none_and_no_temporaries_after_the_next_run() {
    let d = scratch("kill");
    let fits = d.join("fits");
    std::fs::create_dir_all(&fits).unwrap();
    std::fs::write(fits.join("multiscale-alpha-me.toml"), ALPHA_ME_SPEC).unwrap();
    let results = d.join("results");
    let manifest = ndfbench::io::results_manifest(&results, "multiscale-alpha-me");
    let run = || {
        let mut c = common::regen_in(
            &fits,
            &results,
            &["--only", "multiscale-alpha-me", "--preset", "quick"],
        );
        c.stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null());
        c
    };
    // kill at spread-out moments of a run (the delays only spread the kill points; the
    // assertions hold wherever the kill lands)
    for k in 0..24u64 {
        let mut child = run().spawn().unwrap();
        std::thread::sleep(std::time::Duration::from_millis(k * 9));
        let _ = child.kill();
        let _ = child.wait();
        // the invariant: a manifest on disk means the set it lists is complete
        if manifest.exists() {
            assert!(
                ndfbench::io::set_is_complete(&manifest),
                "kill {k}: mixed set"
            );
        }
    }
    let st = run().status().unwrap();
    assert!(st.success());
    assert!(ndfbench::io::set_is_complete(&manifest));
    let temps: Vec<String> = files_under(&results)
        .into_iter()
        .filter(|f| f.contains(".tmp."))
        .collect();
    assert!(temps.is_empty(), "stale temporaries {temps:?}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn inputs_that_are_not_what_they_claim() {
    // an empty selection is an error, as for regen --only
    let out = bin()
        .args(["verify", "--only", "no-such-check", "--preset", "quick"])
        .output()
        .unwrap();
    assert_typed_error(&out, "verify --only", &["no-such-check"]);
    // --only takes exact names: a part of one is refused with the names that contain it
    let out = bin()
        .args(["verify", "--only", "jacobian", "--preset", "quick"])
        .output()
        .unwrap();
    assert_typed_error(
        &out,
        "verify --only part",
        &["jacobian-reflection", "proofs/"],
    );
    let out = bin().args(["regen", "--only", "ltc"]).output().unwrap();
    assert_typed_error(
        &out,
        "regen --only part",
        &[
            "\"ltc\"",
            "ltc-ggx",
            "ltc-sheen",
            "multiscale-convolution",
            "valid",
        ],
    );
    let d = scratch("claims");
    // a shipped table with nothing comparable
    let nan = vec!["NaN"; 64 * 64 * 4].join(", ");
    let js = d.join("nan.js");
    std::fs::write(
        &js,
        format!("const LTC_MAT_1 = [{nan}];\nconst LTC_MAT_2 = [{nan}];\n"),
    )
    .unwrap();
    let out_dir = d.join("cmp");
    let out = bin()
        .args(["ltc-compare", "--shipped"])
        .arg(&js)
        .arg("--out")
        .arg(&out_dir)
        .output()
        .unwrap();
    assert_typed_error(&out, "all-NaN table", &["nan.js"]);
    assert!(files_under(&out_dir).is_empty());
    // a partial criterion directory with a negative time
    let crit = d.join("criterion/g/f/new");
    std::fs::create_dir_all(&crit).unwrap();
    std::fs::write(
        crit.join("benchmark.json"),
        r#"{"group_id":"filters","function_id":"toksvig","value_str":null}"#,
    )
    .unwrap();
    std::fs::write(
        crit.join("estimates.json"),
        r#"{"mean":{"point_estimate":-5.0,"confidence_interval":{"lower_bound":-6.0,"upper_bound":-4.0}}}"#,
    )
    .unwrap();
    let res = d.join("results");
    let out = bin()
        .args(["bench-report", "--criterion"])
        .arg(d.join("criterion"))
        .arg("--results")
        .arg(&res)
        .output()
        .unwrap();
    assert_typed_error(
        &out,
        "negative criterion time",
        &["estimates.json", "positive"],
    );
    assert!(files_under(&res).is_empty(), "{:?}", files_under(&res));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn missing_values_show_as_dashes() {
    let md = "| a | NaN× | inf | 1.5× | NaN % |\nx NaN\n";
    let out = ndfbench::studies::performance::missing_as_dash(md);
    assert_eq!(out, "| a | — | — | 1.5× | — % |\nx —\n");
}

#[test]
fn horizon_command_rejects_bad_height_maps_and_writes_nothing() {
    let d = scratch("horizon");
    let out_dir = d.join("out");
    let good = d.join("h.png");
    image::GrayImage::from_fn(32, 32, |x, y| image::Luma([((x * 7 + y * 3) % 256) as u8]))
        .save(&good)
        .unwrap();
    let wide = d.join("wide.png");
    image::GrayImage::from_fn(64, 32, |x, _| image::Luma([x as u8]))
        .save(&wide)
        .unwrap();
    let broken = d.join("broken.png");
    std::fs::write(&broken, b"\x89PNG\r\n\x1a\n truncated").unwrap();
    let cases: [(&std::path::Path, &str, &[&str]); 5] = [
        (&good, "nan", &["scale"]),
        (&good, "-1", &["scale"]),
        (&good, "1e300", &["scale"]),
        (&wide, "1", &["square"]),
        (&broken, "1", &["height map"]),
    ];
    for (input, scale, needles) in cases {
        let out = bin()
            .args(["horizon", "--input"])
            .arg(input)
            .arg(format!("--scale={scale}"))
            .args(["--preset", "quick", "--out"])
            .arg(&out_dir)
            .output()
            .unwrap();
        assert_typed_error(&out, "horizon", needles);
        assert!(
            !out_dir.join("horizon.md").exists(),
            "horizon wrote output for bad input {input:?} --scale {scale}"
        );
    }
    // a good map writes both files
    let out = bin()
        .args(["horizon", "--input"])
        .arg(&good)
        .args(["--scale", "8", "--preset", "quick", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    common::assert_success(&out);
    let md = std::fs::read_to_string(out_dir.join("horizon.md")).unwrap();
    assert!(md.contains("Tan et al.") && !md.contains("NaN"));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("converted to grey"));
    // an RGB map is converted to grey, and the command and the report say so
    let rgb = d.join("rgb.png");
    image::RgbImage::from_fn(32, 32, |x, y| {
        image::Rgb([(x * 7) as u8, (y * 5) as u8, 40])
    })
    .save(&rgb)
    .unwrap();
    let out = bin()
        .args(["horizon", "--input"])
        .arg(&rgb)
        .args(["--scale", "8", "--preset", "quick", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("converted to grey"), "{err}");
    let md = std::fs::read_to_string(out_dir.join("horizon.md")).unwrap();
    assert!(md.contains("converted to grey"));
    std::fs::remove_dir_all(&d).ok();
}

/// One writer per results folder: a set is published under `.publish.lock` beside its
/// manifest. A lock held by a running process holds the next writer back until that
/// process is gone (its lock is then stale and taken over); a lock left by a dead process
/// is taken over at once; the lock is gone after the set is published.
#[test]
fn one_writer_per_results_folder() {
    use ndfbench::io::in_set;
    let dir = scratch("lock");
    let manifest = dir.join(".sets").join("x.json");
    let lock = dir.join(".sets").join(".publish.lock");
    std::fs::create_dir_all(dir.join(".sets")).unwrap();
    // a dead holder: a child that has exited
    let mut dead = Command::new("true").spawn().expect("true runs");
    let pid = dead.id();
    dead.wait().unwrap();
    std::fs::write(&lock, format!("{pid}\n")).unwrap();
    in_set("x", &manifest, |set| {
        set.put(dir.join("a.txt"), b"a");
        Ok(())
    })
    .expect("taken over");
    assert_eq!(std::fs::read(dir.join("a.txt")).unwrap(), b"a");
    assert!(!lock.exists(), "released after publishing");
    // a live holder: nothing is published while it runs
    let mut live = Command::new("sleep").arg("60").spawn().expect("sleep runs");
    std::fs::write(&lock, format!("{}\n", live.id())).unwrap();
    let (d2, m2) = (dir.clone(), manifest.clone());
    let writer = std::thread::spawn(move || {
        in_set("x", &m2, |set| {
            set.put(d2.join("b.txt"), b"b");
            Ok(())
        })
    });
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert!(
        !dir.join("b.txt").exists(),
        "published while another process held the folder"
    );
    live.kill().unwrap();
    live.wait().unwrap();
    writer
        .join()
        .unwrap()
        .expect("published once the holder is gone");
    assert_eq!(std::fs::read(dir.join("b.txt")).unwrap(), b"b");
    assert!(!lock.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A result file that exists but is not JSON is an error naming it, never "not run yet";
/// a missing one is `None`.
#[test]
fn a_malformed_result_is_an_error_not_an_absent_one() {
    let dir = common::scratch("hardening", "result");
    std::fs::create_dir_all(dir.join("fits")).unwrap();
    assert!(matches!(
        ndfbench::results::read::<ndfbench::results::filters::Filters>(&dir),
        Ok(None)
    ));
    std::fs::write(dir.join("fits/filters.json"), b"{\"fitted\": [1, 2").unwrap();
    let e = ndfbench::results::read::<ndfbench::results::filters::Filters>(&dir)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("filters.json") && e.contains("not a well-formed result"),
        "{e}"
    );
    // and the readers that used to take it for absent now say so
    let e = ndfbench::prefilter::measured(&dir).unwrap_err().to_string();
    assert!(e.contains("filters.json"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The tensor study quotes results/tensor-tensorly.json: a file there that is not a
/// TensorLy comparison stops the study with a one-line error naming it (exit 2, nothing
/// written), instead of reading as "not measured".
#[test]
fn a_foreign_tensorly_comparison_stops_the_tensor_study() {
    let dir = common::scratch("hardening", "tensorly");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("tensor-tensorly.json"), b"{\"not\": \"a report\"}").unwrap();
    let out = common::bin()
        .args(["--no-cache", "--results"])
        .arg(&dir)
        .args(["regen", "--only", "tensor", "--preset", "quick"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let line = err.lines().last().unwrap_or("");
    assert!(
        line.contains("tensor-tensorly.json") && line.contains("not a TensorLy comparison"),
        "{err}"
    );
    assert!(!dir.join("tensor.md").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `engines-sheen` with bad runs: a missing file, a file that is not JSON, a run that names
/// no scene file, one that names a missing scene file, and a run of another table each exit
/// 2 with one line naming the defect, and write nothing.
#[test]
fn engines_sheen_refuses_bad_runs_with_one_line() {
    let dir = common::scratch("hardening", "engines-sheen");
    let out = dir.join("out");
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let cases: Vec<(std::path::PathBuf, &str, Vec<&str>)> = vec![
        (
            dir.join("absent.json"),
            "a missing run",
            vec!["absent.json"],
        ),
        (
            write("text.json", "not json"),
            "a run that is not JSON",
            vec!["text.json", "names no scene file"],
        ),
        (
            write(
                "noscenes.json",
                r#"{"table": "sheen", "engine": "three.js", "paths": {}}"#,
            ),
            "a run naming no scene file",
            vec!["names no scene file"],
        ),
        (
            write(
                "missing.json",
                r#"{"table": "sheen", "engine": "three.js", "scenes": "engines/three/none.json", "paths": {}}"#,
            ),
            "a run naming a missing scene file",
            vec!["none.json"],
        ),
        (
            write(
                "ours.json",
                r#"{"table": "ours", "engine": "three.js", "scenes": "engines/three/scenes_sheen.json", "paths": {}}"#,
            ),
            "another table's run",
            vec!["not the sheen run"],
        ),
    ];
    for (run, what, needles) in cases {
        let o = common::bin()
            .args(["engines-sheen", "--three"])
            .arg(&run)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert_typed_error(&o, what, &needles);
        assert!(
            !out.join("engines-sheen.md").exists(),
            "{what}: a report was written"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

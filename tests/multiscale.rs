//! Multi-scale LTC (seed 000 §3.3): closed form against an independent 1D integral, limits,
//! derivative, inverse, the α_me fit and its spec handling.

mod common;

use ndfbench::fit::spec::FitSpec;
use ndfbench::integrate::quad::{gk15_breaks, Tol};
use ndfbench::multiscale::alpha_me::{fit_ours, held_out, held_out_alphas, training_alphas};
use ndfbench::multiscale::mrl::{
    alpha_from_mrl, alpha_from_one_minus, alpha_me_paper, mrl_derivative, mrl_pair,
};
use ndfbench::Error;
use proptest::prelude::*;

/// ‖b̄‖ = ∫₀^∞ α²(α² + u)⁻²(1 + u)^(−1/2) du (the slope-space form of Eq 4), by 1D
/// quadrature in v = ln u (u = e^v, du = u dv): the mass spreads over every scale between
/// α² and 1, which a log variable turns into a smooth bounded integrand.
fn mrl_1d(a: f64) -> f64 {
    let f = |v: f64| {
        let u = v.exp();
        u * a * a / ((a * a + u) * (a * a + u)) / (1.0 + u).sqrt()
    };
    let lo = (a * a).ln() - 45.0;
    let breaks: Vec<f64> = (0..=24)
        .map(|k| lo + (90.0 - lo) * k as f64 / 24.0)
        .collect();
    let e = gk15_breaks(&f, &breaks, Tol::new(1e-16, 1e-15, 2_000_000));
    e.value
}

#[test]
fn closed_form_matches_the_slope_space_integral() {
    for a in [
        1e-4, 1e-3, 0.05, 0.3, 0.95, 0.999, 1.0, 1.001, 1.05, 2.0, 7.0,
    ] {
        let (b, y) = mrl_pair(a);
        let q = mrl_1d(a);
        assert!((b - q).abs() < 1e-12, "α={a}: {b} vs {q}");
        assert!((b + y - 1.0).abs() < 1e-15);
    }
    assert_eq!(mrl_pair(1.0).0, 2.0 / 3.0);
}

#[test]
fn limits_and_branch_joins() {
    // α → 0: 1 − ‖b̄‖ ≈ α²(ln(2/α) − 1)
    let a = 1e-7;
    let r = mrl_pair(a).1 / (a * a * ((2.0 / a).ln() - 1.0));
    assert!((r - 1.0).abs() < 1e-9, "{r}");
    // α → ∞: ‖b̄‖ ≈ π/(2α)
    let a = 1e6;
    assert!((mrl_pair(a).0 * 2.0 * a / std::f64::consts::PI - 1.0).abs() < 1e-5);
    // the series (|1 − α²| < 0.1) joins both closed-form branches continuously
    for edge in [0.1f64, -0.1] {
        let a = (1.0 - edge).sqrt();
        let below = mrl_pair(a * (1.0 - 1e-12)).0;
        let above = mrl_pair(a * (1.0 + 1e-12)).0;
        assert!((below - above).abs() < 1e-11, "{below} vs {above}");
    }
}

proptest! {
    #![proptest_config(common::config(10_000))] // was 500

    #[test]
    fn derivative_matches_central_differences(l in -4.0f64..1.5) {
        let a = 10f64.powf(l);
        let h = 1e-6 * a;
        // differentiate 1 − ‖b̄‖ (full relative precision as ‖b̄‖ → 1)
        let fd = -(mrl_pair(a + h).1 - mrl_pair(a - h).1) / (2.0 * h);
        let d = mrl_derivative(a);
        prop_assert!((fd - d).abs() <= 1e-6 * d.abs() + 1e-9, "α={a}: {d} vs FD {fd}");
    }

    #[test]
    fn inverse_round_trips(l in -6.0f64..2.0) {
        let a = 10f64.powf(l);
        let back = alpha_from_one_minus(mrl_pair(a).1).unwrap();
        prop_assert!((back - a).abs() <= 1e-13 * a, "α={a}: {back}");
    }

    /// Over the whole f64 range (α from 1e-300 to 1e300): ‖b̄‖ and 1 − ‖b̄‖ are finite,
    /// in [0, 1], and agree with the asymptotic series at both ends (an independent
    /// reference: 1 − ‖b̄‖ = α²(ln(2/α) − 1)(1 + O(α²)), ‖b̄‖ = π/(2α) − 2/α² + O(α⁻³)).
    #[test]
    fn mrl_is_finite_over_the_whole_range(l in -300.0f64..300.0) {
        let a = 10f64.powf(l);
        let (b, y) = mrl_pair(a);
        prop_assert!(b.is_finite() && y.is_finite() && (0.0..=1.0).contains(&b) && (0.0..=1.0).contains(&y), "α {a}: {b} {y}");
        if a < 1e-8 && a > 1e-150 {
            let want = a * a * ((2.0 / a).ln() - 1.0);
            prop_assert!((y / want - 1.0).abs() < 1e-12, "α {a}: {y} vs {want}");
        }
        if a > 1e8 {
            let want = std::f64::consts::FRAC_PI_2 / a - 2.0 / (a * a);
            prop_assert!((b / want - 1.0).abs() < 1e-12, "α {a}: {b} vs {want}");
        }
        // the inverse recovers α wherever the pair carries the information
        if a > 1e-150 && a < 1e150 {
            let back = ndfbench::multiscale::mrl::alpha_from_pair(b, y).unwrap();
            prop_assert!((back / a - 1.0).abs() < 1e-12, "α {a}: {back}");
        }
    }
}

#[test]
fn inverse_rejects_out_of_range_input() {
    for b in [0.0, 1.0, -0.5, 1.5, f64::NAN] {
        assert!(
            matches!(alpha_from_mrl(b), Err(Error::InvalidArgument(_))),
            "{b}"
        );
    }
}

#[test]
fn paper_eq5_goes_negative_as_b_tends_to_1() {
    // straight arithmetic on the printed coefficients (seed 000 Eq 5)
    let num1 = 1.629 + 17.05 - 18.96 - 23.37 + 23.65;
    let den1 = 1.0 - 28.07 + 31.1 - 3.545;
    assert!(num1 < 0.0 && den1 > 0.0);
    assert!((alpha_me_paper(1.0) - num1 / den1).abs() < 1e-15);
    assert!(alpha_me_paper(0.9999) < 0.0);
}

#[test]
fn our_fit_meets_its_goal_with_the_right_limits() {
    // the goal: max relative error ≤ 1e-3 on α ∈ [1e-4, 1e2]
    let train = training_alphas(600, 1e-4, 1e2);
    let c = fit_ours(7, 8, &train).unwrap();
    let h = held_out(&held_out_alphas(3000, 1e-4, 1e2), &|_b, y| c.eval(y));
    assert!(h.max_rel <= 1e-3, "{h:?}");
    // pinned: ‖b̄‖ = 2/3 ↦ α = 1, from both sides
    assert!((c.eval(1.0 / 3.0) - 1.0).abs() < 1e-6);
    assert!((c.eval(1.0 / 3.0 + 1e-12) - 1.0).abs() < 1e-6);
    // right limits far outside the fit domain: α = 1e-6 and 1e-12 (small end), α = 1e6
    // and 1e12 (large end, ‖b̄‖ ~ π/(2α)); the references are the asymptotic series,
    // independent of the fit
    for a in [1e-6f64, 1e-12] {
        let y = a * a * ((2.0 / a).ln() - 1.0);
        assert!((c.eval(y) / a - 1.0).abs() < 1e-3, "α {a}: {}", c.eval(y));
    }
    for a in [1e6f64, 1e12] {
        let b = std::f64::consts::FRAC_PI_2 / a - 2.0 / (a * a);
        let y = 1.0 - b;
        // y ≥ ½ so b = 1 − y is what the form sees; compare with π/(2b) − 4/π
        let b_seen = 1.0 - y;
        let want = std::f64::consts::FRAC_PI_2 / b_seen - 4.0 / std::f64::consts::PI;
        assert!(
            (c.eval(y) / want - 1.0).abs() < 1e-3,
            "α {a}: {}",
            c.eval(y)
        );
    }
    // total: the ends and nonsense give finite α ≥ 0 in f64 and f32
    for y in [0.0, 1.0, -1.0, 2.0, f64::NAN, f64::INFINITY, 1e-320] {
        let v = c.eval(y);
        assert!(v.is_finite() && v >= 0.0, "y {y}: {v}");
        let v = c.eval_f32(y as f32);
        assert!(v.is_finite() && v >= 0.0, "y {y}: {v}");
    }
    assert!(c.eval(0.0) < 1e-150 && c.eval(1.0) > 1e300);
}

const SPEC: &str = include_str!("../fits/multiscale-alpha-me.toml");
use ndfbench::integrate::Preset;
use ndfbench::studies::multiscale_alpha_me::Params as AlphaMeParams;

#[test]
fn the_shipped_spec_parses() {
    let s = FitSpec::parse(SPEC, "fits/multiscale-alpha-me.toml").unwrap();
    assert_eq!(s.name, "multiscale-alpha-me");
}

#[test]
fn malformed_specs_are_typed_errors_naming_the_problem() {
    let unknown = format!("bogus_key = 1\n{SPEC}");
    match FitSpec::parse(&unknown, "x.toml") {
        Err(Error::InvalidArgument(m)) => {
            assert!(m.contains("bogus_key") && m.contains("x.toml"), "{m}")
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        FitSpec::parse("name = [", "y.toml"),
        Err(Error::InvalidArgument(_))
    ));
    // the header parses; the study's parameters are checked where they are read
    let bad_domain = SPEC.replace("alpha_min = 1e-4", "alpha_min = 200.0");
    assert!(bad_domain != SPEC);
    let s = FitSpec::parse(&bad_domain, "z.toml").unwrap();
    match s.params::<AlphaMeParams>(Preset::Default) {
        Err(Error::InvalidArgument(m)) => {
            assert!(m.contains("alpha_min") && m.contains("z.toml"), "{m}")
        }
        other => panic!("{other:?}"),
    }
    // a key the study does not read, inside [params], is named
    let unread = SPEC.replace("[params]\n", "[params]\nsamples = 4\n");
    assert!(unread != SPEC);
    let s = FitSpec::parse(&unread, "u.toml").unwrap();
    match s.params::<AlphaMeParams>(Preset::Quick) {
        Err(Error::InvalidArgument(m)) => {
            assert!(m.contains("samples") && m.contains("u.toml"), "{m}")
        }
        other => panic!("{other:?}"),
    }
    // and so is a key a preset's table sets that the study does not read
    let unread = format!("{SPEC}\n[quick]\nmetric_points = 3\n");
    let s = FitSpec::parse(&unread, "q.toml").unwrap();
    assert!(s.params::<AlphaMeParams>(Preset::Default).is_ok());
    match s.params::<AlphaMeParams>(Preset::Quick) {
        Err(Error::InvalidArgument(m)) => {
            assert!(m.contains("metric_points") && m.contains("[quick]"), "{m}")
        }
        other => panic!("{other:?}"),
    }
}

/// A preset's table replaces the keys it names and keeps the others: the convolution
/// study's quick preset fits a 3² metric grid, its default the spec's 7².
#[test]
fn a_preset_table_replaces_only_the_keys_it_names() {
    let text = include_str!("../fits/multiscale-convolution.toml");
    let s = FitSpec::parse(text, "fits/multiscale-convolution.toml").unwrap();
    type P = ndfbench::studies::multiscale_convolution::Params;
    let (d, q, p) = (
        s.params::<P>(Preset::Default).unwrap(),
        s.params::<P>(Preset::Quick).unwrap(),
        s.params::<P>(Preset::Precise).unwrap(),
    );
    assert_eq!(
        (d.metric_points, q.metric_points, p.metric_points),
        (7, 3, 7)
    );
    assert_eq!((d.dense_points, q.dense_points), (40, 40));
    assert_eq!((q.alpha_min, q.alpha_max), (0.01, 1.0));
}

#[test]
fn regen_writes_its_results_atomically() {
    let dir = common::scratch("multiscale", "regen");
    let fits = dir.join("fits");
    std::fs::create_dir_all(&fits).unwrap();
    std::fs::write(fits.join("multiscale-alpha-me.toml"), SPEC).unwrap();
    let out = ndfbench::studies::regen(
        &fits,
        &dir.join("results"),
        Some("multiscale-alpha-me"),
        ndfbench::integrate::Preset::Quick,
    )
    .unwrap();
    assert!(out.iter().all(|o| o.passed), "{out:?}");
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("results/fits/multiscale-alpha-me.json")).unwrap(),
    )
    .unwrap();
    assert!(json["ours"]["held_out"]["max_rel"].as_f64().unwrap() <= 1e-3);
    // no temporary files left behind
    let leftovers: Vec<_> = std::fs::read_dir(dir.join("results"))
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp."))
        .collect();
    assert!(leftovers.is_empty());
    // a spec that parses but cannot drive this fit is a typed error, not a panic
    std::fs::write(
        fits.join("multiscale-alpha-me.toml"),
        SPEC.replace("terms = 7", "terms = 0"),
    )
    .unwrap();
    assert!(matches!(
        ndfbench::studies::regen(
            &fits,
            &dir.join("results"),
            Some("multiscale-alpha-me"),
            ndfbench::integrate::Preset::Quick
        ),
        Err(Error::InvalidArgument(ref m)) if m.contains("terms")
    ));
    std::fs::write(fits.join("multiscale-alpha-me.toml"), SPEC).unwrap();
    // --only takes exact names: a part of one, or a study without a spec here, is an
    // error listing the valid names, not silence and not a guess
    for wrong in [
        "multiscale",
        "nothing-here",
        "ltc-ggx",
        "multiscale-alpha-me,",
    ] {
        match ndfbench::studies::regen(
            &fits,
            &dir.join("results"),
            Some(wrong),
            ndfbench::integrate::Preset::Quick,
        ) {
            Err(Error::InvalidArgument(m)) => assert!(
                m.contains("valid: multiscale-alpha-me") && m.contains("--only"),
                "{wrong}: {m}"
            ),
            other => panic!("--only {wrong}: {other:?}"),
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn convolution_regen_runs_at_the_quick_preset() {
    let dir = common::scratch("multiscale", "conv");
    let fits = dir.join("fits");
    std::fs::create_dir_all(&fits).unwrap();
    std::fs::write(fits.join("multiscale-alpha-me.toml"), SPEC).unwrap();
    std::fs::write(
        fits.join("multiscale-convolution.toml"),
        include_str!("../fits/multiscale-convolution.toml"),
    )
    .unwrap();
    let out = ndfbench::studies::regen(
        &fits,
        &dir.join("results"),
        Some("multiscale-convolution"),
        ndfbench::integrate::Preset::Quick,
    )
    .unwrap();
    assert_eq!(out.len(), 1);
    assert!(out[0].passed, "{out:?}");
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("results/fits/multiscale-convolution.json")).unwrap(),
    )
    .unwrap();
    // every metric produced a finite α at every grid point, and the limits of ours hold
    for p in json["metric_grid"].as_array().unwrap() {
        for k in ["moment_unclipped", "moment_clipped", "l2", "caps"] {
            assert!(p[k].as_f64().unwrap().is_finite(), "{p}");
        }
    }
    let md = std::fs::read_to_string(dir.join("results/multiscale-convolution.md")).unwrap();
    assert!(md.contains("Eq 7 recomputed") && md.contains("vMF"));
    let _ = std::fs::remove_dir_all(&dir);
}

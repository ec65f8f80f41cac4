//! Integration engines against closed forms (expected values are analytic, not produced
//! by the engines).

mod common;

use nalgebra::Vector3;
use ndfbench::integrate::mc::{mis, CosineHemisphere, Strategy, UniformHemisphere, UniformSphere};
use ndfbench::integrate::qmc::{qmc_mis, MAX_POINTS};
use ndfbench::integrate::quad::{gauss_legendre, gk15, gl_1d, gl_2d, integrate_1d, Subst, Tol};
use ndfbench::integrate::sphere::{integrate_sphere, SphereRule};
use ndfbench::Error;
use std::f64::consts::PI;

#[test]
fn gauss_legendre_is_exact_for_degree_2n_minus_1() {
    for n in [1usize, 2, 3, 5, 8, 17, 64] {
        let deg = 2 * n - 1;
        // ∫_{-1}^{1} x^k dx = 2/(k+1) for even k, 0 for odd k
        for k in 0..=deg {
            let e = gl_1d(&|x: f64| x.powi(k as i32), -1.0, 1.0, n);
            let exact = if k % 2 == 0 {
                2.0 / (k as f64 + 1.0)
            } else {
                0.0
            };
            assert!(
                (e.value - exact).abs() < 1e-13,
                "n={n} k={k}: {} vs {exact}",
                e.value
            );
        }
    }
    let (x, w) = gauss_legendre(200);
    assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-13);
    assert!(x.windows(2).all(|p| p[0] < p[1]));
}

#[test]
fn gl_2d_tensor_product() {
    // ∫_0^1∫_0^2 x² e^y dy dx = (1/3)(e² − 1)
    let e = gl_2d(
        &|x: f64, y: f64| x * x * y.exp(),
        [0.0, 1.0],
        [0.0, 2.0],
        8,
        16,
    );
    let exact = (2f64.exp() - 1.0) / 3.0;
    assert!((e.value - exact).abs() < 1e-13);
    assert!(e.error < 1e-5);
}

#[test]
fn adaptive_gk_reports_honest_errors() {
    let tol = Tol::new(1e-12, 1e-12, 1_000_000);
    let e = gk15(&|x: f64| x.sin(), 0.0, PI, tol);
    assert!(
        e.converged && (e.value - 2.0).abs() < 1e-12 && (e.value - 2.0).abs() <= e.error.max(1e-15)
    );
    // a sharp peak: ∫ ε/(π(x² + ε²)) over [-1, 1] = (2/π) atan(1/ε)
    let eps = 1e-6;
    let e = gk15(&|x: f64| eps / (PI * (x * x + eps * eps)), -1.0, 0.7, tol);
    let exact = ((0.7 / eps).atan() + (1.0 / eps).atan()) / PI;
    assert!(e.converged, "{e}");
    assert!((e.value - exact).abs() < 1e-10, "{e} vs {exact}");
}

#[test]
fn substitutions_handle_endpoint_singularities_and_infinite_ranges() {
    let tol = Tol::new(1e-12, 1e-12, 1_000_000);
    let e = integrate_1d(&|x: f64| 1.0 / x.sqrt(), 0.0, 1.0, Subst::Smoothstep, tol);
    assert!((e.value - 2.0).abs() < 1e-10, "{e}");
    let e = integrate_1d(&|x: f64| x.ln(), 0.0, 1.0, Subst::Smoothstep, tol);
    assert!((e.value + 1.0).abs() < 1e-10, "{e}");
    let e = integrate_1d(
        &|x: f64| (-x).exp(),
        0.0,
        0.0,
        Subst::SemiInfinite { scale: 1.0 },
        tol,
    );
    assert!((e.value - 1.0).abs() < 1e-12, "{e}");
    // Cauchy tail with tiny scale
    let a = 1e-4;
    let e = integrate_1d(
        &|x: f64| 2.0 * a / (PI * (x * x + a * a)),
        0.0,
        0.0,
        Subst::SemiInfinite { scale: a },
        tol,
    );
    assert!((e.value - 1.0).abs() < 1e-10, "{e}");
}

#[test]
fn sphere_quadrature_of_peaked_lobes() {
    // normalised vMF-like lobe κ/(2π(1 − e^{−2κ})) e^{κ(cos θ − 1)} around an off-axis pole
    let kappa: f64 = 1e7; // width ~ 3e-4 rad
    let pole = Vector3::new(0.3, -0.2, 0.9).normalize();
    let f = |w: &Vector3<f64>| {
        // cos θ − 1 = −|w − pole|²/2, without cancellation
        kappa / (2.0 * PI * (1.0 - (-2.0 * kappa).exp()))
            * (-0.5 * kappa * (w - pole).norm_squared()).exp()
    };
    let e = integrate_sphere(
        &f,
        &SphereRule::sphere(pole, kappa.powf(-0.5)),
        Tol::new(1e-11, 1e-11, 50_000_000),
    );
    assert!(e.converged, "{e}");
    assert!((e.value - 1.0).abs() < 1e-10, "{e}");
}

#[test]
fn mc_is_bit_identical_across_thread_counts() {
    let f = |w: &Vector3<f64>| w.z * w.z + w.x;
    let s: [&dyn Strategy<Vector3<f64>>; 2] = [&UniformHemisphere, &CosineHemisphere];
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| mis(&f, &s, 100_003, 42))
    };
    let a = run(1);
    let b = run(2);
    let c = run(7);
    assert_eq!(a.value.to_bits(), b.value.to_bits());
    assert_eq!(a.value.to_bits(), c.value.to_bits());
    assert_eq!(a.error.to_bits(), c.error.to_bits());
    // ∫_{H²} z² dω = 2π/3; ∫ x dω = 0
    let exact = 2.0 * PI / 3.0;
    assert!(a.agrees_with(exact, 4.0, 0.0), "{a} vs {exact}");
    let q = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| qmc_mis(&f, &s, 4096, 8, 7).unwrap())
    };
    assert_eq!(q(1).value.to_bits(), q(3).value.to_bits());
}

#[test]
fn mc_standard_error_is_calibrated() {
    // 40 independent seeds: the fraction within 2 s.e. should be near 95 % (loose bounds).
    let f = |w: &Vector3<f64>| (3.0 * w.z).exp();
    let exact = 2.0 * PI * ((3f64).exp() - (-3f64).exp()) / 3.0; // ∫_{S²} e^{3z} dω
    let s: [&dyn Strategy<Vector3<f64>>; 1] = [&UniformSphere];
    let inside = (0..40)
        .filter(|&seed| mis(&f, &s, 20_000, seed).agrees_with(exact, 2.0, 0.0))
        .count();
    assert!((30..=40).contains(&inside), "{inside}/40 within 2 s.e.");
}

#[test]
fn qmc_beats_mc_and_respects_crate_limit() {
    let f = |w: &Vector3<f64>| w.z.powi(3);
    let exact = PI / 2.0; // ∫_{H²} z³ dω = 2π/4
    let s: [&dyn Strategy<Vector3<f64>>; 1] = [&UniformHemisphere];
    let q = qmc_mis(&f, &s, 1 << 14, 16, 3).unwrap();
    let m = mis(&f, &s, (1 << 14) * 16, 3);
    assert!(q.agrees_with(exact, 4.0, 1e-15), "{q}");
    assert!(q.error < 0.1 * m.error, "QMC {q} vs MC {m}");
    match qmc_mis(&f, &s, MAX_POINTS + 1, 4, 0) {
        Err(Error::QmcTooManyPoints { .. }) => {}
        other => panic!("expected QmcTooManyPoints, got {other:?}"),
    }
}

#[test]
fn tolerance_driven_entry_point_meets_its_target() {
    use ndfbench::integrate::auto::{solve, Method, SphereProblem};
    use ndfbench::microfacet::sampling::NdfSampler;
    use ndfbench::microfacet::{Microsurface, Roughness};
    let s = Microsurface::ggx(Roughness::iso(0.05).unwrap());
    let f = |m: &Vector3<f64>| s.d(m) * m.z.max(0.0);
    let ns = NdfSampler { surface: s };
    let p = SphereProblem {
        f: &f,
        rule: SphereRule::hemisphere(0.05),
        strategies: vec![&ns, &CosineHemisphere],
    };
    for (method, target) in [
        (Method::Quadrature, 1e-10),
        (Method::MonteCarlo, 1e-3),
        (Method::Qmc, 1e-4),
    ] {
        let r = solve(&p, method, target, 50_000_000, 9).unwrap();
        assert!(r.met, "{method:?}: {:?}", r.estimate);
        // the reported error is honest: the true error (exact value 1) is within 4 of them
        assert!(
            r.estimate.agrees_with(1.0, 4.0, 1e-14),
            "{method:?}: {}",
            r.estimate
        );
    }
    assert!(solve(&p, Method::Quadrature, -1.0, 10, 0).is_err());
}

#[test]
fn mc_over_the_plane_with_heavy_and_light_tailed_proposals() {
    use nalgebra::Vector2;
    use ndfbench::integrate::mc::{GaussianPlane, HeavyTailPlane};
    // ∫_ℝ² e^(−|x|²) dx = π, and the unit GGX slope law integrates to 1
    let g = |x: &Vector2<f64>| (-x.norm_squared()).exp();
    let gp = GaussianPlane {
        mean: Vector2::new(0.3, -0.2),
        sigma: 0.8,
    };
    let s: [&dyn Strategy<Vector2<f64>>; 1] = [&gp];
    let e = mis(&g, &s, 200_000, 1);
    assert!(e.agrees_with(PI, 4.0, 0.0), "{e}");
    let a = 0.01;
    let p22 = |x: &Vector2<f64>| 1.0 / (PI * a * a * (1.0 + x.norm_squared() / (a * a)).powi(2));
    let ht = HeavyTailPlane {
        mean: Vector2::zeros(),
        scale: 2.0 * a,
    };
    let both: [&dyn Strategy<Vector2<f64>>; 2] = [&ht, &gp];
    let e = mis(&p22, &both, 200_000, 2);
    assert!(e.agrees_with(1.0, 4.0, 0.0), "{e}");
}

/// The one measured-value type every report prints: mean and standard error by hand for
/// a small sample, NaN for none, one formatter rule (a mean over nothing is "—"), and the
/// kind of error carried by the type (a quadrature bar prints to its own digit, an s.e.
/// at fixed decimals), stored as `{value, error}` either way.
#[test]
fn a_sample_mean_carries_its_standard_error_and_prints_one_way() {
    use ndfbench::integrate::{ErrorKind, Figure, Quad};
    // 1, 2, 3, 4: mean 2.5, sample variance 5/3, s.e. √(5/12)
    let m = Figure::mean_of(&[1.0, 2.0, 3.0, 4.0]);
    assert_eq!(m.value, 2.5);
    assert!((m.error - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
    assert_eq!(m.kind(), ErrorKind::StandardError);
    // one sample: no spread to speak of
    assert_eq!(Figure::mean_of(&[0.25]).pair(), (0.25, 0.0));
    // non-finite samples are left out only where asked
    assert_eq!(
        Figure::mean_of_finite(&[1.0, f64::NAN, 3.0]).pair(),
        (2.0, 1.0)
    );
    assert!(Figure::mean_of(&[1.0, f64::NAN]).value.is_nan());
    let none = Figure::mean_of(&[]);
    assert!(none.value.is_nan() && none.error.is_nan());
    for s in [
        none.pct(1),
        none.pct_signed(2),
        none.sci(3, 1),
        none.fixed(2),
        none.points_signed(1),
    ] {
        assert_eq!(s, "—");
    }
    let e = Figure::with_se(0.0123, 0.00045);
    assert_eq!(e.pct(1), "1.2 % ± 0.0");
    assert_eq!(e.pct(2), "1.23 % ± 0.04");
    assert_eq!(e.pct_signed(1), "+1.2 % ± 0.0");
    assert_eq!(e.sci(3, 1), "1.230e-2 ± 4.5e-4");
    assert_eq!(e.sci_signed(1, 1), "+1.2e-2 ± 4.5e-4");
    assert_eq!(e.fixed(3), "0.012 ± 0.000");
    assert_eq!(e.points_signed(2), "+1.23 ± 0.04 points");
    // an estimate against an MC truth: relative error ± the truth's relative s.e.
    assert_eq!(Figure::with_se(2.0, 0.1).rel_error_of(2.2), "+10.0 % ± 5.0");
    assert_eq!(Figure::with_se(0.0, 0.1).rel_error_of(2.2), "—");
    // the same numbers as a quadrature bar print to the bar's first digit
    let q = Figure::<Quad>::new(0.0123, 0.0004);
    assert_eq!(q.kind(), ErrorKind::Quadrature);
    assert_eq!(q.pct(1), "1.23 ± 0.04 %");
    // a mean of bounded figures is bounded by the mean of the bars: true values anywhere
    // in [1 ± 0.1] and [3 ± 0.3] average within [2 ± 0.2]
    let m = Figure::<Quad>::mean_bounded(&[Figure::new(1.0, 0.1), Figure::new(3.0, 0.3)]);
    assert_eq!(m.pair(), (2.0, 0.2));
    assert!(Figure::<Quad>::mean_bounded(&[]).value.is_nan());
    // stored as {value, error}; a null (serde_json's NaN) reads back as NaN
    assert_eq!(
        serde_json::to_string(&e).unwrap(),
        r#"{"value":0.0123,"error":0.00045}"#
    );
    let back: Figure = serde_json::from_str(r#"{"value":null,"error":0.5}"#).unwrap();
    assert!(back.value.is_nan() && back.error == 0.5);
    assert!(serde_json::from_str::<Figure>(r#"{"value":1.0}"#).is_err());
}

/// The difference estimator of a population mean from a random sample without
/// replacement: by hand for a population of 4, exact (± 0) for the whole population, NaN
/// for no sample or more than the population; over 4000 samples of 60 from a population
/// of 500 the estimates average to the population's own mean (summed directly) within 4
/// standard errors of that average, and their spread matches the s.e. they report, both
/// with a control that follows y closely and with one that does not (a constant).
#[test]
fn the_difference_estimator_is_unbiased_and_its_standard_error_is_calibrated() {
    use ndfbench::integrate::Figure;
    use rand::{Rng, SeedableRng};
    // y = 1, 2, 3, 4, x = 1 everywhere (x̄ = 1): the sample {2, 4} gives d = 1, 3; mean
    // 1 + 2 = 3, s² = 2, s.e. √((1 − 2/4)·2/2)
    let f = Figure::difference_mean(1.0, &[1.0, 3.0], 4);
    assert_eq!(f.value, 3.0);
    assert!((f.error - 0.5f64.sqrt()).abs() < 1e-15);
    assert_eq!(
        Figure::difference_mean(1.0, &[0.0, 1.0, 2.0, 3.0], 4).pair(),
        (2.5, 0.0)
    );
    assert!(Figure::difference_mean(1.0, &[], 4).value.is_nan());
    assert!(Figure::difference_mean(1.0, &[1.0; 5], 4).value.is_nan());
    let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let (n, m, draws) = (500usize, 60usize, 4000usize);
    let x: Vec<f64> = (0..n).map(|_| r.random_range(0.0..10.0)).collect();
    let y: Vec<f64> = x
        .iter()
        .map(|v| v * v / 10.0 + r.random_range(-0.5..0.5))
        .collect();
    let truth = y.iter().sum::<f64>() / n as f64;
    for close in [true, false] {
        let c: Vec<f64> = if close {
            x.iter().map(|v| v * v / 10.0).collect()
        } else {
            vec![3.0; n]
        };
        let c_mean = c.iter().sum::<f64>() / n as f64;
        let (mut est, mut var) = (Vec::new(), 0.0);
        for _ in 0..draws {
            let ks = rand::seq::index::sample(&mut r, n, m);
            let d: Vec<f64> = ks.iter().map(|k| y[k] - c[k]).collect();
            let f = Figure::difference_mean(c_mean, &d, n);
            est.push(f.value);
            var += f.error * f.error / draws as f64;
        }
        let avg = Figure::mean_of(&est);
        assert!(
            (avg.value - truth).abs() < 4.0 * avg.error,
            "control follows y: {close}; {} vs {truth}",
            avg.value
        );
        let spread = avg.error * avg.error * draws as f64;
        assert!(
            (spread / var - 1.0).abs() < 0.1,
            "control follows y: {close}; spread {spread} vs reported {var}"
        );
    }
}

proptest::proptest! {
    #![proptest_config(common::config(10_000))]

    /// The cubature's sin/cos memo returns f64::sin_cos's bits for every argument, whether
    /// it was asked for before, evicted (more than 16 distinct since), or new: sequences
    /// drawn from pools of 1 to 40 values, extremes (±0, subnormals, 1e300, NaN) included,
    /// in random order, cycling through the pool (a panel's y nodes along a row: the
    /// memo's next-entry guess) or each value asked for several times in a row (a row's x).
    #[test]
    fn sin_cos_memo_returns_sin_cos_bit_for_bit(
        pool_size in 1usize..40,
        picks in proptest::collection::vec(0usize..1000, 1..300),
        seed in proptest::prelude::any::<u64>(),
        order in 0usize..3,
    ) {
        use ndfbench::integrate::cubature::SinCosMemo;
        let special = [0.0, -0.0, 5e-324, -1e300, 1e300, f64::NAN, std::f64::consts::FRAC_PI_2];
        let pool: Vec<f64> = (0..pool_size)
            .map(|k| {
                if k < special.len() {
                    special[k]
                } else {
                    let x = seed.wrapping_mul(6364136223846793005).wrapping_add(k as u64 * 1442695040888963407);
                    (x >> 11) as f64 / (1u64 << 53) as f64 * 20.0 - 10.0
                }
            })
            .collect();
        let mut memo = SinCosMemo::default();
        let first = picks[0];
        for (k, p) in picks.iter().enumerate() {
            let p = match order {
                0 => *p,
                1 => first + k,
                _ => first + k / (1 + first % 15),
            };
            let a = pool[p % pool.len()];
            let (s, c) = memo.get(a);
            let (s0, c0) = a.sin_cos();
            proptest::prop_assert_eq!((s.to_bits(), c.to_bits()), (s0.to_bits(), c0.to_bits()));
        }
    }
}

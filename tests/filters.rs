//! Footprint filters: statistics, filter forms (f32 vs f64), the truth
//! and its estimators, and the Listing 3 observation.

mod common;

use nalgebra::Vector3;
use ndfbench::filters::footprint::{MipChain, NormalMap, Procedural, Stats};
use ndfbench::filters::registry::screen_index;
use ndfbench::filters::rules as r;
use ndfbench::filters::study::{pixel_footprint, screen_alphas, Field, PixelFilter};
use ndfbench::filters::truth::{draw, Candidate, Footprint, Frame, Truth};
use ndfbench::integrate::quad::Tol;
use ndfbench::integrate::sphere::{integrate_sphere, SphereRule};
use ndfbench::microfacet::NdfKind;
use proptest::prelude::*;

type V3 = Vector3<f64>;

#[test]
fn mip_chain_equals_direct_block_average() {
    // repeated 2×2 averaging must equal the direct average of the 2^L × 2^L block
    for kind in Procedural::ALL {
        let map = NormalMap::procedural(kind, 32, 3).unwrap();
        let chain = MipChain::build(&map);
        assert_eq!(chain.levels.len(), 6);
        for level in [1usize, 3, 5] {
            let lv = &chain.levels[level];
            for idx in [0usize, lv.width * lv.height - 1] {
                let (i, j) = (idx % lv.width, idx / lv.width);
                let block = map.block(level, i, j);
                let n = block.len() as f64;
                let mean = block.iter().fold(V3::zeros(), |a, b| a + b) / n;
                let sxx = block.iter().map(|b| (b.x / b.z).powi(2)).sum::<f64>() / n;
                let sxy = block.iter().map(|b| (b.x / b.z) * (b.y / b.z)).sum::<f64>() / n;
                let s = &lv.stats[idx];
                assert!(
                    (V3::from(s.mean_normal) - mean).norm() < 1e-13,
                    "{kind:?} L{level}"
                );
                assert!((s.m2[0] - sxx).abs() < 1e-12 * (1.0 + sxx));
                assert!((s.m2[2] - sxy).abs() < 1e-12 * (1.0 + sxx));
            }
        }
    }
}

#[test]
fn two_normal_footprint_has_the_expected_statistics() {
    // ±θ about x: |μ| = cos θ, slopes ±tan θ ⇒ Var x̃ = tan² θ, mean slope 0
    let th: f64 = 0.3;
    let a = Stats::of_normal(&V3::new(th.sin(), 0.0, th.cos()));
    let b = Stats::of_normal(&V3::new(-th.sin(), 0.0, th.cos()));
    let map = NormalMap {
        name: "t".into(),
        width: 2,
        height: 2,
        normals: vec![
            V3::new(th.sin(), 0.0, th.cos()),
            V3::new(-th.sin(), 0.0, th.cos()),
            V3::new(-th.sin(), 0.0, th.cos()),
            V3::new(th.sin(), 0.0, th.cos()),
        ],
    };
    let s = MipChain::build(&map).levels[1].stats[0];
    assert!((s.mrl() - th.cos()).abs() < 1e-15);
    let c = s.covariance();
    assert!((c[0] - th.tan().powi(2)).abs() < 1e-15 && c[1].abs() < 1e-15);
    assert!(s.mean_slope().norm() < 1e-15);
    assert!(a.m1[0] == -b.m1[0]);
}

#[test]
fn toksvig_forms_agree_in_the_small_alpha_limit() {
    // with s = 2/α² − 2 the Blinn–Phong form gives α′² = 2σ²(1 + …)/(1 + 2σ² + …): it
    // agrees with α² + 2σ² to first order in (α², σ²), and differs at second order
    for &r0 in &[0.9999f64, 0.999, 0.99, 0.9] {
        let s2 = r::toksvig_sigma2(r0);
        let bp = r::toksvig_bp(1e-3f64, r0);
        let a2 = r::toksvig_alpha2(1e-3, r0, 2.0);
        let diff = (bp / a2 - 1.0).abs();
        assert!(diff < 2.0 * (1e-6 + 2.0 * s2), "r = {r0}: {bp} vs {a2}");
        assert!(diff > 0.1 * s2, "second-order term present: {diff}");
    }
}

/// The exact mean resultant length of a vMF distribution, coth κ − 1/κ (physics of the
/// distribution, independent of Banerjee's approximation).
fn vmf_r(kappa: f64) -> f64 {
    1.0 / kappa.tanh() - 1.0 / kappa
}

#[test]
fn banerjee_kappa_inverts_the_vmf_mean_length() {
    // κ ≈ (3r − r³)/(1 − r²) over-estimates the exact inverse by at most ≈ 4.9 % (near
    // κ = 5) and by ≈ 0.5/κ for large κ
    for &kappa in &[1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 20.0, 100.0, 1e4] {
        let rr = vmf_r(kappa);
        // α′² − α² = 2/κ_banerjee
        let inv = (r::vmf(0.0, rr, 2.0)).powi(2) / 2.0;
        let kb = 1.0 / inv;
        let e = kb / kappa - 1.0;
        assert!(e > 0.0 && e < 0.05, "κ = {kappa}: Banerjee {kb}");
        if kappa >= 20.0 {
            assert!(e < 0.6 / kappa, "κ = {kappa}: {e}");
        }
    }
}

#[test]
fn lean_adds_twice_the_covariance() {
    let a = r::lean(0.1, [0.01, 0.04, 0.005]);
    for (x, y) in a.iter().zip([0.03f64, 0.09, 0.01]) {
        assert!((x - y).abs() < 1e-15, "{a:?}");
    }
}

#[test]
fn seed000_moment_fit_matches_newton_within_the_fit_error() {
    // held-out max relative error of the α_me fit is 1.6e-4 (results/multiscale-alpha-me.md)
    let c = ndfbench::studies::multiscale_alpha_me::params_in(std::path::Path::new("fits"))
        .unwrap()
        .fit()
        .unwrap();
    for &alpha in &[0.01, 0.1, 0.5] {
        let rho = ndfbench::multiscale::mrl::mrl_pair(alpha).0;
        // down to |μ| = 0.05: rough footprints (α′ up to ≈ 30) use the α > 1 branch
        for &m in &[0.999, 0.95, 0.8, 0.5, 0.3, 0.05] {
            let exact = ndfbench::multiscale::mrl::alpha_from_one_minus(1.0 - m * rho).unwrap();
            let fit = r::seed000_moment_fit(m, rho, &c.small, &c.large);
            {
                assert!(
                    (fit / exact - 1.0).abs() < 2e-4,
                    "α {alpha}, |μ| {m}: {fit} vs {exact}"
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(common::config(10_000))] // was 400

    /// f32 shading forms against the f64 reference, inputs exactly representable in
    /// f32. Bounds: 4e-7 relative (≈ 7 ulp) for every mean-normal and kernel filter;
    /// the inputs' own rounding is excluded because the reference gets the same f32
    /// inputs (the conditioning of |μ| near 1 is a property of the input, not the form).
    #[test]
    fn f32_filters_match_f64(
        alpha in prop_oneof![1e-4f32..1e-2, 1e-2f32..1.0],
        m in prop_oneof![0.5f32..0.99, 0.99f32..1.0],
        d in prop::array::uniform3(-0.5f32..0.5),
        e in prop::array::uniform3(-0.5f32..0.5),
    ) {
        let (a64, m64) = (alpha as f64, m as f64);
        let d64 = d.map(|x| x as f64);
        let e64 = e.map(|x| x as f64);
        let rel = |x: f32, y: f64| ((x as f64) - y).abs() / y.abs().max(1e-30);
        let checks: Vec<(&str, f32, f64)> = vec![
            ("toksvig_bp", r::toksvig_bp(alpha, m), r::toksvig_bp(a64, m64)),
            ("toksvig2", r::toksvig_alpha2(alpha, m, 2.0), r::toksvig_alpha2(a64, m64, 2.0)),
            ("vmf2", r::vmf(alpha, m, 2.0), r::vmf(a64, m64, 2.0)),
            ("vmf05", r::vmf(alpha, m, 0.5), r::vmf(a64, m64, 0.5)),
            ("deferred", r::deferred(alpha, d, e, 0.25, 0.18), r::deferred(a64, d64, e64, 0.25, 0.18)),
            ("on_alpha", r::deferred_on_alpha(alpha, d, e, 0.25, 0.18), r::deferred_on_alpha(a64, d64, e64, 0.25, 0.18)),
            ("eigen", r::eigen_eq10(alpha, [d[0], d[1]], [e[0], e[1]], 0.25, 0.18), r::eigen_eq10(a64, [d64[0], d64[1]], [e64[0], e64[1]], 0.25, 0.18)),
            ("rect", r::kaplanyan_rect(alpha, [d[0], d[1]], [e[0], e[1]], 0.25, 0.18), r::kaplanyan_rect(a64, [d64[0], d64[1]], [e64[0], e64[1]], 0.25, 0.18)),
        ];
        for (name, x, y) in checks {
            prop_assert!(rel(x, y) < 4e-7, "{name}: f32 {x} vs f64 {y} (α {alpha}, |μ| {m})");
        }
        // projected space: p = α²/(1 − α²) amplifies the rounding of α² by 1/(1 − α²)
        let x = r::projected_space(alpha, d, e, 0.1, 0.04);
        let y = r::projected_space(a64, d64, e64, 0.1, 0.04);
        let bound = 4e-7 * (1.0 + 1.0 / (1.0 - a64 * a64));
        prop_assert!(rel(x, y) < bound, "projected: {x} vs {y}");
        // Eq 5 + Eq 7: the cancelling numerator of Eq 5 (≈ 23.6 · ε absolute)
        let x = r::seed000_paper(alpha, m);
        let y = r::seed000_paper(a64, m64);
        prop_assert!(((x as f64) - y).abs() < 4e-7 * y.abs() + 1e-5, "eq5+7: {x} vs {y}");
    }

    /// Every filter's α′ is finite and ≥ α for |μ| ∈ (0, 1] and any derivatives (extremes
    /// included), and no α′ exceeds 1 for the saturating kernels.
    #[test]
    fn filters_widen_and_stay_finite(
        alpha in prop_oneof![Just(1e-4f64), 1e-4f64..1.0],
        m in prop_oneof![Just(1.0f64), Just(1e-3), 1e-3f64..1.0],
        d in prop::array::uniform3(-10f64..10.0),
    ) {
        let z = [0.0; 3];
        for (name, a) in [
            ("toksvig_bp", r::toksvig_bp(alpha, m)),
            ("toksvig2", r::toksvig_alpha2(alpha, m, 2.0)),
            ("vmf1", r::vmf(alpha, m, 1.0)),
            ("deferred", r::deferred(alpha, d, z, 0.25, 0.18)),
            ("projected", r::projected_space(alpha, d, z, 0.1, 0.04)),
            ("on_alpha", r::deferred_on_alpha(alpha, d, z, 0.25, 0.18)),
            ("eigen", r::eigen_eq10(alpha, [d[0], d[1]], [d[2], 0.0], 0.25, 0.18)),
            ("rect", r::kaplanyan_rect(alpha, [d[0], d[1]], [d[2], 0.0], 0.25, 0.18)),
        ] {
            prop_assert!(a.is_finite() && a >= alpha * (1.0 - 1e-12), "{name}: {a} < α {alpha}");
            if !name.starts_with("toksvig") && !name.starts_with("vmf") {
                prop_assert!(a <= 1.0 + 1e-12, "{name}: {a} > 1");
            }
        }
    }
}

/// Listing 3 (seed 003) as printed: simulate a 2×2 quad with ddx_fine/ddy_fine as pairwise
/// differences. avgNormal then differs across the quad only by (a multiple of) the mixed
/// second difference n11 − n10 − n01 + n00, so ddx/ddy of its projection are second-order
/// quantities (exactly 0 along the top row and left column with pixel centres at .5,
/// i.e. for coarse derivatives), not the first differences the kernel needs.
#[test]
fn listing3_as_printed_is_quad_constant() {
    let f = Field {
        kappa_u: 0.2,
        kappa_v: 0.1,
        psi: 0.4,
    };
    let n = |i: usize, j: usize| f.normal(i as f64, j as f64);
    let mixed = (n(1, 1) - n(1, 0) - n(0, 1) + n(0, 0)).norm();
    let first = (n(1, 0) - n(0, 0)).norm().min((n(0, 1) - n(0, 0)).norm());
    assert!(
        mixed < 0.2 * first,
        "the field is smooth: mixed {mixed} vs first {first}"
    );
    for centre_offset in [0.5f64, 0.0] {
        let pos = |i: usize| 10.0 + i as f64 + centre_offset;
        let mut avg = [[V3::zeros(); 2]; 2];
        for j in 0..2 {
            for i in 0..2 {
                let dirx = 0.5 - 2.0 * (pos(i) * 0.5).fract();
                let diry = 0.5 - 2.0 * (pos(j) * 0.5).fract();
                let ddx = n(1, j) - n(0, j);
                let ddy = n(i, 1) - n(i, 0);
                avg[j][i] = n(i, j) + ddx * dirx + ddy * diry;
            }
        }
        for j in 0..2 {
            for i in 0..2 {
                let d = (avg[j][i] - avg[0][0]).norm();
                assert!(
                    d <= mixed * (1.0 + 1e-9) + 1e-15,
                    "offset {centre_offset}: {d} > {mixed}"
                );
            }
        }
        if centre_offset == 0.5 {
            assert!((avg[0][1] - avg[0][0]).norm() < 1e-15, "coarse ddx");
            assert!((avg[1][0] - avg[0][0]).norm() < 1e-15, "coarse ddy");
        }
    }
}

#[test]
fn estimator_algebra_is_exact_for_a_scaled_truth() {
    // a candidate equal to 1.1 × truth has energy error +10 % and L2 error 10 % in every
    // sample, whatever the sampling noise
    let fp = Footprint::uniform(vec![V3::z(), V3::new(0.2, 0.1, 1.0).normalize()]);
    let t = Truth::new(NdfKind::Ggx, 0.1, &fp).unwrap();
    let v = V3::new(0.3, 0.1, 0.9).normalize();
    let s = draw(&t, &v, &[(V3::z(), 0.2)], 512, 9).unwrap();
    let res = s.measure(&|v, l| 1.1 * t.value(v, l), &V3::z());
    assert!((res.energy.value - 0.1).abs() < 1e-12 && res.energy.error < 1e-12);
    assert!((res.l2.value - 0.1).abs() < 1e-12);
    assert!(res.peak.abs() < 0.1 + 1e-12 && res.peak > 0.1 - 1e-12);
}

#[test]
fn mc_energy_matches_quadrature() {
    // ∫ f_truth dl of a single-normal footprint = the directional albedo of that lobe,
    // by nested adaptive quadrature (independent of the sampler)
    for (alpha, tilt) in [(0.05f64, 0.0f64), (0.3, 0.4)] {
        let n = V3::new(tilt, 0.0, 1.0).normalize();
        let fp = Footprint::uniform(vec![n]);
        let t = Truth::new(NdfKind::Ggx, alpha, &fp).unwrap();
        let v = V3::new(0.5, 0.2, 0.8).normalize();
        let q = integrate_sphere(
            &|l: &V3| t.value(&v, l),
            &SphereRule::hemisphere(alpha),
            Tol::new(1e-9, 1e-9, 20_000_000),
        );
        let s = draw(&t, &v, &[(n, alpha)], 4096, 3).unwrap();
        let e = s.truth_energy();
        let z = (e.value - q.value) / e.error;
        assert!(
            z.abs() < 4.0,
            "α {alpha}: MC {} ± {} vs quad {} (z {z})",
            e.value,
            e.error,
            q.value
        );
    }
}

#[test]
fn draws_are_deterministic() {
    let fp = Footprint::uniform(vec![V3::z(), V3::new(0.1, 0.3, 1.0).normalize()]);
    let t = Truth::new(NdfKind::Beckmann, 0.2, &fp).unwrap();
    let v = V3::new(0.1, 0.0, 1.0).normalize();
    let c = Candidate::iso("x", NdfKind::Beckmann, V3::z(), 0.3).unwrap();
    let a = draw(&t, &v, &[c.proposal], 300, 5)
        .unwrap()
        .measure(&*c.value, &V3::z());
    let b = draw(&t, &v, &[c.proposal], 300, 5)
        .unwrap()
        .measure(&*c.value, &V3::z());
    assert_eq!(a.l2.value.to_bits(), b.l2.value.to_bits());
    assert_eq!(a.energy.value.to_bits(), b.energy.value.to_bits());
}

#[test]
fn pixel_truth_is_resolved_by_its_node_count() {
    // the automatic midpoint rule against one with twice the nodes per axis
    let f = Field {
        kappa_u: 0.3,
        kappa_v: 0.15,
        psi: 0.5,
    };
    let alpha = 0.1;
    let fp = pixel_footprint(&f, PixelFilter::Gaussian, alpha);
    let n = (fp.normals.len() as f64).sqrt() as usize;
    let m = 2 * n;
    let h = 4.0 / m as f64;
    let nodes: Vec<f64> = (0..m).map(|i| -2.0 + (i as f64 + 0.5) * h).collect();
    let w: Vec<f64> = nodes.iter().map(|x| (-2.0 * x * x).exp()).collect();
    let sw: f64 = w.iter().sum();
    let mut ns = Vec::new();
    let mut ws = Vec::new();
    for (i, x) in nodes.iter().enumerate() {
        for (j, y) in nodes.iter().enumerate() {
            ns.push(f.normal(*x, *y));
            ws.push(w[i] * w[j] / (sw * sw));
        }
    }
    let fine = Footprint {
        normals: ns,
        weights: ws,
    };
    let (ta, tb) = (
        Truth::new(NdfKind::Ggx, alpha, &fp).unwrap(),
        Truth::new(NdfKind::Ggx, alpha, &fine).unwrap(),
    );
    let v = V3::new(0.2, 0.1, 1.0).normalize();
    let peak = (0..40)
        .map(|k| {
            let th = -0.8 + 0.04 * k as f64;
            tb.value(&v, &V3::new(th.sin(), 0.0, th.cos()))
        })
        .fold(0.0, f64::max);
    for k in 0..40 {
        let th = -0.8 + 0.04 * k as f64;
        let l = V3::new(th.sin(), 0.0, th.cos());
        let (a, b) = (ta.value(&v, &l), tb.value(&v, &l));
        assert!((a - b).abs() < 2e-3 * peak, "θ {th}: {a} vs {b}");
    }
}

#[test]
fn small_curvature_beckmann_is_the_gaussian_convolution() {
    // Beckmann slopes convolved with a Gaussian slope spread σ²κ² (per axis) are Beckmann
    // with α′² = α² + 2σ²κ² (Gaussians convolve exactly); for κ ≪ α the footprint of the
    // synthetic field is such a spread, so Eq 10's lobe must match the truth closely.
    let f = Field {
        kappa_u: 0.02,
        kappa_v: 0.02,
        psi: 0.0,
    };
    let alpha = 0.1;
    let fp = pixel_footprint(&f, PixelFilter::Gaussian, alpha);
    let t = Truth::new(NdfKind::Beckmann, alpha, &fp).unwrap();
    let exact = (alpha * alpha + 2.0 * 0.25 * 0.02f64.powi(2)).sqrt();
    let a10 = screen_alphas(alpha, &f)[screen_index("eigen-eq10")];
    assert!(
        (a10 / exact - 1.0).abs() < 1e-3,
        "Eq 10 α′ {a10} vs {exact}"
    );
    let c = Candidate::iso("eq10", NdfKind::Beckmann, V3::z(), a10).unwrap();
    let v = V3::new(0.3, 0.0, 1.0).normalize();
    let s = draw(&t, &v, &[c.proposal], 2048, 4).unwrap();
    let res = s.measure(&*c.value, &V3::z());
    assert!(
        res.l2.value < 5e-3,
        "L2 {} ± {}",
        res.l2.value,
        res.l2.error
    );
    assert!(res.energy.value.abs() < 3.0 * res.energy.error + 1e-3);
    let _ = Frame::around(V3::z());
}

#[test]
fn png_round_trip_and_bad_input() {
    let dir = common::scratch("filters", "png");
    std::fs::create_dir_all(&dir).unwrap();
    let map = NormalMap::procedural(Procedural::IsotropicNoise, 16, 1).unwrap();
    let p = dir.join("n.png");
    std::fs::write(&p, map.png().unwrap()).unwrap();
    let back = NormalMap::from_png(&p).unwrap();
    assert_eq!((back.width, back.height), (16, 16));
    for (a, b) in map.normals.iter().zip(&back.normals) {
        // 8-bit quantisation: ≤ 1/255 per component before renormalisation
        assert!((a - b).norm() < 0.012, "{a:?} vs {b:?}");
    }
    let broken = dir.join("broken.png");
    std::fs::write(&broken, b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let e = NormalMap::from_png(&broken).unwrap_err().to_string();
    assert!(e.contains("cannot read"), "{e}");
    // 3×2 is not a power of two
    let img = image::RgbImage::from_pixel(3, 2, image::Rgb([128, 128, 255]));
    let odd = dir.join("odd.png");
    img.save(&odd).unwrap();
    let e = NormalMap::from_png(&odd).unwrap_err().to_string();
    assert!(e.contains("powers of two"), "{e}");
    // a texel pointing below the surface
    let img = image::RgbImage::from_pixel(2, 2, image::Rgb([128, 128, 0]));
    let below = dir.join("below.png");
    img.save(&below).unwrap();
    assert!(NormalMap::from_png(&below).is_err());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn regen_filters_quick_writes_the_report() {
    let dir = common::scratch("filters", "filters");
    std::fs::create_dir_all(&dir).unwrap();
    let out = ndfbench::studies::regen(
        std::path::Path::new("fits"),
        &dir,
        Some("filters"),
        ndfbench::integrate::Preset::Quick,
    )
    .unwrap();
    let names: Vec<&str> = out.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["leadr-grids", "smith-lambda", "filters"]);
    let md = std::fs::read_to_string(dir.join("filters.md")).unwrap();
    for key in [
        "## Map: flakes",
        "## Verdicts",
        "## LEADR numerical integration",
        "## Smith Λ approximations",
        "±",
    ] {
        assert!(md.contains(key), "missing {key}");
    }
    let json: ndfbench::results::filters::Filters = ndfbench::results::require(&dir).unwrap();
    assert!(json.fitted.len() >= 4);
    // the survey on the same cases: every row, the five maps, the verdicts, no NaN
    let sv = std::fs::read_to_string(dir.join("filters-survey.md")).unwrap();
    for key in [
        "## Verdicts: the best representation",
        "| scratches |",
        "Fournier, 7 lobes",
        "Han et al. SH, degree 15",
        "Tan et al., 4 lobes, MIP-mapped (aligned)",
        "SGGX / Neyret ellipsoid (Eq 18)",
        "## Han et al.'s rule of thumb",
    ] {
        assert!(sv.contains(key), "filters-survey.md misses {key}");
    }
    assert!(!sv.contains("NaN"), "filters-survey.md holds a NaN");
    assert!(std::fs::read_to_string(dir.join("filters-survey.svg"))
        .unwrap()
        .contains("parameters per texel"));
    let rows = &json.survey.rows;
    assert_eq!(
        rows.len(),
        12 + ndfbench::studies::filters::survey::ROWS.len()
    );
    // the exact distribution is the floor: no stored representation beats it on average
    let floor = rows[12].all.l2.value;
    assert!(floor.is_finite());
    assert!(
        rows.iter().all(|r| r.all.l2.value >= floor - 0.02),
        "a representation beats the exact q_A"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn each_footprint_filter_is_listed_once_by_a_unique_key() {
    use ndfbench::filters::registry::{map_index, MAP, SCREEN};
    for list in [
        MAP.iter().map(|f| (f.key, f.label)).collect::<Vec<_>>(),
        SCREEN.iter().map(|f| (f.key, f.label)).collect(),
    ] {
        let mut keys: Vec<&str> = list.iter().map(|x| x.0).collect();
        let mut labels: Vec<&str> = list.iter().map(|x| x.1).collect();
        keys.sort();
        keys.dedup();
        labels.sort();
        labels.dedup();
        assert_eq!((keys.len(), labels.len()), (list.len(), list.len()));
    }
    // the lobes that propose samples come first: the engines' rules after them were added
    // later and measured on the same samples
    let first_quiet = MAP.iter().position(|f| !f.proposes).unwrap();
    assert!(MAP[first_quiet..].iter().all(|f| !f.proposes));
    assert_eq!(first_quiet, map_index("filament-prefilter"));
}

/// The registry of footprint filters: unique keys; each refit replaces a constant of a
/// map filter or kernel; every generated function, bench, summary entry and fitted family
/// it names exists.
mod registry {
    use ndfbench::filters::registry::{Filter, REFIT};

    #[test]
    fn keys_are_unique_and_refits_name_a_base_with_a_constant() {
        let keys: Vec<&str> = Filter::all().map(|f| f.key()).collect();
        let mut sorted = keys.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), keys.len(), "{keys:?}");
        for r in REFIT.iter() {
            let base = Filter::find(r.base).expect(r.base);
            assert!(!matches!(base, Filter::Refit(_)), "{}", r.key);
            // the refit changes the rule: its base has a constant to replace
            let refitted = Filter::Refit(r).rule_with(|_| Some(0.123)).unwrap();
            assert_ne!(refitted, base.rule(), "{}", r.key);
        }
    }

    #[test]
    fn every_shader_bench_and_summary_the_registry_names_exists() {
        // bench ids as criterion names them: the first string of each bench!( call
        let benches: String = include_str!("../benches/engines.rs")
            .split_whitespace()
            .collect();
        let summary: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string("results/fits/filters.json")
                .expect("results/fits/filters.json"),
        )
        .expect("json");
        let families: Vec<&str> = summary["fitted"]
            .as_array()
            .expect("fitted")
            .iter()
            .filter_map(|f| f["family"].as_str())
            .collect();
        for f in Filter::all() {
            let u = f.uses();
            if let Some(name) = u.shader {
                assert!(
                    ndfbench::codegen::desc::FUNCTIONS
                        .iter()
                        .any(|d| d.name == name),
                    "{}: no generated function {name}",
                    f.key()
                );
            }
            if let Some(b) = u.bench {
                assert!(
                    benches.contains(&format!("bench!(\"{b}\"")),
                    "{}: no bench {b}",
                    f.key()
                );
            }
            if let Some(k) = u.summary {
                assert!(
                    summary["summary"][k].is_object(),
                    "{}: no summary {k}",
                    f.key()
                );
            }
            if let Some(fam) = f.family() {
                assert!(
                    families.contains(&fam),
                    "{}: no fitted family {fam}",
                    f.key()
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// The truth seen from one view (`Truth::viewed`: each texel's lobe with Λ(v) prepared
    /// once, what the samplers evaluate) is `Truth::value` bit for bit, GGX and Beckmann,
    /// roughness down to 1e-4 and directions to the horizon.
    #[test]
    fn the_viewed_truth_is_the_truth_bit_for_bit(
        beck in any::<bool>(),
        la in -4.0f64..0.0,
        n1 in (-0.9f64..0.9, -0.9f64..0.9),
        n2 in (-0.9f64..0.9, -0.9f64..0.9),
        n3 in (-0.9f64..0.9, -0.9f64..0.9),
        n4 in (-0.9f64..0.9, -0.9f64..0.9),
        tv in 0.0f64..1.5706,
        pv in 0.0f64..6.2832,
        tl in 0.0f64..1.5707,
        pl in 0.0f64..6.2832,
    ) {
        let kind = if beck { NdfKind::Beckmann } else { NdfKind::Ggx };
        let fp = Footprint::uniform(vec![
            V3::new(n1.0, n1.1, 1.0).normalize(),
            V3::new(n2.0, n2.1, 1.0).normalize(),
            V3::z(),
            V3::new(n3.0, n3.1, 1.0).normalize(),
            V3::new(n4.0, n4.1, 1.0).normalize(),
        ]);
        let t = Truth::new(kind, 10f64.powf(la), &fp).unwrap();
        let dir = |th: f64, ph: f64| V3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
        let (v, l) = (dir(tv, pv), dir(tl, pl));
        let a = t.value(&v, &l);
        let seen = t.viewed(&v);
        let (b, c) = (seen.value(&l), seen.value_reference(&l));
        prop_assert_eq!(a.to_bits(), b.to_bits(), "{} against {}", a, b);
        prop_assert_eq!(c.to_bits(), b.to_bits(), "{} against {}", c, b);
    }
}

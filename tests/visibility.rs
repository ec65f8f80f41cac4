//! Visibility and procedural maps (seed 004 §4–6, §8.1): closed forms on simple height
//! fields and scenes, independent references for the procedural averages, bad input, and
//! the extremes.

mod common;

use nalgebra::Vector2;
use ndfbench::microfacet::NdfKind;
use ndfbench::visibility::correlation::separation_cost;
use ndfbench::visibility::horizon::{self, Dir, HdfMoments, LegendreHorizon};
use ndfbench::visibility::procedural::{self, Spectral, Waves};
use ndfbench::visibility::shadow::{Method, Occluders, Precision, Receiver, Scene};
use ndfbench::visibility::{HeightField, Relief};
use proptest::prelude::*;
use std::f64::consts::PI;

fn field(size: usize, f: &dyn Fn(usize, usize) -> f64) -> HeightField {
    HeightField {
        name: "test".into(),
        size,
        h: (0..size * size).map(|k| f(k % size, k / size)).collect(),
    }
}

#[test]
fn horizon_of_a_flat_field_is_zero_and_of_a_wall_is_its_angle() {
    let flat = field(64, &|_, _| 0.0);
    assert_eq!(horizon::horizon(&flat, 10, 10, 0.7), 0.0);
    // a wall of height 4 from x = 40 on: seen from x = 32 toward +x at distance 8 − ½ of
    // the bilinear ramp, the steepest rise is 4/8 where the wall reaches full height
    let wall = field(64, &|i, _| if (40..56).contains(&i) { 4.0 } else { 0.0 });
    let t = horizon::horizon(&wall, 32, 5, 0.0);
    assert!((t - (4.0f64 / 8.0).atan()).abs() < 1e-12, "{t}");
    // toward −x the wall is 40 texels away (periodic: 8 + 16 = beyond the 32-texel reach)
    assert_eq!(horizon::horizon(&wall, 32, 5, PI), 0.0);
    // the exact fractions: a view above the wall sees every texel; the joint form is 1 at l = v
    let texels = wall.block(3, 4, 0);
    let v = Dir {
        elev: 0.6,
        azim: 0.0,
    };
    let (vv, lv) = horizon::exact(&wall, &texels, &v, &v);
    assert!(vv > 0.0 && (lv.unwrap() - 1.0).abs() < 1e-15);
}

#[test]
fn hdf_methods_match_a_single_horizon_exactly() {
    // every texel of a footprint on a uniform slope shares one horizon: σ = 0, the ramp and
    // the erf form are the step, and Legendre converges to it away from the step
    let wall = field(64, &|i, _| if (40..56).contains(&i) { 4.0 } else { 0.0 });
    let texels = vec![(32usize, 5usize); 4];
    let th = horizon::stored_horizons(&wall, &texels);
    let m = HdfMoments::new(&th);
    let theta = (0.5f64).atan();
    for e in [theta - 0.05, theta + 0.05] {
        let d = Dir { elev: e, azim: 0.0 };
        let want = (e > theta) as u8 as f64;
        assert_eq!(horizon::fournier(&m, &d), want);
        assert_eq!(horizon::tan_erf(&m, &d), want);
        let lg = LegendreHorizon::new(&th, 64);
        assert!((lg.eval(&d) - want).abs() < 0.1, "{}", lg.eval(&d));
    }
}

#[test]
fn height_fields_reject_bad_input() {
    assert!(HeightField::procedural(Relief::Noise, 48, 1).is_err());
    assert!(HeightField::procedural(Relief::Bumps, 8, 1).is_err());
    let dir = common::scratch("visibility", "height");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("h.png");
    image::GrayImage::from_fn(32, 16, |x, _| image::Luma([x as u8]))
        .save(&p)
        .unwrap();
    assert!(HeightField::from_png(&p, 1.0).is_err(), "not square");
    let q = dir.join("ok.png");
    image::GrayImage::from_fn(32, 32, |x, y| image::Luma([(x * y) as u8]))
        .save(&q)
        .unwrap();
    assert!(HeightField::from_png(&q, f64::NAN).is_err());
    assert!(HeightField::from_png(&q, 0.0).is_err());
    let h = HeightField::from_png(&q, 10.0).unwrap();
    assert_eq!(h.size, 32);
    std::fs::write(dir.join("broken.png"), b"\x89PNG not really").unwrap();
    assert!(HeightField::from_png(&dir.join("broken.png"), 1.0).is_err());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn shadow_methods_on_a_fully_lit_and_a_fully_shadowed_footprint() {
    let sc = Scene {
        occluders: Occluders::Plane,
        receiver: Receiver::Parallel,
        size: 64,
    };
    let z = sc.depth_map();
    let lit: Vec<(usize, usize)> = (40..48).map(|i| (i, 3)).collect(); // right half: no occluder
    let dark: Vec<(usize, usize)> = (4..12).map(|i| (i, 3)).collect();
    for m in [
        Method::Vsm,
        Method::Csm {
            terms: 16,
            fixed: true,
        },
        Method::Esm { c: 80.0 },
        Method::Evsm { c: 20.0 },
    ] {
        let u = m.lookup(&m.filter(&z, 64, &lit, Precision::F32), 0.9);
        assert!((u - 1.0).abs() < 1e-3, "{m:?} lit: {u}");
        let u = m.lookup(&m.filter(&z, 64, &dark, Precision::F32), 0.9);
        assert!(u < 0.02, "{m:?} shadowed: {u}");
    }
    // the raw Fourier series passes through ½ at the receiver's own depth
    let m = Method::Csm {
        terms: 16,
        fixed: false,
    };
    assert!((m.lookup(&m.filter(&z, 64, &lit, Precision::F64), 0.9) - 0.5).abs() < 1e-9);
    // binary16 overflows ESM's e^{cz} beyond c = ln 65504 ≈ 11.09
    assert!(Precision::F16.store((12.0f64).exp()).is_infinite());
    assert!(Precision::F16.store((11.0f64).exp()).is_finite());
    assert!(
        (ndfbench::visibility::shadow::max_usable_c(false, Precision::F16) - 65504f64.ln()).abs()
            < 1e-12
    );
}

#[test]
fn procedural_averages_against_independent_quadrature() {
    // the sheared grid's exact average against a 1200² midpoint rule over the parallelogram
    let (c, e1, e2) = (
        Vector2::new(3.3, 7.1),
        Vector2::new(1.3, 0.4),
        Vector2::new(-0.2, 0.7),
    );
    let exact = procedural::grid_average_exact(c, e1, e2);
    let n = 1200;
    let mut s = 0.0;
    for a in 0..n {
        for b in 0..n {
            let (u, v) = (
                (a as f64 + 0.5) / n as f64 - 0.5,
                (b as f64 + 0.5) / n as f64 - 0.5,
            );
            let p = c + e1 * u + e2 * v;
            s += procedural::pulse(p.x) * procedural::pulse(p.y);
        }
    }
    assert!(
        (exact - s / (n * n) as f64).abs() < 2e-3,
        "{exact} vs {}",
        s / (n * n) as f64
    );
    // axis-aligned footprints: the separable product is exact
    let (a1, a2) = (Vector2::new(1.7, 0.0), Vector2::new(0.0, 0.6));
    assert!(
        (procedural::grid_average_exact(c, a1, a2) - procedural::grid_average_separable(c, a1, a2))
            .abs()
            < 1e-12
    );
    // the spectral sum's box average against Gauss–Legendre
    let f = Spectral::octaves(8, 3);
    let (x, w) = (0.37, 0.05);
    let (gx, gw) = ndfbench::integrate::quad::gauss_legendre(200);
    let q: f64 = gx
        .iter()
        .zip(&gw)
        .map(|(t, wt)| 0.5 * wt * f.clamped(x + 0.5 * w * t, 0.0, 1.0))
        .sum();
    assert!((q - f.box_average(x, w)).abs() < 1e-12);
    // the waves' clamped covariance is the sample slope covariance of those waves alone
    let waves = Waves::new(5, 0.3);
    let all = waves.clamped_covariance(-1.0);
    let mut emp = 0.0;
    let m = 20000;
    for k in 0..m {
        let p = Vector2::new(
            1000.0 * ((k * 7919) % m) as f64 / m as f64,
            1000.0 * ((k * 104729) % m) as f64 / m as f64,
        );
        let nn = waves.normal(p, f64::INFINITY);
        emp += (nn.x / nn.z).powi(2) + (nn.y / nn.z).powi(2);
    }
    assert!(
        ((emp / m as f64) - all.trace()).abs() < 0.1 * all.trace(),
        "{} vs {}",
        emp / m as f64,
        all.trace()
    );
}

#[test]
fn separation_costs_nothing_without_correlation() {
    // flat field: every texel has the same colour, normal and visibility
    let view = Dir {
        elev: 0.7,
        azim: 0.2,
    };
    let cost = |hf: &HeightField, texels: &[(usize, usize)]| {
        separation_cost(hf, texels, NdfKind::Ggx, 0.3, &view, 12).unwrap()
    };
    let flat = field(32, &|_, _| 0.0);
    let (c, v) = cost(&flat, &flat.block(2, 1, 1));
    assert!(c < 1e-14 && v < 1e-14, "{c} {v}");
    // the bumps: colour follows slope, so separating them costs
    let b = HeightField::procedural(Relief::Bumps, 64, 2).unwrap();
    let (c, _) = cost(&b, &b.block(3, 1, 1));
    assert!(c > 0.01, "{c}");
}

proptest! {
    #![proptest_config(common::config(10_000))]
    /// Over the f64 range: the pulse train's box average lies in [0, 1]; every joint form
    /// and every shadow lookup from arbitrary (even inconsistent) moments is finite in [0, 1].
    #[test]
    fn visibility_forms_stay_in_range(
        a in -1e12f64..1e12, len in 0.0f64..1e3,
        vl in 0.0f64..=1.0, vv in 0.0f64..=1.0, c in -1.0f64..=1.0,
        z in proptest::collection::vec(0.0f64..=1.0, 1..12), d in 0.0f64..=1.0,
        s in 0.0f64..=1.0,
    ) {
        let b = procedural::box_average(a, a + len);
        prop_assert!(b.is_finite() && (-1e-3..=1.0 + 1e-3).contains(&b), "{b}");
        for j in [horizon::joint_eq28(vl, vv, c), horizon::joint_ashikhmin(vl, vv, c, 0.25), horizon::joint_product(vl, vv)] {
            prop_assert!(j.is_finite() && (0.0..=1.0).contains(&j));
        }
        let texels: Vec<(usize, usize)> = (0..z.len()).map(|i| (i, 0)).collect();
        for m in [Method::Vsm, Method::Csm { terms: 8, fixed: true }, Method::Csm { terms: 8, fixed: false }, Method::Esm { c: 80.0 }, Method::Evsm { c: 40.0 }] {
            for p in [Precision::F64, Precision::F32, Precision::F16] {
                let u = m.lookup(&m.filter(&z, z.len(), &texels, p), d);
                prop_assert!(u.is_finite() && (0.0..=1.0).contains(&u), "{m:?} {p:?}: {u}");
            }
        }
        let k = horizon::legendre_coeffs(s, 64);
        prop_assert!(k.iter().all(|x| x.is_finite()));
    }
}

//! f32 shading forms against the f64 reference, with the bounds stated in
//! src/microfacet/shading.rs. Inputs are generated in f32 and widened exactly, so the
//! comparison measures arithmetic error only.

mod common;

use nalgebra::Vector3;
use ndfbench::microfacet::shading::{self, Rough32};
use ndfbench::microfacet::{Microsurface, NdfKind, Roughness};
use proptest::prelude::*;

/// Roughness with principal values in [1e-4, 1] (condition number of A up to 1e8) and
/// any orientation, plus exact isotropic and axis-aligned cases.
fn rough() -> impl Strategy<Value = Roughness> {
    prop_oneof![
        (-4.0f64..0.0, -4.0f64..0.0, 0.0f64..std::f64::consts::PI).prop_map(|(l1, l2, phi)| {
            Roughness::rotated(10f64.powf(l1), 10f64.powf(l2), phi).unwrap()
        }),
        (-4.0f64..0.0).prop_map(|l| Roughness::iso(10f64.powf(l)).unwrap()),
        (-4.0f64..0.0, -4.0f64..0.0).prop_map(|(l1, l2)| Roughness::aniso(
            10f64.powf(l1),
            10f64.powf(l2)
        )
        .unwrap()),
    ]
}

/// Unit direction with polar angle up to 89.99° (and a share at the extremes), in f32.
fn dir32() -> impl Strategy<Value = [f32; 3]> {
    prop_oneof![
        (0.0f64..89.99, 0.0f64..std::f64::consts::TAU),
        (89.0f64..89.99, 0.0f64..std::f64::consts::TAU),
        (0.0f64..0.01, 0.0f64..std::f64::consts::TAU),
    ]
    .prop_map(|(t, p): (f64, f64)| {
        let t = t.to_radians();
        [
            (t.sin() * p.cos()) as f32,
            (t.sin() * p.sin()) as f32,
            t.cos() as f32,
        ]
    })
}

/// Unit roundoff of f32.
const EPS: f64 = 5.960_464_477_539_063e-8;

/// Extra relative error of rotated anisotropic forms: the minor-axis coordinate
/// −s·x + c·y cancels for directions along the major axis, costing ~ε·√cond(A).
fn aniso_term(r: &Roughness) -> f64 {
    let (lo, hi) = r.eigenvalues();
    let rotated = r.a()[(0, 1)] != 0.0;
    if rotated {
        8.0 * EPS * (hi / lo).sqrt()
    } else {
        0.0
    }
}

fn widen(v: [f32; 3]) -> Vector3<f64> {
    Vector3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

/// The f32 roughness and the f64 roughness it represents exactly (see
/// `Rough32::reference`): the comparison then measures arithmetic, not the rounding of
/// the roughness parameters (which moves a needle-like lobe by ~1e-7 rad).
fn r32_and_ref(r: &Roughness) -> (Rough32, Roughness) {
    let r32 = Rough32::from(r);
    (r32, r32.reference().expect("rounded roughness stays SPD"))
}

proptest! {
    #![proptest_config(common::config(10_000))] // was 2000

    #[test]
    fn ggx_d_and_lambda_within_2e_6(r in rough(), m in dir32(), o in dir32()) {
        let (r32, r64) = r32_and_ref(&r);
        let s = Microsurface::new(NdfKind::Ggx, r64);
        let d64 = s.d(&widen(m));
        let d32 = shading::d_ggx(&r32, m) as f64;
        prop_assert!(d32.is_finite() && d64.is_finite());
        // the cached inverse/normaliser are rounded to f32 too: a few ulp each
        let k = aniso_term(&r64);
        prop_assert!((d32 - d64).abs() <= (2e-6 + 2.0 * k) * d64, "D: {d32} vs {d64}");
        let l64 = s.lambda(&widen(o));
        let l32 = shading::lambda_ggx(&r32, o) as f64;
        prop_assert!((l32 - l64).abs() <= (2e-6 + 2.0 * k) * l64 + 1e-30, "Λ: {l32} vs {l64}");
    }

    #[test]
    fn beckmann_d_within_exponent_scaled_bound(r in rough(), m in dir32()) {
        let (r32, r64) = r32_and_ref(&r);
        let s = Microsurface::new(NdfKind::Beckmann, r64);
        let mv = widen(m);
        let d64 = s.d(&mv);
        let d32 = shading::d_beckmann(&r32, m) as f64;
        prop_assert!(d32.is_finite());
        let x = r64.quad_inv(&nalgebra::Vector2::new(mv.x, mv.y)) / (mv.z * mv.z);
        // f32 underflow: values below the smallest normal f32 are flushed
        let floor = f32::MIN_POSITIVE as f64 * 4.0;
        let k = aniso_term(&r64);
        prop_assert!((d32 - d64).abs() <= (1e-6 + 2.0 * k) * (4.0 + x) * d64 + floor, "D: {d32} vs {d64} (x = {x})");
    }

    #[test]
    fn beckmann_lambda_within_bound(r in rough(), o in dir32()) {
        let (r32, r64) = r32_and_ref(&r);
        let s = Microsurface::new(NdfKind::Beckmann, r64);
        let ov = widen(o);
        let l64 = s.lambda(&ov);
        let l32 = shading::lambda_beckmann(&r32, o) as f64;
        let nu = s.nu(&ov);
        prop_assert!(l32.is_finite() && l32 >= 0.0);
        let k = aniso_term(&r64);
        prop_assert!((l32 - l64).abs() <= (2e-5 + 2.0 * k) * (1.0 + nu * nu) * l64 + 1e-30, "Λ: {l32} vs {l64} at ν = {nu}");
    }

    #[test]
    fn g1_g2_within_1e_5(r in rough(), i in dir32(), o in dir32()) {
        let (r32, r64) = r32_and_ref(&r);
        let s = Microsurface::new(NdfKind::Ggx, r64);
        let (iv, ov) = (widen(i), widen(o));
        let g1 = shading::g1_from_lambda(shading::lambda_ggx(&r32, o)) as f64;
        prop_assert!((g1 - s.g1_dir(&ov)).abs() <= 1e-5);
        let g2 = shading::g2_from_lambdas(shading::lambda_ggx(&r32, i), shading::lambda_ggx(&r32, o)) as f64;
        let ref2 = 1.0 / (1.0 + s.lambda(&iv) + s.lambda(&ov));
        prop_assert!((g2 - ref2).abs() <= 1e-5);
        prop_assert!((0.0..=1.0).contains(&g1) && (0.0..=1.0).contains(&g2));
    }
}

/// Why D is written with |n×h|²-type terms: the textbook f32 form with (n·h)² and
/// 1 − (n·h)² is useless at α = 1e-4, ours is not.
#[test]
fn cancellation_free_form_beats_cos_form_at_alpha_1e_4() {
    let a = 1e-4f64;
    let r = Roughness::iso(a).unwrap();
    let r32 = Rough32::from(&r);
    let s = Microsurface::ggx(r);
    let mut worst_naive = 0.0f64;
    let mut worst_ours = 0.0f64;
    for k in 1..200 {
        let t = a * 3.0 * k as f64 / 200.0; // inside the lobe
        let m = [(t.sin()) as f32, 0.0, (t.cos()) as f32];
        let d64 = s.d(&widen(m));
        let ours = shading::d_ggx(&r32, m) as f64;
        // naive: D = α²/(π((n·h)²(α² − 1) + 1)²)
        let c = m[2];
        let a2 = (a * a) as f32;
        let den = c * c * (a2 - 1.0) + 1.0;
        let naive = (a2 / (std::f32::consts::PI * den * den)) as f64;
        worst_naive = worst_naive.max((naive - d64).abs() / d64);
        worst_ours = worst_ours.max((ours - d64).abs() / d64);
    }
    assert!(worst_ours <= 2e-6, "ours {worst_ours}");
    assert!(
        worst_naive > 1e-2,
        "naive form unexpectedly fine: {worst_naive}"
    );
}

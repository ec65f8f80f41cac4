//! Property tests of the Jacobian closed forms against finite differences at random
//! points, extremes included (θ to 89.99°, n·o and o·h to 1e-4, LTC cond to 1e4).

mod common;

use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use ndfbench::jacobian::{
    step_study, DirMap, HalfToSlope, HalfVector, Ltc, NormalToSlope, ProjectedDisk, Reflection,
};
use proptest::prelude::*;

/// Tolerance of jacobian-* proofs (best step of the study, relative).
const FD_TOL: f64 = 1e-7;

fn upper() -> impl Strategy<Value = Vector3<f64>> {
    prop_oneof![
        (0.5f64..89.99, 0.0f64..std::f64::consts::TAU),
        (89.0f64..89.99, 0.0f64..std::f64::consts::TAU)
    ]
    .prop_map(|(t, p): (f64, f64)| {
        let t = t.to_radians();
        Vector3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
    })
}

fn any_dir() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0f64..1.0, 0.0f64..std::f64::consts::TAU).prop_map(|(z, p): (f64, f64)| {
        let r = (1.0 - z * z).sqrt();
        Vector3::new(r * p.cos(), r * p.sin(), z)
    })
}

fn check(map: &dyn DirMap, w: &Vector3<f64>) -> Result<(), TestCaseError> {
    check_tol(map, w, FD_TOL)
}

fn check_tol(map: &dyn DirMap, w: &Vector3<f64>, tol: f64) -> Result<(), TestCaseError> {
    let st = step_study(map, w);
    prop_assert!(
        st.best_error <= tol,
        "{}: best FD error {:.2e} at h = {:.0e}, w = {w:?}",
        map.name(),
        st.best_error,
        st.best_h
    );
    Ok(())
}

proptest! {
    #![proptest_config(common::config(10_000))] // was 300

    #[test]
    fn slope_maps(w in upper()) {
        check(&NormalToSlope, &w)?;
        check(&HalfToSlope, &w)?;
        check(&ProjectedDisk, &w)?;
    }

    #[test]
    fn reflection_and_half_vector(o in any_dir(), w in any_dir(), lc in -4.0f64..0.0) {
        // put the point at a chosen n·o = 10^lc (down to 1e-4)
        let c = 10f64.powf(lc);
        let t = (w - o * w.dot(&o)).try_normalize(1e-9).unwrap_or_else(|| ndfbench::integrate::sphere::frame(&o).0);
        let n = o * c + t * (1.0 - c * c).sqrt();
        check(&Reflection { o }, &n)?;
        let wi = n * (2.0 * c) - o; // o·h = c at h = n
        // |ω_i + o| = 2c: the sum cancels, so the best central difference reaches only
        // ~(ε/c)^(2/3) (truncation (h/c)² balanced against rounding ε/(c h))
        // (×30: derivative constants and the half-decade grid of steps)
        let tol = FD_TOL.max(30.0 * (f64::EPSILON / c).powf(2.0 / 3.0));
        check_tol(&HalfVector { o }, &wi, tol)?;
    }

    #[test]
    fn ltc(w in any_dir(), l1 in -2.0f64..0.0, l2 in 0.0f64..2.0, a in 0.0f64..3.0, b in 0.0f64..3.0) {
        let r1 = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(1.0, 2.0, 0.5)), a).into_inner();
        let r2 = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(-0.3, 0.2, 1.0)), b).into_inner();
        let m = r1 * Matrix3::from_diagonal(&Vector3::new(10f64.powf(l1), 1.0, 10f64.powf(l2))) * r2;
        check(&Ltc::new(m).unwrap(), &w)?;
    }
}

//! The microfacet targets' albedo (the norm every GGX and anisotropic table stores) by
//! nested adaptive quadrature in half-vector space, against the same integral taken in
//! the other variable: f(l) over directions, on a polar grid about the mirror direction
//! with the horizon l_z = 0 as a great-circle kink. In half-vector space the horizon is a
//! curve the polar grid crosses; until its crossings became break points the adaptive
//! rule settled on values up to 9e-7 off while reporting 1e-9 (α 0.012 at 89.99°).

use nalgebra::Vector3;
use ndfbench::integrate::quad::Tol;
use ndfbench::integrate::sphere::{integrate_sphere, SphereRule};
use ndfbench::ltc::aniso::AnisoGgxTarget;
use ndfbench::ltc::target::{GgxTarget, LtcTarget};

type V3 = Vector3<f64>;

/// ∫ f(l) dl over the upper hemisphere of directions, about the mirror direction of v.
fn l_space_albedo(t: &dyn LtcTarget, scale: f64, tol: f64) -> (f64, f64) {
    let v = t.view();
    let mirror = V3::new(-v.x, -v.y, v.z);
    let f = |l: &V3| if l.z <= 0.0 { 0.0 } else { t.eval(l).0 };
    let rule = SphereRule::sphere(mirror, scale).with_kink(V3::z());
    let e = integrate_sphere(&f, &rule, Tol::new(tol, tol, 400_000_000));
    (e.value, e.error)
}

fn check(name: &str, t: &dyn LtcTarget, scale: f64) -> f64 {
    let (a, err, fres) = t.albedo(1e-9);
    let (r, r_err) = l_space_albedo(t, scale, 1e-10);
    let gap = (a - r).abs();
    // the requested 1e-9 twice over on top of both estimates: the half-vector rule's
    // estimate is not always conservative in GGX's far tail (measured: 1.2e-9 against a
    // stated 1.1e-10 at α 1e-3 seen head-on, where a 1D integral agrees with the
    // directions to 1e-13), but the missed horizon crossings were off by 2.5e-8–9e-7
    assert!(
        gap <= 3.0 * (err + r_err) + 2e-9,
        "{name}: half-vector {a:.13} (± {err:.1e}) vs directions {r:.13} (± {r_err:.1e})"
    );
    assert!(
        a > 0.0 && a <= 1.0 + 1e-9 && (0.0..a).contains(&fres),
        "{name}: {a} {fres}"
    );
    gap
}

#[test]
fn ggx_albedo_agrees_with_the_direction_space_integral_at_grazing_views() {
    let mut worst = (0.0f64, String::new());
    for &alpha in &[1e-5, 1e-3, 0.0123, 0.0494, 0.198, 0.605, 1.0] {
        for &deg in &[0.0, 45.0, 77.88, 85.0, 89.0, 89.99] {
            let t = GgxTarget::new(alpha, f64::to_radians(deg)).unwrap();
            let name = format!("GGX α {alpha} θ {deg}°");
            let gap = check(&name, &t, 2.0 * alpha);
            if gap > worst.0 {
                worst = (gap, name);
            }
        }
    }
    eprintln!("largest gap {:.1e} ({})", worst.0, worst.1);
}

#[test]
fn anisotropic_albedo_agrees_with_the_direction_space_integral() {
    for &(ax, ay) in &[(0.05, 0.4), (0.3, 0.1), (1.0, 0.25)] {
        for &phi in &[0.0, 0.6] {
            for &deg in &[0.0, 70.0, 89.9] {
                let t = AnisoGgxTarget::new(ax, ay, f64::to_radians(deg), phi).unwrap();
                let name = format!("aniso ({ax}, {ay}) φ {phi} θ {deg}°");
                check(&name, &t, 2.0 * f64::min(ax, ay));
            }
        }
    }
}

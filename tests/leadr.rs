//! LEADR grid integration (seed 001 §3.4–3.7): rules, reference, artificial micronormal.

use nalgebra::Vector3;
use ndfbench::integrate::quad::Tol;
use ndfbench::integrate::sphere::{integrate_sphere, SphereRule};
use ndfbench::leadr::{grid_estimate, reference, Grid, Slopes};
use ndfbench::microfacet::{Microsurface, Roughness};

#[test]
fn gauss_hermite_rules_are_exact_for_polynomials() {
    for n in [2usize, 3, 5, 8, 16, 32] {
        let g = Grid::gauss_hermite(n);
        // E[x^{2k}] = (2k − 1)!! for the standard normal, exact up to degree 2n − 1
        let mut df = 1.0;
        for k in 0..n {
            if 2 * k > 2 * n - 1 {
                break;
            }
            let m: f64 = g
                .nodes
                .iter()
                .zip(&g.weights)
                .map(|(x, w)| w * x.powi(2 * k as i32))
                .sum();
            assert!((m - df).abs() <= 1e-11 * df, "n={n} k={k}: {m} vs {df}");
            df *= (2 * k + 1) as f64;
        }
    }
}

#[test]
fn the_paper_weights_are_the_normalised_gaussian_at_spacing_0_9() {
    let p = Grid::paper5();
    let r = Grid::riemann(5, 0.9);
    for (a, b) in p.weights.iter().zip(&r.weights) {
        assert!((a - b).abs() < 1e-4, "{a} vs {b}");
    }
}

#[test]
fn reference_agrees_with_the_direction_space_integral() {
    // the same shading ratio written with the Beckmann NDF over directions:
    // ∫ L(m) ⟨v·m⟩ D(m) dm / ∫ ⟨v·m⟩ D(m) dm, with α = σ√2 (seed 001 §1.2)
    let sigma = 0.3;
    let t = 50f64.to_radians();
    let v = Vector3::new(t.sin(), 0.0, t.cos());
    let l = Vector3::new(-0.3, 0.4, 0.87).normalize();
    let shade = |n: &Vector3<f64>| n.dot(&l).max(0.0);
    let r = reference(&Slopes::iso(sigma), &v, &shade, 1e-11).unwrap();
    let d = Microsurface::beckmann(Roughness::iso(sigma * std::f64::consts::SQRT_2).unwrap());
    let rule = SphereRule::hemisphere(0.4).with_kink(v).with_kink(l);
    let tol = Tol::new(1e-12, 1e-12, 20_000_000);
    let num = integrate_sphere(&|m| shade(m) * v.dot(m).max(0.0) * d.d(m), &rule, tol);
    let den = integrate_sphere(&|m| v.dot(m).max(0.0) * d.d(m), &rule, tol);
    assert!(
        (r - num.value / den.value).abs() < 1e-9,
        "{r} vs {}",
        num.value / den.value
    );
}

#[test]
fn artificial_micronormal_keeps_silhouettes_defined() {
    // every grid normal faces away from V: the plain estimate is 0/0
    let s = Slopes {
        x0: 3.0,
        y0: 0.0,
        sx: 0.05,
        sy: 0.05,
        rxy: 0.0,
    };
    let v = Vector3::new(0.999, 0.0, 0.0447).normalize();
    let env = |n: &Vector3<f64>| 0.5 + 0.5 * n.z;
    assert!(grid_estimate(&Grid::paper5(), &s, &v, &env, None).is_nan());
    let with = grid_estimate(&Grid::paper5(), &s, &v, &env, Some((1.01, 1e-5)));
    assert!(with.is_finite() && with > 0.0);
    // where normals are visible the 1e-5 weight changes the result by < 1e-4 relative
    let s = Slopes::iso(0.3);
    let v = Vector3::new(0.5, 0.0, 0.866).normalize();
    let a = grid_estimate(&Grid::paper5(), &s, &v, &env, None);
    let b = grid_estimate(&Grid::paper5(), &s, &v, &env, Some((1.01, 1e-5)));
    assert!((a - b).abs() <= 1e-4 * a);
}

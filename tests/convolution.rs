//! Spherical convolution of isotropic LTCs (seed 000 Eq 6) and the overall-roughness
//! models: independent checks (commutativity, mass, caps that are whole hemispheres,
//! limits of every rule).

use ndfbench::integrate::quad::Tol;
use ndfbench::multiscale::convolution::{ltc_cap_integral, Convolution};
use ndfbench::multiscale::mrl::mrl;
use ndfbench::multiscale::overall::{
    alpha_moment, conv_cap, eq7, sum_of_squares, table_cap, vmf, CAPS,
};
use std::f64::consts::PI;

const TOL: Tol = Tol {
    abs: 1e-8,
    rel: 1e-8,
    max_evals: 5_000_000,
};

#[test]
fn convolution_of_zonal_lobes_commutes() {
    let a = Convolution::new(0.4, 0.1).unwrap().moments_quad(TOL);
    let b = Convolution::new(0.1, 0.4).unwrap().moments_quad(TOL);
    assert!((a.mass_below.value - b.mass_below.value).abs() < 1e-8);
    assert!((a.mrl_clipped - b.mrl_clipped).abs() < 1e-8);
    assert!((a.mrl_unclipped.value - mrl(0.4) * mrl(0.1)).abs() < 1e-8);
}

#[test]
fn caps_that_are_hemispheres_give_the_known_masses() {
    // an LTC has all its mass above the horizon
    for a in [0.05, 0.5, 1.0] {
        let e = ltc_cap_integral(a, 0.0, PI / 2.0, TOL).unwrap();
        assert!((e.value - 1.0).abs() < 1e-7, "α={a}: {e}");
    }
    // the convolution's upper hemisphere holds 1 − (mass below the horizon)
    let c = Convolution::new(0.5, 0.5).unwrap();
    let m = c.moments_quad(TOL);
    let up = conv_cap(&c, 0.0, PI / 2.0, TOL);
    assert!(
        (up.value - (1.0 - m.mass_below.value)).abs() < 1e-6,
        "{up} vs {}",
        1.0 - m.mass_below.value
    );
    // a tilted cap of half-angle π covers the sphere
    let all = conv_cap(&c, 0.7, PI, TOL);
    assert!((all.value - 1.0).abs() < 1e-6, "{all}");
}

#[test]
fn every_rule_has_the_limits_it_claims() {
    for x in [0.01, 0.1, 0.5, 1.0] {
        // moment matching: exact in both limits, symmetric
        assert!((alpha_moment(x, 1e-12).unwrap() / x - 1.0).abs() < 1e-9);
        assert!((alpha_moment(1e-12, x).unwrap() / x - 1.0).abs() < 1e-9);
        assert!((alpha_moment(x, 0.3).unwrap() - alpha_moment(0.3, x).unwrap()).abs() < 1e-12);
        assert_eq!(sum_of_squares(x, 0.0), x);
        // vMF rules keep α_mi as α_me → 0 (κ → ∞)
        assert!((vmf(x, 1e-9, 2.0) / x - 1.0).abs() < 1e-6);
        // Eq 7 (seed 000) as printed: α(α_mi, 0) = 0.07α_mi² + 0.94α_mi, not α_mi
        assert!((eq7(x, 0.0) - (0.07 * x * x + 0.94 * x)).abs() < 1e-15);
        assert_eq!(eq7(0.0, x), x);
    }
}

/// Solid angle of a spherical triangle (Van Oosterom & Strackee 1983).
fn triangle_solid_angle(
    a: &nalgebra::Vector3<f64>,
    b: &nalgebra::Vector3<f64>,
    c: &nalgebra::Vector3<f64>,
) -> f64 {
    let num = a.dot(&b.cross(c)).abs();
    let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
    2.0 * num.atan2(den)
}

#[test]
fn polygon_quadrature_matches_the_closed_form_solid_angle() {
    use ndfbench::multiscale::convolution::Polygon;
    for (t, h1, h2) in [
        (0.4, 0.15, 0.15),
        (0.0, 0.5, 0.2),
        (1.2, 0.15, 0.05),
        (0.8, 0.02, 0.02),
    ] {
        let p = Polygon::quad("q", t, h1, h2);
        let v: Vec<nalgebra::Vector3<f64>> = p
            .vertices
            .iter()
            .map(|x| nalgebra::Vector3::new(x[0], x[1], x[2]))
            .collect();
        let exact =
            triangle_solid_angle(&v[0], &v[1], &v[2]) + triangle_solid_angle(&v[0], &v[2], &v[3]);
        let e = p.integral(&|_m| 1.0, Tol::new(1e-13, 1e-12, 5_000_000));
        assert!(
            (e.value - exact).abs() < 1e-10 * exact,
            "{t}: {e} vs {exact}"
        );
    }
}

#[test]
fn tabulated_convolution_interpolates_to_the_direct_quadrature() {
    use ndfbench::multiscale::convolution::density_table;
    let c = Convolution::new(0.2, 0.05).unwrap();
    let table = density_table(&c, 16, Tol::new(1e-11, 1e-10, 2_000_000));
    // above the horizon (where the polygon lights sit) the interpolant is good to 1e-6;
    // below it c is less smooth (the two support boundaries b_z = 0 and m·b = 0 meet) and
    // the table is only good to ~1e-3 there
    for (t, tol) in [
        (0.013, 1e-6),
        (0.07, 1e-6),
        (0.31, 1e-6),
        (0.9, 1e-6),
        (1.4, 1e-6),
        (1.7, 1e-3),
    ] {
        let direct = c.density(t, Tol::new(1e-12, 1e-11, 5_000_000)).value;
        let interp = table.eval(t);
        assert!(
            (interp - direct).abs() <= tol * direct.abs().max(1e-12),
            "θ={t}: {interp} vs {direct}"
        );
    }
}

#[test]
fn caps_read_from_the_table_agree_with_caps_by_nested_quadrature() {
    use ndfbench::multiscale::convolution::density_table;
    // the fit's caps read the tabulated density; the reference integrates a fresh sphere
    // quadrature of c(θ) at every θ node. Both bars together must cover the difference,
    // and the table's bar must be tight enough for the fit (1e-5 relative)
    for (mi, me) in [(0.01, 0.01), (0.3, 0.05), (0.02, 1.0), (1.0, 1.0)] {
        let c = Convolution::new(me, mi).unwrap();
        let tt = Tol::new(1e-10, 1e-9, 2_000_000);
        let (fine, coarse) = (density_table(&c, 16, tt), density_table(&c, 12, tt));
        for &(t, r) in &CAPS {
            let a = table_cap(
                &fine,
                &coarse,
                mi.max(me).min(1.0),
                t,
                r,
                Tol::new(1e-11, 1e-9, 5_000_000),
            );
            let b = conv_cap(&c, t, r, Tol::new(1e-9, 1e-7, 5_000_000));
            assert!(
                (a.value - b.value).abs() <= a.error + b.error,
                "({mi}, {me}) cap ({t}, {r}): table {a} vs nested {b}"
            );
            assert!(
                a.error <= 1e-5 * a.value.abs(),
                "({mi}, {me}) cap ({t}, {r}): {a}"
            );
        }
    }
}

//! The anisotropic GGX LTC target, its general production form and its table, checked
//! against physics and independent code paths: the production form is the same
//! distribution (the rotation about z and the scale it removes change nothing), the lobe
//! has the symmetries the table's layout relies on, its albedo agrees with the isotropic
//! target where α_x = α_y and with Monte Carlo elsewhere, the fit beats the engines'
//! isotropic substitute on anisotropic cells, and the table's lookup honours the
//! symmetries.

mod common;

use nalgebra::{Matrix3, Vector3};
use ndfbench::ltc::aniso::{fit_cell, inverse_of, mirror_y, production_of, rel_l2, AnisoGgxTarget};
use ndfbench::ltc::aniso_table::{AnisoGrid, AnisoTable};
use ndfbench::ltc::target::{GgxTarget, LtcTarget};
use ndfbench::ltc::LtcDist;
use ndfbench::parmap::Plain;
use proptest::prelude::*;

type V3 = Vector3<f64>;

fn dir(u: f64, v: f64) -> V3 {
    let z = 1.0 - 2.0 * u;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let p = std::f64::consts::TAU * v;
    V3::new(r * p.cos(), r * p.sin(), z)
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// The production form of any invertible M⁻¹ (well conditioned or not) is the same
    /// LTC: equal densities at every direction (relative 1e-9).
    #[test]
    fn the_production_form_is_the_same_distribution(
        e in prop::array::uniform9(-2.0f64..2.0),
        scale in -6.0f64..6.0,
        u in 0.0f64..1.0, v in 0.0f64..1.0,
    ) {
        let m = Matrix3::from_row_slice(&e) * 10f64.powf(scale);
        prop_assume!(m.determinant().abs() > 1e-6 * 10f64.powf(3.0 * scale));
        let Some(p) = production_of(&m) else { return Ok(()); };
        prop_assert_eq!(p.len(), 7);
        let (a, b) = match (m.try_inverse(), inverse_of(&p).try_inverse()) {
            (Some(x), Some(y)) => (x, y),
            _ => return Ok(()),
        };
        let (Ok(da), Ok(db)) = (LtcDist::new(a), LtcDist::new(b)) else { return Ok(()); };
        let w = dir(u, v);
        let (x, y) = (da.eval(&w), db.eval(&w));
        prop_assert!((x - y).abs() <= 1e-9 * x.abs().max(y.abs()) + 1e-300, "{x} vs {y}");
    }
}

#[test]
fn the_lobe_has_the_symmetries_the_layout_uses() {
    for &(ax, ay) in &[(0.5, 0.1), (0.05, 0.3), (0.9, 0.9)] {
        for &deg in &[0.0, 35.0, 80.0] {
            for &phi in &[0.0, 0.3, 1.1, 1.5] {
                let th = f64::to_radians(deg);
                let t = AnisoGgxTarget::new(ax, ay, th, phi).unwrap();
                // the mirror y → −y: φ → π − φ
                let m = AnisoGgxTarget::new(ax, ay, th, std::f64::consts::PI - phi).unwrap();
                // a quarter turn of the tangent with the roughnesses swapped
                let q = AnisoGgxTarget::new(ay, ax, th, phi + std::f64::consts::FRAC_PI_2).unwrap();
                for k in 0..50 {
                    let l = dir(0.5 * (k as f64 + 0.5) / 50.0, (k * 7 % 50) as f64 / 50.0);
                    let f = t.eval(&l).0;
                    let fm = m.eval(&V3::new(l.x, -l.y, l.z)).0;
                    let fq = q.eval(&l).0;
                    assert!(
                        (f - fm).abs() <= 1e-9 * f.max(1e-300),
                        "mirror {ax} {ay} {deg} {phi}: {f} {fm}"
                    );
                    assert!(
                        (f - fq).abs() <= 1e-9 * f.max(1e-300),
                        "swap {ax} {ay} {deg} {phi}: {f} {fq}"
                    );
                }
            }
        }
    }
}

#[test]
fn albedo_agrees_with_the_isotropic_target_and_with_monte_carlo() {
    for &alpha in &[0.01, 0.2, 1.0] {
        for &deg in &[0.0, 60.0, 88.0] {
            let th = f64::to_radians(deg);
            let a = AnisoGgxTarget::new(alpha, alpha, th, 0.7)
                .unwrap()
                .albedo(1e-8)
                .0;
            let i = GgxTarget::new(alpha, th).unwrap().norm_quad(1e-8).0;
            assert!(
                (a - i).abs() <= 1e-6 * i,
                "α {alpha} θ {deg}: {a} vs isotropic {i}"
            );
        }
    }
    for &(ax, ay) in &[(0.4, 0.02), (0.05, 0.5), (0.8, 0.2)] {
        for &deg in &[20.0, 70.0] {
            let t = AnisoGgxTarget::new(ax, ay, f64::to_radians(deg), 0.4).unwrap();
            let (q, _, _) = t.albedo(1e-8);
            let (mc, _, se, _) = t.moments(256);
            assert!(
                (q - mc).abs() <= 4.0 * se + 1e-9,
                "{ax} {ay} {deg}: quadrature {q} vs MC {mc} ± {se}"
            );
        }
    }
}

#[test]
fn the_fit_beats_the_isotropic_substitute_on_anisotropic_cells() {
    use ndfbench::ltc::fit::{fit_table, Grid, Method, Metric};
    // an isotropic start fitted here (the committed table is not needed)
    for &(ax, ay, phi, deg) in &[(0.3, 0.05, 0.4, 30.0), (0.1, 0.4, 1.2, 60.0)] {
        let th = f64::to_radians(deg);
        let g = (ax * ay as f64).sqrt();
        let iso = fit_table(
            &Plain,
            Grid { n: 2, alpha_min: g },
            &|_, _| GgxTarget::new(g, th),
            12,
            Metric::Cubic,
            Method::NelderMead,
            300,
            ndfbench::ltc::fit::Polish::NelderMead,
            &|| {},
        )
        .unwrap();
        let c = &iso.cells[0][0];
        let start = [c.inv[0], c.inv[1], c.inv[2], c.inv[3], 0.0, 0.0, 0.0];
        let t = AnisoGgxTarget::new(ax, ay, th, phi).unwrap();
        let norm = t.albedo(1e-7).0;
        let (p, _) = fit_cell(&t, &start, norm, 12, 600).unwrap();
        let before = rel_l2(&t, &start, c.norm, 24, 0.25);
        let after = rel_l2(&t, &p, norm, 24, 0.25);
        assert!(
            after < 0.8 * before,
            "{ax} {ay} {phi} {deg}: {after} vs isotropic {before}"
        );
    }
}

#[test]
fn the_lookup_honours_the_symmetries_and_hits_its_nodes() {
    let grid = AnisoGrid {
        n_r: 3,
        n_phi: 3,
        n_t: 3,
        alpha_min: 1e-3,
    };
    let cells: Vec<[f64; 9]> = (0..grid.cells())
        .map(|k| std::array::from_fn(|q| ((k * 31 + q * 7) % 17) as f64 / 17.0 + 0.1))
        .collect();
    let t = AnisoTable { grid, cells };
    // at a node, the node (φ = π/4 is the middle node)
    let (ix, iy, k, j) = (1, 2, 1, 1);
    let got = t.lookup(
        grid.alpha(ix),
        grid.alpha(iy),
        grid.phi(k),
        grid.theta(j).cos(),
    );
    let want = t.cells[grid.index(ix, iy, k, j)];
    for q in 0..9 {
        assert!(
            (got[q] - want[q]).abs() < 1e-12,
            "{q}: {} vs {}",
            got[q],
            want[q]
        );
    }
    // φ + π is the same tangent; π − φ the mirror
    for &phi in &[0.2, 0.9, 1.4] {
        let a = t.lookup(0.3, 0.1, phi, 0.6);
        let b = t.lookup(0.3, 0.1, phi + std::f64::consts::PI, 0.6);
        let m = t.lookup(0.3, 0.1, std::f64::consts::PI - phi, 0.6);
        let mm = mirror_y(&[m[0], m[1], m[2], m[3], m[4], m[5], m[6]]);
        for q in 0..7 {
            assert!((a[q] - b[q]).abs() < 1e-12);
            assert!((a[q] - mm[q]).abs() < 1e-12, "mirror {phi} {q}");
        }
    }
}

/// Bad input is a typed error, never a panic: NaN, zero, negative or infinite roughness,
/// a NaN angle; the extremes of the domain (α 1e-4 across 1, 89.99°) give finite lobes.
#[test]
fn bad_input_is_a_typed_error_and_the_extremes_are_finite() {
    for (ax, ay, th, phi) in [
        (f64::NAN, 0.1, 0.3, 0.0),
        (0.0, 0.1, 0.3, 0.0),
        (-0.2, 0.1, 0.3, 0.0),
        (0.2, f64::INFINITY, 0.3, 0.0),
        (0.2, 0.1, 0.3, f64::NAN),
    ] {
        assert!(
            AnisoGgxTarget::new(ax, ay, th, phi).is_err(),
            "{ax} {ay} {th} {phi}"
        );
    }
    let t = AnisoGgxTarget::new(1e-4, 1.0, f64::to_radians(89.99), 0.7).unwrap();
    let (a, e, f) = t.albedo(1e-6);
    assert!(
        a.is_finite() && a > 0.0 && e.is_finite() && f.is_finite() && f < a,
        "{a} {e} {f}"
    );
}

/// A malformed results/fits/ltc-aniso.json is a typed error naming the file.
#[test]
fn a_malformed_table_file_is_a_typed_error() {
    let dir = common::scratch("ltc_aniso", "aniso");
    std::fs::create_dir_all(dir.join("fits")).unwrap();
    for body in [
        "{",
        r#"{"grid": {"n_r": 2, "n_phi": 2, "n_t": 2, "alpha_min": 0.001}, "cells": []}"#,
        r#"{"grid": {"n_r": 100000, "n_phi": 2, "n_t": 2, "alpha_min": 0.001}, "cells": []}"#,
    ] {
        std::fs::write(dir.join("fits/ltc-aniso.json"), body).unwrap();
        let e = ndfbench::results::ltc_aniso::aniso_table(&dir)
            .unwrap_err()
            .to_string();
        assert!(e.contains("ltc-aniso.json"), "{e}");
    }
    // the committed table with a norm of 0 in one cell
    let mut v: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("results/fits/ltc-aniso.json").expect("committed table"),
    )
    .unwrap();
    v["cells"][3][7] = serde_json::json!(0.0);
    std::fs::write(dir.join("fits/ltc-aniso.json"), v.to_string()).unwrap();
    let e = ndfbench::results::ltc_aniso::aniso_table(&dir)
        .unwrap_err()
        .to_string();
    assert!(e.contains("ltc-aniso.json") && e.contains("cell 3"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

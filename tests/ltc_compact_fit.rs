//! The lobe fit of a compact LTC table (`ltc::compact_fit`) against independent
//! references: its LTC density and ∫D² against `LtcDist` (the proved Jacobian of
//! `jacobian::Ltc`) and against closed forms and quadrature, their derivatives against
//! finite differences, the fit against the exact held-out judge (`ltc::lobe_error`), its
//! bits at one and two threads, bad input as typed errors; and the `OverAlpha` transform
//! of `ltc::compact`.

mod common;

use nalgebra::Vector3;
use ndfbench::integrate::mc::{CosineHemisphere, Strategy as _};
use ndfbench::ltc::compact::{Compact, Transform};
use ndfbench::ltc::compact_fit::{density_grad, refine, self_overlap, LobeFit};
use ndfbench::ltc::compare::{cell_error_of, square_entries, stored_half};
use ndfbench::ltc::fit::inverse_from_production;
use ndfbench::ltc::lobe_error::Tolerance;
use ndfbench::ltc::target::{GgxTarget, LtcTarget};
use ndfbench::ltc::LtcDist;
use proptest::prelude::*;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// The LTC of production entries (a, b, c, d) as `LtcDist` builds it (M = (M⁻¹)⁻¹).
fn dist(e: &[f64; 4]) -> Option<LtcDist> {
    inverse_from_production(e)
        .try_inverse()
        .and_then(|m| LtcDist::new(m).ok())
}

/// A direction on the whole sphere from two uniforms.
fn sphere(u: f64, v: f64) -> V3 {
    let z = 1.0 - 2.0 * u;
    let s = (1.0 - z * z).max(0.0).sqrt();
    let p = 2.0 * PI * v;
    V3::new(s * p.cos(), s * p.sin(), z)
}

/// Production entries over the range a fitted table holds, its extremes included: a and
/// d down to 1e-5 (GGX at α_min and the grazing row), b and c of either sign.
fn entries() -> impl Strategy<Value = [f64; 4]> {
    let mag = prop_oneof![
        Just(1e-5),
        Just(1.0),
        Just(2.0),
        (-5.0f64..0.35).prop_map(|x| 10f64.powf(x)),
    ];
    let signed = prop_oneof![Just(0.0), (-1.0f64..1.0), (-1e-3f64..1e-3)];
    (mag.clone(), signed.clone(), signed, mag).prop_map(|(a, b, c, d)| [a, b, c, d])
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// D_e equals `LtcDist::eval` of the same matrix on the whole sphere (below the
    /// horizon too), and its four derivatives equal central differences wherever the
    /// direction is not at the lobe's own horizon (x_z = 0, a kink).
    #[test]
    fn density_and_its_gradient_match_independent_forms(
        e in entries(), u in 0.0f64..1.0, v in 0.0f64..1.0
    ) {
        // singular matrices are outside the model (LtcDist refuses them)
        let det = e[0] * e[3] - e[2] * e[1];
        let l = sphere(u, v);
        let Some(d_ref) = dist(&e).filter(|_| det.abs() > 1e-9).map(|g| g.eval(&l)) else {
            return Ok(());
        };
        let (d, g) = density_grad(&e, &l);
        prop_assert!(
            (d - d_ref).abs() <= 1e-7 * d_ref.abs() + 1e-300,
            "D {d:e} vs LtcDist {d_ref:e} at {e:?}, {l:?}"
        );
        let x3 = e[1] * l.x + e[3] * l.z;
        let xn = ((e[0] * l.x + e[2] * l.z).powi(2) + l.y * l.y + x3 * x3).sqrt();
        if x3.abs() <= 1e-3 * xn {
            return Ok(());
        }
        for i in 0..4 {
            let h = 1e-6 * e[i].abs().max(1e-3);
            let (mut p, mut m) = (e, e);
            p[i] += h;
            m[i] -= h;
            let fd = (density_grad(&p, &l).0 - density_grad(&m, &l).0) / (2.0 * h);
            // a difference across the kink at x_z = 0 measures nothing
            if (p[1] * l.x + p[3] * l.z) * (m[1] * l.x + m[3] * l.z) <= 0.0 {
                continue;
            }
            // truncation relative to the slope, plus the difference's rounding, ε·D/h
            let tol = 1e-4 * g[i].abs().max(fd.abs()) + 1e-14 * d / h;
            prop_assert!(
                (g[i] - fd).abs() <= tol,
                "∂D/∂e{i}: {:e} vs difference {fd:e} at {e:?}, {l:?}", g[i]
            );
        }
    }
}

/// The clamped-cosine points of an n×n stratified set (offset ½).
fn cosine_points(n: usize) -> Vec<V3> {
    (0..n * n)
        .filter_map(|k| {
            CosineHemisphere.sample([
                ((k % n) as f64 + 0.5) / n as f64,
                ((k / n) as f64 + 0.5) / n as f64,
            ])
        })
        .collect()
}

/// ∫D² over the sphere by the midpoint rule in (z, φ) (uniform in solid angle).
fn overlap_by_quadrature(e: &[f64; 4], nz: usize, nphi: usize) -> f64 {
    let g = dist(e).unwrap();
    let mut s = 0.0;
    for i in 0..nz {
        for j in 0..nphi {
            let l = sphere((i as f64 + 0.5) / nz as f64, (j as f64 + 0.5) / nphi as f64);
            let d = g.eval(&l);
            s += d * d;
        }
    }
    s * 4.0 * PI / (nz * nphi) as f64
}

/// ∫D² on the lobe's own samples: the same sum as `LtcDist` gives through its Jacobian on
/// the same points (to rounding); the clamped cosine's 2/(3π) in closed form; a general
/// lobe's ∫D² by quadrature over the sphere (lobe mass below the horizon included); and
/// its gradient against central differences.
#[test]
fn self_overlap_matches_its_references() {
    let xs = cosine_points(64);
    for e in [
        [1.0, 0.0, 0.0, 1.0],
        [0.8, -0.3, 0.4, 0.6],
        [1.0, 0.0, 0.0, 2e-3],
        [0.05, -0.02, 0.2, 1e-4],
        [1.0, 0.6, -0.2, 0.3],
    ] {
        let g = dist(&e).unwrap();
        let by_dist: f64 = xs
            .iter()
            .map(|x| g.eval(&g.from_cosine(x).unwrap()))
            .sum::<f64>()
            / xs.len() as f64;
        let (s, grad) = self_overlap(&e, &xs);
        assert!(
            (s - by_dist).abs() <= 1e-9 * by_dist,
            "{e:?}: {s:e} vs LtcDist's {by_dist:e}"
        );
        for i in 0..4 {
            let h = 1e-6 * e[i].abs().max(1e-3);
            let (mut p, mut m) = (e, e);
            p[i] += h;
            m[i] -= h;
            let fd = (self_overlap(&p, &xs).0 - self_overlap(&m, &xs).0) / (2.0 * h);
            assert!(
                (grad[i] - fd).abs() <= 1e-5 * grad[i].abs().max(fd.abs()) + 1e-13 * s / h,
                "{e:?}: ∂/∂e{i} {:e} vs {fd:e}",
                grad[i]
            );
        }
    }
    // the clamped cosine: ∫(z/π)² over the hemisphere = 2/(3π)
    let (s, _) = self_overlap(&[1.0, 0.0, 0.0, 1.0], &cosine_points(256));
    assert!((s - 2.0 / (3.0 * PI)).abs() <= 1e-4 * s, "{s} vs 2/(3π)");
    // broad lobes, one with mass below the horizon, against quadrature over the sphere
    for e in [[0.8, -0.3, 0.4, 0.6], [1.0, 0.6, -0.2, 0.3]] {
        let (s, _) = self_overlap(&e, &cosine_points(256));
        let q = overlap_by_quadrature(&e, 2000, 2000);
        assert!((s - q).abs() <= 2e-3 * q, "{e:?}: {s} vs quadrature {q}");
    }
    // no points, or a singular matrix: no finite overlap
    assert!(self_overlap(&[1.0, 0.0, 0.0, 1.0], &[]).0.is_infinite());
    assert!(self_overlap(&[1.0, 1.0, 1.0, 1.0], &xs).0.is_infinite());
}

fn ggx(alpha: f64, theta: f64) -> ndfbench::error::Result<GgxTarget> {
    GgxTarget::new(alpha, theta)
}

/// The published GGX table and its grid's α floor.
fn published() -> (ndfbench::ltc::table::FittedTable, f64) {
    let t = ndfbench::results::ltc::table(std::path::Path::new("results"), "ltc-ggx").unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("results/fits/ltc-ggx.json").unwrap())
            .unwrap();
    (t, v["grid"]["alpha_min"].as_f64().unwrap())
}

const OVER_ALPHA: [Transform; 6] = [
    Transform::Raw,
    Transform::OverAlpha,
    Transform::Raw,
    Transform::OverAlpha,
    Transform::Raw,
    Transform::Raw,
];

/// The lobe fit lowers the error the shader sees, as the exact held-out judge measures
/// it (adaptive cubature, none of the fit's nodes) at square centres the fit never
/// trained on: from the least-squares p = 6 series of the published GGX table, the mean
/// relative L2 of the rebuilt table read bilinearly falls by more than the bars.
#[test]
fn the_lobe_fit_lowers_the_judged_error() {
    let (table, alpha_min) = published();
    let start = Compact::fit_scaled(&table, 6, OVER_ALPHA, alpha_min).unwrap();
    let plan = LobeFit {
        nodes: 16,
        iterations: 10,
        passes: 1,
    };
    let (fitted, trace) = refine(&start, table.n, alpha_min, &ggx, plan, "test").unwrap();
    assert_eq!(trace.places, 63 * 63 + 64 * 64);
    assert!(trace.passes[0][1] < trace.passes[0][0], "{trace:?}");
    let (a, b) = (
        stored_half(&start.rebuild(64).unwrap()),
        stored_half(&fitted.rebuild(64).unwrap()),
    );
    let (mut sa, mut sb, mut bars) = (0.0, 0.0, 0.0);
    let picks = [3, 13, 23, 33, 43, 53];
    for &i in &picks {
        for &j in &picks {
            let (r, t) = ((i as f64 + 0.5) / 63.0, (j as f64 + 0.5) / 63.0);
            let lobe = ggx((r * r).max(alpha_min), (1.0 - t * t).acos()).unwrap();
            let (albedo, _, _) = lobe.albedo(1e-8);
            let ent = [
                square_entries(&a, i, j).unwrap(),
                square_entries(&b, i, j).unwrap(),
            ];
            let figs = cell_error_of(&lobe, albedo, &ent, Tolerance::relative(1e-2));
            let (fa, fb) = (figs[0].unwrap(), figs[1].unwrap());
            sa += fa.l2.value;
            sb += fb.l2.value;
            bars += fa.l2.error + fb.l2.error;
        }
    }
    let k = (picks.len() * picks.len()) as f64;
    eprintln!(
        "mean rel. L2 at {k} squares: least squares {:.4}, lobe fit {:.4} (bars {:.1e})",
        sa / k,
        sb / k,
        bars / k
    );
    assert!(
        sb / k + bars / k < sa / k,
        "mean rel. L2: lobe fit {:.4} vs least squares {:.4} (bars {:.1e})",
        sb / k,
        sa / k,
        bars / k
    );
}

/// The same bits at one thread and at two: the normal equations are summed over a fixed
/// number of place blocks in order.
#[test]
fn the_lobe_fit_is_thread_count_independent() {
    let (table, alpha_min) = published();
    let start = Compact::fit_scaled(&table, 4, OVER_ALPHA, alpha_min).unwrap();
    let plan = LobeFit {
        nodes: 4,
        iterations: 3,
        passes: 2,
    };
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| refine(&start, table.n, alpha_min, &ggx, plan, "test").unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one, two);
    assert_ne!(one.0, start, "the fit moved nothing");
}

/// Bad input is a typed error: no nodes, no passes, a side below 2, an α floor outside
/// (0, 1) or NaN, a target that cannot be built; an over-α series without an α floor.
#[test]
fn bad_lobe_fit_input_is_a_typed_error() {
    let (table, alpha_min) = published();
    let start = Compact::fit_scaled(&table, 3, OVER_ALPHA, alpha_min).unwrap();
    let ok = LobeFit {
        nodes: 2,
        iterations: 1,
        passes: 1,
    };
    for plan in [LobeFit { nodes: 0, ..ok }, LobeFit { passes: 0, ..ok }] {
        assert!(refine(&start, 64, alpha_min, &ggx, plan, "t").is_err());
    }
    assert!(refine(&start, 1, alpha_min, &ggx, ok, "t").is_err());
    for floor in [0.0, -1.0, 1.0, f64::NAN] {
        assert!(
            refine(&start, 8, floor, &ggx, ok, "t").is_err(),
            "α floor {floor}"
        );
    }
    let bad = |_: f64, _: f64| GgxTarget::new(f64::NAN, 0.0);
    assert!(refine(&start, 8, alpha_min, &bad, ok, "t").is_err());
    let e = Compact::fit(&table, 3, OVER_ALPHA).unwrap_err().to_string();
    assert!(e.contains("α floor"), "{e}");
    let mut c = start.clone();
    c.alpha_min = 0.0;
    assert!(c.check().unwrap_err().to_string().contains("α floor"));
}

/// An over-α channel reproduces α(r)·q(r, t) for a polynomial q of degree ≤ 5 (α(r) =
/// max(r², α_min), the kink at r = √α_min included), in f64 and, to its f32 rounding,
/// in the shading form.
#[test]
fn over_alpha_reproduces_alpha_times_a_polynomial() {
    let alpha_min = 1e-3;
    let q = |r: f64, t: f64| 0.5 + r - 0.3 * t * t + 0.2 * r.powi(4) * t;
    let n = 64;
    let cells = (0..n * n)
        .map(|k| {
            let (r, t) = (
                (k % n) as f64 / (n - 1) as f64,
                (k / n) as f64 / (n - 1) as f64,
            );
            [
                1.0,
                (r * r).max(alpha_min) * q(r, t),
                0.5,
                (r * r).max(alpha_min) * q(r, t),
                1.0,
                0.0,
            ]
        })
        .collect();
    let table = ndfbench::ltc::table::FittedTable {
        n,
        cells,
        half: None,
    };
    let c = Compact::fit_scaled(&table, 6, OVER_ALPHA, alpha_min).unwrap();
    let c32 = c.coeffs_f32();
    for i in 0..=50 {
        for j in 0..=50 {
            let (r, t) = (i as f64 / 50.0, j as f64 / 50.0);
            let want = (r * r).max(alpha_min) * q(r, t);
            let got = c.eval(r, t);
            assert!(
                (got[3] - want).abs() <= 1e-12 * want.max(1e-3),
                "({r}, {t})"
            );
            let got32 = f64::from(c.eval_f32(&c32, r as f32, t as f32)[1]);
            assert!(
                (got32 - want).abs() <= 1e-5 * want.max(alpha_min),
                "f32 at ({r}, {t}): {got32} vs {want}"
            );
        }
    }
}

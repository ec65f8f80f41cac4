//! Jacobian identities: each closed form against (1) finite-difference matrices with a
//! step-size study and (2) a Monte Carlo solid-angle ratio.

use super::cases::dir;
use super::outcome::{Outcome, Worst};
use crate::integrate::Preset;
use crate::jacobian::{
    mc_jacobian, step_study, DirMap, HalfToSlope, HalfVector, Ltc, NormalToSlope, ProjectedDisk,
    Reflection,
};
use nalgebra::{Matrix3, Rotation3, Vector3};

type V3 = Vector3<f64>;

/// FD tolerance (relative, best step of the study).
pub const FD_TOL: f64 = 1e-7;
/// Largest accepted |z| of the MC solid-angle ratio.
pub const MAX_Z: f64 = 5.0;

struct Point {
    label: String,
    map: Box<dyn DirMap>,
    w: V3,
    radius: f64,
}

fn run_points(
    id: &'static str,
    title: &'static str,
    source: &'static str,
    ranges: &str,
    points: Vec<Point>,
    p: Preset,
) -> Outcome {
    let mut fd = Worst::default();
    let mut z = Worst::default();
    let mut mc_rel = Worst::default();
    let mut orders: Vec<f64> = Vec::new();
    let mut boundary = 0.0f64;
    let mut matrix = false;
    let mut example = String::new();
    let samples = match p {
        Preset::Quick => 100_000,
        Preset::Default => 400_000,
        Preset::Precise => 4_000_000,
    };
    for (k, pt) in points.iter().enumerate() {
        let st = step_study(pt.map.as_ref(), &pt.w);
        matrix |= st.matrix_checked;
        fd.update(st.best_error, || {
            format!("{} (best h = {:.0e})", pt.label, st.best_h)
        });
        if st.observed_order.is_finite() {
            orders.push(st.observed_order);
        }
        if k == 1 {
            example = st
                .rows
                .iter()
                .step_by(2)
                .map(|r| format!("h={:.0e}: {:.1e}", r.h, r.rel_error))
                .collect::<Vec<_>>()
                .join(", ");
            example = format!("step study at {}: {example}", pt.label);
        }
        let det = pt.map.det(&pt.w);
        let mc = mc_jacobian(pt.map.as_ref(), &pt.w, pt.radius, samples, 1000 + k as u64);
        boundary = boundary.max(mc.boundary_mass);
        z.update((mc.value - det).abs() / mc.std_error, || {
            format!(
                "{}: MC {} vs closed {:.6e}",
                pt.label,
                crate::integrate::Figure::with_se(mc.value, mc.std_error).sci(6, 1),
                det
            )
        });
        mc_rel.update((mc.value - det).abs() / det, || pt.label.clone());
    }
    let (omin, omax) = orders
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, &o| {
            (a.0.min(o), a.1.max(o))
        });
    // central differences: truncation error at least second order (4 where symmetry cancels h²)
    let orders_ok = orders.iter().all(|o| *o >= 1.8);
    Outcome {
        id,
        title,
        source,
        ranges: ranges.to_string(),
        cases: points.len(),
        worst_error: fd.err,
        error_kind: if matrix { "rel FD (matrix, Frobenius)" } else { "rel FD (det)" },
        worst_case: fd.case,
        tolerance: FD_TOL,
        passed: fd.err <= FD_TOL && z.err <= MAX_Z && boundary == 0.0 && orders_ok,
        seconds: 0.0,
        notes: vec![
            format!("MC solid-angle ratio ({samples} samples per point): worst |z| = {:.2} ({}); worst relative deviation {:.2e}", z.err, z.case, mc_rel.err),
            format!("observed FD order {omin:.2}…{omax:.2} (central differences: 2) over {} points in the truncation regime", orders.len()),
            example,
        ],
    }
}

fn polar_points(make: &dyn Fn() -> Box<dyn DirMap>, p: Preset) -> Vec<Point> {
    let thetas: &[f64] = if p == Preset::Quick {
        &[30.0, 85.0, 89.99]
    } else {
        &[5.0, 30.0, 60.0, 85.0, 89.9, 89.99]
    };
    let mut v = Vec::new();
    for &th in thetas {
        for phi in [0.4, 2.5, -1.9] {
            let w = dir(th, phi);
            v.push(Point {
                label: format!("θ={th}° φ={phi}"),
                map: make(),
                w,
                radius: 1e-3 * w.z,
            });
        }
    }
    v
}

pub fn normal_to_slope(p: Preset) -> Outcome {
    run_points(
        "jacobian-normal-to-slope",
        "Normal→slope Jacobian 1/|cos³θ|",
        "seed 001 Eq 1",
        "θ 5°…89.99°, 3 azimuths",
        polar_points(&|| Box::new(NormalToSlope), p),
        p,
    )
}

pub fn slope_parallel(p: Preset) -> Outcome {
    run_points(
        "jacobian-slope-parallel",
        "Spherical→slope J∥ matrix and det 1/h_z³",
        "seed 003 Eq 5–6, App. B Eq 23–26",
        "θ 5°…89.99°, 3 azimuths; full matrix vs Eq 5",
        polar_points(&|| Box::new(HalfToSlope), p),
        p,
    )
}

pub fn projected_disk(p: Preset) -> Outcome {
    run_points(
        "jacobian-projected-disk",
        "Spherical→projected disk J⊥ matrix and det h_z",
        "seed 003 Eq 8–9",
        "θ 5°…89.99°, 3 azimuths; full matrix vs Eq 8",
        polar_points(&|| Box::new(ProjectedDisk), p),
        p,
    )
}

/// Points for the o-dependent maps: unit vectors u at 40° with o·u = 1/√(1 + k²) from 1
/// down to 1e-3; `at(u, o·u)` turns each into the map and its input point.
fn o_points(
    p: Preset,
    what: &str,
    at: &dyn Fn(V3, V3, f64) -> (Box<dyn DirMap>, V3),
) -> Vec<Point> {
    let o = dir(40.0, 0.3);
    let t = crate::integrate::sphere::frame(&o).0;
    let ks: &[f64] = if p == Preset::Quick {
        &[0.2, 5.0, 1000.0]
    } else {
        &[0.0, 0.2, 1.0, 5.0, 100.0, 1000.0]
    };
    ks.iter()
        .map(|&k| {
            let u = (o + t * k).normalize();
            let c = u.dot(&o);
            let (map, w) = at(o, u, c);
            Point {
                label: format!("{what} = {c:.3e}"),
                map,
                w,
                radius: 1e-3 * c.min(1.0),
            }
        })
        .collect()
}

pub fn reflection(p: Preset) -> Outcome {
    let points = o_points(p, "n·o", &|o, n, _| (Box::new(Reflection { o }), n));
    run_points(
        "jacobian-reflection",
        "Reflection Jacobian ‖∂ω_i/∂ω_n‖ = 4|ω_n·ω_o|",
        "seed 001 Eq 3",
        "o at 40°, n·o from 1 down to 1e-3",
        points,
        p,
    )
}

pub fn half_vector(p: Preset) -> Outcome {
    // the point is ω_i = reflect(o, h), so that o·h takes the listed values
    let points = o_points(p, "o·h", &|o, h, c| {
        (Box::new(HalfVector { o }), h * (2.0 * c) - o)
    });
    run_points(
        "jacobian-half-vector",
        "Half-vector Jacobian ‖∂h/∂ω_i‖ = 1/(4|o·h|)",
        "Walter et al. 2007 Eq 14; seed 001 Eq 3 (inverse)",
        "o at 40°, o·h from 1 down to 1e-3 (ω_i → −o)",
        points,
        p,
    )
}

pub fn ltc(p: Preset) -> Outcome {
    let rot = |ax: [f64; 3], ang: f64| {
        Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(V3::from(ax)), ang).into_inner()
    };
    let mut mats: Vec<(String, Matrix3<f64>, f64)> = vec![
        ("identity".into(), Matrix3::identity(), 1.0),
        (
            "LTC a=0.1 b=0.3 c=−0.2".into(),
            Matrix3::new(0.1, 0.0, 0.3, 0.0, 0.1, 0.0, -0.2, 0.0, 1.0),
            20.0,
        ),
        (
            "LTC a=1e-2 (sharp)".into(),
            Matrix3::new(1e-2, 0.0, 0.05, 0.0, 1e-2, 0.0, 0.0, 0.0, 1.0),
            100.0,
        ),
    ];
    if p != Preset::Quick {
        let m = rot([1.0, 2.0, 0.5], 0.7)
            * Matrix3::from_diagonal(&V3::new(1.0, 1e-2, 1e2))
            * rot([-0.3, 0.2, 1.0], 1.9);
        mats.push(("R·diag(1, 1e-2, 1e2)·R' (cond 1e4)".into(), m, 1e4));
    }
    let dirs: &[(f64, f64)] = if p == Preset::Quick {
        &[(10.0, 0.2), (89.99, 1.0)]
    } else {
        &[
            (0.0, 0.0),
            (10.0, 0.2),
            (60.0, 2.0),
            (89.99, 1.0),
            (120.0, -0.5),
        ]
    };
    let mut points = Vec::new();
    for (label, m, cond) in &mats {
        for &(th, ph) in dirs {
            let w = dir(th, ph);
            points.push(Point {
                label: format!("{label}, ω at {th}°"),
                map: Box::new(Ltc::new(*m).expect("invertible")),
                w,
                radius: 1e-3 / cond,
            });
        }
    }
    run_points(
        "jacobian-ltc",
        "LTC Jacobian |M⁻¹|/‖M⁻¹ω‖³",
        "Heitz et al. 2016 Eq 18; seed 000 Eq 1",
        "identity, LTC-shaped M (a down to 1e-2), rotated M with cond 1e4; ω from 0° to 120°",
        points,
        p,
    )
}

//! Shared pieces of the broad (non-microfacet-peaked) LTC targets: cosine-hemisphere
//! sampling with its density, and the albedo of a cosine-weighted lobe by nested adaptive
//! Gauss–Kronrod over (cos θ_l, φ) — the view lies in the xz-plane, so the lobe is
//! symmetric in φ ↔ −φ and φ runs over [0, π] (doubled).

use crate::integrate::quad::{gk15, gk15_breaks, Tol};
use nalgebra::Vector3;

type V3 = Vector3<f64>;

/// The largest view angle of a table cell, in degrees: a cell at θ = 90° is clamped here so
/// that v_z > 0 (as the shipped tables' fitter does).
pub const THETA_MAX_DEG: f64 = 89.99;

/// The view of a cell at θ (radians, clamped to ≤ [`THETA_MAX_DEG`] so that v_z > 0) for a lobe of
/// roughness α ∈ (0, 1] (anything else, NaN included, is a typed error).
pub fn checked_view(alpha: f64, theta: f64) -> crate::error::Result<V3> {
    if !(alpha.is_finite() && alpha > 0.0 && alpha <= 1.0) {
        return Err(crate::error::Error::InvalidRoughness(alpha));
    }
    let th = theta.clamp(0.0, THETA_MAX_DEG.to_radians());
    Ok(V3::new(th.sin(), 0.0, th.cos()))
}

/// A cosine-distributed direction (density l_z/π) from two uniforms.
pub fn cosine_sample(u: [f64; 2]) -> Option<V3> {
    let r = u[0].sqrt();
    let phi = 2.0 * std::f64::consts::PI * u[1];
    let z = (1.0 - u[0]).max(0.0).sqrt();
    (z > 0.0).then(|| V3::new(r * phi.cos(), r * phi.sin(), z))
}

/// The density of [`cosine_sample`].
pub fn cosine_pdf(l: &V3) -> f64 {
    if l.z > 0.0 {
        l.z / std::f64::consts::PI
    } else {
        0.0
    }
}

/// (∫f dl, error estimate, ∫f·(1 − v·h)⁵ dl) of a cosine-weighted lobe f over the upper
/// hemisphere, to relative tolerance `tol`: outer adaptive GK over u = cos θ_l ∈ [0, 1]
/// with breaks at the mirror direction's u = v_z and at `u_kinks` (where f has a kink in
/// l_z, e.g. the two branches of Estevez & Kulla's Λ at ½), inner over φ ∈ [0, π] (×2 by
/// symmetry).
pub fn albedo(
    f: &(dyn Fn(&V3) -> f64 + Sync),
    v: &V3,
    u_kinks: &[f64],
    tol: f64,
) -> (f64, f64, f64) {
    let t = Tol::new(tol * 1e-3, tol, 2_000_000);
    let dir = |u: f64, phi: f64| {
        let s = (1.0 - u * u).max(0.0).sqrt();
        V3::new(s * phi.cos(), s * phi.sin(), u)
    };
    let inner = |u: f64, fres: bool| {
        gk15(
            &|phi: f64| {
                let l = dir(u, phi);
                let w = f(&l);
                if fres {
                    let h = (v + l).normalize();
                    w * (1.0 - v.dot(&h)).max(0.0).powi(5)
                } else {
                    w
                }
            },
            0.0,
            std::f64::consts::PI,
            t,
        )
    };
    // the mirror direction (u = v_z, φ = π, an endpoint of the inner range) is where a
    // half-vector lobe such as the Charlie sin^(1/α)θ_h has its cone point for α ≥ ½
    let mut breaks = vec![0.0, 1.0, v.z];
    breaks.extend(u_kinks.iter().copied());
    breaks.retain(|&k| (0.0..=1.0).contains(&k));
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    let a = gk15_breaks(&|u| 2.0 * inner(u, false).value, &breaks, t);
    let b = gk15_breaks(&|u| 2.0 * inner(u, true).value, &breaks, t);
    (a.value, a.error, b.value)
}

//! Shared pieces of the broad (non-microfacet-peaked) LTC targets: cosine-hemisphere
//! sampling with its density, and the albedo of a cosine-weighted lobe by nested adaptive
//! Gauss–Kronrod over (cos θ_l, φ) — the view lies in the xz-plane, so the lobe is
//! symmetric in φ ↔ −φ and φ runs over [0, π] (doubled).

use crate::integrate::quad::{adaptive_batched, gk15_breaks, NodeValues, Tol};
use crate::lanes::{by_four, Dirs, Lanes};
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
    albedo_by(&|d| std::array::from_fn(|k| f(&d[k])), v, u_kinks, tol)
}

/// [`albedo`] with f taking four directions at a time (`crate::lanes`): each inner
/// G7–K15 segment's 15 nodes go through it in four calls, the same nodes and sums as one
/// node at a time (`tests::albedo_in_lanes_is_one_node_at_a_time`).
pub fn albedo_lanes(
    f: &(dyn Fn(&Dirs) -> Lanes + Sync),
    v: &V3,
    u_kinks: &[f64],
    tol: f64,
) -> (f64, f64, f64) {
    albedo_by(&|d| by_four(d, f), v, u_kinks, tol)
}

/// The outer break points in u = cos θ_l: the ends, the mirror direction's u = v_z (where
/// a half-vector lobe such as the Charlie sin^(1/α)θ_h has its cone point for α ≥ ½, at
/// φ = π, an end of the inner range) and the kinks, those inside [0, 1], sorted, once each.
fn u_breaks(v: &V3, u_kinks: &[f64]) -> Vec<f64> {
    let mut breaks = vec![0.0, 1.0, v.z];
    breaks.extend(u_kinks.iter().copied());
    breaks.retain(|&k| (0.0..=1.0).contains(&k));
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    breaks
}

/// The albedo given `f15`, f at the 15 directions of one inner segment.
fn albedo_by(
    f15: &(dyn Fn(&[V3; 15]) -> [f64; 15] + Sync),
    v: &V3,
    u_kinks: &[f64],
    tol: f64,
) -> (f64, f64, f64) {
    let t = Tol::new(tol * 1e-3, tol, 2_000_000);
    let dir = |u: f64, phi: f64| {
        let s = (1.0 - u * u).max(0.0).sqrt();
        // every u node's inner rule has the same φ nodes: remembered (`integrate::trig`)
        let (sp, cp) = crate::integrate::trig::sin_cos(phi);
        V3::new(s * cp, s * sp, u)
    };
    let inner = |u: f64, fres: bool| {
        // `gk15` over [0, π], a segment's 15 nodes in one call of f15
        let nodes = |phis: &[f64; 15]| -> NodeValues {
            let l: [V3; 15] = std::array::from_fn(|k| dir(u, phis[k]));
            let w = f15(&l);
            let out = std::array::from_fn(|k| {
                if fres {
                    let h = (v + l[k]).normalize();
                    w[k] * (1.0 - v.dot(&h)).max(0.0).powi(5)
                } else {
                    w[k]
                }
            });
            (out, [0.0; 15], 15)
        };
        adaptive_batched(&nodes, &[0.0, std::f64::consts::PI], t)
    };
    let breaks = u_breaks(v, u_kinks);
    let a = gk15_breaks(&|u| 2.0 * inner(u, false).value, &breaks, t);
    let b = gk15_breaks(&|u| 2.0 * inner(u, true).value, &breaks, t);
    (a.value, a.error, b.value)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::quad::gk15;
    use crate::lanes::map;
    use crate::ltc::diffuse::{BurleyRoughness, BurleyTarget};
    use crate::ltc::sheen::{CharlieTarget, SheenVisibility};
    use crate::ltc::target::LtcTarget;

    /// The albedo one node at a time, as it was written before `albedo` took lanes: the
    /// reference its lanes form must equal bit for bit.
    fn one_node_at_a_time(f: &dyn Fn(&V3) -> f64, v: &V3, u_kinks: &[f64], tol: f64) -> [f64; 3] {
        let t = Tol::new(tol * 1e-3, tol, 2_000_000);
        let dir = |u: f64, phi: f64| {
            let s = (1.0 - u * u).max(0.0).sqrt();
            V3::new(s * phi.cos(), s * phi.sin(), u)
        };
        let inner = |u: f64, fres: bool| {
            let g = |phi: f64| {
                let l = dir(u, phi);
                let w = f(&l);
                if fres {
                    let h = (v + l).normalize();
                    w * (1.0 - v.dot(&h)).max(0.0).powi(5)
                } else {
                    w
                }
            };
            gk15(&g, 0.0, std::f64::consts::PI, t)
        };
        let breaks = u_breaks(v, u_kinks);
        let a = gk15_breaks(&|u| 2.0 * inner(u, false).value, &breaks, t);
        let b = gk15_breaks(&|u| 2.0 * inner(u, true).value, &breaks, t);
        [a.value, a.error, b.value]
    }

    /// `albedo`, its inner segments' nodes four at a time through the targets'
    /// `eval_lanes`, gives the one-node form's bits (value, error estimate, Fresnel
    /// moment): both sheens and both diffuse roughnesses at α from 0.01 (the sheen's
    /// floor) or 1e-4 to 1 and views from 0° to 89.99°, at two tolerances.
    #[test]
    fn albedo_in_lanes_is_one_node_at_a_time() {
        let thetas = [0.0, 0.7, 1.3, 89.99f64.to_radians()];
        let mut checked = 0;
        for (k, &alpha) in [1e-4f64, 0.01, 0.2, 0.6, 1.0].iter().enumerate() {
            for &th in &thetas {
                let tol = if k % 2 == 0 { 1e-8 } else { 1e-6 };
                let sheens = [SheenVisibility::EstevezKulla, SheenVisibility::Neubelt]
                    .map(|vis| CharlieTarget::new(alpha.max(0.01), th, vis).unwrap());
                for t in &sheens {
                    let kinks: &[f64] = match t.visibility {
                        SheenVisibility::EstevezKulla => &[0.5],
                        SheenVisibility::Neubelt => &[],
                    };
                    let want = one_node_at_a_time(&|l| t.value(l), &t.view(), kinks, tol);
                    let got = t.albedo(tol);
                    assert_eq!(
                        [got.0, got.1, got.2].map(f64::to_bits),
                        want.map(f64::to_bits)
                    );
                    checked += 1;
                }
                for r in [BurleyRoughness::Paper, BurleyRoughness::Engines] {
                    let t = BurleyTarget::new(alpha, th, r).unwrap();
                    let want = one_node_at_a_time(&|l| t.value(l), &t.view(), &[], tol);
                    let got = t.albedo(tol);
                    assert_eq!(
                        [got.0, got.1, got.2].map(f64::to_bits),
                        want.map(f64::to_bits)
                    );
                    checked += 1;
                }
                // a lanes closure that is not a target's: the same nodes reach it
                let v = V3::new(th.sin(), 0.0, th.cos());
                let g = |l: &V3| l.z.max(0.0).powf(1.0 / alpha.max(0.05)) * (1.0 + l.x);
                let got = albedo_lanes(&|l| map(|i| g(&l.get(i))), &v, &[0.3], tol);
                let scalar = albedo(&g, &v, &[0.3], tol);
                assert_eq!(got, scalar);
                let want = one_node_at_a_time(&g, &v, &[0.3], tol);
                assert_eq!(
                    [got.0, got.1, got.2].map(f64::to_bits),
                    want.map(f64::to_bits)
                );
            }
        }
        assert_eq!(checked, 5 * 4 * 4);
    }
}

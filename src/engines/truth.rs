//! Per pixel: the exact value of a scene (a lobe, GGX or the sheen check's, integrated over the light) and the
//! value an LTC table gives there (its lookup, its edge integral).

use super::scenes::Rect;
use crate::integrate::cubature::{cubature, SAFETY_SMOOTH};
use crate::integrate::{Figure, Quad};
use crate::ltc::polygon::{ltc_integral, EdgeForm};
use crate::ltc::target::{GgxTarget, LtcTarget};
use nalgebra::{Matrix3, Vector3};

type V3 = Vector3<f64>;

/// The lobe at a pixel: α = roughness², the view at `view_deg` in the xz-plane.
pub fn lobe(roughness: f64, view_deg: f64) -> crate::error::Result<GgxTarget> {
    GgxTarget::new((roughness * roughness).max(1e-7), view_deg.to_radians())
}

/// The exact radiance at surface point `x` (z = 0): ∫_P f(l) dω over the light (unit
/// radiance), by adaptive cubature in the rectangle's (u, v) ∈ [0, 1]² with dω =
/// |front·(p − x)|/|p − x|³ dA, to `rel` relative accuracy; ± its error bar.
pub fn truth_value<T: LtcTarget + ?Sized>(t: &T, light: &Rect, x: &V3, rel: f64) -> Figure<Quad> {
    if !light.lights(x) {
        return Figure::<Quad>::new(0.0, 0.0);
    }
    let area = 4.0 * light.hw.norm() * light.hh.norm();
    let integrand = |u: f64, v: f64, out: &mut [f64]| {
        let p = light.c + light.hw * (2.0 * u - 1.0) + light.hh * (2.0 * v - 1.0);
        let d = p - x;
        let r2 = d.norm_squared();
        if r2 <= 0.0 {
            return;
        }
        let r = r2.sqrt();
        let l = d / r;
        if l.z <= 0.0 {
            return;
        }
        let cos_light = (-l).dot(&light.front).abs();
        out[0] = t.eval(&l).0 * cos_light / r2 * area;
    };
    // the horizon (p_z = x_z) is a kink; where it crosses the rectangle along a line of
    // constant u or v, it becomes a break
    let mut ub = vec![0.0, 1.0];
    let mut vb = vec![0.0, 1.0];
    let hz = |a: f64| light.c.z - x.z + a;
    if light.hw.z.abs() < 1e-15 && light.hh.z.abs() > 0.0 {
        let v0 = 0.5 * (1.0 - hz(0.0) / light.hh.z);
        if v0 > 0.0 && v0 < 1.0 {
            vb.insert(1, v0);
        }
    } else if light.hh.z.abs() < 1e-15 && light.hw.z.abs() > 0.0 {
        let u0 = 0.5 * (1.0 - hz(0.0) / light.hw.z);
        if u0 > 0.0 && u0 < 1.0 {
            ub.insert(1, u0);
        }
    }
    // a fine start: the specular spot of a smooth lobe is a small part of the light
    let refine = |b: Vec<f64>| -> Vec<f64> {
        let mut out = Vec::new();
        for w in b.windows(2) {
            for k in 0..4 {
                out.push(w[0] + (w[1] - w[0]) * k as f64 / 4.0);
            }
        }
        out.push(1.0);
        out
    };
    let (ub, vb) = (refine(ub), refine(vb));
    let r = cubature(
        integrand,
        &[SAFETY_SMOOTH],
        &ub,
        &vb,
        |v| vec![1.0 / v[0].abs().max(1e-300)],
        |v, e| e[0] <= (rel * v[0].abs()).max(1e-12),
        20_000_000,
    );
    Figure::<Quad>::new(r.value[0], r.error[0])
}

/// The value an LTC table gives at `x`: norm × the exact edge integral of the light
/// transformed by M⁻¹ (clipped in the LTC's space), with (a, b, c, d, norm) as the
/// engine's lookup returns them. Points behind the light get 0.
pub fn table_value(entries: &[f64; 5], light: &Rect, x: &V3) -> f64 {
    if !light.lights(x) {
        return 0.0;
    }
    let m_inv = m_inv_of(entries);
    let poly: Vec<V3> = light.corners().iter().map(|p| p - x).collect();
    entries[4] * ltc_integral(&m_inv, &poly, EdgeForm::Exact)
}

/// What an engine's bilinear lookup of a table (n×n cells of [a, b, c, d, norm], i + n·j)
/// returns at perceptual roughness r and N·V: uv = (r, √(1 − N·V))·(n − 1)/n + 0.5/n,
/// the four texels around it weighted linearly (clamped at the edges).
pub fn lookup(cells: &[[f64; 5]], n: usize, r: f64, ndotv: f64) -> [f64; 5] {
    let t = (1.0 - ndotv.clamp(0.0, 1.0)).sqrt();
    crate::ltc::table::bilinear(n, r, t, |i, j| cells[i + n * j])
}

/// three.js r187's own evaluation (`LTC_Evaluate` of lights_physical_pars_fragment) in
/// f64: 0 behind the light; the frame (T1, T2, N) = (x, −y, z) it builds for a view in
/// the xz-plane (T2 = −N × T1); the corners transformed by M⁻¹ and normalised; the
/// vector form factor summed over the edges with the rational fit of θ/(2π sin θ); the
/// horizon by the clipped-sphere approximation max((|F|² + F_z)/(|F| + 1), 0); times
/// the norm.
pub fn three_value(entries: &[f64; 5], light: &Rect, x: &V3) -> f64 {
    if !light.lights(x) {
        return 0.0;
    }
    let m_inv = m_inv_of(entries);
    let q: Vec<V3> = light
        .corners()
        .iter()
        .map(|p| {
            let d = p - x;
            (m_inv * V3::new(d.x, -d.y, d.z)).normalize()
        })
        .collect();
    let mut f = V3::zeros();
    for k in 0..4 {
        let (a, b) = (q[k], q[(k + 1) % 4]);
        let c = a.dot(&b);
        let t = crate::ltc::polygon::theta_over_sin(EdgeForm::Rational, c, 0.0);
        f += a.cross(&b) * (t / (2.0 * std::f64::consts::PI));
    }
    let l = f.norm();
    entries[4] * ((l * l + f.z) / (l + 1.0)).max(0.0)
}

/// Bevy 0.19.1's own evaluation (`rect_light` and `ltc_integrate_quad` of bevy_pbr's
/// pbr_lighting.wgsl) in f64: 0 behind the light; the same frame as three.js's; the
/// corners transformed by M⁻¹, the polygon clipped at z = 0 in the LTC's space (no
/// clipped-sphere approximation), normalised, and summed over the edges with the same
/// rational fit of θ/(2π sin θ); times the norm (F0 = 1).
pub fn bevy_value(entries: &[f64; 5], light: &Rect, x: &V3) -> f64 {
    if !light.lights(x) {
        return 0.0;
    }
    let m_inv = m_inv_of(entries);
    let poly: Vec<V3> = light
        .corners()
        .iter()
        .map(|p| {
            let d = p - x;
            V3::new(d.x, -d.y, d.z)
        })
        .collect();
    entries[4] * ltc_integral(&m_inv, &poly, EdgeForm::Rational)
}

/// M⁻¹ from the entries an engine's lookup returns: [[a, 0, c], [0, 1, 0], [b, 0, d]].
fn m_inv_of(entries: &[f64; 5]) -> Matrix3<f64> {
    Matrix3::new(
        entries[0], 0.0, entries[2], 0.0, 1.0, 0.0, entries[1], 0.0, entries[3],
    )
}

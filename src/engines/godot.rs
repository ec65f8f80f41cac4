//! Godot 4's area-light LTC tables, read from Godot's source (renderer_rd
//! `shaders/area_lights_inc.glsl`, `storage/make_ltc_lut.py`): what its two textures hold,
//! how its shader samples and evaluates them, and our GGX table in that layout.
//!
//! - **Files.** `servers/rendering/storage/ltc/ltc_lut1.dds` and `ltc_lut2.dds` are
//!   compiled into the engine: make_ltc_lut.py drops each file's first 148 bytes (the DX10
//!   DDS header) and embeds the rest, which the renderer uploads as a 64×64
//!   R32G32B32A32_SFLOAT texture with a linear sampler (texel (i, j) at i + 64·j).
//! - **Sampling.** uv = (max(r, 0.02), θ/(π/2))·63/64 + 0.5/64 with r the perceptual
//!   roughness (α = r²) and θ = `acos_approx(N·V)` = (π/2 − 0.156583·x)·√(1 − x) for
//!   x = N·V ≥ 0: texel (i, j) serves r = i/63 and the view whose *approximate* angle is
//!   (j/63)·π/2 (linear in θ, where three.js and Bevy use √(1 − cos θ)).
//! - **Layout.** lut1 = (a, b, c, d), lut2 = (e, mag, fres, ·). The shader builds
//!   M⁻¹ = mat3(vec3(0, 0, 1/c), vec3(−d·s, a·s, 0), vec3(−e·s, b·s, 0)), s = 1/(a·e − b·d),
//!   in the basis (x, N, z) with z = −normalize(V − N(N·V)) and x = N × z, so the lobe's
//!   "up" is the second coordinate: (a, b; d, e) is the forward matrix M of the
//!   (normal, view-plane) block and c its scale across the view plane. From our
//!   M⁻¹ ∝ [[A, 0, C], [0, 1, 0], [B, 0, D]] in (T1, T2, N) (T1 toward the view): with
//!   Δ = AD − BC, (a, b, c, d, e) = (D/Δ, −B/Δ, 1, −C/Δ, A/Δ) — the inverse of the
//!   2×2 block, up to reflections, which the shader's `abs` ignores.
//! - **Evaluation.** The quad clipped at the horizon in the LTC's space, each edge by
//!   Hill's rational fit of θ/sin θ (a = 5.42031 + (3.12829 + 0.0902326y)y, b = 3.45068 +
//!   (4.18814 + y)y; for x < 0, π/√(1 − x²) − a/b), an edge whose ends are nearly
//!   opposite split at the point nearest the shading point, |Σ|/(2π); the Fresnel weight
//!   f0·mag + (f90 − f0)·fres (f90 = 1 for a metal).

use super::scenes::Rect;
use crate::ltc::polygon::{ltc_integral, EdgeForm};
use crate::ltc::table::FittedTable;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::{FRAC_PI_2, PI};

type V3 = Vector3<f64>;

/// Godot's table size.
pub const N: usize = 64;

/// Godot's `acos_approx` in f64.
pub fn acos_approx(x: f64) -> f64 {
    let y = x.abs().min(1.0);
    let r = (-0.156583 * y + FRAC_PI_2) * (1.0 - y).sqrt();
    if x >= 0.0 {
        r
    } else {
        PI - r
    }
}

/// The N·V that row j serves: the x ∈ [0, 1] with acos_approx(x) = (j/63)·π/2
/// (acos_approx falls monotonically on [0, 1]; bisection to f64 resolution).
pub fn row_cos(j: usize) -> f64 {
    if j == 0 {
        return 1.0;
    }
    let want = j as f64 / (N - 1) as f64 * FRAC_PI_2;
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if acos_approx(mid) > want {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= f64::EPSILON {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// Godot's (a, b, c, d, e) from our M⁻¹ entries (A, B, C, D); `None` where the 2×2 block
/// is singular or not finite.
pub fn from_inverse(m: [f64; 4]) -> Option<[f64; 5]> {
    let [a, b, c, d] = m;
    let det = a * d - b * c;
    let g = [d / det, -b / det, 1.0, -c / det, a / det];
    (det != 0.0 && g.iter().all(|v| v.is_finite())).then_some(g)
}

/// Our M⁻¹ entries (A, B, C, D), up to a positive scale, from Godot's (a, b, c, d, e):
/// the inverse of [`from_inverse`] (Godot's c only scales the axis across the view plane,
/// so it is carried as 1/c into the other entries).
pub fn to_inverse(g: [f64; 5]) -> Option<[f64; 4]> {
    let [a, b, c, d, e] = g;
    let det = a * e - b * d;
    // Godot's map is (1/c)·(our M⁻¹) up to reflections: A = s·e·c, B = −s·b·c,
    // C = −s·d·c, D = s·a·c with s = 1/det
    let s = c / det;
    let m = [e * s, -b * s, -d * s, a * s];
    (det != 0.0 && c != 0.0 && m.iter().all(|v| v.is_finite())).then_some(m)
}

/// Our GGX table in Godot's layout: lut1 and lut2 texels (i + 64·j), each cell our
/// table's bilinear lookup (f64 entries) at r = i/63 and the row's N·V ([`row_cos`]),
/// converted by [`from_inverse`]; lut2 = (e, norm, fresnel, 0).
pub fn texels(t: &FittedTable) -> crate::error::Result<(Vec<[f64; 4]>, Vec<[f64; 4]>)> {
    let mut l1 = Vec::with_capacity(N * N);
    let mut l2 = Vec::with_capacity(N * N);
    for j in 0..N {
        let x = row_cos(j);
        for i in 0..N {
            let r = i as f64 / (N - 1) as f64;
            let e = t.bilinear(r * r, x, false);
            // our storage keeps det M⁻¹ > 0 in every cell, so its interpolation stays
            // invertible; a table where it does not is refused, never written
            let g = from_inverse([e[0], e[1], e[2], e[3]]).ok_or_else(|| {
                crate::error::Error::InvalidArgument(format!(
                    "Godot layout: our table is singular at texel ({i}, {j})"
                ))
            })?;
            l1.push([g[0], g[1], g[2], g[3]]);
            l2.push([g[4], e[4], e[5], 0.0]);
        }
    }
    Ok((l1, l2))
}

/// What Godot's bilinear lookup returns at perceptual roughness r and N·V: (a, b, c, d,
/// e, mag) from lut1 and lut2 at uv = (max(r, 0.02), acos_approx(N·V)/(π/2))·63/64 + 0.5/64.
pub fn lookup(l1: &[[f64; 4]], l2: &[[f64; 4]], r: f64, ndotv: f64) -> [f64; 6] {
    let u = r.max(0.02);
    let v = acos_approx(ndotv) / FRAC_PI_2;
    crate::ltc::table::bilinear(N, u, v, |i, j| {
        let (p, q) = (l1[i + N * j], l2[i + N * j]);
        [p[0], p[1], p[2], p[3], q[0], q[1]]
    })
}

/// Godot's `ltc_evaluate_specular` for a metal (f0 = f90 = 1) in f64 at surface point `x`
/// (plane z = 0, normal +z, view in the xz-plane toward +x), with the entries `g` its
/// lookup returned: the shader's frame and M⁻¹, the horizon clip, the edges by Hill's fit
/// (`EdgeForm::Rational` is not Godot's fit; [`hill_theta_over_sin`] is), times mag.
/// Points behind the light get 0 (Godot's light is one-sided like three.js's).
pub fn godot_value(g: &[f64; 6], light: &Rect, x: &V3) -> f64 {
    if !light.lights(x) {
        return 0.0;
    }
    let q = godot_polygon(g, light, x);
    let Some(q) = q else { return 0.0 };
    // clip at y' = 0 (Godot's "up" is the second coordinate)
    let clipped = clip_y(&q);
    if clipped.len() < 3 {
        return 0.0;
    }
    let proj: Vec<V3> = clipped.iter().map(|v| v.normalize()).collect();
    let mut sum = 0.0;
    for k in 0..clipped.len() {
        let k1 = (k + 1) % clipped.len();
        sum += integrate_edge(&proj[k], &proj[k1], &clipped[k], &clipped[k1]);
    }
    g[5] * sum.abs() / (2.0 * PI)
}

/// The same lobe with the exact edge integral (our `ltc_integral` after mapping Godot's
/// frame onto ours): what Godot's texels are worth before its edge fit.
pub fn godot_exact(g: &[f64; 6], light: &Rect, x: &V3) -> f64 {
    if !light.lights(x) {
        return 0.0;
    }
    let Some(q) = godot_polygon(g, light, x) else {
        return 0.0;
    };
    // (x', y', z') with y' up → (x', z', y') with z up; ltc_integral takes M⁻¹ = identity
    let p: Vec<V3> = q.iter().map(|v| V3::new(v.x, v.z, v.y)).collect();
    g[5] * ltc_integral(&Matrix3::identity(), &p, EdgeForm::Exact)
}

/// The light's corners relative to `x` in Godot's LTC space, `None` if the entries are
/// singular.
fn godot_polygon(g: &[f64; 6], light: &Rect, x: &V3) -> Option<Vec<V3>> {
    let [a, b, c, d, e, _] = *g;
    let s = 1.0 / (a * e - b * d);
    if !s.is_finite() || c == 0.0 {
        return None;
    }
    // world → (x, N, z): N = +z, z = −T1 = −(1, 0, 0), x = N × z = (0, −1, 0)
    let m_inv = Matrix3::from_columns(&[
        V3::new(0.0, 0.0, 1.0 / c),
        V3::new(-d * s, a * s, 0.0),
        V3::new(-e * s, b * s, 0.0),
    ]);
    Some(
        godot_corners(light)
            .iter()
            .map(|p| {
                let w = p - x;
                m_inv * V3::new(-w.y, w.z, -w.x)
            })
            .collect(),
    )
}

/// The corners in Godot's order (position ∓ hw ∓ hh: −−, +−, ++, −+).
fn godot_corners(l: &Rect) -> [V3; 4] {
    [
        l.c - l.hw - l.hh,
        l.c + l.hw - l.hh,
        l.c + l.hw + l.hh,
        l.c - l.hw + l.hh,
    ]
}

/// Sutherland–Hodgman at y ≥ 0 (Godot's `clip_quad_to_horizon` enumerates the same
/// polygons case by case).
fn clip_y(p: &[V3]) -> Vec<V3> {
    let mut out = Vec::with_capacity(p.len() + 1);
    for k in 0..p.len() {
        let (a, b) = (p[k], p[(k + 1) % p.len()]);
        if a.y > 0.0 {
            out.push(a);
        }
        if (a.y > 0.0) != (b.y > 0.0) {
            out.push(a + (b - a) * (a.y / (a.y - b.y)));
        }
    }
    out
}

/// Hill's rational fit of θ/sin θ as Godot ships it (x = cos θ).
pub fn hill_theta_over_sin(x: f64) -> f64 {
    let y = x.abs();
    let a = 5.42031 + (3.12829 + 0.0902326 * y) * y;
    let b = 3.45068 + (4.18814 + y) * y;
    let v = a / b;
    if x < 0.0 {
        PI / (1.0 - x * x).sqrt() - v
    } else {
        v
    }
}

/// Godot's `integrate_edge`: the y-component of the edge's vector form factor, an edge
/// whose ends are within 1e-5 of opposite split at the point nearest the origin.
fn integrate_edge(p0: &V3, p1: &V3, q0: &V3, q1: &V3) -> f64 {
    let edge = |u: &V3, v: &V3| hill_theta_over_sin(u.dot(v)) * u.cross(v).y;
    if p0.dot(p1) < -1.0 + 1e-5 {
        let dir = (q1 - q0).normalize();
        let half = (q0 + dir * q0.dot(&(q0 - q1).normalize())).normalize();
        edge(p0, &half) + edge(&half, p1)
    } else {
        edge(p0, p1)
    }
}

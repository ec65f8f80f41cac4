//! Polygonal lights: the integral of a clamped cosine — and, through M⁻¹,
//! of an LTC — over a polygon, with horizon clipping; the exact edge integral and the
//! production rational approximations of θ/sin θ; Monte Carlo ground truth of the true
//! BRDF over the polygon.
//!
//! Lambert's form factor: for unit vertices p_k (shading point at the origin, normal +z),
//! ∫_P max(0, z)/π dω = (1/2π)·|Σ_k θ_k · (p_k × p_{k+1})_z / |p_k × p_{k+1}||,
//! θ_k = angle(p_k, p_{k+1}) (Heitz et al. 2016 §4; Arvo 1995). The polygon is clipped to
//! z ≥ 0 first, so only the upper hemisphere contributes. Lights are two-sided (the
//! absolute value).
//!
//! Degenerate inputs never give NaN or a negative value: zero-area, line and point
//! polygons integrate to 0; a polygon edge-on to the shading point (its plane through
//! the origin) integrates to 0; a polygon entirely below the horizon integrates to 0.

use crate::error::{Error, Result};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// How θ/sin θ of an edge is evaluated from x = cos θ = p1·p2.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum EdgeForm {
    /// atan2(|p1 × p2|, p1·p2)/|p1 × p2| in f64 (the reference).
    Exact,
    /// The rational fit shipped with the LTC demos and three.js, which approximates
    /// θ/(2π sin θ): a = 0.8543985 + (0.4965155 + 0.0145206 y)y, b = 3.4175940 +
    /// (4.1616724 + y)y, y = |x|; a/b for x > 0, else ½/√max(1 − x², 1e-7) − a/b
    /// (returned here times 2π, i.e. as θ/sin θ).
    Rational,
    /// The earlier cubic 1.5708 + (−0.879406 + 0.308609 |x|)|x| (for x < 0:
    /// π/√(1 − x²) − cubic).
    Cubic,
}

/// θ/sin θ of an edge from x = cos θ (and |p1 × p2| for the exact form).
// the cubic's 1.5708 is the shipped constant, not π/2: measured as it ships
#[allow(clippy::approx_constant)]
pub fn theta_over_sin(form: EdgeForm, x: f64, sin_theta: f64) -> f64 {
    match form {
        EdgeForm::Exact => {
            if sin_theta <= 1e-300 {
                if x > 0.0 {
                    1.0
                } else {
                    f64::INFINITY
                }
            } else {
                sin_theta.atan2(x) / sin_theta
            }
        }
        EdgeForm::Rational => {
            let y = x.abs();
            let a = 0.8543985 + (0.4965155 + 0.0145206 * y) * y;
            let b = 3.4175940 + (4.1616724 + y) * y;
            let v = a / b;
            2.0 * PI
                * if x > 0.0 {
                    v
                } else {
                    0.5 / (1.0 - x * x).max(1e-7).sqrt() - v
                }
        }
        EdgeForm::Cubic => {
            let y = x.abs();
            let c = 1.5708 + (-0.879406 + 0.308609 * y) * y;
            if x > 0.0 {
                c
            } else {
                PI / (1.0 - x * x).max(1e-7).sqrt() - c
            }
        }
    }
}

/// Clip a polygon (world vertices, shading point at the origin) to z ≥ 0
/// (Sutherland–Hodgman); returns the clipped vertices (possibly empty).
pub fn clip_to_horizon(poly: &[V3]) -> Vec<V3> {
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 2);
    for k in 0..n {
        let a = poly[k];
        let b = poly[(k + 1) % n];
        let (ia, ib) = (a.z >= 0.0, b.z >= 0.0);
        if ia {
            out.push(a);
        }
        if ia != ib {
            let t = a.z / (a.z - b.z);
            let mut p = a + (b - a) * t;
            p.z = 0.0;
            out.push(p);
        }
    }
    out
}

/// Form factor of the polygon for the clamped cosine: ∫_P max(0, z)/π dω (two-sided).
pub fn form_factor(poly: &[V3], form: EdgeForm) -> f64 {
    let c = clip_to_horizon(poly);
    if c.len() < 3 {
        return 0.0;
    }
    let p: Vec<V3> = c
        .iter()
        .filter_map(|v| {
            let n = v.norm();
            (n > 0.0 && n.is_finite()).then(|| v / n)
        })
        .collect();
    if p.len() < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for k in 0..p.len() {
        let (a, b) = (p[k], p[(k + 1) % p.len()]);
        let cr = a.cross(&b);
        let s = cr.norm();
        if s <= 1e-300 {
            continue; // repeated or antipodal vertices contribute no area
        }
        let x = a.dot(&b).clamp(-1.0, 1.0);
        let t = theta_over_sin(form, x, s);
        if t.is_finite() {
            sum += t * cr.z;
        }
    }
    let r = (sum / (2.0 * PI)).abs();
    if r.is_finite() {
        r.min(1.0)
    } else {
        0.0
    }
}

/// ∫_P γ_M(ω) dω for the LTC with matrix M: transform the vertices by M⁻¹ and integrate
/// the clamped cosine (seed 000 Eq 1; Heitz et al. 2016 Eq 9).
pub fn ltc_integral(m_inv: &Matrix3<f64>, poly: &[V3], form: EdgeForm) -> f64 {
    let q: Vec<V3> = poly.iter().map(|v| m_inv * v).collect();
    form_factor(&q, form)
}

/// A planar polygon light given by its vertices (world space, shading point at origin).
#[derive(Clone, Debug)]
pub struct Light {
    pub vertices: Vec<V3>,
}

impl Light {
    /// A rectangle centred at `c` with half-extents along unit `u` and `w` (u ⊥ w).
    pub fn rect(c: V3, u: V3, w: V3, hu: f64, hw: f64) -> Light {
        Light {
            vertices: vec![
                c - u * hu - w * hw,
                c + u * hu - w * hw,
                c + u * hu + w * hw,
                c - u * hu + w * hw,
            ],
        }
    }
    fn normal_area(&self) -> (V3, f64) {
        let v = &self.vertices;
        let mut a = V3::zeros();
        for k in 1..v.len().saturating_sub(1) {
            a += (v[k] - v[0]).cross(&(v[k + 1] - v[0]));
        }
        let n = a.norm();
        (if n > 0.0 { a / n } else { V3::z() }, 0.5 * n)
    }
    /// Uniform point on the (convex) polygon by fan triangulation, area-weighted.
    fn sample_point(&self, u: [f64; 3]) -> V3 {
        let v = &self.vertices;
        let areas: Vec<f64> = (1..v.len() - 1)
            .map(|k| 0.5 * (v[k] - v[0]).cross(&(v[k + 1] - v[0])).norm())
            .collect();
        let tot: f64 = areas.iter().sum();
        let mut acc = 0.0;
        let mut k = areas.len() - 1;
        for (i, a) in areas.iter().enumerate() {
            acc += a / tot;
            if u[0] < acc {
                k = i;
                break;
            }
        }
        let (mut s, mut t) = (u[1], u[2]);
        if s + t > 1.0 {
            s = 1.0 - s;
            t = 1.0 - t;
        }
        v[0] + (v[k + 1] - v[0]) * s + (v[k + 2] - v[0]) * t
    }
    /// Does the ray from the origin along unit d hit the polygon? (Convex, planar.)
    fn hit(&self, d: &V3) -> bool {
        let (n, _) = self.normal_area();
        let dn = d.dot(&n);
        if dn.abs() < 1e-300 {
            return false;
        }
        let t = self.vertices[0].dot(&n) / dn;
        if t <= 0.0 {
            return false;
        }
        let p = d * t;
        let v = &self.vertices;
        let mut sign = 0.0;
        for k in 0..v.len() {
            let e = v[(k + 1) % v.len()] - v[k];
            let s = e.cross(&(p - v[k])).dot(&n);
            if sign == 0.0 {
                sign = s.signum();
            } else if s * sign < 0.0 {
                return false;
            }
        }
        true
    }
}

/// Monte Carlo ∫_P f(l) dl of a BRDF (cosine-weighted) over a polygon light, with MIS of
/// light-area sampling and BRDF sampling (balance heuristic). `f` returns (value, pdf of
/// its own sampler); `sample` draws from the BRDF. Returns (estimate, standard error).
pub fn mc_polygon(
    light: &Light,
    f: &dyn Fn(&V3) -> (f64, f64),
    sample: &dyn Fn([f64; 2]) -> Option<V3>,
    n: usize,
    seed: u64,
) -> Result<(f64, f64)> {
    use rand::{Rng, SeedableRng};
    let (nrm, area) = light.normal_area();
    if !(area > 0.0) {
        return Ok((0.0, 0.0));
    }
    if light.vertices.len() < 3 {
        return Err(Error::InvalidArgument(
            "a polygon needs ≥ 3 vertices".into(),
        ));
    }
    let pdf_light = |d: &V3, t: f64| -> f64 {
        let c = d.dot(&nrm).abs();
        if c <= 0.0 {
            0.0
        } else {
            t * t / (area * c)
        }
    };
    let dist = |d: &V3| -> f64 { light.vertices[0].dot(&nrm) / d.dot(&nrm) };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let mut x = 0.0;
        // light sample
        let p = light.sample_point([rng.random(), rng.random(), rng.random()]);
        let t = p.norm();
        if t > 0.0 {
            let d = p / t;
            let (fv, pb) = f(&d);
            let pl = pdf_light(&d, t);
            if pl > 0.0 && fv > 0.0 {
                x += fv / (pl + pb);
            }
        }
        // BRDF sample
        if let Some(d) = sample([rng.random(), rng.random()]) {
            if light.hit(&d) {
                let (fv, pb) = f(&d);
                let pl = pdf_light(&d, dist(&d));
                if fv > 0.0 && pl + pb > 0.0 {
                    x += fv / (pl + pb);
                }
            }
        }
        s += x;
        s2 += x * x;
    }
    let m = s / n as f64;
    let var = (s2 / n as f64 - m * m).max(0.0);
    Ok((m, (var / n as f64).sqrt()))
}

/// The quad lights every table is checked against at a view angle θ (radians): one
/// overhead, one large and one small on the mirror direction, one straddling the horizon.
pub fn check_lights(theta: f64) -> Vec<(&'static str, Light)> {
    let mirror = V3::new(-theta.sin(), 0.0, theta.cos().max(0.05)).normalize();
    let side = V3::y().cross(&mirror).normalize();
    vec![
        (
            "quad 1×1 overhead at 2",
            Light::rect(V3::new(0.0, 0.0, 2.0), V3::x(), V3::y(), 0.5, 0.5),
        ),
        (
            "quad 2×0.5 facing the mirror direction, 2 away",
            Light::rect(mirror * 2.0, side, V3::y(), 1.0, 0.25),
        ),
        (
            "small quad 0.1×0.1 on the mirror direction, 1 away",
            Light::rect(mirror, side, V3::y(), 0.05, 0.05),
        ),
        (
            "quad straddling the horizon",
            Light::rect(V3::new(0.0, 2.0, 0.2), V3::x(), V3::z(), 1.0, 0.5),
        ),
    ]
}

/// One fitted cell × one light: the MC truth of the true lobe with its standard error,
/// and the LTC integral with the exact and the rational edge forms.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PolygonCheck {
    pub light: String,
    pub mc: crate::integrate::Figure,
    pub ltc_exact: f64,
    pub ltc_rational: f64,
}

/// Every light of [`check_lights`] for one cell: truth by [`mc_polygon`] (`mc` samples
/// per technique, seeds 17, 18, …) of the target, against norm × the LTC integral of
/// the cell's M⁻¹.
pub fn check_cell<T: crate::ltc::target::LtcTarget + ?Sized>(
    t: &T,
    m_inv: &Matrix3<f64>,
    norm: f64,
    theta: f64,
    mc: usize,
) -> Result<Vec<PolygonCheck>> {
    check_lights(theta)
        .into_iter()
        .enumerate()
        .map(|(k, (light_name, light))| {
            let (m, se) = mc_polygon(&light, &|l| t.eval(l), &|u| t.sample(u), mc, 17 + k as u64)?;
            Ok(PolygonCheck {
                light: light_name.to_string(),
                mc: crate::integrate::Figure::with_se(m, se),
                ltc_exact: norm * ltc_integral(m_inv, &light.vertices, EdgeForm::Exact),
                ltc_rational: norm * ltc_integral(m_inv, &light.vertices, EdgeForm::Rational),
            })
        })
        .collect()
}

//! Jacobians of the direction maps used in microfacet theory, in closed form, with two
//! independent checks: finite-difference matrices with a step-size study, and a Monte
//! Carlo solid-angle (area) ratio.
//!
//! All maps take a unit direction. Output is either a direction (solid-angle measure) or
//! a point of the plane (area measure, stored as (x, y, 0)). `det` is the closed-form
//! density ratio |d(output measure)/d(input solid angle)|.
//!
//! Charts: the input is parameterised by the gnomonic chart ω(s) = normalize(ω₀ + s₁e₁ +
//! s₂e₂) with an orthonormal tangent basis (e₁, e₂) at ω₀ (its area element is 1 at
//! s = 0), sphere outputs by the gnomonic chart at F(ω₀). A central difference of the
//! chart-to-chart map at s = 0 is therefore the Jacobian matrix in those bases.

use crate::integrate::estimate::Estimate;
use crate::integrate::mc::{mis, Strategy};
use crate::integrate::sphere::frame;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};
use serde::Serialize;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// Where a map's output lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Space {
    Sphere,
    Plane,
}

/// A direction map with a closed-form Jacobian.
pub trait DirMap: Sync {
    fn name(&self) -> &'static str;
    fn out_space(&self) -> Space;
    /// F(ω). Plane outputs are (x, y, 0).
    fn forward(&self, w: &V3) -> V3;
    /// F⁻¹(y), `None` outside the image.
    fn inverse(&self, y: &V3) -> Option<V3>;
    /// Closed-form |det| of the Jacobian (output measure per input solid angle).
    fn det(&self, w: &V3) -> f64;
    /// Closed-form Jacobian matrix together with the input basis it is written in.
    fn matrix(&self, _w: &V3) -> Option<(Matrix2<f64>, (V3, V3))> {
        None
    }
    /// Input tangent basis used when no closed-form matrix fixes one.
    fn basis(&self, w: &V3) -> (V3, V3) {
        self.matrix(w).map(|m| m.1).unwrap_or_else(|| frame(w))
    }
}

/// (e_θ, e_φ) at a direction with 0 < θ < π: the basis of seed 003 App. B (ψ_x along the
/// great circle through h and n, ψ_y along the one through h and n×h/|n×h|).
pub fn polar_basis(h: &V3) -> (V3, V3) {
    let rho = (h.x * h.x + h.y * h.y).sqrt();
    let (c, s) = if rho > 0.0 {
        (h.x / rho, h.y / rho)
    } else {
        (1.0, 0.0)
    };
    (V3::new(h.z * c, h.z * s, -rho), V3::new(-s, c, 0.0))
}

fn slope_of(w: &V3) -> V3 {
    V3::new(-w.x / w.z, -w.y / w.z, 0.0)
}
fn from_slope(y: &V3) -> Option<V3> {
    let v = V3::new(-y.x, -y.y, 1.0);
    let n = v.norm();
    n.is_finite().then(|| v / n)
}

/// Normal → slope, x̃ = −m_xy/m_z; |J| = 1/|m_z|³ (seed 001 Eq 1).
pub struct NormalToSlope;
impl DirMap for NormalToSlope {
    fn name(&self) -> &'static str {
        "normal→slope (seed 001 Eq 1)"
    }
    fn out_space(&self) -> Space {
        Space::Plane
    }
    fn forward(&self, w: &V3) -> V3 {
        slope_of(w)
    }
    fn inverse(&self, y: &V3) -> Option<V3> {
        from_slope(y)
    }
    fn det(&self, w: &V3) -> f64 {
        1.0 / w.z.abs().powi(3)
    }
}

/// Spherical → slope J_{o→∥} of seed 003 Eq 5 (matrix) and Eq 6 (det 1/h_z³): the same
/// map as [`NormalToSlope`] (slope convention −h_xy/h_z, the sign that makes Eq 5's
/// leading minus correct), with the closed-form matrix in the basis (e_θ, e_φ).
pub struct HalfToSlope;
impl DirMap for HalfToSlope {
    fn name(&self) -> &'static str {
        "spherical→slope J∥ (seed 003 Eq 5–6)"
    }
    fn out_space(&self) -> Space {
        NormalToSlope.out_space()
    }
    fn forward(&self, w: &V3) -> V3 {
        NormalToSlope.forward(w)
    }
    fn inverse(&self, y: &V3) -> Option<V3> {
        NormalToSlope.inverse(y)
    }
    fn det(&self, w: &V3) -> f64 {
        NormalToSlope.det(w)
    }
    fn matrix(&self, h: &V3) -> Option<(Matrix2<f64>, (V3, V3))> {
        let s = (1.0 - h.z * h.z).max(0.0).sqrt();
        let rho = (h.x * h.x + h.y * h.y).sqrt();
        if rho == 0.0 || s == 0.0 {
            return None;
        }
        let k = -1.0 / (h.z * h.z * rho);
        let m = Matrix2::new(h.x, -h.y * h.z, h.y, h.x * h.z) * k;
        Some((m, polar_basis(h)))
    }
}

/// Spherical → projected unit disk J_{o→⊥} (seed 003 Eq 8, det h_z Eq 9).
pub struct ProjectedDisk;
impl DirMap for ProjectedDisk {
    fn name(&self) -> &'static str {
        "spherical→projected disk J⊥ (seed 003 Eq 8–9)"
    }
    fn out_space(&self) -> Space {
        Space::Plane
    }
    fn forward(&self, w: &V3) -> V3 {
        V3::new(w.x, w.y, 0.0)
    }
    fn inverse(&self, y: &V3) -> Option<V3> {
        let r2 = y.x * y.x + y.y * y.y;
        (r2 < 1.0).then(|| V3::new(y.x, y.y, (1.0 - r2).sqrt()))
    }
    fn det(&self, w: &V3) -> f64 {
        w.z.abs()
    }
    fn matrix(&self, h: &V3) -> Option<(Matrix2<f64>, (V3, V3))> {
        let rho = (h.x * h.x + h.y * h.y).sqrt();
        if rho == 0.0 {
            return None;
        }
        let m = Matrix2::new(h.x * h.z, -h.y, h.y * h.z, h.x) / rho;
        Some((m, polar_basis(h)))
    }
}

/// Reflection about the micronormal, n ↦ ω_i = 2(n·o)n − o; |J| = 4|n·o| (seed 001 Eq 3).
pub struct Reflection {
    pub o: V3,
}
impl DirMap for Reflection {
    fn name(&self) -> &'static str {
        "reflection n→ω_i (seed 001 Eq 3)"
    }
    fn out_space(&self) -> Space {
        Space::Sphere
    }
    fn forward(&self, n: &V3) -> V3 {
        n * (2.0 * n.dot(&self.o)) - self.o
    }
    fn inverse(&self, wi: &V3) -> Option<V3> {
        let h = wi + self.o;
        let l = h.norm();
        (l > 0.0).then(|| h / l)
    }
    fn det(&self, n: &V3) -> f64 {
        4.0 * n.dot(&self.o).abs()
    }
}

/// Half-vector map ω_i ↦ h = normalize(ω_i + o); |J| = 1/(4|o·h|) (Walter et al. 2007).
pub struct HalfVector {
    pub o: V3,
}
impl DirMap for HalfVector {
    fn name(&self) -> &'static str {
        "half-vector ω_i→h"
    }
    fn out_space(&self) -> Space {
        Space::Sphere
    }
    fn forward(&self, wi: &V3) -> V3 {
        (wi + self.o).normalize()
    }
    fn inverse(&self, h: &V3) -> Option<V3> {
        Some(h * (2.0 * h.dot(&self.o)) - self.o)
    }
    fn det(&self, wi: &V3) -> f64 {
        let h = self.forward(wi);
        1.0 / (4.0 * self.o.dot(&h).abs())
    }
}

/// LTC map ω ↦ ω_o = normalize(M⁻¹ω); |J| = |det M⁻¹|/‖M⁻¹ω‖³ (Heitz et al. 2016;
/// seed 000 Eq 1).
pub struct Ltc {
    pub m: Matrix3<f64>,
    pub m_inv: Matrix3<f64>,
    /// |det M⁻¹|, computed once: every density needs it.
    det_inv_abs: f64,
}
impl Ltc {
    /// `None` if M is singular.
    pub fn new(m: Matrix3<f64>) -> Option<Self> {
        let m_inv = m.try_inverse()?;
        Some(Ltc {
            m,
            m_inv,
            det_inv_abs: m_inv.determinant().abs(),
        })
    }

    /// |det M⁻¹|, as `det` uses it.
    pub fn det_inv_abs(&self) -> f64 {
        self.det_inv_abs
    }

    /// The clamped cosine's density at ω's image, max(0, ω_o,z)/π, times |J| at ω: the
    /// LTC's density (seed 000 Eq 1). The same operations as `forward` and `det` (M⁻¹ω and
    /// its norm computed once, only the z of the normalised image), so the same bits.
    pub fn density(&self, w: &V3) -> f64 {
        let v = self.m_inv * w;
        let n = v.norm();
        let z = v.z / n;
        // both sides computed, then chosen: no branch on a sign that varies from sample to
        // sample (the loops that call this overlap their samples)
        let d = z / std::f64::consts::PI * (self.det_inv_abs / n.powi(3));
        if z <= 0.0 {
            0.0
        } else {
            d
        }
    }
}
impl DirMap for Ltc {
    fn name(&self) -> &'static str {
        "LTC ω→ω_o"
    }
    fn out_space(&self) -> Space {
        Space::Sphere
    }
    fn forward(&self, w: &V3) -> V3 {
        (self.m_inv * w).normalize()
    }
    fn inverse(&self, wo: &V3) -> Option<V3> {
        let v = self.m * wo;
        let n = v.norm();
        (n > 0.0).then(|| v / n)
    }
    fn det(&self, w: &V3) -> f64 {
        self.det_inv_abs / (self.m_inv * w).norm().powi(3)
    }
}

fn in_chart(w: &V3, b: &(V3, V3), s: Vector2<f64>) -> V3 {
    (w + b.0 * s.x + b.1 * s.y).normalize()
}

struct OutChart {
    space: Space,
    c: V3,
    t: (V3, V3),
}
impl OutChart {
    fn new<M: DirMap + ?Sized>(map: &M, w: &V3) -> Self {
        let c = map.forward(w);
        OutChart {
            space: map.out_space(),
            c,
            t: if map.out_space() == Space::Sphere {
                frame(&c)
            } else {
                (V3::x(), V3::y())
            },
        }
    }
    fn coords(&self, y: &V3) -> Vector2<f64> {
        match self.space {
            Space::Plane => Vector2::new(y.x, y.y),
            Space::Sphere => {
                let d = y.dot(&self.c);
                Vector2::new(y.dot(&self.t.0) / d, y.dot(&self.t.1) / d)
            }
        }
    }
    fn point(&self, u: &Vector2<f64>) -> V3 {
        match self.space {
            Space::Plane => V3::new(u.x, u.y, 0.0),
            Space::Sphere => (self.c + self.t.0 * u.x + self.t.1 * u.y).normalize(),
        }
    }
    /// Output-measure area element of the chart at u.
    fn area_element(&self, u: &Vector2<f64>) -> f64 {
        match self.space {
            Space::Plane => 1.0,
            Space::Sphere => (1.0 + u.norm_squared()).powf(-1.5),
        }
    }
}

/// Central-difference Jacobian matrix of the chart-to-chart map at ω with step h.
pub fn fd_matrix<M: DirMap + ?Sized>(map: &M, w: &V3, basis: &(V3, V3), h: f64) -> Matrix2<f64> {
    let oc = OutChart::new(map, w);
    let g = |s: Vector2<f64>| oc.coords(&map.forward(&in_chart(w, basis, s)));
    let c0 = (g(Vector2::new(h, 0.0)) - g(Vector2::new(-h, 0.0))) / (2.0 * h);
    let c1 = (g(Vector2::new(0.0, h)) - g(Vector2::new(0.0, -h))) / (2.0 * h);
    Matrix2::from_columns(&[c0, c1])
}

/// One row of a step-size study.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct StepRow {
    pub h: f64,
    /// Relative error of the FD matrix (Frobenius) when a closed-form matrix exists,
    /// else of its determinant.
    pub rel_error: f64,
}

/// Result of a finite-difference step-size study at one point.
#[derive(Clone, Debug, Serialize)]
pub struct StepStudy {
    pub rows: Vec<StepRow>,
    pub best_h: f64,
    pub best_error: f64,
    /// Observed order from the two largest steps in the truncation regime (≈ 2 for
    /// central differences), NaN when the errors there are at rounding level.
    pub observed_order: f64,
    pub matrix_checked: bool,
}

/// FD study over h = 10^(−1), 10^(−1.5), …, 10^(−10).
pub fn step_study<M: DirMap + ?Sized>(map: &M, w: &V3) -> StepStudy {
    let closed = map.matrix(w);
    let basis = map.basis(w);
    let det = map.det(w);
    let rows: Vec<StepRow> = (2..=20)
        .map(|k| {
            let h = 10f64.powf(-(k as f64) / 2.0);
            let j = fd_matrix(map, w, &basis, h);
            let rel_error = match &closed {
                Some((m, _)) => (j - m).norm() / m.norm(),
                None => (j.determinant().abs() - det).abs() / det,
            };
            StepRow { h, rel_error }
        })
        .collect();
    let best = rows
        .iter()
        .filter(|r| r.rel_error.is_finite())
        .min_by(|a, b| a.rel_error.total_cmp(&b.rel_error))
        .copied()
        .unwrap_or(StepRow {
            h: f64::NAN,
            rel_error: f64::INFINITY,
        });
    // order: first pair (h, h/10) in the asymptotic truncation regime — error already
    // below 1e-2 and both errors far above the rounding floor (the best error)
    let mut order = f64::NAN;
    for i in 0..rows.len().saturating_sub(2) {
        let (a, b) = (rows[i], rows[i + 2]);
        if a.rel_error < 1e-2
            && a.rel_error > 10.0 * b.rel_error
            && a.rel_error > 1e4 * best.rel_error
            && b.rel_error > 1e2 * best.rel_error
        {
            order = (a.rel_error / b.rel_error).log10() / (a.h / b.h).log10();
            break;
        }
    }
    StepStudy {
        rows,
        best_h: best.h,
        best_error: best.rel_error,
        observed_order: order,
        matrix_checked: closed.is_some(),
    }
}

/// Monte Carlo solid-angle ratio: the image of a cap of angular radius r around ω has
/// output measure ≈ |J|·Ω_cap. Estimated by hit-or-miss over a parallelogram in the
/// output chart (shaped by an FD matrix, which only sets the proposal, not the answer),
/// mapping proposals back with F⁻¹. The bias is O(r²) (|J| varies over the cap).
#[derive(Clone, Debug, Serialize)]
pub struct McJacobian {
    pub value: f64,
    pub std_error: f64,
    pub samples: u64,
    /// Hits in the outer 10 % of the proposal: must be 0 (else the proposal clipped the image).
    pub boundary_mass: f64,
}

struct Parallelogram {
    l: Matrix2<f64>,
    c: f64,
}
impl Strategy<Vector2<f64>> for Parallelogram {
    fn sample(&self, u: [f64; 2]) -> Option<Vector2<f64>> {
        Some(self.l * Vector2::new(self.c * (2.0 * u[0] - 1.0), self.c * (2.0 * u[1] - 1.0)))
    }
    fn pdf(&self, _: &Vector2<f64>) -> f64 {
        1.0 / (self.l.determinant().abs() * 4.0 * self.c * self.c)
    }
}

pub fn mc_jacobian<M: DirMap + ?Sized>(
    map: &M,
    w: &V3,
    radius: f64,
    samples: u64,
    seed: u64,
) -> McJacobian {
    let basis = map.basis(w);
    let oc = OutChart::new(map, w);
    let y0 = oc.coords(&map.forward(w));
    let l = fd_matrix(map, w, &basis, radius * 1e-2) * radius;
    let prop = Parallelogram { l, c: 1.5 };
    let l_inv = l.try_inverse().unwrap_or_else(Matrix2::identity);
    let chord = 2.0 * (0.5 * radius).sin();
    let hit = |u: &Vector2<f64>| -> Option<f64> {
        let y = oc.point(&(y0 + u));
        let back = map.inverse(&y)?;
        ((back - w).norm() < chord).then(|| oc.area_element(&(y0 + u)))
    };
    let f = |u: &Vector2<f64>| hit(u).unwrap_or(0.0);
    let ring = |u: &Vector2<f64>| {
        let s = l_inv * u;
        if s.x.abs().max(s.y.abs()) > 0.9 * prop.c {
            hit(u).unwrap_or(0.0)
        } else {
            0.0
        }
    };
    let strategies: [&dyn Strategy<Vector2<f64>>; 1] = [&prop];
    let e: Estimate = mis(&f, &strategies, samples, seed);
    let b: Estimate = mis(&ring, &strategies, samples / 4, seed ^ 0x5eed);
    let cap = 4.0 * PI * (0.5 * radius).sin().powi(2);
    McJacobian {
        value: e.value / cap,
        std_error: e.error / cap,
        samples,
        boundary_mass: b.value,
    }
}

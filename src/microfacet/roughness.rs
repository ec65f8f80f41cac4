//! The 2×2 roughness matrix A (Tokuyoshi 2017 App. A Eq 17–18; A = 2 × slope covariance
//! for Beckmann, seed 003 §2 Eq 3). Isotropic α: A = α²I; axis-aligned (αx, αy):
//! A = diag(αx², αy²); general: any symmetric positive-definite A.

use crate::error::{finite, Error, Result};
use nalgebra::{Matrix2, Vector2};

/// Smallest and largest supported roughness α: α⁴ (the determinant of A = α²I) stays a
/// normal f64, so every derived quantity (A⁻¹, √det A, D's normalisation) is finite.
pub const ALPHA_MIN: f64 = 1e-75;
pub const ALPHA_MAX: f64 = 1e75;

fn check_alpha(v: f64) -> Result<()> {
    if v.is_finite() && (ALPHA_MIN..=ALPHA_MAX).contains(&v) {
        Ok(())
    } else {
        Err(Error::InvalidRoughness(v))
    }
}

/// A validated symmetric positive-definite roughness matrix with cached derived values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roughness {
    a: Matrix2<f64>,
    inv: Matrix2<f64>,
    sqrt_det: f64,
    /// Symmetric square root S (S·S = A): the slope-space stretch of the unit surface.
    sqrt_a: Matrix2<f64>,
}

impl Roughness {
    /// Isotropic roughness α > 0.
    pub fn iso(alpha: f64) -> Result<Self> {
        Self::aniso(alpha, alpha)
    }

    /// Axis-aligned anisotropic roughness (αx, αy), both > 0.
    pub fn aniso(ax: f64, ay: f64) -> Result<Self> {
        for v in [ax, ay] {
            check_alpha(v)?;
        }
        Self::matrix(Matrix2::new(ax * ax, 0.0, 0.0, ay * ay))
    }

    /// Roughness with principal values (α1, α2) along the axis at angle `phi` (radians).
    pub fn rotated(a1: f64, a2: f64, phi: f64) -> Result<Self> {
        for v in [a1, a2] {
            check_alpha(v)?;
        }
        finite("rotation angle", phi)?;
        let (s, c) = phi.sin_cos();
        let r = Matrix2::new(c, -s, s, c);
        let d = Matrix2::new(a1 * a1, 0.0, 0.0, a2 * a2);
        let mut m = r * d * r.transpose();
        let off = 0.5 * (m[(0, 1)] + m[(1, 0)]);
        m[(0, 1)] = off;
        m[(1, 0)] = off;
        Self::matrix(m)
    }

    /// General SPD matrix. Rejects NaN/Inf, asymmetry beyond 1e-12 relative, and
    /// non-positive eigenvalues (`NotSpd`), and diagonal entries outside
    /// [ALPHA_MIN², ALPHA_MAX²] (`InvalidRoughness`, reporting √entry), with a typed error
    /// and a one-line message.
    pub fn matrix(a: Matrix2<f64>) -> Result<Self> {
        for v in a.iter() {
            finite("roughness matrix entry", *v)?;
        }
        let scale = a.abs().max();
        if (a[(0, 1)] - a[(1, 0)]).abs() > 1e-12 * scale {
            return Err(Error::NotSpd(format!(
                "not symmetric: A12 = {:e}, A21 = {:e}",
                a[(0, 1)],
                a[(1, 0)]
            )));
        }
        let b = a[(0, 1)];
        let (p, q) = (a[(0, 0)], a[(1, 1)]);
        // a positive diagonal out of range is a roughness out of range, not a shape problem
        for d in [p, q] {
            if d > 0.0 && !(ALPHA_MIN * ALPHA_MIN..=ALPHA_MAX * ALPHA_MAX).contains(&d) {
                return Err(Error::InvalidRoughness(d.sqrt()));
            }
        }
        let det = p * q - b * b;
        if !(p > 0.0 && q > 0.0 && det > 0.0) {
            return Err(Error::NotSpd(format!(
                "A = [[{p:e}, {b:e}], [{b:e}, {q:e}]] has det {det:e} (needs A11 > 0, A22 > 0, det > 0)"
            )));
        }
        let inv = Matrix2::new(q / det, -b / det, -b / det, p / det);
        // symmetric square root of a 2×2 SPD matrix: (A + √det·I)/√(tr A + 2√det)
        let sd = det.sqrt();
        let t = (p + q + 2.0 * sd).sqrt();
        let sqrt_a = Matrix2::new((p + sd) / t, b / t, b / t, (q + sd) / t);
        Ok(Roughness {
            a: Matrix2::new(p, b, b, q),
            inv,
            sqrt_det: sd,
            sqrt_a,
        })
    }

    pub fn a(&self) -> &Matrix2<f64> {
        &self.a
    }
    pub fn inv(&self) -> &Matrix2<f64> {
        &self.inv
    }
    /// √det A (= αx·αy for axis-aligned).
    pub fn sqrt_det(&self) -> f64 {
        self.sqrt_det
    }
    pub fn sqrt_a(&self) -> &Matrix2<f64> {
        &self.sqrt_a
    }
    /// Eigenvalues of A (ascending).
    pub fn eigenvalues(&self) -> (f64, f64) {
        let (lo, hi, _) = crate::linalg::sym2_eigen(&self.a);
        (lo, hi)
    }
    /// Smallest principal roughness √λ_min: the lobe width used to place quadrature nodes.
    pub fn min_alpha(&self) -> f64 {
        self.eigenvalues().0.sqrt()
    }
    /// vᵀ A v.
    pub fn quad(&self, v: &Vector2<f64>) -> f64 {
        v.dot(&(self.a * v))
    }
    /// vᵀ A⁻¹ v.
    pub fn quad_inv(&self, v: &Vector2<f64>) -> f64 {
        v.dot(&(self.inv * v))
    }
}

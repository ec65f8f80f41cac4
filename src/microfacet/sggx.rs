//! The SGGX distribution (Heitz, Dupuy, Crassin & Dachsbacher 2015): the modern form of
//! Neyret's ellipsoid normal distribution (seed 004 §3.2.1 Eq 18, f_A(η) ∝ (ηᵀQ⁻¹η)⁻²
//! for the ellipsoid pᵀQp = 1). For a symmetric positive definite 3×3 matrix S:
//! - D(m) = 1/(π √|S| (mᵀS⁻¹m)²) on the whole sphere (D(−m) = D(m));
//! - the projected area σ(ω) = ∫ ⟨ω·m⟩ D(m) dm = √(ωᵀSω), ⟨·⟩ the clamped dot product
//!   (proofs/sggx-projected-area.md);
//! - the visible normals D_ω(m) = ⟨ω·m⟩ D(m)/σ(ω), sampled exactly by mapping a
//!   cosine-distributed point of the unit disk through the ellipsoid's linear map
//!   (Heitz et al. 2015 §4 and their supplemental listing).
//!
//! Six parameters per texel (the entries of S); S is linear in the second moments of the
//! ellipsoid's projected-area distribution, which is why it can be MIP-mapped linearly.

use crate::error::{Error, Result};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// An SGGX microflake distribution.
#[derive(Clone, Copy, Debug)]
pub struct Sggx {
    s: Matrix3<f64>,
    inv: Matrix3<f64>,
    sqrt_det: f64,
}

impl Sggx {
    /// From S (typed error when S has a non-finite entry, is not symmetric to 1e-12 of
    /// its largest entry, or is not positive definite).
    pub fn new(s: Matrix3<f64>) -> Result<Sggx> {
        if s.iter().any(|v| !v.is_finite()) {
            return Err(Error::NotSpd("SGGX matrix has a non-finite entry".into()));
        }
        let scale = s.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if !(scale > 0.0) || (s - s.transpose()).iter().any(|v| v.abs() > 1e-12 * scale) {
            return Err(Error::NotSpd(format!(
                "SGGX matrix is not symmetric: {s:?}"
            )));
        }
        let det = s.determinant();
        let chol = nalgebra::Cholesky::new(s);
        match (chol, det > 0.0) {
            (Some(c), true) => Ok(Sggx {
                s,
                inv: c.inverse(),
                sqrt_det: det.sqrt(),
            }),
            _ => Err(Error::NotSpd(format!(
                "SGGX matrix is not positive definite: {s:?}"
            ))),
        }
    }

    /// S = Σ_k σ_k² a_k a_kᵀ for orthonormal axes a_k (columns of `axes`) and the
    /// projected areas σ_k along them.
    pub fn from_axes(axes: &Matrix3<f64>, sigma: [f64; 3]) -> Result<Sggx> {
        let d = Matrix3::from_diagonal(&V3::new(
            sigma[0] * sigma[0],
            sigma[1] * sigma[1],
            sigma[2] * sigma[2],
        ));
        Sggx::new(axes * d * axes.transpose())
    }

    pub fn matrix(&self) -> &Matrix3<f64> {
        &self.s
    }

    /// D(m) for a unit m.
    pub fn d(&self, m: &V3) -> f64 {
        let q = m.dot(&(self.inv * m));
        1.0 / (PI * self.sqrt_det * q * q)
    }

    /// σ(ω) = √(ωᵀSω) for a unit ω.
    pub fn projected_area(&self, w: &V3) -> f64 {
        w.dot(&(self.s * w)).max(0.0).sqrt()
    }

    /// Density of the visible normals seen from ω: ⟨ω·m⟩ D(m)/σ(ω).
    pub fn vndf_pdf(&self, w: &V3, m: &V3) -> f64 {
        let c = w.dot(m);
        if c <= 0.0 {
            return 0.0;
        }
        c * self.d(m) / self.projected_area(w)
    }

    /// A visible normal seen from the unit ω for uniforms u: a cosine-distributed point
    /// (x, y, z) of the hemisphere around ω, mapped by the lower-triangular factor of S in
    /// the basis (k, j, i = ω) and normalised.
    pub fn sample_vndf(&self, w: &V3, u: [f64; 2]) -> V3 {
        let r = u[0].sqrt();
        let phi = 2.0 * PI * u[1];
        let (x, y) = (r * phi.cos(), r * phi.sin());
        let z = (1.0 - x * x - y * y).max(0.0).sqrt();
        let wi = w.normalize();
        let helper = if wi.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let wk = helper.cross(&wi).normalize();
        let wj = wi.cross(&wk);
        let q = |a: &V3, b: &V3| a.dot(&(self.s * b));
        let (skk, sjj, sii) = (q(&wk, &wk), q(&wj, &wj), q(&wi, &wi));
        let (skj, ski, sji) = (q(&wk, &wj), q(&wk, &wi), q(&wj, &wi));
        let det = (skk * sjj * sii - skj * skj * sii - ski * ski * sjj - sji * sji * skk
            + 2.0 * skj * ski * sji)
            .abs();
        let inv_sqrt_sii = 1.0 / sii.sqrt();
        let t = (sjj * sii - sji * sji).max(0.0).sqrt();
        let mk = V3::new(det.sqrt() / t, 0.0, 0.0);
        let mj = V3::new(
            -inv_sqrt_sii * (ski * sji - skj * sii) / t,
            inv_sqrt_sii * t,
            0.0,
        );
        let mi = V3::new(inv_sqrt_sii * ski, inv_sqrt_sii * sji, inv_sqrt_sii * sii);
        let m = (mk * x + mj * y + mi * z).normalize();
        wk * m.x + wj * m.y + wi * m.z
    }
}

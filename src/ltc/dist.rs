//! Linearly transformed cosines (Heitz et al. 2016; seed 000 Eq 1):
//! γ(x) = γ_o(M⁻¹x/‖M⁻¹x‖)·|M⁻¹|/‖M⁻¹x‖³ with γ_o the clamped cosine max(0, z)/π.
//! The Jacobian is the one proved in proofs/jacobian-ltc.md ([`crate::jacobian::Ltc`]).

use crate::error::{Error, Result};
use crate::integrate::mc::{CosineHemisphere, Strategy};
use crate::jacobian::{DirMap, Ltc};
use crate::lanes::{map, Dirs, Lanes, LANES};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// An LTC distribution on the sphere.
pub struct LtcDist {
    map: Ltc,
}

impl LtcDist {
    /// General invertible M (typed error if singular or non-finite).
    pub fn new(m: Matrix3<f64>) -> Result<Self> {
        if m.iter().any(|v| !v.is_finite()) {
            return Err(Error::InvalidArgument(
                "LTC matrix has a non-finite entry".into(),
            ));
        }
        let map =
            Ltc::new(m).ok_or_else(|| Error::InvalidArgument("LTC matrix is singular".into()))?;
        Ok(LtcDist { map })
    }

    /// The isotropic scaling LTC M = diag(α, α, 1) (seed 000 Eq 2).
    pub fn isotropic(alpha: f64) -> Result<Self> {
        if !(alpha.is_finite() && alpha > 0.0) {
            return Err(Error::InvalidRoughness(alpha));
        }
        Self::new(Matrix3::from_diagonal(&Vector3::new(alpha, alpha, 1.0)))
    }

    /// Density γ(x) w.r.t. solid angle (seed 000 Eq 1).
    pub fn eval(&self, x: &Vector3<f64>) -> f64 {
        self.map.density(x)
    }

    /// [`Self::eval`] as the map's `forward` and `det` compute it, each in full: the
    /// reference the shared-work form is checked against, bit for bit.
    pub fn eval_reference(&self, x: &Vector3<f64>) -> f64 {
        let xo = self.map.forward(x);
        if xo.z <= 0.0 {
            return 0.0;
        }
        xo.z / PI * self.map.det(x)
    }

    /// The sample of this LTC that the clamped-cosine sample `c` maps to (what
    /// [`Strategy::sample`] returns for the uniforms `c` was drawn from): a fitter draws
    /// its cosine samples once and maps them through every trial matrix.
    pub fn from_cosine(&self, c: &Vector3<f64>) -> Option<Vector3<f64>> {
        self.map.inverse(c)
    }

    /// [`Self::from_cosine`] of four clamped-cosine samples (`ltc::lanes`, the same bits
    /// per lane): the images, and whether each exists (a zero image has none).
    pub fn from_cosine_lanes(&self, c: &Dirs) -> (Dirs, [bool; LANES]) {
        let v = c.times(&self.map.m);
        let n = v.norm();
        (v.over(&n), std::array::from_fn(|i| n[i] > 0.0))
    }

    /// [`Self::eval`] of four directions (`ltc::lanes`, the same bits per lane).
    pub fn eval_lanes(&self, x: &Dirs) -> Lanes {
        let v = x.times(&self.map.m_inv);
        let n = v.norm();
        let z = map(|i| v.z[i] / n[i]);
        let det = self.map.det_inv_abs();
        let j = map(|i| det / n[i].powi(3));
        map(|i| if z[i] <= 0.0 { 0.0 } else { z[i] / PI * j[i] })
    }

    pub fn matrix(&self) -> &Matrix3<f64> {
        &self.map.m
    }
}

impl Strategy<Vector3<f64>> for LtcDist {
    /// Cosine sample, transformed by M and renormalised.
    fn sample(&self, u: [f64; 2]) -> Option<Vector3<f64>> {
        self.from_cosine(&CosineHemisphere.sample(u)?)
    }
    fn pdf(&self, x: &Vector3<f64>) -> f64 {
        self.eval(x)
    }
}

//! Microsurfaces: Beckmann or GGX slope distributions with a roughness matrix A and an
//! optional mean slope, giving P22, D, Λ, G1 and G2 (f64 reference forms).
//!
//! Conventions (seed 001 §1.1): tangent space with macro-normal ω_g = +z; the slope of a
//! normal m is x̃ = (−m_x/m_z, −m_y/m_z); D(m) = P22(x̃)/m_z⁴ (seed 001 Eq 2). Directions
//! are unit vectors in tangent space (callers normalise; see [`unit`]).
//!
//! Domain and clamps (documented, never NaN for finite unit inputs):
//! - D(m) = 0 for m_z ≤ 0 (χ⁺ in seed 003 Eq 15, 17).
//! - Λ(o) = +∞ and G1 = 0 when o is at or below the mean surface (ν ≤ 0, i.e.
//!   o_z ≤ x̄·o_xy; for centred surfaces o_z ≤ 0). This is the reflection convention; the
//!   |o_z| of seed 003 Eq 16/18 (for transmission) is not used.

use super::lambda;
use super::roughness::Roughness;
use crate::error::{finite, Error, Result};
use nalgebra::{Vector2, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The slope distribution family.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NdfKind {
    /// Gaussian slopes with covariance A/2 (seed 001 §1.2).
    Beckmann,
    /// Trowbridge–Reitz / GGX: P22 = 1/(π√det A (1 + x̃ᵀA⁻¹x̃)²) (seed 003 Eq 17).
    Ggx,
}

/// Which Λ a surface uses for masking.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LambdaKind {
    /// The exact Smith Λ of the slope distribution.
    Exact,
    /// Walter et al.'s rational approximation as printed (Beckmann only).
    WalterPrinted,
    /// The shader listing of seed 001 §3.2 (ν clamped to [0.001, 1.599]).
    WalterListing,
}

/// A microsurface: family, roughness matrix, mean slope and masking model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microsurface {
    pub kind: NdfKind,
    pub rough: Roughness,
    /// Mean slope (E[x̃], E[ỹ]) (LEAN/LEADR non-centred distributions).
    pub mean: Vector2<f64>,
    pub lambda_kind: LambdaKind,
}

/// Normalise a direction, rejecting NaN/Inf/zero with a typed error.
pub fn unit(v: Vector3<f64>, what: &'static str) -> Result<Vector3<f64>> {
    let n = v.norm();
    if !(n.is_finite() && n > 0.0) {
        return Err(Error::DegenerateDirection { what });
    }
    Ok(v / n)
}

impl Microsurface {
    pub fn new(kind: NdfKind, rough: Roughness) -> Self {
        Microsurface {
            kind,
            rough,
            mean: Vector2::zeros(),
            lambda_kind: LambdaKind::Exact,
        }
    }
    pub fn ggx(rough: Roughness) -> Self {
        Self::new(NdfKind::Ggx, rough)
    }
    pub fn beckmann(rough: Roughness) -> Self {
        Self::new(NdfKind::Beckmann, rough)
    }
    /// Shift the slope distribution to a non-zero mean (finite components required).
    pub fn with_mean(mut self, mean: Vector2<f64>) -> Result<Self> {
        finite("mean slope x", mean.x)?;
        finite("mean slope y", mean.y)?;
        self.mean = mean;
        Ok(self)
    }
    /// Use an approximate Λ (only defined for Beckmann).
    pub fn with_lambda(mut self, lk: LambdaKind) -> Result<Self> {
        if lk != LambdaKind::Exact && self.kind != NdfKind::Beckmann {
            return Err(Error::InvalidArgument(
                "Walter's Λ approximation is defined for Beckmann only".into(),
            ));
        }
        self.lambda_kind = lk;
        Ok(self)
    }

    /// Slope density P22(x̃) (seed 001 §3.1 listing; seed 003 Eq 17 in slope form).
    pub fn p22(&self, slope: &Vector2<f64>) -> f64 {
        let d = slope - self.mean;
        let q = self.rough.quad_inv(&d);
        let norm = 1.0 / (PI * self.rough.sqrt_det());
        match self.kind {
            NdfKind::Beckmann => norm * (-q).exp(),
            NdfKind::Ggx => norm / ((1.0 + q) * (1.0 + q)),
        }
    }

    /// NDF D(m) = P22(x̃(m))/m_z⁴, evaluated without dividing by m_z where possible:
    /// with w = (m_xy + x̄ m_z)ᵀA⁻¹(m_xy + x̄ m_z), (x̃ − x̄)ᵀA⁻¹(x̃ − x̄) = w/m_z², so
    /// GGX: D = 1/(π√det A (w + m_z²)²) — stable as m_z → 0 and for α = 1e-4.
    pub fn d(&self, m: &Vector3<f64>) -> f64 {
        self.d_with(m, self.d_norm())
    }

    /// D's constant factor 1/(π √det A), which [`Self::d`] computes at every call: a
    /// caller evaluating one surface many times computes it once for [`Self::d_with`].
    pub fn d_norm(&self) -> f64 {
        1.0 / (PI * self.rough.sqrt_det())
    }

    /// [`Self::d`] given `norm` = [`Self::d_norm`]: the same operations, the same bits.
    pub fn d_with(&self, m: &Vector3<f64>, norm: f64) -> f64 {
        let mz = m.z;
        if !(mz > 0.0) {
            return 0.0;
        }
        let v = Vector2::new(m.x + self.mean.x * mz, m.y + self.mean.y * mz);
        let w = self.rough.quad_inv(&v);
        match self.kind {
            NdfKind::Ggx => {
                let s = w + mz * mz;
                norm / (s * s)
            }
            NdfKind::Beckmann => {
                let mz2 = mz * mz;
                let e = (-w / mz2).exp();
                if e == 0.0 {
                    return 0.0;
                }
                norm * e / (mz2 * mz2)
            }
        }
    }

    /// Projected area of the mean surface seen from o, (ω_n̄·o)/(ω_n̄·ω_g) = o_z − x̄·o_xy
    /// (seed 001 Eq 4–5).
    pub fn projected_area(&self, o: &Vector3<f64>) -> f64 {
        o.z - self.mean.x * o.x - self.mean.y * o.y
    }

    /// Normalised slope ν = (cot θ − μ(φ))/α(φ) = (o_z − x̄·o_xy)/√(o_xyᵀ A o_xy)
    /// (seed 001 §3.2 with α(φ)² = 2σ²(φ); seed 003 Eq 18 for GGX).
    ///
    /// Convention: ν is signed everywhere. It is negative below the mean surface (where
    /// o_z − x̄·o_xy < 0), +∞ along the mean normal from above and −∞ along it from below;
    /// 0 only for directions in the mean surface. Λ is +∞ wherever ν ≤ 0.
    pub fn nu(&self, o: &Vector3<f64>) -> f64 {
        let num = self.projected_area(o);
        let den = self.rough.quad(&Vector2::new(o.x, o.y)).sqrt();
        if den == 0.0 {
            return if num > 0.0 {
                f64::INFINITY
            } else if num < 0.0 {
                f64::NEG_INFINITY
            } else {
                0.0
            };
        }
        num / den
    }

    /// Smith Λ(o); +∞ at or below the mean surface (documented clamp, G1 = 0 there).
    pub fn lambda(&self, o: &Vector3<f64>) -> f64 {
        let nu = self.nu(o);
        if !(nu > 0.0) {
            return f64::INFINITY;
        }
        match (self.kind, self.lambda_kind) {
            (NdfKind::Ggx, _) => lambda::ggx(nu),
            (NdfKind::Beckmann, LambdaKind::Exact) => lambda::beckmann(nu),
            (NdfKind::Beckmann, LambdaKind::WalterPrinted) => lambda::walter_printed(nu),
            (NdfKind::Beckmann, LambdaKind::WalterListing) => lambda::walter_listing(nu),
        }
    }

    /// Smith masking of direction o alone, 1/(1 + Λ(o)) ∈ [0, 1] (exact Λ).
    pub fn g1_dir(&self, o: &Vector3<f64>) -> f64 {
        g1_from_lambda(self.lambda(o))
    }

    /// G1(o, m) = χ⁺(o·m)/(1 + Λ(o)) (seed 003 App. A).
    pub fn g1(&self, o: &Vector3<f64>, m: &Vector3<f64>) -> f64 {
        if o.dot(m) <= 0.0 {
            0.0
        } else {
            self.g1_dir(o)
        }
    }

    /// Height-correlated G2 = χ⁺(i·m)χ⁺(o·m)/(1 + Λ(i) + Λ(o)) (seed 003 Eq 14).
    pub fn g2_correlated(&self, i: &Vector3<f64>, o: &Vector3<f64>, m: &Vector3<f64>) -> f64 {
        if i.dot(m) <= 0.0 || o.dot(m) <= 0.0 {
            return 0.0;
        }
        g2_from_lambdas(self.lambda(i), self.lambda(o))
    }

    /// Separable G2 = G1(i, m)·G1(o, m).
    pub fn g2_separable(&self, i: &Vector3<f64>, o: &Vector3<f64>, m: &Vector3<f64>) -> f64 {
        self.g1(i, m) * self.g1(o, m)
    }

    /// Lobe width used to place quadrature nodes (smallest principal roughness).
    pub fn width(&self) -> f64 {
        self.rough.min_alpha()
    }

    /// Direction of the mean normal ω_n̄ ∝ (−x̄, −ȳ, 1).
    pub fn mean_normal(&self) -> Vector3<f64> {
        Vector3::new(-self.mean.x, -self.mean.y, 1.0).normalize()
    }
}

/// Smith G1(o) = 1/(1 + Λ(o)) given Λ (0 where Λ is infinite: o at or below the horizon);
/// the f64 reference of `shading::g1_from_lambda`.
pub fn g1_from_lambda(l: f64) -> f64 {
    if l.is_infinite() {
        0.0
    } else {
        1.0 / (1.0 + l)
    }
}

/// Height-correlated G2 of two directions both facing m, from their Λ:
/// 1/(1 + Λ(i) + Λ(o)), 0 where the sum is infinite (seed 003 Eq 14).
pub fn g2_from_lambdas(lambda_i: f64, lambda_o: f64) -> f64 {
    g1_from_lambda(lambda_i + lambda_o)
}

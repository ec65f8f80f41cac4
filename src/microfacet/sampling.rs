//! Sampling techniques on microsurfaces, usable as MC/QMC [`Strategy`]s.
//!
//! - [`NdfSampler`]: m with density D(m)·m_z (any family, any A, any mean slope), by
//!   sampling the slope law P22 directly (seed 001 §1.2: D(m) m_z dm = P22 dx̃).
//! - [`VndfSampler`]: GGX visible normals (Heitz 2018; spherical-cap form of Dupuy &
//!   Benyoub 2023) for the general roughness matrix via its symmetric square root, with
//!   the exact pdf D_o(m) = G1(o)·⟨o·m⟩·D(m)/o_z.

use super::surface::{Microsurface, NdfKind};
use crate::error::{Error, Result};
use crate::integrate::mc::Strategy;
use crate::lanes::{map, Dirs, Lanes, LANES};
use nalgebra::{Vector2, Vector3};
use std::f64::consts::PI;

/// Samples microfacet normals proportionally to D(m)·m_z.
pub struct NdfSampler {
    pub surface: Microsurface,
}

impl Strategy<Vector3<f64>> for NdfSampler {
    fn sample(&self, u: [f64; 2]) -> Option<Vector3<f64>> {
        let r = match self.surface.kind {
            NdfKind::Ggx => {
                if u[0] >= 1.0 {
                    return None;
                }
                (u[0] / (1.0 - u[0])).sqrt()
            }
            NdfKind::Beckmann => (-(1.0 - u[0]).ln()).sqrt(),
        };
        let phi = 2.0 * PI * u[1];
        let y = Vector2::new(r * phi.cos(), r * phi.sin());
        let slope = self.surface.mean + self.surface.rough.sqrt_a() * y;
        let m = Vector3::new(-slope.x, -slope.y, 1.0);
        let n = m.norm();
        if !n.is_finite() {
            return None;
        }
        Some(m / n)
    }
    fn pdf(&self, m: &Vector3<f64>) -> f64 {
        self.surface.d(m) * m.z.max(0.0)
    }
}

/// GGX visible-normal sampler for a fixed outgoing direction o (o_z > 0, centred GGX).
pub struct VndfSampler {
    surface: Microsurface,
    o: Vector3<f64>,
    o_stretched: Vector3<f64>,
    /// G1(o), computed once: every density the sampler gives is seen from o.
    g1_o: f64,
}

impl VndfSampler {
    /// Errors: not GGX, non-zero mean slope, or o not in the upper hemisphere.
    pub fn new(surface: Microsurface, o: Vector3<f64>) -> Result<Self> {
        Self::seen_with(surface, o, surface.lambda(&o))
    }

    /// [`VndfSampler::new`] given Λ(o) = `surface.lambda(&o)` already computed (a shader
    /// that has it for the lobe too): the same sampler, bit for bit.
    pub fn seen_with(surface: Microsurface, o: Vector3<f64>, lambda_o: f64) -> Result<Self> {
        if surface.kind != NdfKind::Ggx {
            return Err(Error::InvalidArgument(
                "VNDF sampling is implemented for GGX".into(),
            ));
        }
        if surface.mean != Vector2::zeros() {
            return Err(Error::InvalidArgument(
                "VNDF sampling needs a centred surface (mean slope 0)".into(),
            ));
        }
        if !(o.z > 0.0) {
            return Err(Error::BelowHorizon { what: "o", z: o.z });
        }
        let s = surface.rough.sqrt_a() * Vector2::new(o.x, o.y);
        let o_stretched = Vector3::new(s.x, s.y, o.z).normalize();
        Ok(VndfSampler {
            surface,
            o,
            o_stretched,
            // Microsurface::g1_dir from its Λ
            g1_o: super::surface::g1_from_lambda(lambda_o),
        })
    }

    /// Exact density of the visible normal m: G1(o)·max(0, o·m)·D(m)/o_z.
    pub fn pdf_exact(&self, m: &Vector3<f64>) -> f64 {
        let c = self.o.dot(m);
        if c <= 0.0 {
            return 0.0;
        }
        self.g1_o * c * self.surface.d(m) / self.o.z
    }

    /// [`Self::pdf_exact`] of sampler `s[i]` at normal `m`'s lane i (one sampler may fill
    /// several lanes), step by step across the lanes (`crate::lanes`; D by
    /// `Microsurface::d_lanes` where every sampler has the same surface, else lane by
    /// lane): each lane's bits are `pdf_exact`'s.
    pub fn pdf_lanes(s: [&VndfSampler; LANES], m: &Dirs) -> Lanes {
        let surface = &s[0].surface;
        if s.iter().any(|s| s.surface != *surface) {
            return map(|i| s[i].pdf_exact(&m.get(i)));
        }
        let c = map(|i| {
            let o = &s[i].o;
            o.x * m.x[i] + o.y * m.y[i] + o.z * m.z[i]
        });
        let d = surface.d_lanes(m, surface.d_norm());
        map(|i| {
            if c[i] <= 0.0 {
                0.0
            } else {
                s[i].g1_o * c[i] * d[i] / s[i].o.z
            }
        })
    }
}

impl Strategy<Vector3<f64>> for VndfSampler {
    fn sample(&self, u: [f64; 2]) -> Option<Vector3<f64>> {
        let wi = self.o_stretched;
        let phi = 2.0 * PI * u[0];
        let z = (1.0 - u[1]) * (1.0 + wi.z) - wi.z;
        let st = (1.0 - z * z).max(0.0).sqrt();
        let c = Vector3::new(st * phi.cos(), st * phi.sin(), z);
        let h = c + wi;
        // unstretch the normal: m ∝ (S h_xy, h_z)
        let sxy = self.surface.rough.sqrt_a() * Vector2::new(h.x, h.y);
        let m = Vector3::new(sxy.x, sxy.y, h.z.max(0.0));
        let n = m.norm();
        if !(n > 0.0 && n.is_finite()) {
            return None;
        }
        Some(m / n)
    }
    fn pdf(&self, m: &Vector3<f64>) -> f64 {
        self.pdf_exact(m)
    }
}

//! Burley's diffuse lobe as an LTC target (Burley 2012, "Physically-Based Shading at
//! Disney", §5.3): f = (1/π)(1 + (F_D90 − 1)(1 − l_z)⁵)(1 + (F_D90 − 1)(1 − v_z)⁵),
//! F_D90 = ½ + 2·ρ·cos²θ_d with cos θ_d = l·h — the retro-reflection term that brightens
//! rough surfaces at grazing angles and darkens smooth ones. The paper's ρ is the
//! artist's (perceptual) roughness r = √α; Filament and Bevy pass α itself
//! (`Fd_Burley(roughness = perceptualRoughness², …)`): both conventions are targets.
//! Sampled by the cosine hemisphere; albedo by nested adaptive quadrature.

use super::hemisphere;
use super::target::LtcTarget;
use crate::error::Result;
use crate::lanes::{map, Dirs, LANES};
use nalgebra::Vector3;

type V3 = Vector3<f64>;

/// What F_D90's roughness is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum BurleyRoughness {
    /// Burley 2012: the perceptual roughness r = √α.
    Paper,
    /// Filament / Bevy: α = r².
    Engines,
}

/// The Burley diffuse BRDF of one cell (albedo 1), cosine-weighted.
#[derive(Clone, Copy, Debug)]
pub struct BurleyTarget {
    pub alpha: f64,
    pub v: V3,
    pub roughness: BurleyRoughness,
}

impl BurleyTarget {
    /// θ in radians (clamped to ≤ 89.99°), α ∈ (0, 1] finite.
    pub fn new(alpha: f64, theta: f64, roughness: BurleyRoughness) -> Result<BurleyTarget> {
        Ok(BurleyTarget {
            alpha,
            v: hemisphere::checked_view(alpha, theta)?,
            roughness,
        })
    }

    /// F_D90 for a light direction l.
    pub fn fd90(&self, l: &V3) -> f64 {
        let h = (self.v + l).normalize();
        let ld = l.dot(&h);
        0.5 + 2.0 * self.rho() * ld * ld
    }

    /// The roughness in F_D90: √α (the paper's r) or α (the engines').
    fn rho(&self) -> f64 {
        match self.roughness {
            BurleyRoughness::Paper => self.alpha.sqrt(),
            BurleyRoughness::Engines => self.alpha,
        }
    }

    /// BRDF(l, v)·l_z (0 below the horizon).
    pub fn value(&self, l: &V3) -> f64 {
        if l.z <= 0.0 {
            return 0.0;
        }
        let f90 = self.fd90(l);
        let s = |c: f64| 1.0 + (f90 - 1.0) * (1.0 - c).max(0.0).powi(5);
        s(l.z) * s(self.v.z) * l.z / std::f64::consts::PI
    }
}

impl LtcTarget for BurleyTarget {
    fn view(&self) -> V3 {
        self.v
    }
    fn eval(&self, l: &V3) -> (f64, f64) {
        (self.value(l), hemisphere::cosine_pdf(l))
    }
    /// Step by step across the lanes (`lanes`): `value`'s and `cosine_pdf`'s operations
    /// in their order, each lane with their bits.
    fn eval_lanes(&self, l: &Dirs, live: [bool; LANES]) -> [(f64, f64); LANES] {
        let s = l.plus(&self.v);
        let h = s.over(&s.norm());
        let ld = l.dot(&h);
        let rho = self.rho();
        let f90 = map(|i| 0.5 + 2.0 * rho * ld[i] * ld[i]);
        let sh = |f90: f64, c: f64| 1.0 + (f90 - 1.0) * (1.0 - c).max(0.0).powi(5);
        let f = map(|i| sh(f90[i], l.z[i]) * sh(f90[i], self.v.z) * l.z[i] / std::f64::consts::PI);
        std::array::from_fn(|i| {
            let p = if l.z[i] > 0.0 {
                l.z[i] / std::f64::consts::PI
            } else {
                0.0
            };
            match (live[i], l.z[i] <= 0.0) {
                (false, _) => (0.0, 0.0),
                (true, true) => (0.0, p),
                (true, false) => (f[i], p),
            }
        })
    }
    fn sample(&self, u: [f64; 2]) -> Option<V3> {
        hemisphere::cosine_sample(u)
    }
    fn width(&self) -> f64 {
        1.0
    }
    fn albedo(&self, tol: f64) -> (f64, f64, f64) {
        hemisphere::albedo_lanes(
            &|l| {
                let r = self.eval_lanes(l, [true; LANES]);
                map(|i| r[i].0)
            },
            &self.v,
            &[],
            tol,
        )
    }
}

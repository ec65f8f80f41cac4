//! The Charlie sheen lobe as an LTC target (Estevez & Kulla 2017, "Production Friendly
//! Microfacet Sheen BRDF"): the inverted-Gaussian-like NDF
//! D(h) = (2 + 1/α) sin^(1/α)θ_h / (2π), with either of the two visibility terms in use:
//! - `EstevezKulla`: their height-correlated Smith form 1/((1 + Λ(v) + Λ(l))·4 v_z l_z)
//!   with their fitted Λ (five coefficients interpolated in (1 − α)², Λ(cos θ) =
//!   exp(L(cos θ)) below cos θ = ½ and exp(2L(½) − L(1 − cos θ)) above; without the
//!   optional terminator softening);
//! - `Neubelt`: the simpler 1/(4(l_z + v_z − l_z v_z)) of Neubelt & Pettineo 2013 that
//!   glTF's KHR_materials_sheen names as the cheap alternative.
//!
//! α is the sheen α of glTF (α = sheenRoughness²). Sampled by a defensive mixture: half
//! the samples from the cosine hemisphere, half from the Charlie NDF (sin θ_h = u^(1/(2 + 1/α)),
//! the exact inverse of its projected CDF) reflected about h — at small α the lobe lives at
//! grazing half-vectors, where the cosine density alone vanishes; albedo by nested
//! adaptive quadrature (`hemisphere`).

use super::hemisphere;
use super::target::LtcTarget;
use crate::error::Result;
use crate::lanes::{map, Dirs, LANES};
use nalgebra::Vector3;

type V3 = Vector3<f64>;

/// Which visibility term multiplies the Charlie NDF.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum SheenVisibility {
    EstevezKulla,
    Neubelt,
}

/// The Charlie sheen BRDF of one cell (F = 1), cosine-weighted.
#[derive(Clone, Copy, Debug)]
pub struct CharlieTarget {
    pub alpha: f64,
    pub v: V3,
    pub visibility: SheenVisibility,
    /// Estevez & Kulla's Λ(v_z), computed once (every value needs it).
    lambda_v: f64,
    /// Their Λ at this α, for Λ(l_z).
    ek: EkLambda,
}

/// Estevez & Kulla's L(x) of their Λ fit, with the coefficients interpolated in
/// t = (1 − α)² between their α = 1 and α = 0 values.
pub fn ek_l(x: f64, alpha: f64) -> f64 {
    EkLambda::new(alpha).l(x)
}

/// Estevez & Kulla's fitted Smith Λ of the Charlie NDF at cos θ ∈ (0, 1].
pub fn ek_lambda(cos_theta: f64, alpha: f64) -> f64 {
    EkLambda::new(alpha).at(cos_theta)
}

/// Estevez & Kulla's Λ at one α: L's five coefficients and 2L(½) computed once (a target
/// evaluates Λ(l) for every sample), the same operations as [`ek_l`] and [`ek_lambda`],
/// so the same bits.
#[derive(Clone, Copy, Debug)]
struct EkLambda {
    /// a, b, c, d, e of L(x) = a/(1 + b·x^c) + d·x + e.
    k: [f64; 5],
    /// 2·L(½), the upper branch's constant.
    two_l_half: f64,
}

impl EkLambda {
    fn new(alpha: f64) -> EkLambda {
        let t = (1.0 - alpha.clamp(0.0, 1.0)).powi(2);
        let mix = |at1: f64, at0: f64| at1 * (1.0 - t) + at0 * t;
        let k = [
            mix(21.5473, 25.3245),
            mix(3.82987, 3.32435),
            mix(0.19823, 0.16801),
            mix(-1.97760, -1.27393),
            mix(-4.32054, -4.85967),
        ];
        let mut e = EkLambda { k, two_l_half: 0.0 };
        e.two_l_half = 2.0 * e.l(0.5);
        e
    }

    fn l(&self, x: f64) -> f64 {
        let [a, b, c, d, e] = self.k;
        a / (1.0 + b * x.powf(c)) + d * x + e
    }

    /// Λ(cos θ): exp(L(cos θ)) below cos θ = ½, exp(2L(½) − L(1 − cos θ)) above.
    fn at(&self, cos_theta: f64) -> f64 {
        if cos_theta < 0.5 {
            self.l(cos_theta).exp()
        } else {
            (self.two_l_half - self.l(1.0 - cos_theta)).exp()
        }
    }
}

/// The Charlie NDF at a half-vector with cosine `hz` (normalised: ∫ D h_z dh = 1).
pub fn charlie_d(hz: f64, alpha: f64) -> f64 {
    let inv = 1.0 / alpha;
    let s2 = (1.0 - hz * hz).max(0.0);
    (2.0 + inv) * s2.powf(0.5 * inv) / (2.0 * std::f64::consts::PI)
}

impl CharlieTarget {
    /// θ in radians (clamped to ≤ 89.99°), α ∈ (0, 1] finite.
    pub fn new(alpha: f64, theta: f64, visibility: SheenVisibility) -> Result<CharlieTarget> {
        let v = hemisphere::checked_view(alpha, theta)?;
        let ek = EkLambda::new(alpha);
        Ok(CharlieTarget {
            alpha,
            v,
            visibility,
            lambda_v: ek.at(v.z),
            ek,
        })
    }

    /// A half-vector from the Charlie NDF's projected density D(h)·h_z: its CDF in
    /// s = sin θ_h is s^(2 + 1/α), so s = u₀^(1/(2 + 1/α)); φ = 2π u₁.
    pub fn sample_h(&self, u: [f64; 2]) -> V3 {
        let s = u[0].max(0.0).powf(1.0 / (2.0 + 1.0 / self.alpha)).min(1.0);
        let c = (1.0 - s * s).max(0.0).sqrt();
        let phi = 2.0 * std::f64::consts::PI * u[1];
        V3::new(s * phi.cos(), s * phi.sin(), c)
    }

    /// The density of [`LtcTarget::sample`] at l: ½ cosine + ½ D(h)·h_z/(4 |v·h|).
    pub fn pdf(&self, l: &V3) -> f64 {
        if l.z <= 0.0 {
            return 0.0;
        }
        let h = (self.v + l).normalize();
        self.pdf_at(l, &h, charlie_d(h.z, self.alpha))
    }

    /// [`Self::pdf`] at l above the horizon, given its half-vector h and D(h).
    fn pdf_at(&self, l: &V3, h: &V3, d: f64) -> f64 {
        let vh = self.v.dot(h).abs().max(1e-300);
        0.5 * hemisphere::cosine_pdf(l) + 0.5 * d * h.z / (4.0 * vh)
    }

    /// BRDF(l, v)·l_z (0 below the horizon).
    pub fn value(&self, l: &V3) -> f64 {
        if l.z <= 0.0 {
            return 0.0;
        }
        let h = (self.v + l).normalize();
        self.value_at(l, charlie_d(h.z, self.alpha))
    }

    /// [`Self::value`] at l above the horizon, given D of its half-vector.
    fn value_at(&self, l: &V3, d: f64) -> f64 {
        let (lz, vz) = (l.z, self.v.z);
        match self.visibility {
            SheenVisibility::EstevezKulla => {
                let g = 1.0 / (1.0 + self.lambda_v + self.ek.at(lz));
                d * g / (4.0 * vz)
            }
            SheenVisibility::Neubelt => d * lz / (4.0 * (lz + vz - lz * vz)),
        }
    }
}

impl LtcTarget for CharlieTarget {
    fn view(&self) -> V3 {
        self.v
    }
    /// (value, density) with the half-vector and D(h) computed once for both.
    fn eval(&self, l: &V3) -> (f64, f64) {
        if l.z <= 0.0 {
            return (0.0, 0.0);
        }
        let h = (self.v + l).normalize();
        let d = charlie_d(h.z, self.alpha);
        (self.value_at(l, d), self.pdf_at(l, &h, d))
    }
    /// Step by step across the lanes (`ltc::lanes`): the half-vectors, then the four D(h)
    /// (a power each), then the four Λ(l), each lane by `eval`'s operations in its order.
    fn eval_lanes(&self, l: &Dirs, live: [bool; LANES]) -> [(f64, f64); LANES] {
        let s = l.plus(&self.v);
        let h = s.over(&s.norm());
        let d = map(|i| charlie_d(h.z[i], self.alpha));
        let f = map(|i| self.value_at(&l.get(i), d[i]));
        let p = map(|i| self.pdf_at(&l.get(i), &h.get(i), d[i]));
        std::array::from_fn(|i| {
            // as `eval`: only l_z ≤ 0 is (0, 0) (a NaN l_z is evaluated)
            if live[i] && !(l.z[i] <= 0.0) {
                (f[i], p[i])
            } else {
                (0.0, 0.0)
            }
        })
    }
    fn sample(&self, u: [f64; 2]) -> Option<V3> {
        if u[0] < 0.5 {
            hemisphere::cosine_sample([2.0 * u[0], u[1]])
        } else {
            let h = self.sample_h([(2.0 * u[0] - 1.0).min(1.0), u[1]]);
            let l = h * (2.0 * self.v.dot(&h)) - self.v;
            (l.z > 0.0).then_some(l)
        }
    }
    fn width(&self) -> f64 {
        1.0
    }
    fn albedo(&self, tol: f64) -> (f64, f64, f64) {
        // Λ's two branches meet at l_z = ½ with a kink
        let kinks: &[f64] = match self.visibility {
            SheenVisibility::EstevezKulla => &[0.5],
            SheenVisibility::Neubelt => &[],
        };
        hemisphere::albedo_lanes(
            &|l| {
                let r = self.eval_lanes(l, [true; LANES]);
                map(|i| r[i].0)
            },
            &self.v,
            kinks,
            tol,
        )
    }
}

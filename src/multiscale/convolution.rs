//! Spherical convolution of two isotropic LTCs (seed 000 Eq 6):
//! c(m) = (γ_me ∗ γ_mi)(m) = ∫_{S²} γ_me(b) γ_mi(R_b⁻¹ m) db.
//!
//! Both lobes are isotropic about n, so γ_mi(R_b⁻¹ m) = g_mi(m·b) (its zonal profile,
//! independent of the twist of R_b) and c depends on θ_m only. Micro-normals rotated below
//! the horizon (m_z < 0) are kept in the unclipped quantities and counted as lost mass in
//! the clipped ones.

use crate::error::Result;
use crate::integrate::estimate::{ErrorKind, Estimate, Welford};
use crate::integrate::mc::Strategy;
use crate::integrate::quad::Tol;
use crate::integrate::sphere::{frame, integrate_sphere, SphereRule};
use crate::ltc::LtcDist;
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// Zonal profile g(cos θ) of the isotropic LTC: γ at polar angle θ.
pub fn zonal(d: &LtcDist, cos_t: f64) -> f64 {
    let c = cos_t.clamp(-1.0, 1.0);
    let s = (1.0 - c * c).max(0.0).sqrt();
    d.eval(&V3::new(s, 0.0, c))
}

/// The convolution of two isotropic LTCs.
pub struct Convolution {
    pub alpha_me: f64,
    pub alpha_mi: f64,
    me: LtcDist,
    mi: LtcDist,
}

/// Moments of the convolution, each with its error.
#[derive(Clone, Debug, Serialize)]
pub struct Moments {
    /// ∫_{S²} c (should be 1).
    pub mass_total: Estimate,
    /// ∫_{m_z<0} c: micro-normals rotated below the horizon.
    pub mass_below: Estimate,
    /// ∫_{S²} m_z c (unclipped mean resultant length).
    pub mrl_unclipped: Estimate,
    /// ∫_{m_z>0} m_z c / ∫_{m_z>0} c (clipped and renormalised).
    pub mrl_clipped: f64,
}

impl Convolution {
    pub fn new(alpha_me: f64, alpha_mi: f64) -> Result<Self> {
        Ok(Convolution {
            alpha_me,
            alpha_mi,
            me: LtcDist::isotropic(alpha_me)?,
            mi: LtcDist::isotropic(alpha_mi)?,
        })
    }

    /// c(θ_m) by adaptive sphere quadrature over b (kinks: b_z = 0 and m·b = 0).
    pub fn density(&self, theta_m: f64, tol: Tol) -> Estimate {
        let m = V3::new(theta_m.sin(), 0.0, theta_m.cos());
        let f = |b: &V3| {
            if b.z <= 0.0 {
                return 0.0;
            }
            let c = m.dot(b);
            if c <= 0.0 {
                return 0.0;
            }
            self.me.eval(b) * zonal(&self.mi, c)
        };
        // pole at the narrower lobe's centre, scale its width
        let (pole, scale) = if self.alpha_mi <= self.alpha_me {
            (m, self.alpha_mi)
        } else {
            (V3::z(), self.alpha_me)
        };
        let rule = SphereRule::sphere(pole, scale.min(1.0))
            .with_kink(V3::z())
            .with_kink(m);
        integrate_sphere(&f, &rule, tol)
    }

    /// ∫ w(θ) c(θ) 2π sin θ dθ over [θ0, θ1] by adaptive GK, with geometric break points
    /// following the lobe; inner errors are propagated.
    fn radial(&self, w: &(dyn Fn(f64) -> f64 + Sync), t0: f64, t1: f64, tol: Tol) -> Estimate {
        let width = self.alpha_me.max(self.alpha_mi).min(1.0);
        let mut breaks = vec![t0, t1];
        let mut th = 0.25 * width;
        while th < t1 {
            if th > t0 {
                breaks.push(th);
            }
            th *= 2.0;
        }
        breaks.sort_by(|a, b| a.total_cmp(b));
        let inner = Tol::new(tol.abs * 0.1, tol.rel * 0.1, tol.max_evals / 20);
        let eval = |xs: &[f64; 15]| {
            let r: Vec<Estimate> = xs.par_iter().map(|&t| self.density(t, inner)).collect();
            let mut v = [0.0; 15];
            let mut e = [0.0; 15];
            let mut n = 0;
            for (i, (est, &t)) in r.iter().zip(xs).enumerate() {
                let k = w(t) * 2.0 * PI * t.sin();
                v[i] = k * est.value;
                e[i] = (k * est.error).abs();
                n += est.evals;
            }
            (v, e, n)
        };
        crate::integrate::quad::adaptive_batched(&eval, &breaks, tol)
    }

    /// Moments by nested adaptive quadrature.
    pub fn moments_quad(&self, tol: Tol) -> Moments {
        let one = |_t: f64| 1.0;
        let cz = |t: f64| t.cos();
        let above = self.radial(&one, 0.0, PI / 2.0, tol);
        let below = self.radial(&one, PI / 2.0, PI, tol);
        let mrl_above = self.radial(&cz, 0.0, PI / 2.0, tol);
        let mrl_below = self.radial(&cz, PI / 2.0, PI, tol);
        let sum = |a: &Estimate, b: &Estimate| Estimate {
            value: a.value + b.value,
            error: a.error + b.error,
            evals: a.evals + b.evals,
            kind: ErrorKind::Quadrature,
            converged: a.converged && b.converged,
        };
        Moments {
            mass_total: sum(&above, &below),
            mass_below: below,
            mrl_unclipped: sum(&mrl_above, &mrl_below),
            mrl_clipped: mrl_above.value / above.value,
        }
    }

    /// Moments by Monte Carlo: b ~ γ_me, m′ ~ γ_mi, m = R_b m′ (the sampling the paper's MC
    /// uses); returns (mass below, unclipped MRL, clipped MRL) with standard errors.
    pub fn moments_mc(&self, n: u64, seed: u64) -> (Estimate, Estimate, Estimate) {
        let chunks = n.div_ceil(4096);
        let acc: Vec<(Welford, Welford, Welford, Welford)> = (0..chunks)
            .into_par_iter()
            .map(|k| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                rng.set_stream(k);
                let mut a = (
                    Welford::default(),
                    Welford::default(),
                    Welford::default(),
                    Welford::default(),
                );
                for _ in 0..4096.min(n - k * 4096) {
                    let b = self.me.sample([rng.random(), rng.random()]);
                    let mp = self.mi.sample([rng.random(), rng.random()]);
                    let (Some(b), Some(mp)) = (b, mp) else {
                        continue;
                    };
                    let (t1, t2) = frame(&b);
                    let m = t1 * mp.x + t2 * mp.y + b * mp.z;
                    a.0.push(if m.z < 0.0 { 1.0 } else { 0.0 });
                    a.1.push(m.z);
                    a.2.push(m.z.max(0.0));
                    a.3.push(if m.z >= 0.0 { 1.0 } else { 0.0 });
                }
                a
            })
            .collect();
        let t = acc.into_iter().fold(
            (
                Welford::default(),
                Welford::default(),
                Welford::default(),
                Welford::default(),
            ),
            |x, y| {
                (
                    x.0.merge(y.0),
                    x.1.merge(y.1),
                    x.2.merge(y.2),
                    x.3.merge(y.3),
                )
            },
        );
        let est = |w: &Welford| Estimate {
            value: w.mean,
            error: w.std_error(),
            evals: w.n,
            kind: ErrorKind::StandardError,
            converged: true,
        };
        // clipped MRL = E[m_z⁺]/P(m_z ≥ 0); first-order error propagation
        let (num, den) = (est(&t.2), est(&t.3));
        let clipped = Estimate {
            value: num.value / den.value,
            error: (num.error / den.value).hypot(num.value * den.error / (den.value * den.value)),
            evals: num.evals,
            kind: ErrorKind::StandardError,
            converged: true,
        };
        (est(&t.0), est(&t.1), clipped)
    }
}

/// ∫_cap γ_α(m) dm for the isotropic LTC (same cap parameterisation).
pub fn ltc_cap_integral(alpha: f64, theta_c: f64, r: f64, tol: Tol) -> Result<Estimate> {
    let d = LtcDist::isotropic(alpha)?;
    let axis = V3::new(theta_c.sin(), 0.0, theta_c.cos());
    let rule = SphereRule {
        pole: axis,
        scale: r,
        theta_max: r,
        phi_segments: 4,
        t_breaks: 0,
        stretch: None,
        kinks: Vec::new(),
    };
    Ok(integrate_sphere(&|m: &V3| d.eval(m), &rule, tol))
}

/// Signed L2 distance² between the convolution and an isotropic LTC of roughness α over
/// the sphere, from a tabulated c(θ): 2π ∫ (c(θ) − g_α(θ))² sin θ dθ (trapezoid-free GK on
/// the table's smooth interpolant is avoided: the table nodes are GL nodes).
pub fn l2_distance2(table: &[(f64, f64, f64)], alpha: f64) -> f64 {
    let d = LtcDist::isotropic(alpha).expect("α > 0");
    table
        .iter()
        .map(|&(t, w, c)| {
            let g = zonal(&d, t.cos());
            w * (c - g) * (c - g) * 2.0 * PI * t.sin()
        })
        .sum()
}

/// c(θ) on Gauss–Legendre nodes of [0, π] split at geometric breaks (θ, weight, c).
pub fn density_table(conv: &Convolution, nodes_per_panel: usize, tol: Tol) -> Vec<(f64, f64, f64)> {
    let width = conv.alpha_me.max(conv.alpha_mi).min(1.0);
    let mut breaks = vec![0.0, PI];
    let mut th = 0.25 * width;
    while th < PI {
        breaks.push(th);
        th *= 2.0;
    }
    breaks.push(PI / 2.0);
    breaks.sort_by(|a, b| a.total_cmp(b));
    breaks.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let (x, w) = crate::integrate::quad::gauss_legendre(nodes_per_panel);
    let pts: Vec<(f64, f64)> = breaks
        .windows(2)
        .flat_map(|p| {
            let (c, h) = (0.5 * (p[0] + p[1]), 0.5 * (p[1] - p[0]));
            x.iter()
                .zip(&w)
                .map(move |(xi, wi)| (c + h * xi, h * wi))
                .collect::<Vec<_>>()
        })
        .collect();
    pts.par_iter()
        .map(|&(t, wt)| (t, wt, conv.density(t, tol).value))
        .collect()
}

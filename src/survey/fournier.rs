//! Fournier's sums of Blinn–Phong lobes (seed 004 §3.2.2 Eq 20), q̂(η) = Σ_k a_k (μ_k·η)₊^{e_k}:
//! a direct spanning-set method (§7.4.1, [`super::tools`]) — the lobes are fitted to the
//! footprint's distribution itself, at every level from the base texels, by non-linear
//! least squares; 4 parameters per lobe (a, μ as two angles, e), 1–7 lobes.
//!
//! The objective is the L2 distance over the sphere, ∫ (q̂ − q_A)² dη, estimated on a fixed
//! set of directions drawn from 0.8 q_A + 0.2 × uniform ([`Target`]), each weighted by
//! 1/(M × density). The fit starts from a vMF mixture ([`super::em::VmfMixture`]) with
//! exponents from its κ and the base lobe's width, then runs L-BFGS (argmin) on
//! (ln a, m, ln e) per lobe, μ = m/‖m‖, with the analytic gradient.

use super::em::VmfMixture;
use super::{ExactPdf, NormalPdf, Texels};
use crate::error::{Error, Result};
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// The fixed directions of the least-squares objective with their weights and the exact
/// footprint distribution there.
pub struct Target {
    pub dirs: Vec<V3>,
    pub weights: Vec<f64>,
    pub values: Vec<f64>,
    /// Σ w q_A², the squared L2 norm of the target (for relative errors).
    pub norm2: f64,
}

impl Target {
    /// `m` directions, seeded: 80 % from the texel lobes (texel by its weight, microfacet
    /// normal from the base lobe), 20 % uniform on the sphere.
    pub fn new(t: &Texels, m: usize, seed: u64) -> Target {
        let exact = ExactPdf::new(t);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut cum = Vec::with_capacity(t.weights.len());
        let mut acc = 0.0;
        for w in t.weights {
            acc += w;
            cum.push(acc);
        }
        let (mut dirs, mut weights, mut values) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..m {
            let u: [f64; 4] = [rng.random(), rng.random(), rng.random(), rng.random()];
            let d = if u[0] < 0.8 {
                let i = cum.partition_point(|&c| c <= u[1] * acc).min(cum.len() - 1);
                let f = crate::microfacet::lobe::Frame::around(t.normals[i]);
                let c = t.base.sample_cos(u[2]);
                let s = (1.0 - c * c).max(0.0).sqrt();
                let p = 2.0 * PI * u[3];
                f.world(&V3::new(s * p.cos(), s * p.sin(), c))
            } else {
                let z = 2.0 * u[2] - 1.0;
                let s = (1.0 - z * z).max(0.0).sqrt();
                let p = 2.0 * PI * u[3];
                V3::new(s * p.cos(), s * p.sin(), z)
            };
            let q = exact.pdf(&d);
            let dens = 0.8 * q + 0.2 / (4.0 * PI);
            dirs.push(d);
            weights.push(1.0 / (m as f64 * dens));
            values.push(q);
        }
        let norm2 = weights.iter().zip(&values).map(|(w, q)| w * q * q).sum();
        Target {
            dirs,
            weights,
            values,
            norm2,
        }
    }
    /// Relative L2 distance ‖q̂ − q_A‖/‖q_A‖ on the target's directions.
    pub fn rel_l2(&self, q: &dyn NormalPdf) -> f64 {
        let e: f64 = self
            .dirs
            .iter()
            .zip(&self.weights)
            .zip(&self.values)
            .map(|((d, w), v)| w * (q.pdf(d) - v).powi(2))
            .sum();
        (e / self.norm2).sqrt()
    }
}

/// One Blinn–Phong lobe a (μ·η)₊^e.
#[derive(Clone, Copy, Debug)]
pub struct BpLobe {
    pub a: f64,
    pub mu: V3,
    pub e: f64,
}

/// A sum of Blinn–Phong lobes.
#[derive(Clone, Debug)]
pub struct BlinnPhongSum {
    pub lobes: Vec<BpLobe>,
    /// Relative L2 distance to the footprint distribution on the fit's directions.
    pub fit_rel_l2: f64,
    pub iterations: u64,
}

impl NormalPdf for BlinnPhongSum {
    fn pdf(&self, h: &V3) -> f64 {
        self.lobes
            .iter()
            .map(|l| {
                let c = l.mu.dot(h);
                if c > 0.0 {
                    l.a * c.powf(l.e)
                } else {
                    0.0
                }
            })
            .sum()
    }
}

/// Parameters (ln a, m_x, m_y, m_z, ln e) per lobe.
fn unpack(p: &[f64]) -> Vec<BpLobe> {
    p.chunks(5)
        .map(|c| {
            let m = V3::new(c[1], c[2], c[3]);
            let n = m.norm().max(1e-300);
            BpLobe {
                a: c[0].exp(),
                mu: m / n,
                e: c[4].exp(),
            }
        })
        .collect()
}

struct Objective<'a> {
    target: &'a Target,
}

impl Objective<'_> {
    /// Σ w (q̂ − q)² / ‖q‖² and its gradient.
    fn eval(&self, p: &[f64], grad: Option<&mut [f64]>) -> f64 {
        let lobes = unpack(p);
        let t = self.target;
        let mut g = vec![0.0; p.len()];
        let mut cost = 0.0;
        // one buffer for every direction's lobe values (no allocation per direction)
        let mut vals = Vec::with_capacity(lobes.len());
        // each lobe's ‖m‖ (the gradient's chain rule), once rather than per direction
        let mnorms: Vec<f64> = (0..lobes.len())
            .map(|k| {
                let base = 5 * k;
                V3::new(p[base + 1], p[base + 2], p[base + 3])
                    .norm()
                    .max(1e-300)
            })
            .collect();
        for ((d, w), q) in t.dirs.iter().zip(&t.weights).zip(&t.values) {
            vals.clear();
            let mut f = 0.0;
            for l in &lobes {
                let c = l.mu.dot(d);
                let v = if c > 0.0 { l.a * c.powf(l.e) } else { 0.0 };
                vals.push((c, v));
                f += v;
            }
            let r = f - q;
            cost += w * r * r;
            if grad.is_some() {
                let k2 = 2.0 * w * r;
                for (k, (l, &(c, v))) in lobes.iter().zip(&vals).enumerate() {
                    if v <= 0.0 {
                        continue;
                    }
                    let base = 5 * k;
                    let mnorm = mnorms[k];
                    g[base] += k2 * v;
                    // ∂v/∂m = a e c^{e−1} (d − c μ)/‖m‖
                    let dv = v * l.e / c;
                    let dm = (d - l.mu * c) * (dv / mnorm);
                    g[base + 1] += k2 * dm.x;
                    g[base + 2] += k2 * dm.y;
                    g[base + 3] += k2 * dm.z;
                    g[base + 4] += k2 * v * c.ln() * l.e;
                }
            }
        }
        if let Some(gr) = grad {
            for (o, x) in gr.iter_mut().zip(&g) {
                *o = x / t.norm2;
            }
        }
        cost / t.norm2
    }
}

impl argmin::core::CostFunction for Objective<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
        Ok(self.eval(p, None))
    }
}
impl argmin::core::Gradient for Objective<'_> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;
    fn gradient(&self, p: &Vec<f64>) -> std::result::Result<Vec<f64>, argmin::core::Error> {
        let mut g = vec![0.0; p.len()];
        self.eval(p, Some(&mut g));
        Ok(g)
    }
}

/// The Blinn–Phong exponent whose lobe has the width of a vMF lobe of concentration κ
/// convolved with the base lobe: (μ·η)^e ≈ exp(−eθ²/2), so 1/e = 1/κ + α²/2 (the base
/// lobe's Blinn–Phong equivalent e_α = 2/α², seed 004 §3.2.1's Toksvig form).
fn exponent(kappa: f64, alpha: f64) -> f64 {
    1.0 / (1.0 / kappa.max(1e-6) + 0.5 * alpha * alpha)
}

/// Fit `k` lobes to the footprint (≤ `max_iters` L-BFGS iterations).
pub fn fit(t: &Texels, target: &Target, k: usize, max_iters: u64) -> Result<BlinnPhongSum> {
    if k == 0 || k > 16 {
        return Err(Error::InvalidArgument(format!(
            "Fournier lobe count {k} not in 1..=16"
        )));
    }
    let start = VmfMixture::fit(t.normals, t.weights, k)?;
    let mut p = Vec::with_capacity(5 * k);
    for c in &start.comps {
        let e = exponent(c.kappa, t.base.alpha);
        // a normalised lobe of weight a_k integrates to a_k: ∫(μ·η)₊^e dη = 2π/(e + 1)
        p.extend([
            (c.weight.max(1e-12) * (e + 1.0) / (2.0 * PI)).ln(),
            c.mu.x,
            c.mu.y,
            c.mu.z,
            e.ln(),
        ]);
    }
    let obj = Objective { target };
    let initial = obj.eval(&p, None);
    use argmin::core::{Executor, State};
    use argmin::solver::linesearch::MoreThuenteLineSearch;
    use argmin::solver::quasinewton::LBFGS;
    let err = |e: argmin::core::Error| Error::InvalidArgument(format!("Fournier fit: {e}"));
    let solver = LBFGS::new(MoreThuenteLineSearch::new(), 7)
        .with_tolerance_grad(1e-10)
        .map_err(err)?
        .with_tolerance_cost(1e-12)
        .map_err(err)?;
    let (best, iters) = match Executor::new(obj, solver)
        .configure(|s| s.param(p.clone()).max_iters(max_iters))
        .run()
    {
        Ok(res) => (
            res.state()
                .get_best_param()
                .cloned()
                .unwrap_or_else(|| p.clone()),
            res.state().get_iter(),
        ),
        Err(_) => (p.clone(), 0),
    };
    let obj = Objective { target };
    let (best, cost) = {
        let c = obj.eval(&best, None);
        if c.is_finite() && c <= initial {
            (best, c)
        } else {
            (p, initial)
        }
    };
    Ok(BlinnPhongSum {
        lobes: unpack(&best),
        fit_rel_l2: cost.max(0.0).sqrt(),
        iterations: iters,
    })
}

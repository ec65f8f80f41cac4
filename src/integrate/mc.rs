//! Monte Carlo integration with importance sampling and multiple importance sampling
//! (balance heuristic), parallel with rayon and bit-identical for a given seed at any
//! thread count.
//!
//! Determinism: the N sample tuples are cut into fixed chunks of [`CHUNK`]. Chunk `k`
//! draws from its own ChaCha8 stream (seed, stream = k), is accumulated sequentially,
//! and the chunk accumulators are merged in chunk order after the parallel map. Nothing
//! depends on which thread ran which chunk.

use super::estimate::{ErrorKind, Estimate, Welford};
use nalgebra::{Vector2, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Tuples per deterministic chunk.
pub const CHUNK: u64 = 4096;

/// A sampling technique: maps two uniforms in [0,1)² to a point and knows its density.
pub trait Strategy<P>: Sync {
    /// Draw a point; `None` when the uniforms map outside the support (counts as f = 0).
    fn sample(&self, u: [f64; 2]) -> Option<P>;
    /// Density of `p` under this technique, with respect to the integration measure.
    fn pdf(&self, p: &P) -> f64;
}

/// One MIS observation for tuple `u` (two uniforms per strategy): the balance-heuristic
/// estimator with one sample per technique, Σ_s f(x_s) / Σ_k p_k(x_s).
pub(crate) fn mis_observation<P, F>(f: &F, strategies: &[&dyn Strategy<P>], u: &[f64]) -> f64
where
    F: Fn(&P) -> f64 + Sync,
{
    let mut y = 0.0;
    for (s, strat) in strategies.iter().enumerate() {
        if let Some(x) = strat.sample([u[2 * s], u[2 * s + 1]]) {
            let fx = f(&x);
            if fx != 0.0 {
                let denom: f64 = strategies.iter().map(|k| k.pdf(&x)).sum();
                if denom > 0.0 && denom.is_finite() {
                    y += fx / denom;
                }
            }
        }
    }
    y
}

/// Multiple importance sampling (balance heuristic, one sample per technique per tuple)
/// with `tuples` tuples. With a single strategy this is plain importance sampling.
/// `evals` counts integrand evaluations (tuples × strategies).
pub fn mis<P, F>(f: &F, strategies: &[&dyn Strategy<P>], tuples: u64, seed: u64) -> Estimate
where
    F: Fn(&P) -> f64 + Sync,
{
    assert!(!strategies.is_empty(), "MIS needs at least one strategy");
    let dims = 2 * strategies.len();
    let chunks = tuples.div_ceil(CHUNK);
    let accs: Vec<Welford> = (0..chunks)
        .into_par_iter()
        .map(|k| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(k);
            let n = CHUNK.min(tuples - k * CHUNK);
            let mut acc = Welford::default();
            let mut u = vec![0.0; dims];
            for _ in 0..n {
                for v in u.iter_mut() {
                    *v = rng.random::<f64>();
                }
                acc.push(mis_observation(f, strategies, &u));
            }
            acc
        })
        .collect();
    let acc = accs.into_iter().fold(Welford::default(), Welford::merge);
    Estimate {
        value: acc.mean,
        error: acc.std_error(),
        evals: tuples * strategies.len() as u64,
        kind: ErrorKind::StandardError,
        converged: true,
    }
}

/// Uniform directions on the unit sphere (pdf 1/4π).
pub struct UniformSphere;
impl Strategy<Vector3<f64>> for UniformSphere {
    fn sample(&self, u: [f64; 2]) -> Option<Vector3<f64>> {
        let z = 1.0 - 2.0 * u[0];
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        Some(Vector3::new(r * phi.cos(), r * phi.sin(), z))
    }
    fn pdf(&self, _: &Vector3<f64>) -> f64 {
        1.0 / (4.0 * PI)
    }
}

/// Uniform directions on the upper hemisphere z > 0 (pdf 1/2π).
pub struct UniformHemisphere;
impl Strategy<Vector3<f64>> for UniformHemisphere {
    fn sample(&self, u: [f64; 2]) -> Option<Vector3<f64>> {
        let z = 1.0 - u[0];
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        Some(Vector3::new(r * phi.cos(), r * phi.sin(), z))
    }
    fn pdf(&self, w: &Vector3<f64>) -> f64 {
        if w.z > 0.0 {
            1.0 / (2.0 * PI)
        } else {
            0.0
        }
    }
}

/// Cosine-weighted directions on the upper hemisphere (pdf z/π).
pub struct CosineHemisphere;
impl Strategy<Vector3<f64>> for CosineHemisphere {
    fn sample(&self, u: [f64; 2]) -> Option<Vector3<f64>> {
        let r = u[0].sqrt();
        let phi = 2.0 * PI * u[1];
        let z = (1.0 - u[0]).max(0.0).sqrt();
        if z <= 0.0 {
            return None;
        }
        Some(Vector3::new(r * phi.cos(), r * phi.sin(), z))
    }
    fn pdf(&self, w: &Vector3<f64>) -> f64 {
        w.z.max(0.0) / PI
    }
}

/// Isotropic Gaussian on the plane with the given mean and standard deviation.
pub struct GaussianPlane {
    pub mean: Vector2<f64>,
    pub sigma: f64,
}
impl Strategy<Vector2<f64>> for GaussianPlane {
    fn sample(&self, u: [f64; 2]) -> Option<Vector2<f64>> {
        let r = self.sigma * (-2.0 * (1.0 - u[0]).ln()).sqrt();
        let phi = 2.0 * PI * u[1];
        Some(self.mean + Vector2::new(r * phi.cos(), r * phi.sin()))
    }
    fn pdf(&self, p: &Vector2<f64>) -> f64 {
        let d2 = (p - self.mean).norm_squared();
        (-0.5 * d2 / (self.sigma * self.sigma)).exp() / (2.0 * PI * self.sigma * self.sigma)
    }
}

/// Heavy-tailed plane density 1/(π s² (1 + r²/s²)²) (the unit GGX slope law scaled by s):
/// the right proposal for integrands with polynomial tails.
pub struct HeavyTailPlane {
    pub mean: Vector2<f64>,
    pub scale: f64,
}
impl Strategy<Vector2<f64>> for HeavyTailPlane {
    fn sample(&self, u: [f64; 2]) -> Option<Vector2<f64>> {
        if u[0] >= 1.0 {
            return None;
        }
        let r = self.scale * (u[0] / (1.0 - u[0])).sqrt();
        let phi = 2.0 * PI * u[1];
        Some(self.mean + Vector2::new(r * phi.cos(), r * phi.sin()))
    }
    fn pdf(&self, p: &Vector2<f64>) -> f64 {
        let s2 = self.scale * self.scale;
        let q = (p - self.mean).norm_squared() / s2;
        1.0 / (PI * s2 * (1.0 + q) * (1.0 + q))
    }
}

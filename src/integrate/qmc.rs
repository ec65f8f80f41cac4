//! Randomised quasi-Monte Carlo: Owen-scrambled Sobol points (sobol_burley) with
//! independent scrambling replicates; the error is the standard error over replicates.
//!
//! Crate limits, checked here rather than trusted: sobol_burley gives at most 2^16
//! points per scrambled sequence (in release builds it silently returns garbage beyond
//! that, so we refuse with [`Error::QmcTooManyPoints`]) and returns f32, i.e. 24 bits.
//! The missing low bits are filled with an independent uniform jitter in [0, 2^-24),
//! which keeps each replicate an unbiased randomised-QMC estimator in f64. More points
//! than 2^16 are obtained with more replicates. At most 128 MIS strategies (256 dims).

use super::estimate::{ErrorKind, Estimate, Welford};
use super::mc::{mis_observation, Strategy};
use crate::error::{Error, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Largest number of points per scrambled sequence supported by sobol_burley.
pub const MAX_POINTS: u64 = 1 << 16;

/// 64-bit mix (SplitMix64 finaliser) used to derive per-replicate seeds.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// RQMC estimate with `points` Sobol points per replicate and `replicates` replicates.
pub fn qmc_mis<P, F>(
    f: &F,
    strategies: &[&dyn Strategy<P>],
    points: u64,
    replicates: u32,
    seed: u64,
) -> Result<Estimate>
where
    F: Fn(&P) -> f64 + Sync,
{
    if points > MAX_POINTS {
        return Err(Error::QmcTooManyPoints {
            max: MAX_POINTS,
            asked: points,
        });
    }
    if replicates < 2 || points == 0 {
        return Err(Error::InvalidArgument(
            "QMC needs at least 2 replicates and 1 point for an error estimate".into(),
        ));
    }
    if strategies.is_empty() || strategies.len() > 128 {
        return Err(Error::InvalidArgument(
            "QMC needs between 1 and 128 strategies".into(),
        ));
    }
    let dims = 2 * strategies.len();
    let means: Vec<f64> = (0..replicates)
        .into_par_iter()
        .map(|r| {
            let h = mix(seed ^ mix(r as u64));
            let scramble = (h >> 32) as u32;
            let mut jitter = ChaCha8Rng::seed_from_u64(h);
            let mut u = vec![0.0; dims];
            let mut sum = 0.0;
            for i in 0..points as u32 {
                for (d, v) in u.iter_mut().enumerate() {
                    let s = sobol_burley::sample(i, d as u32, scramble) as f64;
                    let j = jitter.random::<f64>() * (1.0 / (1u64 << 24) as f64);
                    *v = (s + j).min(1.0 - f64::EPSILON / 2.0);
                }
                sum += mis_observation(f, strategies, &u);
            }
            sum / points as f64
        })
        .collect();
    let acc = means.iter().fold(Welford::default(), |mut a, &m| {
        a.push(m);
        a
    });
    Ok(Estimate {
        value: acc.mean,
        error: acc.std_error(),
        evals: points * replicates as u64 * strategies.len() as u64,
        kind: ErrorKind::StandardError,
        converged: true,
    })
}

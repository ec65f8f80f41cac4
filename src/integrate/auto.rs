//! Tolerance-driven entry point: the caller states the error it wants, the engine picks
//! the sample count / subdivision, and reports the error it actually reached and what it
//! cost. This is how users trade speed for accuracy.

use super::estimate::Estimate;
use super::mc::{mis, Strategy};
use super::qmc::{qmc_mis, MAX_POINTS};
use super::quad::Tol;
use super::sphere::{integrate_sphere, SphereRule};
use crate::error::{Error, Result};
use nalgebra::Vector3;
use serde::Serialize;
use std::time::Instant;

/// Which engine to drive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    Quadrature,
    MonteCarlo,
    Qmc,
}

/// An integral over directions, with the hints each engine needs.
pub struct SphereProblem<'a> {
    pub f: &'a (dyn Fn(&Vector3<f64>) -> f64 + Sync),
    /// Pole/scale layout for quadrature.
    pub rule: SphereRule,
    /// Sampling techniques for (Q)MC, combined with the balance heuristic.
    pub strategies: Vec<&'a dyn Strategy<Vector3<f64>>>,
}

/// What a tolerance-driven run achieved.
#[derive(Clone, Debug, Serialize)]
pub struct Solved {
    pub method: Method,
    pub estimate: Estimate,
    /// The absolute error that was asked for.
    pub target: f64,
    /// Whether the reported error is at or below the target.
    pub met: bool,
    /// Wall-clock seconds (informational only; never asserted).
    pub seconds: f64,
}

/// Integrate to an absolute `target` error within `max_evals` integrand evaluations.
pub fn solve(
    p: &SphereProblem,
    method: Method,
    target: f64,
    max_evals: u64,
    seed: u64,
) -> Result<Solved> {
    if !(target > 0.0) {
        return Err(Error::InvalidArgument(format!(
            "target error must be > 0, got {target:e}"
        )));
    }
    let t0 = Instant::now();
    let f = |w: &Vector3<f64>| (p.f)(w);
    let est = match method {
        Method::Quadrature => integrate_sphere(&f, &p.rule, Tol::new(target, 0.0, max_evals)),
        Method::MonteCarlo => {
            let k = p.strategies.len().max(1) as u64;
            let mut n: u64 = 1 << 12;
            loop {
                let e = mis(&f, &p.strategies, n, seed);
                // error ∝ n^(-1/2): predict the count that meets the target (+20 %)
                let want = ((n as f64) * (e.error / target).powi(2) * 1.2).ceil() as u64;
                if e.error <= target || n * k >= max_evals {
                    break e;
                }
                n = want.clamp(2 * n, (max_evals / k).max(n + 1));
            }
        }
        Method::Qmc => {
            let mut pts: u64 = 1 << 10;
            let mut reps: u32 = 16;
            let k = p.strategies.len().max(1) as u64;
            loop {
                let e = qmc_mis(&f, &p.strategies, pts, reps, seed)?;
                if e.error <= target || e.evals >= max_evals {
                    break e;
                }
                if pts < MAX_POINTS {
                    pts *= 4.min(MAX_POINTS / pts);
                } else {
                    reps *= 2;
                }
                if pts * reps as u64 * k > max_evals {
                    break e;
                }
            }
        }
    };
    let mut est = est;
    if method != Method::Quadrature {
        est.converged = est.error <= target;
    }
    Ok(Solved {
        method,
        met: est.error <= target,
        target,
        estimate: est,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

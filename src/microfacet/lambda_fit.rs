//! A better rational approximation of the Beckmann Smith Λ(ν) than Walter et al.'s
//! (seed 001 §3.2), fitted with argmin on points ν, judged on held-out points by the error
//! that matters for shading, |ΔG1| = |1/(1 + Λ̃) − 1/(1 + Λ)|.
//!
//! Form (six numbers; Walter's has five: four coefficients and the cut at 1.6):
//! Λ̃(ν) = (1 − ν/ν_c)²·(1 + a₁ν + a₂ν²)/(b₁ν + b₂ν² + b₃ν³) for ν < ν_c, 0 beyond.
//! The squared factor makes Λ̃ and its slope vanish at the cut — no jump and no negative
//! band (Walter's numerator changes sign at ν = 1.548, before his cut at 1.6).

use super::lambda;
use crate::error::{Error, Result};
use serde::Serialize;

/// Λ̃ with parameters [a₁, a₂, b₁, b₂, b₃, ν_c]. ν ≤ 0 → +∞ (as the exact Λ).
pub fn rational(p: &[f64], nu: f64) -> f64 {
    if nu.is_nan() {
        return f64::NAN;
    }
    if nu <= 0.0 {
        return f64::INFINITY;
    }
    if nu >= p[5] {
        return 0.0;
    }
    let c = 1.0 - nu / p[5];
    c * c * (1.0 + nu * (p[0] + nu * p[1])) / (nu * (p[2] + nu * (p[3] + nu * p[4])))
}

/// |ΔG1| of an approximation at ν.
pub fn dg1(f: &dyn Fn(f64) -> f64, nu: f64) -> f64 {
    (1.0 / (1.0 + f(nu)) - 1.0 / (1.0 + lambda::beckmann(nu))).abs()
}

/// Worst |ΔG1| over a set of ν and where.
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize)]
pub struct Worst {
    pub max_dg1: f64,
    pub at_nu: f64,
    pub points: usize,
}

pub fn worst(f: &dyn Fn(f64) -> f64, nus: &[f64]) -> Worst {
    let mut w = Worst {
        max_dg1: 0.0,
        at_nu: nus[0],
        points: nus.len(),
    };
    for &n in nus {
        let e = dg1(f, n);
        let e = if e.is_nan() { f64::INFINITY } else { e };
        if e > w.max_dg1 {
            w.max_dg1 = e;
            w.at_nu = n;
        }
    }
    w
}

/// ν grids on [lo, hi]: log-uniform training points (both ends) and held-out points half
/// a step off.
pub fn grids(n: usize, lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let r = (hi / lo).ln();
    let train = (0..n)
        .map(|i| lo * (r * i as f64 / (n - 1) as f64).exp())
        .collect();
    let held = (0..n - 1)
        .map(|i| lo * (r * (i as f64 + 0.5) / (n - 1) as f64).exp())
        .collect();
    (train, held)
}

/// Fit the six parameters with argmin's Nelder–Mead, minimising a smooth surrogate of the
/// max |ΔG1| (the L⁸ norm), from Walter's coefficients with b₃ = 0 and ν_c = 2.5; then a
/// few restarts from the best simplex vertex.
pub fn fit(train: &[f64], max_iters: u64) -> Result<(Vec<f64>, u64)> {
    use argmin::core::{CostFunction, Executor, State};
    use argmin::solver::neldermead::NelderMead;
    struct Obj<'a>(&'a [f64], Vec<f64>);
    impl CostFunction for Obj<'_> {
        type Param = Vec<f64>;
        type Output = f64;
        fn cost(&self, p: &Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
            if p[5] <= 0.5 || p[5] > 6.0 {
                return Ok(1e10);
            }
            let mut s = 0.0;
            for (&n, &exact) in self.0.iter().zip(&self.1) {
                let l = rational(p, n);
                let e = 1.0 / (1.0 + l) - exact;
                s += if e.is_finite() && l > -1.0 {
                    (e * 1e3).powi(8)
                } else {
                    1e30
                };
            }
            Ok((s / self.0.len() as f64).powf(1.0 / 8.0) * 1e-3)
        }
    }
    let exact: Vec<f64> = train
        .iter()
        .map(|&n| 1.0 / (1.0 + lambda::beckmann(n)))
        .collect();
    let mut start: Vec<f64> = vec![0.0, 0.0, 3.545, 2.0, 0.0, 2.5];
    let mut iters = 0;
    for round in 0..6 {
        let step = if round == 0 { 0.2 } else { 0.05 };
        let mut simplex = vec![start.clone()];
        for i in 0..start.len() {
            let mut v = start.clone();
            v[i] += if v[i] != 0.0 { step * v[i].abs() } else { step };
            simplex.push(v);
        }
        let solver = NelderMead::new(simplex)
            .with_sd_tolerance(1e-15)
            .map_err(|e| Error::InvalidArgument(format!("Nelder–Mead setup: {e}")))?;
        let res = Executor::new(Obj(train, exact.clone()), solver)
            .configure(|s| s.max_iters(max_iters))
            .run()
            .map_err(|e| Error::InvalidArgument(format!("Nelder–Mead: {e}")))?;
        iters += res.state().get_iter();
        start = res.state().get_best_param().cloned().unwrap_or(start);
    }
    Ok((start, iters))
}

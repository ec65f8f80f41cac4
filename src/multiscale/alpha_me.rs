//! Ways to get α_me from ‖b̄‖ (seed 000 §3.3), their fits and their measured errors.
//!
//! - `Paper`: seed 000 Eq 5 as printed.
//! - `PaperRefit`: the same rational form in ‖b̄‖ (degree 4/3, monic denominator), refitted.
//! - `Ours`: a form with the right limits, in y = 1 − ‖b̄‖ and s = ln(1/y):
//!   α = √(y/R(s)), R(s) = s/2 + (ln 2)/2 − 1 + ½ ln s + p₁/s + p₂/s² + p₃/s³ + p₄/s⁴.
//!   As α → 0, 1 − ‖b̄‖ = α²(ln(2/α) − 1) gives R = s/2 + ½ ln R + ln 2 − 1 → the fixed
//!   leading terms; p₁ is solved from R(ln 3) = 1/3 so that ‖b̄‖ = 2/3 ↦ α = 1 exactly.
//! - `Newton`: [`super::mrl::alpha_from_one_minus`] on the closed form (the reference).
//! - `Table`: ln α tabulated at uniform s with linear interpolation.

use super::mrl::{alpha_from_one_minus, alpha_me_paper, mrl_pair};
use serde::Serialize;

/// Fixed asymptotic constant of `Ours`: (ln 2)/2 − 1.
const C0: f64 = 0.5 * std::f64::consts::LN_2 - 1.0;

/// The fixed asymptotic part of R(s): s/2 + (ln 2)/2 − 1 + ½ ln s.
fn ours_base(s: f64) -> f64 {
    s * 0.5 + C0 + 0.5 * s.ln()
}

/// `Ours` evaluated from y = 1 − ‖b̄‖: α = √(y/R(s)), R(s) = base(s) + Σ_k c_k s^(−k),
/// k = 1…K (Horner in 1/s).
pub fn ours_eval(c: &[f64], y: f64) -> f64 {
    let s = -y.ln();
    let x = 1.0 / s;
    let mut p = 0.0;
    for &ck in c.iter().rev() {
        p = (p + ck) * x;
    }
    (y / (ours_base(s) + p)).sqrt()
}

/// Fit the K coefficients of `Ours` by weighted linear least squares (nalgebra SVD) on
/// the training α: R_i = y_i/α_i² is known exactly, the residual R_i − base(s_i) is
/// linear in the c_k, and weights 1/R_i make it a relative fit (α's relative error is
/// half of R's). The point α = 1 gets weight 1e6, pinning ‖b̄‖ = 2/3 ↦ α = 1.
pub fn fit_ours(k: usize, train: &[f64]) -> crate::error::Result<Vec<f64>> {
    let n = train.len();
    let mut a = nalgebra::DMatrix::<f64>::zeros(n, k);
    let mut rhs = nalgebra::DVector::<f64>::zeros(n);
    for (i, &al) in train.iter().enumerate() {
        let y = mrl_pair(al).1;
        let s = -y.ln();
        let r = y / (al * al);
        let w = if (al - 1.0).abs() < 1e-12 { 1e6 } else { 1.0 } / r;
        for j in 0..k {
            a[(i, j)] = w * s.powi(-(j as i32 + 1));
        }
        rhs[i] = w * (r - ours_base(s));
    }
    let svd = a.svd(true, true);
    let c = svd
        .solve(&rhs, 1e-14)
        .map_err(|e| crate::error::Error::InvalidArgument(format!("least squares: {e}")))?;
    Ok(c.iter().copied().collect())
}

/// The paper's rational form with coefficients (p4, p3, p2, p1, p0, q2, q1, q0).
pub fn paper_form(c: &[f64], b: f64) -> f64 {
    let num = (((c[0] * b + c[1]) * b + c[2]) * b + c[3]) * b + c[4];
    let den = ((b + c[5]) * b + c[6]) * b + c[7];
    num / den
}

/// Seed 000 Eq 5 coefficients in `paper_form` order.
pub const PAPER: [f64; 8] = [1.629, 17.05, -18.96, -23.37, 23.65, -28.07, 31.1, -3.545];

/// A lookup table of ln α at uniform s = ln(1/(1 − ‖b̄‖)).
#[derive(Clone, Debug, Serialize)]
pub struct Table {
    pub s0: f64,
    pub ds: f64,
    pub ln_alpha: Vec<f64>,
}

impl Table {
    /// n entries covering α ∈ [alpha_min, alpha_max], from the exact inverse.
    pub fn build(n: usize, alpha_min: f64, alpha_max: f64) -> Table {
        let s_lo = -mrl_pair(alpha_max).1.ln();
        let s_hi = -mrl_pair(alpha_min).1.ln();
        let ds = (s_hi - s_lo) / (n - 1) as f64;
        let ln_alpha = (0..n)
            .map(|i| {
                alpha_from_one_minus((-(s_lo + ds * i as f64)).exp())
                    .expect("in range")
                    .ln()
            })
            .collect();
        Table {
            s0: s_lo,
            ds,
            ln_alpha,
        }
    }
    pub fn eval(&self, y: f64) -> f64 {
        let x = ((-y.ln()) - self.s0) / self.ds;
        let n = self.ln_alpha.len();
        let i = (x.floor().max(0.0) as usize).min(n - 2);
        let f = (x - i as f64).clamp(0.0, 1.0);
        (self.ln_alpha[i] * (1.0 - f) + self.ln_alpha[i + 1] * f).exp()
    }
}

/// Error statistics of a method on held-out points.
#[derive(Clone, Debug, Serialize)]
pub struct HeldOut {
    pub points: usize,
    pub max_rel: f64,
    pub rms_rel: f64,
    pub worst_alpha: f64,
    /// Signed relative error at the smallest and largest α of the set.
    pub rel_at_min: f64,
    pub rel_at_max: f64,
}

/// Held-out α grid: `n` log-spaced points in [lo, hi] shifted by half a step from any
/// training grid of the same size (so no held-out point is a training point).
pub fn held_out_alphas(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    let r = (hi / lo).ln();
    (0..n)
        .map(|i| lo * (r * (i as f64 + 0.5) / n as f64).exp())
        .collect()
}

/// Training α grid: n log-spaced points including both ends.
pub fn training_alphas(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    let r = (hi / lo).ln();
    (0..n)
        .map(|i| lo * (r * i as f64 / (n - 1) as f64).exp())
        .collect()
}

/// Evaluate a method (given as α from (‖b̄‖, 1 − ‖b̄‖)) on α points.
pub fn held_out(alphas: &[f64], f: &dyn Fn(f64, f64) -> f64) -> HeldOut {
    let mut max_rel = 0.0f64;
    let mut worst = alphas[0];
    let mut ss = 0.0;
    let mut first = 0.0;
    let mut last = 0.0;
    for (k, &a) in alphas.iter().enumerate() {
        let (b, y) = mrl_pair(a);
        let e = (f(b, y) - a) / a;
        let e = if e.is_nan() { f64::INFINITY } else { e };
        if e.abs() > max_rel {
            max_rel = e.abs();
            worst = a;
        }
        ss += e * e;
        if k == 0 {
            first = e;
        }
        last = e;
    }
    HeldOut {
        points: alphas.len(),
        max_rel,
        rms_rel: (ss / alphas.len() as f64).sqrt(),
        worst_alpha: worst,
        rel_at_min: first,
        rel_at_max: last,
    }
}

/// Paper Eq 5 as a method.
pub fn paper_method(b: f64, _y: f64) -> f64 {
    alpha_me_paper(b)
}

/// Result of a Nelder–Mead fit.
#[derive(Clone, Debug, Serialize)]
pub struct Fitted {
    pub params: Vec<f64>,
    /// Training objective at the optimum (mean squared relative α error).
    pub objective: f64,
    pub iterations: u64,
}

/// Minimise the mean squared relative α error of `model(params, b, y)` over the training
/// α grid with argmin's Nelder–Mead from `start` (simplex: start + `step` on each axis).
pub fn fit_nelder_mead(
    model: &(dyn Fn(&[f64], f64, f64) -> f64 + Sync),
    start: &[f64],
    step: f64,
    train: &[f64],
    max_iters: u64,
    tol: f64,
) -> crate::error::Result<Fitted> {
    use argmin::core::{CostFunction, Executor, State};
    use argmin::solver::neldermead::NelderMead;
    let pts: Vec<(f64, f64, f64)> = train
        .iter()
        .map(|&a| {
            let (b, y) = mrl_pair(a);
            (a, b, y)
        })
        .collect();
    struct Obj<'a> {
        model: &'a (dyn Fn(&[f64], f64, f64) -> f64 + Sync),
        pts: &'a [(f64, f64, f64)],
    }
    impl CostFunction for Obj<'_> {
        type Param = Vec<f64>;
        type Output = f64;
        fn cost(&self, p: &Vec<f64>) -> Result<f64, argmin::core::Error> {
            let mut s = 0.0;
            for &(a, b, y) in self.pts {
                let e = ((self.model)(p, b, y) - a) / a;
                s += if e.is_finite() { e * e } else { 1e6 };
            }
            Ok(s / self.pts.len() as f64)
        }
    }
    let mut simplex = vec![start.to_vec()];
    for i in 0..start.len() {
        let mut v = start.to_vec();
        v[i] += if v[i] != 0.0 { step * v[i].abs() } else { step };
        simplex.push(v);
    }
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(tol)
        .map_err(|e| crate::error::Error::InvalidArgument(format!("Nelder–Mead setup: {e}")))?;
    let res = Executor::new(Obj { model, pts: &pts }, solver)
        .configure(|s| s.max_iters(max_iters))
        .run()
        .map_err(|e| crate::error::Error::InvalidArgument(format!("Nelder–Mead: {e}")))?;
    let st = res.state();
    Ok(Fitted {
        params: st
            .get_best_param()
            .cloned()
            .unwrap_or_else(|| start.to_vec()),
        objective: st.get_best_cost(),
        iterations: st.get_iter(),
    })
}

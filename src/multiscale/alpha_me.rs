//! Ways to get α_me from ‖b̄‖ (seed 000 §3.3), their fits and their measured errors.
//!
//! - `Paper`: seed 000 Eq 5 as printed.
//! - `PaperRefit`: the same rational form in ‖b̄‖ (degree 4/3, monic denominator), refitted.
//! - `Ours`: two branches that meet at ‖b̄‖ = 2/3 ↦ α = 1, each with the exact limit of
//!   its end, so that the form is total over y = 1 − ‖b̄‖ ∈ [0, 1]:
//!   - y ≤ 1/3 (α ≤ 1), in s = ln(1/y): α = √(y/R(s)),
//!     R(s) = s/2 + (ln 2)/2 − 1 + ½ ln s + p₁/s + … + p_K/s^K.
//!     As α → 0, 1 − ‖b̄‖ = α²(ln(2/α) − 1) gives R = s/2 + ½ ln R + ln 2 − 1 → the fixed
//!     leading terms (α = 0 at y = 0 exactly);
//!   - y > 1/3 (α > 1), in b = ‖b̄‖ = 1 − y: α = (π/2) g(b)/b, g(b) = 1 + d₁b + … + d_L b^L.
//!     As α → ∞, ‖b̄‖ = π/(2α) − 2/α² + … (mrl.rs), so g(0) = 1 is the exact asymptote.
//!   Both branches are pinned at ‖b̄‖ = 2/3 ↦ α = 1.
//! - `Newton`: [`super::mrl::alpha_from_one_minus`] on the closed form (the reference).
//! - `Table`: ln α tabulated at uniform s with linear interpolation.

use super::mrl::{alpha_from_one_minus, alpha_me_paper, mrl_pair};
use num_traits::Float;
use serde::Serialize;

/// Fixed asymptotic constant of `Ours`: (ln 2)/2 − 1.
const C0: f64 = 0.5 * std::f64::consts::LN_2 - 1.0;

/// The fixed asymptotic part of R(s): s/2 + (ln 2)/2 − 1 + ½ ln s.
fn ours_base(s: f64) -> f64 {
    s * 0.5 + C0 + 0.5 * s.ln()
}

/// The two coefficient sets of `Ours`: `small` (the p_k of the α ≤ 1 branch, in 1/s) and
/// `large` (the d_k of the α > 1 branch, in b).
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct OursFit {
    pub small: Vec<f64>,
    pub large: Vec<f64>,
}

impl OursFit {
    /// α from y = 1 − ‖b̄‖ (f64); see [`ours_eval_t`].
    pub fn eval(&self, y: f64) -> f64 {
        ours_eval_t(&self.small, &self.large, y)
    }
    /// The coefficients rounded to f32, as the shaders hold them.
    pub fn to_f32(&self) -> (Vec<f32>, Vec<f32>) {
        (
            self.small.iter().map(|&c| c as f32).collect(),
            self.large.iter().map(|&c| c as f32).collect(),
        )
    }
    /// The same form in f32 with the coefficients rounded to f32 (allocates them: for
    /// loops, take [`OursFit::to_f32`] once and call [`ours_eval_t`]).
    pub fn eval_f32(&self, y: f32) -> f32 {
        let (s, l) = self.to_f32();
        ours_eval_t(&s, &l, y)
    }
}

/// `Ours` evaluated from y = 1 − ‖b̄‖ in any float type (the f64 reference and the f32
/// shading form are this one function). Total: y is clamped to [m, 1] with m the smallest
/// normal number (NaN maps to m), and b = 1 − y to ≥ m, so every input gives a finite α ≥ 0;
/// y ≤ m gives the α → 0 end (≈ 1.6e-20 in f32) and y = 1 the α → ∞ end (π/(2m)).
/// For y ≥ ½, b = 1 − y is exact in binary arithmetic (Sterbenz), so the large-α branch
/// adds no input rounding of its own.
pub fn ours_eval_t<T: Float>(small: &[T], large: &[T], y: T) -> T {
    ours_eval_pair_t(small, large, y, T::one() - y)
}

/// The same from the pair (y, b) = (1 − ‖b̄‖, ‖b̄‖), each clamped to [m, 1]: the large-α
/// branch reads b, so a tiny ‖b̄‖ known as such (a product of two, say) keeps its precision.
pub fn ours_eval_pair_t<T: Float>(small: &[T], large: &[T], y: T, b: T) -> T {
    let m = T::min_positive_value();
    let one = T::one();
    let y = y.max(m).min(one);
    let third = T::from(1.0 / 3.0).unwrap_or(one);
    if y > third {
        let b = b.max(m).min(one);
        let mut g = T::zero();
        for &dk in large.iter().rev() {
            g = (g + dk) * b;
        }
        let half_pi = T::from(std::f64::consts::FRAC_PI_2).unwrap_or(one);
        return half_pi * (one + g) / b;
    }
    let s = -y.ln();
    let x = one / s;
    let mut p = T::zero();
    for &ck in small.iter().rev() {
        p = (p + ck) * x;
    }
    let half = T::from(0.5).unwrap_or(one);
    let c0 = T::from(C0).unwrap_or(one);
    (y / (s * half + c0 + half * s.ln() + p)).sqrt()
}

/// Fit both branches of `Ours` by weighted linear least squares (nalgebra SVD) on the
/// training α: `k_small` coefficients on the points α ≤ 1 and `k_large` on α ≥ 1.
///
/// Small branch: R_i = y_i/α_i² is known exactly, the residual R_i − base(s_i) is linear in
/// the p_k, and weights 1/R_i make it a relative fit (α's relative error is half of R's).
/// Large branch: g_i = 2 b_i α_i/π is known exactly, g_i − 1 is linear in the d_k, and
/// weights 1/g_i make it a relative fit (α's relative error is g's). In both, the point
/// α = 1 gets weight 1e6, pinning ‖b̄‖ = 2/3 ↦ α = 1 (it is added when the grid lacks it).
pub fn fit_ours(k_small: usize, k_large: usize, train: &[f64]) -> crate::error::Result<OursFit> {
    let mut small_pts: Vec<f64> = train.iter().copied().filter(|&a| a <= 1.0).collect();
    let mut large_pts: Vec<f64> = train.iter().copied().filter(|&a| a >= 1.0).collect();
    for pts in [&mut small_pts, &mut large_pts] {
        if !pts.iter().any(|&a| (a - 1.0).abs() < 1e-12) {
            pts.push(1.0);
        }
    }
    let rows_small: Vec<(Vec<f64>, f64)> = small_pts
        .iter()
        .map(|&al| {
            let y = mrl_pair(al).1;
            let s = -y.ln();
            let r = y / (al * al);
            let w = if (al - 1.0).abs() < 1e-12 { 1e6 } else { 1.0 } / r;
            let row = (0..k_small).map(|j| w * s.powi(-(j as i32 + 1))).collect();
            (row, w * (r - ours_base(s)))
        })
        .collect();
    let rows_large: Vec<(Vec<f64>, f64)> = large_pts
        .iter()
        .map(|&al| {
            let b = mrl_pair(al).0;
            let g = 2.0 * b * al / std::f64::consts::PI;
            let w = if (al - 1.0).abs() < 1e-12 { 1e6 } else { 1.0 } / g;
            let row = (0..k_large).map(|j| w * b.powi(j as i32 + 1)).collect();
            (row, w * (g - 1.0))
        })
        .collect();
    Ok(OursFit {
        small: weighted_lsq(&rows_small, k_small)?,
        large: weighted_lsq(&rows_large, k_large)?,
    })
}

/// Solve the least-squares system whose rows are (coefficients, right-hand side).
fn weighted_lsq(rows: &[(Vec<f64>, f64)], k: usize) -> crate::error::Result<Vec<f64>> {
    if k == 0 {
        return Ok(Vec::new());
    }
    if rows.len() < k {
        return Err(crate::error::Error::InvalidArgument(format!(
            "least squares: {} points for {k} coefficients",
            rows.len()
        )));
    }
    let a = nalgebra::DMatrix::<f64>::from_fn(rows.len(), k, |i, j| rows[i].0[j]);
    let rhs = nalgebra::DVector::<f64>::from_fn(rows.len(), |i, _| rows[i].1);
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
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
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

/// The α_me fit's settings, as fits/multiscale-alpha-me.toml sets them (the α_me study,
/// the convolution study and `eval` read them).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Coefficients of the small-α branch (c_k).
    pub terms: usize,
    /// Coefficients of the α > 1 branch (d_k).
    pub terms_large: usize,
    pub alpha_min: f64,
    pub alpha_max: f64,
    pub training_points: usize,
    pub held_out_points: usize,
    /// Entries of the lookup table in s.
    pub table_entries: usize,
    /// Nelder–Mead refit of Eq 5's form: iteration cap and tolerance.
    pub refit_max_iters: u64,
    pub refit_tolerance: f64,
}

impl crate::fit::spec::Params for Settings {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::{alpha_range, within};
        within("terms", self.terms, 1, 16)?;
        within("terms_large", self.terms_large, 1, 16)?;
        alpha_range(self.alpha_min, self.alpha_max, 1e-8, 1e4)?;
        if !(self.alpha_min < 1.0 && self.alpha_max > 1.0) {
            return Err(format!(
                "alpha_min … alpha_max must contain α = 1 (both branches are pinned there), got [{:e}, {:e}]",
                self.alpha_min, self.alpha_max
            ));
        }
        within(
            "training_points",
            self.training_points,
            self.terms + self.terms_large + 2,
            200_000,
        )?;
        within("held_out_points", self.held_out_points, 2, 200_000)?;
        within("table_entries", self.table_entries, 2, 65_536)?;
        within("refit_max_iters", self.refit_max_iters, 1, 1_000_000)?;
        within("refit_tolerance", self.refit_tolerance, 1e-300, 0.5)
    }
}

impl Settings {
    /// Our α_me fit at these settings.
    pub fn fit(&self) -> crate::error::Result<OursFit> {
        fit_ours(
            self.terms,
            self.terms_large,
            &training_alphas(self.training_points, self.alpha_min, self.alpha_max),
        )
    }
}

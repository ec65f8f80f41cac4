//! The α_me study's computation: the fits, their held-out errors, the whole-range check and
//! the Eq 5 audit.

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::multiscale::alpha_me::{
    fit_nelder_mead, fit_ours, held_out, held_out_alphas, ours_eval_pair_t, ours_eval_t,
    paper_form, paper_method, training_alphas, HeldOut, Table, PAPER,
};
use crate::multiscale::mrl::{alpha_from_one_minus, alpha_from_pair, alpha_me_paper};
use crate::results::alpha_me::WholeRange;

/// Sign changes of f on a fine grid of (lo, hi), refined by bisection.
pub(super) fn roots(f: &dyn Fn(f64) -> f64, lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let mut out = Vec::new();
    let mut prev = (lo, f(lo));
    for i in 1..=n {
        let x = lo + (hi - lo) * i as f64 / n as f64;
        let fx = f(x);
        if prev.1.signum() != fx.signum() {
            let (mut a, mut b) = (prev.0, x);
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if f(m).signum() == f(a).signum() {
                    a = m;
                } else {
                    b = m;
                }
            }
            out.push(0.5 * (a + b));
        }
        prev = (x, fx);
    }
    out
}

/// Everything the study computes; the plots and the report only read it.
pub(super) struct Computed {
    pub lo: f64,
    pub hi: f64,
    pub c: crate::multiscale::alpha_me::OursFit,
    pub refit: crate::multiscale::alpha_me::Fitted,
    pub h_ours: HeldOut,
    pub h_refit: HeldOut,
    pub h_paper: HeldOut,
    pub table: Table,
    pub h_table: HeldOut,
    pub h_newton: HeldOut,
    pub whole: WholeRange,
    pub poles: Vec<f64>,
    pub zeros: Vec<f64>,
    pub at_one: f64,
    pub at_two_thirds: f64,
    pub sign_alpha: Vec<String>,
    pub pole_alpha: Vec<String>,
}

/// The fits, their held-out errors, the whole-range check and the audit of Eq 5.
pub(super) fn compute(spec: &FitSpec) -> Result<Computed> {
    if !spec.name.starts_with("multiscale-alpha-me") {
        return Err(Error::InvalidArgument(format!(
            "no fit routine for spec '{}'",
            spec.name
        )));
    }
    spec.validate(&spec.name)?;
    let (lo, hi) = (spec.domain.alpha_min, spec.domain.alpha_max);
    let train = training_alphas(spec.training.points, lo, hi);
    let held = held_out_alphas(spec.held_out.points, lo, hi);
    let pb = crate::progress::Progress::new("multiscale", 4);
    // ours: weighted linear least squares
    let c = fit_ours(spec.terms, spec.terms_large, &train)?;
    let h_ours = held_out(&held, &|_b, y| c.eval(y));
    pb.inc(1);
    // the paper's form, refitted with argmin (Nelder–Mead) from the printed coefficients
    let refit = fit_nelder_mead(
        &|p, b, _y| paper_form(p, b),
        &PAPER,
        0.05,
        &train,
        spec.baseline_optimiser.max_iters.unwrap_or(20_000),
        spec.baseline_optimiser.tolerance.unwrap_or(1e-16),
    )?;
    let h_refit = held_out(&held, &|b, _y| paper_form(&refit.params, b));
    pb.inc(1);
    let h_paper = held_out(&held, &paper_method);
    let table = Table::build(spec.table_entries, lo, hi);
    let h_table = held_out(&held, &|_b, y| table.eval(y));
    let h_newton = held_out(&held, &|_b, y| alpha_from_one_minus(y).unwrap_or(f64::NAN));
    let whole = whole_range(&c);
    pb.inc(1);

    // audit of Eq 5 over the whole range ‖b̄‖ ∈ (0, 1)
    let den = |b: f64| ((b - 28.07) * b + 31.1) * b - 3.545;
    let num = |b: f64| (((1.629 * b + 17.05) * b - 18.96) * b - 23.37) * b + 23.65;
    let poles = roots(&den, 1e-6, 1.0 - 1e-12, 100_000);
    let zeros = roots(&num, 1e-6, 1.0 - 1e-12, 100_000);
    let at_one = alpha_me_paper(1.0);
    let at_two_thirds = alpha_me_paper(2.0 / 3.0);
    let sign_alpha: Vec<String> = zeros
        .iter()
        .map(|&b| {
            format!(
                "‖b̄‖ = {b:.9} (exact α there = {:.4e})",
                alpha_from_one_minus(1.0 - b).unwrap_or(f64::NAN)
            )
        })
        .collect();
    let pole_alpha: Vec<String> = poles
        .iter()
        .map(|&b| {
            format!(
                "‖b̄‖ = {b:.6} (exact α there = {:.4})",
                alpha_from_one_minus(1.0 - b).unwrap_or(f64::NAN)
            )
        })
        .collect();
    pb.finish();
    Ok(Computed {
        lo,
        hi,
        c,
        refit,
        h_ours,
        h_refit,
        h_paper,
        table,
        h_table,
        h_newton,
        whole,
        poles,
        zeros,
        at_one,
        at_two_thirds,
        sign_alpha,
        pole_alpha,
    })
}

/// Evaluate `Ours` against the exact inverse from y = 1e-300 to b = 1e-300.
pub fn whole_range(c: &crate::multiscale::alpha_me::OursFit) -> WholeRange {
    let mut pts: Vec<(f64, f64)> = Vec::new(); // (b, y), both exact
    let n = 1500;
    for i in 0..n {
        // y from 1e-300 to 1/3 and b from 1e-300 to 2/3, log-spaced
        let f = i as f64 / (n - 1) as f64;
        let y = (1e-300f64.ln() + f * ((1.0f64 / 3.0).ln() - 1e-300f64.ln())).exp();
        pts.push((1.0 - y, y));
        let b = (1e-300f64.ln() + f * ((2.0f64 / 3.0).ln() - 1e-300f64.ln())).exp();
        pts.push((b, 1.0 - b));
    }
    let mut w = WholeRange {
        points: pts.len(),
        alpha_range: [f64::INFINITY, 0.0],
        f64_max_rel: 0.0,
        f64_worst_alpha: f64::NAN,
        f32_max_rel: 0.0,
        f32_worst_alpha: f64::NAN,
        in_range_f64_max_rel: 0.0,
        in_range_f32_max_rel: 0.0,
        total: true,
    };
    let c32 = c.to_f32();
    // the pair form: a tiny ‖b̄‖ reaches the large-α branch with its full precision
    let eval_b = |b: f64, y: f64| ours_eval_pair_t(&c.small, &c.large, y, b);
    for &(b, y) in &pts {
        let Ok(exact) = alpha_from_pair(b, y) else {
            continue;
        };
        w.alpha_range[0] = w.alpha_range[0].min(exact);
        w.alpha_range[1] = w.alpha_range[1].max(exact);
        let v = eval_b(b, y);
        let e = ((v - exact) / exact).abs();
        let inside = (1e-4..=1e2).contains(&exact);
        if !(v.is_finite() && v >= 0.0) {
            w.total = false;
        }
        if e > w.f64_max_rel || e.is_nan() {
            w.f64_max_rel = if e.is_nan() { f64::INFINITY } else { e };
            w.f64_worst_alpha = exact;
        }
        if inside {
            w.in_range_f64_max_rel = w.in_range_f64_max_rel.max(e);
        }
        // the f32 form at the f32 input (y ≥ ½ keeps b = 1 − y exact; below, y itself)
        let y32 = y as f32;
        if y32 >= f32::MIN_POSITIVE && y32 < 1.0 && (1.0 - y32) >= f32::MIN_POSITIVE {
            let v32 = ours_eval_t(&c32.0, &c32.1, y32) as f64;
            let (b32, yy) = (1.0 - y32 as f64, y32 as f64);
            if let Ok(ex32) = alpha_from_pair(b32, yy) {
                let e32 = ((v32 - ex32) / ex32).abs();
                if !(v32.is_finite() && v32 >= 0.0) {
                    w.total = false;
                }
                if e32 > w.f32_max_rel || e32.is_nan() {
                    w.f32_max_rel = if e32.is_nan() { f64::INFINITY } else { e32 };
                    w.f32_worst_alpha = ex32;
                }
                if (1e-4..=1e2).contains(&ex32) {
                    w.in_range_f32_max_rel = w.in_range_f32_max_rel.max(e32);
                }
            }
        }
    }
    for y in [0.0f32, 1.0, f32::NAN, -1.0, 2.0, f32::INFINITY] {
        let v = ours_eval_t(&c32.0, &c32.1, y);
        if !(v.is_finite() && v >= 0.0) {
            w.total = false;
        }
    }
    for y in [0.0f64, 1.0, f64::NAN, -1.0, 2.0, f64::INFINITY] {
        let v = c.eval(y);
        if !(v.is_finite() && v >= 0.0) {
            w.total = false;
        }
    }
    w
}

//! The α_me study's computation: the fits, their held-out errors, the whole-range check and
//! the Eq 5 audit.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::multiscale::alpha_me::Settings as Params;
use crate::multiscale::alpha_me::{
    fit_nelder_mead, fit_ours, held_out, held_out_alphas, ours_eval_pair_t, ours_eval_t,
    paper_form, paper_method, training_alphas, Fitted, HeldOut, OursFit, Table, PAPER,
};
use crate::multiscale::mrl::{alpha_from_one_minus, alpha_from_pair, alpha_me_paper, mrl_pair};
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
    /// (‖b̄‖, exact α there) where Eq 5's numerator changes sign, and at its poles in (0, 1).
    pub sign_alpha: Vec<(f64, f64)>,
    pub pole_alpha: Vec<(f64, f64)>,
    /// Eq 5's relative error at the fit domain's edge α = 1e-3 and at α = 0.01: (α, error).
    pub eq5_at: [(f64, f64); 2],
    pub curves: Curves,
    /// The parameters it ran with.
    pub params: Params,
    /// The typed result, as results/fits/multiscale-alpha-me.json holds it.
    pub result: crate::results::alpha_me::AlphaMe,
}

/// The plotted curves, beyond the fit domain on both sides: (name, (α or 1 − ‖b̄‖, value)).
pub(super) struct Curves {
    /// Relative error in α of each method.
    pub rel: Vec<(String, Vec<(f64, f64)>)>,
    /// Absolute error of Eq 5.
    pub abs_eq5: Vec<(f64, f64)>,
    /// α_me against 1 − ‖b̄‖ (positive values only).
    pub mrl: Vec<(String, Vec<(f64, f64)>)>,
}

/// The curves of the plots, on 400 α log-spaced over [0.01·lo, 10·hi].
fn curves(spec: &Params, lo: f64, hi: f64, c: &OursFit, refit: &Fitted, table: &Table) -> Curves {
    let curve: Vec<f64> = held_out_alphas(400, 0.01 * lo, 10.0 * hi);
    let rel = |f: &dyn Fn(f64, f64) -> f64| -> Vec<(f64, f64)> {
        curve
            .iter()
            .map(|&a| {
                let (b, y) = mrl_pair(a);
                (a, ((f(b, y) - a) / a).abs().max(1e-17))
            })
            .collect()
    };
    let abs_eq5 = curve
        .iter()
        .map(|&a| {
            let (b, _) = mrl_pair(a);
            (a, (alpha_me_paper(b) - a).abs().max(1e-17))
        })
        .collect();
    let mrl_curve = |f: &dyn Fn(f64, f64) -> f64| -> Vec<(f64, f64)> {
        curve
            .iter()
            .filter_map(|&a| {
                let (b, y) = mrl_pair(a);
                let v = f(b, y);
                (v > 0.0).then_some((y, v))
            })
            .collect()
    };
    Curves {
        rel: vec![
            ("paper Eq 5".into(), rel(&paper_method)),
            (
                "paper form, refitted".into(),
                rel(&|b, _y| paper_form(&refit.params, b)),
            ),
            (
                format!("ours ({} + {} terms)", spec.terms, spec.terms_large),
                rel(&|_b, y| c.eval(y)),
            ),
            (
                format!("table ({} entries)", spec.table_entries),
                rel(&|_b, y| table.eval(y)),
            ),
        ],
        abs_eq5,
        mrl: vec![
            (
                "exact (closed form inverse)".into(),
                mrl_curve(&|_b, y| alpha_from_one_minus(y).unwrap_or(f64::NAN)),
            ),
            ("paper Eq 5".into(), mrl_curve(&paper_method)),
            ("ours".into(), mrl_curve(&|_b, y| c.eval(y))),
        ],
    }
}

/// The fits, their held-out errors, the whole-range check and the audit of Eq 5.
pub(super) fn compute(spec: &FitSpec, pa: &Params) -> Result<Computed> {
    let (lo, hi) = (pa.alpha_min, pa.alpha_max);
    let train = training_alphas(pa.training_points, lo, hi);
    let held = held_out_alphas(pa.held_out_points, lo, hi);
    let pb = crate::progress::Progress::new("multiscale", 4);
    // ours: weighted linear least squares
    let c = fit_ours(pa.terms, pa.terms_large, &train)?;
    let h_ours = held_out(&held, &|_b, y| c.eval(y));
    pb.inc(1);
    // the paper's form, refitted with argmin (Nelder–Mead) from the printed coefficients
    let refit = fit_nelder_mead(
        &|p, b, _y| paper_form(p, b),
        &PAPER,
        0.05,
        &train,
        pa.refit_max_iters,
        pa.refit_tolerance,
    )?;
    let h_refit = held_out(&held, &|b, _y| paper_form(&refit.params, b));
    pb.inc(1);
    let h_paper = held_out(&held, &paper_method);
    let table = Table::build(pa.table_entries, lo, hi);
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
    // where Eq 5's numerator and denominator vanish, with the exact α there
    let exact_at = |b: &f64| (*b, alpha_from_one_minus(1.0 - b).unwrap_or(f64::NAN));
    let sign_alpha = zeros.iter().map(exact_at).collect();
    let pole_alpha = poles.iter().map(exact_at).collect();
    let eq5_at = [1e-3, 1e-2].map(|a| (a, (alpha_me_paper(mrl_pair(a).0) - a) / a));
    let curves = curves(pa, lo, hi, &c, &refit, &table);
    pb.finish();
    let result = result(
        spec,
        pa,
        &c,
        &refit,
        [&h_ours, &h_paper, &h_refit, &h_table, &h_newton],
        &table,
        &whole,
        [at_one, at_two_thirds],
        &zeros,
        &poles,
    );
    Ok(Computed {
        lo,
        hi,
        sign_alpha,
        pole_alpha,
        eq5_at,
        curves,
        params: pa.clone(),
        result,
    })
}

/// The typed result of the study.
#[allow(clippy::too_many_arguments)]
fn result(
    spec: &FitSpec,
    pa: &Params,
    c: &OursFit,
    refit: &Fitted,
    [h_ours, h_paper, h_refit, h_table, h_newton]: [&HeldOut; 5],
    table: &Table,
    whole: &WholeRange,
    [at_one, at_two_thirds]: [f64; 2],
    zeros: &[f64],
    poles: &[f64],
) -> crate::results::alpha_me::AlphaMe {
    use crate::results::alpha_me::{
        AlphaMe, Eq5Audit, Method, NewtonMethod, Ours, Refit, TableMethod,
    };
    AlphaMe {
        spec: spec.clone(),
        command: crate::results::command(&spec.name),
        ours: Ours {
            coefficients: c.small.clone(),
            coefficients_large: c.large.clone(),
            held_out: h_ours.clone(),
            whole_range: whole.clone(),
        },
        paper_eq5: Method {
            coefficients: PAPER.to_vec(),
            held_out: h_paper.clone(),
        },
        paper_form_refit: Refit {
            coefficients: refit.params.clone(),
            objective: refit.objective,
            iterations: refit.iterations,
            held_out: h_refit.clone(),
        },
        table: TableMethod {
            entries: pa.table_entries,
            s0: table.s0,
            ds: table.ds,
            held_out: h_table.clone(),
        },
        newton_closed_form: NewtonMethod {
            held_out: h_newton.clone(),
        },
        integration_error: "none: the targets come from the closed form ‖b̄‖(α), verified against quadrature of Eq 4 to ≤ 1e-10 (results/proofs.md, mrl-closed-form)".into(),
        eq5_audit: Eq5Audit {
            alpha_at_b_1: at_one,
            alpha_at_b_2_3: at_two_thirds,
            numerator_roots_in_0_1: zeros.to_vec(),
            poles_in_0_1: poles.to_vec(),
        },
        passed: h_ours.max_rel <= spec.tolerance.max_rel,
    }
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

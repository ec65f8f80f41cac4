//! Every number the convolution study's report and plots show, computed from its fits:
//! the metric spread per pair, each model against the closed-form target and against each
//! metric, the paper's Eq 7 at its own limits, the study's verdict, and the plotted curves
//! and maps. The report and the plots format these and compute nothing.

use super::compute::{metric_value, models, stats, Computed, Stats};
use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::multiscale::alpha_me::held_out_alphas;
use crate::multiscale::overall::{alpha_moment, eq7, improved, sum_of_squares, Metric};

/// One model against the unclipped-moment target (results/fits/multiscale-convolution.json
/// `models`).
#[derive(Clone, Debug, serde::Serialize)]
pub(super) struct ModelRow {
    pub model: &'static str,
    pub held_out: Stats,
    pub held_out_target_le_1: Stats,
    pub limit_me0: f64,
    pub limit_mi0: f64,
}

/// One pair of the metric grid: the best α under each metric and their spread.
pub(super) struct SpreadRow {
    pub alpha_mi: f64,
    pub alpha_me: f64,
    /// The best α under each of `Metric::ALL`.
    pub values: Vec<f64>,
    /// max/min over the metrics.
    pub ratio: f64,
    pub cap_quad_rel_error: f64,
}

/// A heat map of the plots: title, values on the held-out grid [y][x], log10 range.
pub(super) type Map = (String, Vec<Vec<f64>>, (f64, f64));

/// One slice panel: α_mi and (model name, (α_me, α)) curves.
pub(super) type Slice = (f64, Vec<(String, Vec<(f64, f64)>)>);

/// Everything the report and the plots show.
pub(super) struct Judged {
    pub spread: Vec<SpreadRow>,
    /// The largest metric spread: (factor, α_mi, α_me).
    pub spread_max: (f64, f64, f64),
    pub models: Vec<ModelRow>,
    /// The polynomial's held-out max relative error on every held-out point.
    pub polynomial_all_held: f64,
    /// The unclipped moment's α at the grid's roughest corner (α_mi = α_me = hi).
    pub moment_at_corner: f64,
    /// Eq 7's relative deviation from α(α_mi, 0) = α_mi at α_mi = 0.01 and 1.
    pub eq7_limit: [(f64, f64); 2],
    /// Each model's max relative error in-sample on the metric grid, per metric (points
    /// whose α ≤ 1).
    pub per_metric_in_sample: Vec<(&'static str, Vec<f64>)>,
    /// Whether the per-metric models gate the verdict (metric grid ≥ 20 points).
    pub gate: bool,
    /// Whether every per-metric model meets the tolerance on held-out points.
    pub metrics_ok: bool,
    pub passed: bool,
    pub slices: Vec<Slice>,
    pub maps: Vec<Map>,
}

/// Judge the fits of `c` (spec `spec`).
pub(super) fn judge(spec: &FitSpec, c: &Computed) -> Result<Judged> {
    let models_ = models(c);
    let spread: Vec<SpreadRow> = c
        .fits
        .iter()
        .map(|p| {
            let values: Vec<f64> = Metric::ALL.iter().map(|&k| metric_value(p, k)).collect();
            let (mn, mx) = values
                .iter()
                .fold((f64::INFINITY, 0.0f64), |a, &x| (a.0.min(x), a.1.max(x)));
            SpreadRow {
                alpha_mi: p.alpha_mi,
                alpha_me: p.alpha_me,
                values,
                ratio: mx / mn,
                cap_quad_rel_error: p.cap_quad_rel_error,
            }
        })
        .collect();
    let mut spread_max = (1.0f64, 0.0, 0.0);
    for r in &spread {
        if r.ratio > spread_max.0 {
            spread_max = (r.ratio, r.alpha_mi, r.alpha_me);
        }
    }
    let limit = |f: &dyn Fn(f64, f64) -> f64| -> (f64, f64) {
        let mut a = 0.0f64;
        let mut b = 0.0f64;
        for &t in &c.held_axis {
            a = a.max(((f(t, 1e-9) - t) / t).abs());
            b = b.max(((f(1e-9, t) - t) / t).abs());
        }
        (a, b)
    };
    let model_rows = models_
        .iter()
        .map(|(name, f)| {
            let (l1, l2) = limit(f.as_ref());
            ModelRow {
                model: name,
                held_out: stats(&c.held, f.as_ref()),
                held_out_target_le_1: stats(&c.held_clamp, f.as_ref()),
                limit_me0: l1,
                limit_mi0: l2,
            }
        })
        .collect();
    let per_metric_in_sample = models_
        .iter()
        .map(|(name, f)| {
            let cells = Metric::ALL
                .iter()
                .map(|&k| {
                    let pts: Vec<(f64, f64, f64)> = c
                        .fits
                        .iter()
                        .map(|p| (p.alpha_mi, p.alpha_me, metric_value(p, k)))
                        .filter(|p| p.2 <= 1.0)
                        .collect();
                    stats(&pts, f.as_ref()).max_rel
                })
                .collect();
            (*name, cells)
        })
        .collect();
    // the per-metric models have 10 coefficients: they are only judged (and gate `regen`)
    // when the metric grid has at least twice as many points (not at the quick preset)
    let gate = c.m * c.m >= 20;
    let metrics_ok = c
        .per_metric_corr
        .iter()
        .all(|r| r.3.max_rel <= spec.tolerance.max_rel);
    Ok(Judged {
        spread,
        spread_max,
        models: model_rows,
        polynomial_all_held: stats(&c.held, &|x, y| improved(&c.ci, x, y)).max_rel,
        moment_at_corner: alpha_moment(c.hi, c.hi)?,
        eq7_limit: [0.01, 1.0].map(|t| (t, (eq7(t, 0.0) - t) / t)),
        per_metric_in_sample,
        gate,
        metrics_ok,
        passed: c.passed_moment && (metrics_ok || !gate),
        slices: slices(c),
        maps: maps(c),
    })
}

/// α against α_me at three α_mi: the closed form and every model but the refitted Eq 7.
fn slices(c: &Computed) -> Vec<Slice> {
    let models = models(c);
    [0.03, 0.3, 1.0]
        .iter()
        .map(|&mi| {
            let ys = held_out_alphas(60, c.lo, c.hi);
            let curve =
                |f: &dyn Fn(f64, f64) -> f64| ys.iter().map(|&y| (y, f(mi, y))).collect::<Vec<_>>();
            let mut series = vec![(
                "moment (closed form)".to_string(),
                curve(&|x, y| alpha_moment(x, y).unwrap_or(f64::NAN)),
            )];
            for (name, f) in models
                .iter()
                .filter(|m| m.0 != "Eq 7 form, refitted (linear LS)")
            {
                series.push((name.to_string(), curve(f.as_ref())));
            }
            (mi, series)
        })
        .collect()
}

/// The target surface and each model's relative error on the held-out grid.
fn maps(c: &Computed) -> Vec<Map> {
    let map = |f: &dyn Fn(f64, f64) -> f64| -> Vec<Vec<f64>> {
        c.held_axis
            .iter()
            .map(|&y| c.held_axis.iter().map(|&x| f(x, y)).collect())
            .collect()
    };
    let rel = |f: &dyn Fn(f64, f64) -> f64| {
        map(&|x, y| {
            let a = alpha_moment(x, y).unwrap_or(f64::NAN);
            ((f(x, y) - a) / a).abs()
        })
    };
    let err = (-5.0, 0.0);
    vec![
        (
            "α (unclipped moment)".into(),
            map(&|x, y| alpha_moment(x, y).unwrap_or(f64::NAN)),
            (-2.0, 0.5),
        ),
        ("|rel. error| Eq 7".into(), rel(&eq7), err),
        ("|rel. error| α²-sum".into(), rel(&sum_of_squares), err),
        (
            "|rel. error| polynomial".into(),
            rel(&|x, y| improved(&c.ci, x, y)),
            err,
        ),
        (
            "|rel. error| ours".into(),
            rel(&|x, y| c.product(x, y)),
            err,
        ),
    ]
}

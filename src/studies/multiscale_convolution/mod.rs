//! `regen --only multiscale-convolution`: overall α(α_mi, α_me) under four metrics, the
//! paper's Eq 7 and its refit, engine rules, and a model with both limits built in
//! (seed 000 §3.4–3.5, Eq 6–7). Compute (the fits: [`compute`]; every number shown:
//! [`judged`]), then render (report: [`report`]; plots: [`plots`]; the typed result).
//!
//! - **Targets:** the unclipped moment metric in closed form (ρ(α) = ρ(α_me) ρ(α_mi)) on
//!   a dense `dense_points`² grid, log-uniform over [`alpha_min`, `alpha_max`]² (held out:
//!   half a step off); the clipped moment, L2 and caps metrics fitted per point by
//!   quadrature of Eq 6 and Brent (argmin) on a `metric_points`² grid.
//! - **Ours (moment metric):** α = α_me-fit(1 − ρ(α_me) ρ(α_mi)), the product identity
//!   through the fit of fits/multiscale-alpha-me.toml, no coefficients of its own. Other
//!   metrics: α_mom · exp(Σ c_i b_i) over 10 basis functions of s = α_mi/(α_mi + α_me),
//!   g = 4s(1 − s), p = α_mi α_me, l = ln hypot(α_mi, α_me) that vanish at both limits,
//!   fitted by SVD least squares with relative weights. Also reported: α² = α_mi² + α_me² +
//!   α_mi α_me P2(α_mi, α_me).
//! - **Baseline:** Eq 7 as printed, and refitted by least squares on its basis
//!   {α_mi², α_mi, α_me, α_mi α_me}.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::io::Outputs;
use crate::study::{Ctx, FitOutcome};
use serde::Serialize;
use std::path::Path;

mod compute;
mod judged;
mod params;
mod plots;
mod report;

use compute::{compute, Computed};
pub use params::Params;

/// One fit of a basis against one metric: its coefficients, in-sample and held-out.
#[derive(Serialize)]
struct MetricFit<'a> {
    metric: &'a crate::multiscale::overall::Metric,
    coefficients: &'a [f64],
    in_sample: &'a compute::Stats,
    held_out: &'a compute::Stats,
}

fn metric_fits(rows: &[compute::Row]) -> Vec<MetricFit<'_>> {
    rows.iter()
        .map(|(k, c, s, h)| MetricFit {
            metric: k,
            coefficients: c,
            in_sample: s,
            held_out: h,
        })
        .collect()
}

#[derive(Serialize)]
struct Coefficients<'a> {
    coefficients: &'a [f64],
    held_out: compute::Stats,
}

#[derive(Serialize)]
struct Eq7Refit<'a> {
    coefficients: &'a [f64],
    sse: f64,
    sse_paper_coefficients_same_grid: f64,
}

/// results/fits/multiscale-convolution.json.
#[derive(Serialize)]
struct ConvolutionResult<'a> {
    spec: &'a FitSpec,
    command: &'static str,
    ours: Coefficients<'a>,
    eq7_refit: Eq7Refit<'a>,
    models: &'a [judged::ModelRow],
    metric_grid: &'a [crate::multiscale::overall::PairFit],
    per_metric_polynomial: Vec<MetricFit<'a>>,
    per_metric_corrected: Vec<MetricFit<'a>>,
    metric_grid_held_out: &'a [crate::multiscale::overall::PairFit],
    passed: bool,
}

/// What the study computed: its fits and every number its reports show.
pub struct Convolution {
    spec: FitSpec,
    c: Computed,
    j: judged::Judged,
}

/// Fit and judge (the α_me spec is read from the run's other specs).
fn run(ctx: &Ctx) -> Result<Convolution> {
    let c = compute(ctx.spec, ctx.params()?, ctx.specs, ctx.preset)?;
    let j = judged::judge(ctx.spec, &c)?;
    Ok(Convolution {
        spec: ctx.spec.clone(),
        c,
        j,
    })
}

impl crate::study::Computed for Convolution {
    fn render(&self, set: &mut Outputs, results: &Path) -> Result<()> {
        let (spec, c, j) = (&self.spec, &self.c, &self.j);
        let mut md = report::models_section(spec, c, j);
        md.push_str(&report::per_metric_section(spec, c, j));
        md.push_str(&plots::write(set, j, &c.held_axis, results)?);
        set.put(results.join("multiscale-convolution.md"), md);
        let json = ConvolutionResult {
            spec,
            command: "cargo run --release -- regen --only multiscale-convolution",
            ours: Coefficients {
                coefficients: &c.ci,
                held_out: c.ours,
            },
            eq7_refit: Eq7Refit {
                coefficients: &c.c7,
                sse: c.sse7,
                sse_paper_coefficients_same_grid: c.sse_paper,
            },
            models: &j.models,
            metric_grid: &c.fits,
            per_metric_polynomial: metric_fits(&c.per_metric_ours),
            per_metric_corrected: metric_fits(&c.per_metric_corr),
            metric_grid_held_out: &c.held_fits,
            passed: j.passed,
        };
        crate::results::put_named(set, results, &spec.name, &json)?;
        Ok(())
    }
    fn outcome(&self) -> FitOutcome {
        let (spec, c, j) = (&self.spec, &self.c, &self.j);
        FitOutcome {
            passed: j.passed,
            ..FitOutcome::judged(
                spec,
                c.ours.max_rel,
                format!(
                    "ours {:.2e} max rel on the moment target (tol {:.0e}); per metric held-out {}; metric spread up to ×{:.3}",
                    c.ours.max_rel,
                    spec.tolerance.max_rel,
                    c.per_metric_corr
                        .iter()
                        .map(|r| format!("{:.2e}", r.3.max_rel))
                        .collect::<Vec<_>>()
                        .join("/"),
                    j.spread_max.0
                ),
            )
        }
    }
}

crate::study::study! {
    /// The convolution study, as the registry holds it.
    MultiscaleConvolution = "multiscale-convolution", after [], on request false, params Params, computes run
}

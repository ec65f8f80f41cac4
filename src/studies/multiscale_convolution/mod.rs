//! `regen --only multiscale-convolution`: overall α(α_mi, α_me) under four metrics, the
//! paper's Eq 7 and its refit, engine rules, and a model with both limits built in
//! (seed 000 §3.4–3.5, Eq 6–7). Compute ([`compute`]) → report ([`report`]) → plots
//! ([`plots`]) → the typed result.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::io::Outputs;
use crate::study::{Ctx, FitOutcome};
use serde::Serialize;

mod compute;
mod plots;
mod report;

use compute::{compute, Computed};

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
    models: Vec<report::ModelRow>,
    metric_grid: &'a [crate::multiscale::overall::PairFit],
    per_metric_polynomial: Vec<MetricFit<'a>>,
    per_metric_corrected: Vec<MetricFit<'a>>,
    metric_grid_held_out: &'a [crate::multiscale::overall::PairFit],
    passed: bool,
}

/// `all` is every spec of the fits directory: the α_me spec is taken from it.

/// The study: compute, report and plot, into `set`.
pub fn run(set: &mut Outputs, c: &Ctx) -> Result<FitOutcome> {
    let (spec, all, results, preset) = (c.spec, c.specs, c.results, c.preset);
    let c = compute(spec, all, preset)?;
    let (mut md, model_json, spread_max) = report::models_section(spec, &c)?;
    let (pm_md, passed) = report::per_metric_section(spec, &c);
    md.push_str(&pm_md);
    md.push_str(&plots::write(set, &c, results)?);
    set.put(&results.join("multiscale-convolution.md"), md.as_bytes());
    let Computed {
        ref ci,
        ref c7,
        sse7,
        sse_paper,
        ours,
        ref fits,
        ref held_fits,
        ref per_metric_ours,
        ref per_metric_corr,
        ..
    } = c;
    set.put(&results.join("multiscale-convolution.md"), md.as_bytes());
    let json = ConvolutionResult {
        spec,
        command: "cargo run --release -- regen --only multiscale-convolution",
        ours: Coefficients {
            coefficients: ci,
            held_out: ours,
        },
        eq7_refit: Eq7Refit {
            coefficients: c7,
            sse: sse7,
            sse_paper_coefficients_same_grid: sse_paper,
        },
        models: model_json,
        metric_grid: fits,
        per_metric_polynomial: metric_fits(per_metric_ours),
        per_metric_corrected: metric_fits(per_metric_corr),
        metric_grid_held_out: held_fits,
        passed,
    };
    crate::results::put_named(set, results, &spec.name, &json)?;
    Ok(FitOutcome {
        name: spec.name.clone(),
        held_out_max_rel: ours.max_rel,
        tolerance: spec.tolerance.max_rel,
        passed,
        summary: format!(
            "ours {:.2e} max rel on the moment target (tol {:.0e}); per metric held-out {}; metric spread up to ×{:.3}",
            ours.max_rel,
            spec.tolerance.max_rel,
            per_metric_corr.iter().map(|r| format!("{:.2e}", r.3.max_rel)).collect::<Vec<_>>().join("/"),
            spread_max.0
        ),
    })
}

crate::study::study! {
    /// The convolution study, as the registry holds it.
    MultiscaleConvolution = "multiscale-convolution", after [], on request false, runs run
}

//! `regen --only filters`: the footprint study (maps and screen-space kernels) against
//! the footprint-averaged BRDF (seed 004 Eq 11), its fitted constants, results/filters.md,
//! results/fits/filters.json and the plots. [`compute`] draws and measures the cases
//! ([`cases`]), fits the constants ([`constants`]) and aggregates every figure (the
//! verdicts' in [`verdicts`], the result file's in [`summary`]); the report
//! ([`report`], [`survey_report`]) formats them.
//!
//! - **Models:** one-constant refits of the vMF rule α′² = α² + c/κ (κ = (3r − r³)/(1 − r²),
//!   r = |μ| of the mip-mapped normal), the Toksvig rule α′² = α² + c·σ² (σ² = (1 − r)/r)
//!   and the deferred kernel σ² of seed 003 Eq 13 (α′² = α² + min(2σ²(‖Δn_u‖² + ‖Δn_v‖²),
//!   0.18)), per NDF and pixel footprint; baselines: the engines' constants (vMF 2, 1, 1/2;
//!   Toksvig 2, 1; σ² = 0.25, 0.15, 0.1).
//! - **Training / held out:** the even footprint indices of the map study (every map,
//!   level, α and view of the plan) and the even views of the screen study; held out: the
//!   odd ones.
//! - **Metric:** mean relative L2 error of the lobe over all light directions against the
//!   footprint-averaged per-texel BRDF (seed 004 Eq 11, Hypothesis 1), importance-sampled
//!   Monte Carlo; each constant by a scan over a log grid and Brent (argmin).

use crate::error::Result;
use crate::io::Outputs;
use crate::study::FitOutcome;

mod cases;
mod compute;
mod constants;
mod plan;
mod prefilter;
mod report;
mod summary;
pub mod survey;
mod survey_report;
mod verdicts;

pub use compute::{compute, Computed};
pub use plan::Plan;

pub use cases::{aggregate, Agg};
pub use prefilter::prefilter;

fn render(set: &mut Outputs, results: &std::path::Path, c: &Computed) -> Result<()> {
    let (spec, preset, plan) = (&c.spec, c.preset, &c.plan);
    let mut md = report::intro(preset, plan);
    for s in &c.maps {
        report::map_section(&mut md, s, plan);
        set.put(
            &results.join(format!("filters-{}.svg", s.name)),
            report::map_svg(s)?.as_bytes(),
        );
    }
    report::screen_section(&mut md, plan, &c.screen);
    set.put(
        &results.join("filters-screen.svg"),
        report::screen_svg(&c.screen)?.as_bytes(),
    );
    let json_fits = report::fits_section(&mut md, &c.fits);
    md.push_str(&verdicts::markdown(&c.verdicts));
    md.push_str(report::LISTING3_NOTE);
    md.push_str(&report::embed(&c.embedded));
    set.put(&results.join("filters.md"), md.as_bytes());
    set.put(
        &results.join("filters-survey.md"),
        survey_report::markdown(&c.survey, preset, c.counts.1).as_bytes(),
    );
    set.put(
        &results.join("filters-survey.svg"),
        survey_report::pareto_svg(&c.survey)?.as_bytes(),
    );
    let result = crate::results::filters::Filters {
        spec: spec.clone(),
        command: crate::results::command(&spec.name),
        summary: c.per_filter.clone(),
        by_level_note:
            "filter = index into map_filters; l2/energy = mean (value) ± s.e. (error) over footprints, α and views"
                .into(),
        map_filters: crate::filters::registry::MAP
            .iter()
            .map(|f| f.label.to_string())
            .collect(),
        by_level: c.by_level.clone(),
        preset: preset.name().into(),
        plan: plan.clone(),
        maps: c.maps.iter().map(|m| m.rows()).collect(),
        screen: c.screen.rows(),
        fitted: json_fits,
        survey: c.survey.clone(),
    };
    crate::results::put(set, results, &result)
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        render(set, results, self)
    }

    fn outcome(&self) -> FitOutcome {
        let worst_held = self
            .fits
            .iter()
            .map(|f| f.held_out.l2.value)
            .fold(0.0, f64::max);
        FitOutcome::judged(
            &self.spec,
            worst_held,
            format!(
                "{} map cases, {} screen cases; fitted vMF c (GGX) = {:.3}",
                self.counts.0,
                self.counts.2,
                self.fits.first().map(|f| f.constant).unwrap_or(f64::NAN)
            ),
        )
    }
}

crate::study::study! {
    /// The footprint-filter study; results/filters.md embeds the LEADR and Λ reports, so they
    /// run first, as the registry holds it.
    Filters = "filters", after ["leadr-grids", "smith-lambda"], on request false, params plan::Plan, computes compute
}

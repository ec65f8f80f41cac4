//! `regen --only filters`: the footprint study (maps and screen-space kernels) against
//! the footprint-averaged BRDF (seed 004 Eq 11), its fitted constants, results/filters.md,
//! results/fits/filters.json and the plots. Compute ([`cases`], [`constants`]) → report
//! ([`report`], [`verdicts`], [`summary`]) → write, in that order.

use crate::error::{Error, Result};
use crate::io::Outputs;
use crate::study::{Ctx, FitOutcome};

mod cases;
mod constants;
mod plan;
mod prefilter;
mod report;
mod summary;
pub mod survey;
mod survey_report;
mod verdicts;

pub use plan::Plan;

pub use cases::{aggregate, Agg};
pub use prefilter::prefilter;

/// The study: compute the cases and the fitted constants, then render them into `set`.
pub fn run(set: &mut Outputs, c: &Ctx) -> Result<FitOutcome> {
    let (spec, results, preset) = (c.spec, c.results, c.preset);
    use crate::filters::footprint::{NormalMap, Procedural};
    let plan = Plan::new(preset);
    let seed = spec.seed;
    // the filters' four maps, then seed 002's scratches for the survey only: its cases come
    // last, so the filters' cases keep their indices (and seeds) bit for bit
    let mut all_maps: Vec<NormalMap> = Procedural::ALL
        .iter()
        .map(|&k| NormalMap::procedural(k, plan.map_size, seed + 1))
        .collect::<Result<_>>()?;
    all_maps.push(NormalMap::procedural(
        Procedural::Scratches,
        plan.map_size,
        seed + 1,
    )?);
    let mut map_cases = cases::map_study(&all_maps, &plan, seed)?;
    let views = plan.views_deg.len();
    let survey_cases = survey::survey_study(&all_maps, &map_cases, views, seed)?;
    let first_extra = map_cases
        .iter()
        .position(|c| c.map >= Procedural::ALL.len())
        .unwrap_or(map_cases.len());
    let extra_cases = map_cases.split_off(first_extra);
    let maps = &all_maps[..Procedural::ALL.len()];
    let survey_summary = {
        let names: Vec<String> = all_maps.iter().map(|m| m.name.clone()).collect();
        let all: Vec<&cases::MapCase> = map_cases.iter().chain(&extra_cases).collect();
        survey_report::summarise(&names, &all, &survey_cases)
    };
    let screen_cases = cases::screen_study(&plan, seed)?;
    let fits = constants::fit_constants(&map_cases, &screen_cases);

    let mut md = report::intro(preset, &plan);
    let mut json_maps = Vec::new();
    for (m, map) in maps.iter().enumerate() {
        let row_json = report::map_section(set, &mut md, m, map, &map_cases, &plan, results)?;
        json_maps.push(serde_json::json!({"map": map.name, "filters": row_json}));
    }
    let json_screen = report::screen_section(set, &mut md, &plan, &screen_cases, results)?;
    let json_fits = report::fits_section(&mut md, &fits);
    md.push_str(&verdicts::verdicts(&map_cases, &screen_cases, &fits));
    md.push_str(report::LISTING3_NOTE);
    md.push_str(&report::embed(results));
    set.put(&results.join("filters.md"), md.as_bytes());
    let n_all = map_cases.len() + extra_cases.len();
    set.put(
        &results.join("filters-survey.md"),
        survey_report::markdown(&survey_summary, preset, n_all).as_bytes(),
    );
    set.put(
        &results.join("filters-survey.svg"),
        survey_report::pareto_svg(&survey_summary)?.as_bytes(),
    );
    let result = crate::results::filters::Filters {
        spec: spec.clone(),
        command: crate::results::command(&spec.name),
        summary: summary::per_filter(&map_cases, &screen_cases),
        by_level_note:
            "filter = index into map_filters; l2/energy = [mean, s.e.] over footprints, α and views"
                .into(),
        map_filters: crate::filters::registry::MAP
            .iter()
            .map(|f| f.label.to_string())
            .collect(),
        by_level: summary::by_level(&map_cases, &plan, maps.len()),
        preset: preset.name().into(),
        plan: serde_json::to_value(&plan)
            .map_err(|e| Error::InvalidArgument(format!("filters plan: {e}")))?,
        maps: json_maps,
        screen: json_screen,
        fitted: json_fits,
        survey: survey_summary,
    };
    crate::results::put(set, results, &result)?;
    let worst_held = fits.iter().map(|f| f.held_out.l2_mean).fold(0.0, f64::max);
    Ok(crate::study::FitOutcome {
        name: spec.name.clone(),
        held_out_max_rel: worst_held,
        tolerance: spec.tolerance.max_rel,
        passed: worst_held <= spec.tolerance.max_rel,
        summary: format!(
            "{} map cases, {} screen cases; fitted vMF c (GGX) = {:.3}",
            map_cases.len(),
            screen_cases.len(),
            fits[0].constant
        ),
    })
}

crate::study::study! {
    /// The footprint-filter study; results/filters.md embeds the LEADR and Λ reports, so they
    /// run first, as the registry holds it.
    Filters = "filters", after ["leadr-grids", "smith-lambda"], on request false, runs run
}

//! `regen --only visibility`: seed 004 §4–6 and §8.1 measured ([`crate::visibility`]):
//! horizon maps against the exact visible fractions of height-field footprints, shadow
//! maps against percentage-closer filtering, procedural colour and normals against their
//! exact box averages, and the cost of separating correlated maps. Compute (this file) →
//! report ([`report`]) → results/survey-visibility.{md,svg}, results/fits/visibility.json.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::io::Outputs;
use crate::study::{Ctx, FitOutcome};
use crate::visibility::{HeightField, Relief};
use serde::Serialize;

mod compute;
mod report;
mod user_map;

use compute::{
    colour_rows, correlation_rows, grid_rows, horizon_cases, normal_rows, shadow_cases,
    spectral_rows,
};
pub use compute::{
    shadow_methods, ColourRow, HorizonCase, Measured, NormalRow, Plan, ShadowCase, ASHIKHMIN_WIDTH,
    LEGENDRE_K,
};

pub use user_map::horizon_file;

/// The study: compute and report, into `set`.
pub fn run(set: &mut Outputs, c: &Ctx) -> Result<FitOutcome> {
    let (spec, results, preset) = (c.spec, c.results, c.preset);
    let plan = Plan::new(preset);
    let seed = spec.seed;
    let m = Measured {
        horizon: horizon_cases(
            &[
                HeightField::procedural(Relief::Noise, plan.height_size, seed)?,
                HeightField::procedural(Relief::Bumps, plan.height_size, seed + 1)?,
            ],
            &plan,
            seed,
        )?,
        shadow: shadow_cases(&plan),
        colour: colour_rows(&plan, seed),
        grid: grid_rows(&plan, seed),
        spectral: spectral_rows(&plan, seed),
        normals: normal_rows(&plan, seed)?,
        correlation: correlation_rows(&plan, seed)?,
        plan,
    };
    crate::report::stage("regen visibility: measured");
    let summary = report::summarise(&m);
    set.put(
        &results.join("visibility.md"),
        report::markdown(&summary, &m, preset).as_bytes(),
    );
    set.put(
        &results.join("visibility.svg"),
        report::pareto_svg(&summary)?.as_bytes(),
    );
    #[derive(Serialize)]
    struct Out<'a> {
        spec: &'a FitSpec,
        command: &'static str,
        preset: &'static str,
        summary: &'a report::Summary,
        plan: &'a Plan,
    }
    crate::results::put_named(
        set,
        results,
        &spec.name,
        &Out {
            spec,
            command: "cargo run --release -- regen --only visibility",
            preset: preset.name(),
            summary: &summary,
            plan: &m.plan,
        },
    )?;
    let worst = summary.eq28_hotspot_max;
    Ok(crate::study::FitOutcome {
        name: spec.name.clone(),
        held_out_max_rel: worst,
        tolerance: spec.tolerance.max_rel,
        passed: worst <= spec.tolerance.max_rel,
        summary: format!(
            "{} horizon cases, {} shadow footprints; Eq 28 at l = v within {:.1e} of 1",
            m.horizon.len(),
            m.shadow.len(),
            worst
        ),
    })
}

crate::study::study! {
    /// The visibility survey, as the registry holds it.
    Visibility = "visibility", after [], on request false, runs run
}

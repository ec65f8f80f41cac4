//! `regen --only visibility`: seed 004 §4–6 and §8.1 measured ([`crate::visibility`]):
//! horizon maps against the exact visible fractions of height-field footprints, shadow
//! maps against percentage-closer filtering, procedural colour and normals against their
//! exact box averages, and the cost of separating correlated maps. Compute (the cases in
//! [`compute`], their aggregates in [`summary`]), then render ([`report`]):
//! results/visibility.{md,svg}, results/fits/visibility.json.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::io::Outputs;
use crate::study::{Ctx, FitOutcome};
use crate::visibility::{HeightField, Relief};
use serde::Serialize;

mod compute;
mod report;
mod summary;
mod user_map;

use compute::{
    colour_rows, correlation_rows, grid_rows, horizon_cases, normal_rows, shadow_cases,
    spectral_rows,
};
pub use compute::{
    shadow_methods, ColourRow, HorizonCase, Measured, NormalRow, Plan, ShadowCase, ASHIKHMIN_WIDTH,
    LEGENDRE_K,
};

pub use compute::builtin_plan;
pub use user_map::horizon_file;

/// What the study computed: the measured cases and their aggregates.
pub struct Computed {
    spec: FitSpec,
    preset: Preset,
    m: Measured,
    summary: summary::Summary,
}

/// Measure every case of the plan the preset gives, and aggregate them.
fn compute(c: &Ctx) -> Result<Computed> {
    let (spec, preset) = (c.spec, c.preset);
    let plan: Plan = c.params()?;
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
    let summary = summary::summarise(&m);
    Ok(Computed {
        spec: spec.clone(),
        preset,
        m,
        summary,
    })
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        let (spec, preset) = (&self.spec, self.preset);
        set.put(
            results.join("visibility.md"),
            report::markdown(&self.summary, &self.m, preset),
        );
        set.put(
            results.join("visibility.svg"),
            report::pareto_svg(&self.summary)?,
        );
        #[derive(Serialize)]
        struct Out<'a> {
            spec: &'a FitSpec,
            command: &'static str,
            preset: &'static str,
            summary: &'a summary::Summary,
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
                summary: &self.summary,
                plan: &self.m.plan,
            },
        )?;
        Ok(())
    }
    /// Judged by Eq 28's worst departure from 1 at l = v.
    fn outcome(&self) -> FitOutcome {
        let worst = self.summary.eq28_hotspot_max;
        FitOutcome::judged(
            &self.spec,
            worst,
            format!(
                "{} horizon cases, {} shadow footprints; Eq 28 at l = v within {:.1e} of 1",
                self.m.horizon.len(),
                self.m.shadow.len(),
                worst
            ),
        )
    }
}

crate::study::study! {
    /// The visibility survey, as the registry holds it.
    Visibility = "visibility", after [], on request false, params Plan, computes compute
}

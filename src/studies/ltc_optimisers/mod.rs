//! `regen --only ltc-ggx-optimisers` (on request): diagnostics of the GGX table's fit,
//! kept out of the main job so that every table's fit pays only for itself.
//!
//! - **Variants** (`variants`): the optimiser and metric routes on a `sub`×`sub`
//!   sub-grid, judged by the held-out integrals.
//! - **Floor** (`floor`): how far a single LTC per cell can go, by a multi-start search
//!   around the published table's lobes.
//! - **Reference** (`reference`): the published table's route against the reference route
//!   (Nelder–Mead out to `iters`, Nelder–Mead L2 polish) through the same bilinear pass,
//!   cell by cell on the held-out integrals.
//!
//! Reads the published GGX table (results/fits/ltc-ggx.json) and the route it was fitted
//! with (its spec, at the preset it was run at); writes results/ltc-ggx-optimisers.md and
//! results/fits/ltc-ggx-optimisers.json.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::io::Outputs;
use crate::ltc::fit::Grid;
use crate::ltc::held::Stats;
use crate::results::ltc::{FloorCell, Optimisers, RouteComparison};
use crate::study::{Ctx, FitOutcome};

mod floor;
mod reference;
mod variants;

/// What fits/ltc-ggx-optimisers.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Cells per axis of the sub-grid the variants are fitted on.
    pub sub: usize,
    /// Iteration cap per stage of the variants, the floor's searches and the reference
    /// route's cubic stage.
    pub iters: u64,
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::within;
        within("sub", self.sub, 2, 256)?;
        within("iters", self.iters, 1, 100_000)
    }
}

/// What the study computed.
pub struct Computed {
    spec: FitSpec,
    preset: Preset,
    pl: Plan,
    samples: usize,
    variants: Vec<(String, Stats)>,
    floor: Vec<FloorCell>,
    floor_summary: floor::Summary,
    reference: RouteComparison,
    table_fingerprint: String,
}

/// The study: read the published table, then the three diagnostics.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let pl: Plan = c.params()?;
    let (ggx, table_fingerprint) = crate::results::ltc::published_ggx(c.results)?;
    let route = ggx.route()?;
    let sub = Grid {
        n: pl.sub,
        alpha_min: ggx.grid.alpha_min,
    };
    crate::report::stage("regen ltc-ggx-optimisers: the optimiser variants");
    let variants = variants::measure(sub, route.samples, pl.iters)?;
    crate::report::stage(
        "regen ltc-ggx-optimisers: the floor of a single LTC (multi-start search)",
    );
    let floor = floor::compute(&ggx, route.samples, pl.iters)?;
    let floor_summary = floor::summarise(&floor, &ggx);
    crate::report::stage("regen ltc-ggx-optimisers: the reference route, cell by cell");
    let table = format!(
        "Nelder–Mead (≤ {} iterations per stage) on the cubic metric, then {}",
        route.max_iters,
        route.polish.describe(route.samples)
    );
    let tol = crate::ltc::lobe_error::Tolerance::relative(route.held_out_rel);
    let reference = reference::compare(&ggx, route.samples, pl.iters, tol, table)?;
    Ok(Computed {
        spec: c.spec.clone(),
        preset: c.preset,
        pl,
        samples: route.samples,
        variants,
        floor,
        floor_summary,
        reference,
        table_fingerprint,
    })
}

fn reference_section(r: &RouteComparison) -> String {
    format!(
        "## The table's route against the reference route\n\nThe published table (results/fits/ltc-ggx.json) was fitted by: {}. The reference route: {}. Both go through the same warm starts, bilinear pass and held-out integrals; per cell, the relative L2 of the f64 cell.\n\n- mean over {} cells: table {}, reference {}; change {}.\n- the table is worse than the reference by more than the two figures' bars together in {} cells ({} of them by more than 0.01 points, {} by more than 0.1 points; the largest by {:.3} points), better in {}.\n\n",
        r.table,
        r.reference,
        r.cells,
        r.table_mean.pct(4),
        r.reference_mean.pct(4),
        r.mean_change.points_signed(4),
        r.worse,
        r.worse_by_001pt,
        r.worse_by_01pt,
        100.0 * r.largest_excess,
        r.better,
    )
}

fn markdown(c: &Computed) -> String {
    let mut md = format!(
        "# GGX LTC fit: optimisers, the floor of a single LTC, and the route against the reference\n\nWritten by `{}` (preset {}) from `fits/{}.toml`, on request (the main job leaves it out). It reads the published GGX table and the route its spec names ({}×{} samples per technique). Every error is a held-out integral ± its bar (`ltc::lobe_error`).\n\n",
        crate::results::command(&c.spec.name),
        c.preset.name(),
        c.spec.name,
        c.samples,
        c.samples,
    );
    md.push_str(&reference_section(&c.reference));
    md.push_str(&variants::section(c.pl.sub, c.pl.iters, &c.variants));
    md.push_str(&floor::section(&c.floor, &c.floor_summary));
    md
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        set.put(
            &results.join(format!("{}.md", self.spec.name)),
            markdown(self).as_bytes(),
        );
        crate::results::put(
            set,
            results,
            &Optimisers {
                spec: self.spec.clone(),
                command: crate::results::command(&self.spec.name),
                preset: self.preset.name().into(),
                variants: variants::rows(&self.variants),
                floor: self.floor.clone(),
                reference: self.reference.clone(),
                table_fingerprint: Some(self.table_fingerprint.clone()),
            },
        )
    }

    fn outcome(&self) -> FitOutcome {
        let r = &self.reference;
        FitOutcome::measured(
            &self.spec,
            r.table_mean.value,
            format!(
                "table route vs reference: mean rel. L2 {} vs {}; worse in {} cells (largest {:.3} points), better in {}",
                r.table_mean.pct(4),
                r.reference_mean.pct(4),
                r.worse,
                100.0 * r.largest_excess,
                r.better
            ),
        )
    }
}

crate::study::study! {
    /// The GGX fit's diagnostics, as the registry holds it.
    LtcGgxOptimisers = "ltc-ggx-optimisers", after ["ltc-ggx"], on request true, params Plan, computes compute
}

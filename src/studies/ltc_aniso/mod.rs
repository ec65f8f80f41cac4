//! `regen --only ltc-aniso`: the anisotropic GGX LTC table and its design study.
//!
//! Compute: every cell with α_x ≥ α_y fitted (`ltc::aniso::fit_cell`, the general
//! 7-entry production inverse, Nelder–Mead from the isotropic table's entries at
//! √(α_x α_y)), the others by symmetry; the design study (1D slices through the 4D
//! domain, fitted densely, interpolated at coarser spacings: the error each dimension's
//! resolution costs, and the error predicted for other table sizes); the shipped table
//! at random cases between its cells, in f64 and binary16, against what engines do today
//! (the isotropic table at √(α_x α_y) or at max(α_x, α_y)). `compute` fits, `design`
//! runs the design study, `summary` aggregates; `report` formats only. `work` is a study
//! of its own, run on request (`ltc-aniso-work`): the route's accuracy against its
//! fitting work, formatted by `work_report`.
//!
//! The grid is `n_r`×`n_r`×`n_phi`×`n_t` in (√α_x, √α_y, φ ∈ [0, π/2], √(1 − cos θ)),
//! α = max(r², `alpha_min`); φ ∈ [0, π/2] and α_x ≥ α_y by symmetry. Each cell: M⁻¹ ∝
//! [[a, 0, c], [e, 1, g], [b, h, d]] + norm + fresnel, Nelder–Mead on 7 parameters scaled
//! to the start (≤ `iters` iterations) on the relative L2 over `samples`² stratified
//! samples from the LTC and from the VNDF, from three starts (the isotropic table at
//! √(α_x α_y), the same stretched toward the tangent, the isotropic table at
//! max(α_x, α_y)), the best on a validation set kept. Held out: a fresh (2·`samples`)²
//! set per technique, plus `cases` random cases between cells.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::io::Outputs;
use crate::ltc::aniso_table::AnisoTable;
use crate::study::{Ctx, FitOutcome};

mod compute;
mod design;
mod report;
mod summary;
pub mod work;
mod work_report;

use compute::{between, fit_table, polygons};
pub use compute::{Between, Case, Fitted, PolygonRow};

/// What the study computed: the table, its fitted cells, the summary (the design study
/// inside) and the polygon rows.
pub struct Computed {
    spec: FitSpec,
    preset: Preset,
    pl: compute::Plan,
    table: AnisoTable,
    heat: summary::HeatMaps,
    rep: summary::Summary,
    poly: Vec<PolygonRow>,
}

/// The study: fit, design study, cases between cells, summary and polygon rows.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let (spec, results, preset) = (c.spec, c.results, c.preset);
    let iso = crate::results::ltc::table(results, crate::results::names::LTC_GGX)?;
    let pl = c.params::<compute::Params>()?.plan();
    let (table, fitted) = fit_table(&iso, &pl)?;
    crate::report::stage(&format!(
        "regen ltc-aniso: {} cells fitted; design study next",
        fitted.len()
    ));
    let design = design::design_study(&iso, &pl)?;
    let cases = between(&iso, &table, &pl)?;
    let rep = summary::summarise(&fitted, &cases, &design, &pl);
    let poly = polygons(&iso, &table, pl.mc)?;
    let heat = summary::heat_maps(&fitted, &pl);
    Ok(Computed {
        spec: spec.clone(),
        preset,
        pl,
        table,
        heat,
        rep,
        poly,
    })
}

fn render(set: &mut Outputs, results: &std::path::Path, c: &Computed) -> Result<()> {
    let (spec, pl, rep) = (&c.spec, &c.pl, &c.rep);
    let command = crate::results::command(&spec.name);
    let mut md = report::markdown(spec, c.preset, pl, rep, &command);
    md.push_str(&report::polygon_section(&c.poly, pl.mc));
    set.put(&results.join("ltc-aniso.md"), md.as_bytes());
    let heat = report::heatmap(&c.heat, pl)?;
    set.put(&results.join("ltc-aniso-error.svg"), heat.as_bytes());
    let svg = report::plot(&rep.design, pl)?;
    set.put(&results.join("ltc-aniso.svg"), svg.as_bytes());
    crate::results::put(
        set,
        results,
        &crate::results::ltc_aniso::Aniso {
            spec: spec.clone(),
            command: command.clone(),
            preset: c.preset.name().into(),
            grid: c.table.grid,
            layout: "cells[i_x + n_r·(i_y + n_r·(k + n_phi·j))] = [a, b, c, d, e, g, h, norm, fresnel]; r_x = √α_x = i_x/(n_r − 1), r_y likewise, φ = (π/2)·k/(n_phi − 1) the α_x tangent's azimuth from T1, t = √(1 − cos θ) = j/(n_t − 1); M⁻¹ ∝ [[a, 0, c], [e, 1, g], [b, h, d]] (rows)".into(),
            cells: c.table.cells.clone(),
            summary: rep.clone(),
            polygons: c.poly.clone(),
        },
    )
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        render(set, results, self)
    }

    fn outcome(&self) -> FitOutcome {
        let (g, rep) = (self.pl.grid, &self.rep);
        FitOutcome::judged(
            &self.spec,
            rep.between_table.max,
            format!(
                "{}×{}×{}×{} table: between cells mean {:.2} % (isotropic table at √(αx·αy): {:.2} %)",
                g.n_r,
                g.n_r,
                g.n_phi,
                g.n_t,
                100.0 * rep.between_table.mean.value,
                100.0 * rep.between_iso_geo.mean.value
            ),
        )
    }
}

crate::study::study! {
    /// The anisotropic LTC study; its fits start from the isotropic GGX table, as the registry
    /// holds it.
    LtcAniso = "ltc-aniso", after ["ltc-ggx"], on request false, params compute::Params, computes compute
}

crate::study::study! {
    /// The anisotropic table's accuracy against its fitting work (`work`), on request; it
    /// shares this module's unit, so its cache key follows the table's code.
    LtcAnisoWork = "ltc-aniso-work", after ["ltc-ggx", "ltc-aniso"], on request true, params work::WorkPlan, computes work::compute
}

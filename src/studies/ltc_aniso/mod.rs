//! `regen --only ltc-aniso`: the anisotropic GGX LTC table and its design study.
//!
//! Compute: every cell with α_x ≥ α_y fitted (`ltc::aniso::fit_cell`, the general
//! 7-entry production inverse, Nelder–Mead from the isotropic table's entries at
//! √(α_x α_y)), the others by symmetry; the design study (1D slices through the 4D
//! domain, fitted densely, interpolated at coarser spacings: the error each dimension's
//! resolution costs, and the error predicted for other table sizes); the shipped table
//! at random cases between its cells, in f64 and binary16, against what engines do today
//! (the isotropic table at √(α_x α_y) or at max(α_x, α_y)). Report (`report`) → files.

use crate::error::{Error, Result};
use crate::io::Outputs;
use crate::study::{Ctx, FitOutcome};

mod compute;
mod report;

use compute::{between, fit_table, plan, polygons};
pub use compute::{Between, Case, Fitted, PolygonRow};

/// The study: fit, design study, cases between cells and report, into `set`.
pub fn run(set: &mut Outputs, c: &Ctx) -> Result<FitOutcome> {
    let (spec, results, preset) = (c.spec, c.results, c.preset);
    let iso = crate::results::ltc::table(results, crate::results::names::LTC_GGX)?;
    let pl = plan(preset, spec.domain.alpha_min);
    let (table, fitted) = fit_table(&iso, &pl)?;
    crate::report::stage(&format!(
        "regen ltc-aniso: {} cells fitted; design study next",
        fitted.len()
    ));
    let design = report::design_study(&iso, &pl)?;
    let cases = between(&iso, &table, &pl)?;
    let command = crate::results::command(&spec.name);
    let rep = report::summarise(&fitted, &cases, &design, &pl);
    let poly = polygons(&iso, &table, pl.mc)?;
    let mut md = report::markdown(spec, preset, &pl, &rep, &command);
    md.push_str(&report::polygon_section(&poly, pl.mc));
    set.put(&results.join("ltc-aniso.md"), md.as_bytes());
    let heat = report::heatmap(&fitted, &pl)?;
    set.put(&results.join("ltc-aniso-error.svg"), heat.as_bytes());
    let svg = report::plot(&design, &pl)?;
    set.put(&results.join("ltc-aniso.svg"), svg.as_bytes());
    let summary = serde_json::to_value(&rep)
        .and_then(serde_json::from_value)
        .map_err(|e| Error::InvalidArgument(format!("ltc-aniso summary: {e}")))?;
    let polygons = serde_json::to_value(&poly)
        .map_err(|e| Error::InvalidArgument(format!("ltc-aniso polygons: {e}")))?;
    crate::results::put(
        set,
        results,
        &crate::results::ltc::Aniso {
            spec: spec.clone(),
            command: command.clone(),
            preset: preset.name().into(),
            grid: table.grid,
            layout: "cells[i_x + n_r·(i_y + n_r·(k + n_phi·j))] = [a, b, c, d, e, g, h, norm, fresnel]; r_x = √α_x = i_x/(n_r − 1), r_y likewise, φ = (π/2)·k/(n_phi − 1) the α_x tangent's azimuth from T1, t = √(1 − cos θ) = j/(n_t − 1); M⁻¹ ∝ [[a, 0, c], [e, 1, g], [b, h, d]] (rows)".into(),
            cells: table.cells.clone(),
            summary,
            polygons,
        },
    )?;
    let worst = rep.between_table.max;
    Ok(crate::study::FitOutcome {
        name: spec.name.clone(),
        held_out_max_rel: worst,
        tolerance: spec.tolerance.max_rel,
        passed: worst <= spec.tolerance.max_rel,
        summary: format!(
            "{}×{}×{}×{} table: between cells mean {:.2} % (isotropic table at √(αx·αy): {:.2} %)",
            pl.grid.n_r,
            pl.grid.n_r,
            pl.grid.n_phi,
            pl.grid.n_t,
            100.0 * rep.between_table.mean,
            100.0 * rep.between_iso_geo.mean
        ),
    })
}

crate::study::study! {
    /// The anisotropic LTC study; its fits start from the isotropic GGX table, as the registry
    /// holds it.
    LtcAniso = "ltc-aniso", after ["ltc-ggx"], on request false, runs run
}

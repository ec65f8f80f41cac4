//! `regen --only ltc-sheen` and `regen --only ltc-diffuse`: LTC tables of the lobes
//! engines ask for beyond GGX — the Charlie sheen lobe (Estevez & Kulla 2017) and
//! Burley's diffuse (Burley 2012) — through the same generic fitter, bilinear pass and
//! binary16 storage as the GGX table (`ltc::{fit, smooth, storage}`), judged the same
//! way. Each family has a main lobe (its table is shipped) and a variant (the other
//! visibility term, the other roughness convention), fitted on the same grid and shipped
//! too, with the error of shading one with the other's table. Compute (this file) → the
//! report (`report`) → results/fits/<name>.json, results/<name>.md, results/<name>-error.svg.

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::io::Outputs;
use crate::ltc::fit::Table;
use crate::ltc::held::held_out_stats;
use crate::study::{Ctx, FitOutcome};
use serde::Serialize;

mod compute;
mod report;

pub use compute::{family, Family};
use compute::{fit_lobe, plan};

/// Per cell [j][i]: the held-out relative L2 and L1 of the f64 cell, each [value, error].
#[derive(Serialize)]
struct HeldOutCells {
    layout: &'static str,
    l2: Vec<Vec<Option<[f64; 2]>>>,
    l1: Vec<Vec<Option<[f64; 2]>>>,
}

fn per_cell(t: &Table) -> HeldOutCells {
    let fig = |c: &crate::ltc::fit::Cell, l1: bool| {
        c.held
            .and_then(|h| h.f64)
            .map(|e| if l1 { e.l1 } else { e.l2 })
            .map(|b| [b.value, b.error])
    };
    let grid = |l1: bool| {
        t.cells
            .iter()
            .map(|col| col.iter().map(|c| fig(c, l1)).collect())
            .collect()
    };
    HeldOutCells {
        layout: "[j][i] = [value, error] (null where singular)",
        l2: grid(false),
        l1: grid(true),
    }
}

/// results/fits/<name>.json of a lobe table (and of its variant): the table every reader
/// reads (`results::ltc::Tables`), its held-out figures and the study's report.
#[derive(Serialize)]
struct LobeResult<'a> {
    spec: &'a FitSpec,
    command: &'a str,
    preset: &'static str,
    lobe: crate::ltc::lobes::Lobe,
    target: &'static str,
    grid: crate::ltc::fit::Grid,
    layout: &'static str,
    table: crate::results::ltc::Columns,
    table_f16: crate::results::ltc::Columns,
    held_out: crate::ltc::held::Stats,
    held_out_cells: HeldOutCells,
    report: &'a report::TableReport,
    cross: &'a report::Cross,
    bilinear_pass: &'a crate::ltc::smooth::BilinearPass,
}

/// The study: fit both tables of the family and report, into `set`.
pub fn run(set: &mut Outputs, c: &Ctx) -> Result<FitOutcome> {
    let (spec, results, preset) = (c.spec, c.results, c.preset);
    let fam = family(&spec.name).ok_or_else(|| {
        Error::InvalidArgument(format!(
            "fits/{}.toml: no LTC table family of that name (ltc-sheen, ltc-diffuse)",
            spec.name
        ))
    })?;
    let pl = plan(preset);
    let main = fit_lobe(fam.main, spec, &pl)?;
    crate::report::stage(&format!(
        "regen {}: {} fitted; the variant next",
        fam.name,
        fam.main.short(),
    ));
    let variant = fit_lobe(fam.variant, spec, &pl)?;
    crate::report::stage(&format!(
        "regen {}: {} fitted; report next",
        fam.name,
        fam.variant.short(),
    ));
    let rep = report::compute(&fam, &main, &variant, &pl)?;
    let command = format!("cargo run --release -- regen --only {}", fam.name);
    let md = report::markdown(&fam, spec, preset, &pl, &main, &variant, &rep, &command);
    let svg = report::heatmaps(&main, &variant)?;
    // results/fits/<name>.json and the variant's: the one reader (`ltc::table`) reads both
    for (name, f, r) in [
        (fam.name, &main, &rep.main),
        (fam.variant_name, &variant, &rep.variant),
    ] {
        let (table, table_f16) = crate::ltc::fit::stored(&f.table);
        let json = LobeResult {
            spec,
            command: &command,
            preset: preset.name(),
            lobe: f.lobe,
            target: f.lobe.describe(),
            grid: f.table.grid,
            layout: "table[j][i] = [a, b, c, d, norm, fresnel]; j = θ index (t = √(1 − cos θ) = j/(n−1)), i = roughness index (r = √α = i/(n−1)); M⁻¹ ∝ [[a, 0, c], [0, 1, 0], [b, 0, d]]",
            table,
            table_f16,
            held_out: held_out_stats(&f.table),
            held_out_cells: per_cell(&f.table),
            report: r,
            cross: &rep.cross,
            bilinear_pass: &f.bilinear,
        };
        crate::results::put_named(set, results, name, &json)?;
    }
    set.put(&results.join(format!("{}.md", fam.name)), md.as_bytes());
    set.put(
        &results.join(format!("{}-error.svg", fam.name)),
        svg.as_bytes(),
    );
    let st = held_out_stats(&main.table);
    let sv = held_out_stats(&variant.table);
    let worst = st.l2.max.value.max(sv.l2.max.value);
    Ok(crate::study::FitOutcome {
        name: spec.name.clone(),
        held_out_max_rel: worst,
        tolerance: spec.tolerance.max_rel,
        passed: worst <= spec.tolerance.max_rel,
        summary: format!(
            "{n}×{n} tables: {} mean {} (max {}), {} mean {} (max {}) held-out rel. L2",
            fam.main.short(),
            st.l2.mean.pct(2),
            st.l2.max.pct(1),
            fam.variant.short(),
            sv.l2.mean.pct(2),
            sv.l2.max.pct(1),
            n = pl.n
        ),
    })
}

crate::study::study! {
    /// The diffuse LTC table study (Burley; the engines' α), as the registry holds it.
    LtcDiffuse = "ltc-diffuse", after [], on request false, runs run
}

crate::study::study! {
    /// The sheen LTC table study (Charlie, both visibility conventions), as the registry
    /// holds it.
    LtcSheen = "ltc-sheen", after [], on request false, runs run
}

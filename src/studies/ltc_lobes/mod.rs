//! `regen --only ltc-sheen` and `regen --only ltc-diffuse`: LTC tables of the lobes
//! engines ask for beyond GGX — the Charlie sheen lobe (Estevez & Kulla 2017) and
//! Burley's diffuse (Burley 2012) — through the same generic fitter, bilinear pass and
//! binary16 storage as the GGX table (`ltc::{fit, smooth, storage}`), judged the same
//! way. Each family has a main lobe (its table is shipped) and a variant (the other
//! visibility term, the other roughness convention), fitted on the same grid and shipped
//! too (the error of shading one with the other's table is the `ltc-lobe-cross` study's,
//! on request). The fits (`compute`) and
//! their measures (`measures`) → the report (`report`, formatting only) →
//! results/fits/<name>.json, results/<name>.md, results/<name>-error.svg.
//!
//! - **ltc-sheen:** the Charlie sheen BRDF (F = 1) with Estevez & Kulla's fitted-Λ
//!   visibility (glTF KHR_materials_sheen; main) and Neubelt & Pettineo's (three.js,
//!   Filament; variant), α the sheen α = sheenRoughness². Below sheenRoughness 0.1 the
//!   lobe lives at grazing half-vectors with albedo < 1e-3 (hence its `alpha_min`);
//!   Filament clamps the perceptual roughness to ≥ 0.045.
//! - **ltc-diffuse:** Burley's 2012 diffuse BRDF with its retro-reflection term (albedo 1),
//!   F_D90 with the paper's roughness √α (main) and with α as Filament and Bevy evaluate it
//!   (variant).
//! - **Fit, as the GGX table's** (src/studies/ltc_ggx/mod.rs): an `n`×`n` grid in
//!   (√α, √(1 − cos θ)), α = max(r², `alpha_min`); Nelder–Mead (≤ `max_iters` per stage)
//!   on the cubic metric over `samples`² stratified samples from the LTC and from the
//!   cosine hemisphere, warm starts, 3 then 4 parameters, the L2 polish of `polish`, one bilinear pass, binary16
//!   storage. Held out: a fresh (2·`samples`)² set per technique and the exact lobe error.

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::io::Outputs;
use crate::ltc::held::held_out_stats;
use crate::study::{Ctx, FitOutcome};
use serde::Serialize;

mod compute;
mod measures;
mod report;

use crate::integrate::Preset;
use crate::ltc::held::Stats;
pub use compute::{family, Family};
use compute::{fit_lobe, Fitted, Plan};

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
    held_out_cells: crate::results::ltc::HeldCells,
    report: &'a measures::TableReport,
    bilinear_pass: &'a crate::ltc::smooth::BilinearPass,
}

/// What a family's study computed: both fitted tables, their measures and held-out
/// summaries.
pub struct Computed {
    fam: Family,
    spec: FitSpec,
    preset: Preset,
    pl: Plan,
    main: Fitted,
    variant: Fitted,
    rep: measures::Report,
    /// Held-out summaries of the main table and of the variant.
    held: [Stats; 2],
}

/// The study: fit both tables of the family and measure them.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let (spec, preset) = (c.spec, c.preset);
    let fam = family(&spec.name).ok_or_else(|| {
        Error::InvalidArgument(format!(
            "fits/{}.toml: no LTC table family of that name (ltc-sheen, ltc-diffuse)",
            spec.name
        ))
    })?;
    let pl: Plan = c.params()?;
    let main = fit_lobe(fam.main, &pl)?;
    crate::report::stage(&format!(
        "regen {}: {} fitted; the variant next",
        fam.name,
        fam.main.short(),
    ));
    let variant = fit_lobe(fam.variant, &pl)?;
    crate::report::stage(&format!(
        "regen {}: {} fitted; report next",
        fam.name,
        fam.variant.short(),
    ));
    let rep = measures::compute(&main, &variant, &pl, pl.between_sample(preset))?;
    let held = [held_out_stats(&main.table), held_out_stats(&variant.table)];
    Ok(Computed {
        fam,
        spec: spec.clone(),
        preset,
        pl,
        main,
        variant,
        rep,
        held,
    })
}

fn render(set: &mut Outputs, results: &std::path::Path, c: &Computed) -> Result<()> {
    let (fam, spec, preset) = (&c.fam, &c.spec, c.preset);
    let command = format!("cargo run --release -- regen --only {}", fam.name);
    let md = report::markdown(
        fam, spec, preset, &c.pl, &c.main, &c.variant, &c.rep, &c.held, &command,
    );
    let svg = report::heatmaps(&c.main, &c.variant)?;
    // results/fits/<name>.json and the variant's: the one reader (`ltc::table`) reads both
    for (name, f, r, held) in [
        (fam.name, &c.main, &c.rep.main, &c.held[0]),
        (fam.variant_name, &c.variant, &c.rep.variant, &c.held[1]),
    ] {
        let (table, table_f16) = crate::ltc::storage::stored(&f.table);
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
            held_out: *held,
            held_out_cells: crate::results::ltc::HeldCells::of(&f.table),
            report: r,
            bilinear_pass: &f.bilinear,
        };
        crate::results::put_named(set, results, name, &json)?;
    }
    set.put(&results.join(format!("{}.md", fam.name)), md.as_bytes());
    set.put(
        &results.join(format!("{}-error.svg", fam.name)),
        svg.as_bytes(),
    );
    Ok(())
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        render(set, results, self)
    }

    fn outcome(&self) -> FitOutcome {
        let [st, sv] = &self.held;
        let worst = st.l2.max.value.max(sv.l2.max.value);
        FitOutcome::judged(
            &self.spec,
            worst,
            format!(
                "{n}×{n} tables: {} mean {} (max {}), {} mean {} (max {}) held-out rel. L2",
                self.fam.main.short(),
                st.l2.mean.pct(2),
                st.l2.max.pct(1),
                self.fam.variant.short(),
                sv.l2.mean.pct(2),
                sv.l2.max.pct(1),
                n = self.pl.n
            ),
        )
    }
}

crate::study::study! {
    /// The diffuse LTC table study (Burley; the engines' α), as the registry holds it.
    LtcDiffuse = "ltc-diffuse", after [], on request false, params Plan, computes compute
}

crate::study::study! {
    /// The sheen LTC table study (Charlie, both visibility conventions), as the registry
    /// holds it.
    LtcSheen = "ltc-sheen", after [], on request false, params Plan, computes compute
}

//! `regen --only ltc-ggx`: the GGX LTC table fit, the polygon-integration study (§3),
//! results/ltc-ggx.md, results/ltc-error.svg and results/fits/ltc-ggx.json. `compute`
//! fits the tables; each section's file measures (`measure*`) and formats (`section`);
//! `render` assembles the files.
//!
//! - **Target:** the cosine-weighted GGX BRDF with height-correlated G2, F = 1, per
//!   (roughness, view) cell of an `n`×`n` grid in (√α, √(1 − cos θ)), α = max(r²,
//!   `alpha_min`) as in the shipped table; production M⁻¹ (a, b, c, d) + norm + fresnel.
//! - **Model:** norm·γ_M, M = [X Y Z]·[[m11, 0, m13], [0, m22, 0], [0, 0, 1]], Z the mean
//!   BRDF direction turned by φ about Y; parameters (ln m11, ln m22, m13/m11, φ).
//! - **Fit:** Nelder–Mead (argmin, ≤ `max_iters` iterations per stage) on the reference
//!   fitter's cubic metric, mean |f − f_ltc|³/(p_ltc + p_brdf), over `samples`² stratified samples
//!   from the LTC and as many from the GGX VNDF; warm start from the rougher neighbour (φ
//!   carried, scaled by the α ratio); 3 parameters at the carried φ, then all 4, kept only
//!   if training and validation metrics both drop; an L2 polish (`polish`: Nelder–Mead, or
//!   Levenberg–Marquardt on (2·`samples`)² fixed nodes per technique, `ltc::gauss_newton`)
//!   kept only if the validation L2 drops; one bilinear pass (`ltc::smooth`); binary16 storage chosen per
//!   cell among the f16 neighbours (`ltc::storage`).
//! - **Held out:** a fresh (2·`samples`)² set per technique, offset by a quarter cell,
//!   and the exact lobe error of `ltc::held`; relative L2 ‖f − f_ltc‖/‖f‖.
//! - **Diagnostics** (optimiser variants, the floor of a single LTC, the route against the
//!   reference route): `studies::ltc_optimisers`, on request.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::io::Outputs;
use crate::ltc::fit::Table;
use crate::ltc::held::{self, held_out_stats as stats, Stats};
use crate::ltc::lobe_error::Tolerance;
use crate::ltc::smooth::{bilinear_pass, BilinearPass};
use crate::ltc::target::GgxTarget;
use crate::memo::Memo;
use crate::study::{Ctx, FitOutcome};

mod compute;
mod pipeline;
mod polygons;
mod precision;
mod shipped;
mod table;

pub use compute::cell_ltc;
use compute::{fit_main, Plan};

/// The title, the method and the table error.
fn intro(c: &Computed) -> String {
    let (preset, pl, main, st) = (c.preset, &c.pl, &c.main, &c.held);
    let mut md = format!(
        "# GGX LTC table and polygonal lights\n\nWritten by `cargo run --release -- regen --only ltc-ggx` (preset {}) from `fits/ltc-ggx.toml`. Target: the cosine-weighted GGX BRDF with height-correlated Smith G2 and F = 1, f = D·G2/(4 v_z). Model: norm·γ_M with M = [X Y Z]·[[m11, 0, m13], [0, m22, 0], [0, 0, 1]], Z the BRDF's mean direction. Grid {}×{}: perceptual roughness r = √α uniform on [0, 1] (α = max(r², {})), t = √(1 − cos θ) uniform on [0, 1] (θ clamped to {}°). Fit: Nelder–Mead (argmin, ≤ {} iterations per stage) on (ln m11, ln m22, m13/m11) against the reference fitter's cubic metric on {}×{} stratified samples per technique (LTC and VNDF{}), warm-started from the rougher neighbour within each θ column (rayon over columns). Four parameters per cell: (ln m11, ln m22, m13/m11) with the frame axis at the mean direction, then all four with the frame turn φ about Y free (the production form's four degrees of freedom; the reference fitter fixes the axis), kept only if it lowers both the training metric and a separate validation set's; φ is carried from cell to cell like the other parameters. Then an L2 polish: {}, kept only where the validation set's L2 drops too ({} of {} cells). norm and fresnel by nested adaptive quadrature in half-vector space (tolerance {:e}, largest error estimate {:.1e}).\n\n",
        preset.name(),
        pl.n,
        pl.n,
        pl.alpha_min,
        crate::ltc::hemisphere::THETA_MAX_DEG,
        pl.max_iters,
        pl.samples,
        pl.samples,
        pl.nodes.describe(),
        pl.polish.describe(pl.samples),
        main.cells.iter().flatten().filter(|c| c.polished).count(),
        pl.n * pl.n,
        crate::ltc::fit::ALBEDO_TOL,
        main.cells.iter().flatten().map(|c| c.norm_se).fold(0.0, f64::max)
    );
    md.push_str(&held_out_section(st, pl.tolerance()));
    md.push_str(" ![error](ltc-error.svg)\n\n");
    md.push_str(&format!("{}\n\n", c.sampled.sentence(st.l2.mean.value)));
    md
}

/// The held-out paragraph of a table: both figures, mean and largest, with error bars.
pub fn held_out_section(st: &Stats, tol: Tolerance) -> String {
    format!(
        "## Table error (held-out, as integrals)\n\nEach cell's lobe error is computed as integrals over the whole sphere to a stated accuracy, not sampled: ∫(f − norm·γ_M)², ∫f², ∫|f − norm·γ_M| and ∫f by adaptive cubature on charts that follow the BRDF's lobe and the LTC's (`ltc::lobe_error`), each figure ± the half-width of the interval its integrals' errors allow (K15 ⊗ K15 panels against the G7 ⊗ G7 rule on the same panels; {} per figure, met in {} of {} cells). Relative L2 ‖f − norm·γ_M‖/‖f‖: mean {}, max {} at α = {:.3}, θ = {:.1}°. Relative L1 ∫|f − norm·γ_M|/∫f: mean {}, max {}. Mean Nelder–Mead iterations {:.0}.",
        tol.describe(),
        st.converged,
        st.cells,
        st.l2.mean.pct(2),
        st.l2.max.pct(1),
        st.worst_cell.0,
        st.worst_cell.1,
        st.l1.mean.pct(2),
        st.l1.max.pct(1),
        st.mean_iters
    )
}

/// What the GGX study computed: the table, its held-out figures and every section's
/// measures.
pub struct Computed {
    spec: FitSpec,
    preset: Preset,
    pl: Plan,
    main: Table,
    held: Stats,
    sampled: held::Sampled,
    bilinear: BilinearPass,
    structure: table::Structure,
    between: crate::studies::ltc_between::Between,
    compare: Option<crate::results::compare::LtcCompare>,
    precision: precision::Precision,
    polygons: polygons::Polygons,
    pipeline: pipeline::Pipeline,
    /// The published table's fingerprint (`FittedTable::fingerprint`).
    fingerprint: String,
}

/// The study: fit the table and measure it.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let (spec, results, preset) = (c.spec, c.results, c.preset);
    let pl: Plan = c.params()?;
    let mut main = fit_main(&pl)?;
    let bilinear = bilinear_pass(&Memo, &mut main, &GgxTarget::new, pl.samples)?;
    crate::ltc::storage::store_table(&Memo, &mut main, &GgxTarget::new, pl.samples)?;
    crate::report::stage("regen ltc-ggx: held-out figures of every cell (f64, f32, binary16)");
    held::judge_table(&Memo, &mut main, &GgxTarget::new, pl.tolerance())?;
    let st = stats(&main);
    let sampled = held::sampled_estimate(&Memo, &main, &GgxTarget::new, 2 * pl.samples)?;
    let structure = table::measure_structure(&main);
    let between = crate::studies::ltc_between::measure(
        &main,
        &GgxTarget::new,
        pl.tolerance(),
        pl.between_sample(preset),
    )?;
    let compare = crate::results::compare::read(results)?;
    let precision = precision::measure(&main);
    let polygons = polygons::measure(&main, pl.mc)?;
    // the pipeline reads the table as a renderer reads the published file
    let stored = crate::results::ltc::table_of(&spec.name, &tables(spec, &main))?;
    let pipeline = pipeline::measure(&stored, &pl)?;
    Ok(Computed {
        spec: spec.clone(),
        preset,
        pl,
        main,
        held: st,
        sampled,
        bilinear,
        structure,
        between,
        compare,
        precision,
        polygons,
        pipeline,
        fingerprint: stored.fingerprint(),
    })
}

/// The table as the result file publishes it.
fn tables(spec: &FitSpec, main: &Table) -> crate::results::ltc::Tables {
    let (table, table_f16) = crate::ltc::storage::stored(main);
    crate::results::ltc::Tables {
        spec: spec.clone(),
        table,
        table_f16: Some(table_f16),
    }
}

/// Where the diagnostics went: studies of their own, run on request.
const OPTIMISERS: &str = "## Optimisers, the floor of a single LTC, and this route against the reference\n\nDiagnostics of the fit, not part of it, run on request by `cargo run --release -- regen --only ltc-ggx-optimisers` (results/ltc-ggx-optimisers.md): the optimiser and metric variants on a sub-grid, the floor of a single LTC per cell by a multi-start search, and this table's route against the reference route (Nelder–Mead to convergence and a Nelder–Mead L2 polish) through the same bilinear pass and storage, cell by cell on the held-out integrals.\n\n";

fn markdown(c: &Computed) -> String {
    let mut md = intro(c);
    md.push_str(&format!(
        "Bilinear pass (what a shader sees between cells): one sweep in four colours refitted each cell's (a, b, c, d) against its own lobe and, with weight {} each, the lobes at the centres of its squares as a GPU interpolates both textures, each term as its squared error relative to the table's before the pass (so a cell that fits well is not spent on a square that cannot; Nelder–Mead, ≤ {} iterations, kept only where a validation set agrees; the norm stays the albedo): {} of {} cells moved. The errors above and below are after it; results/ltc-compare.md has the squares.\n\nFit cost: results/performance.md (criterion's time for single cells; the main job's wall clock per study, which this report leaves out so that it is the same in every run, sharded or cached).\n\n",
        c.bilinear.square_weight, c.bilinear.max_iters, c.bilinear.cells_moved, c.pl.n * c.pl.n
    ));
    md.push_str(&table::structure_section(&c.structure));
    md.push_str(&table::between_section(&c.between, &c.held));
    md.push_str(&shipped::section(
        c.compare.as_ref(),
        c.held.l2.mean,
        &c.fingerprint,
    ));
    md.push_str(&precision::section(&c.precision));
    md.push_str(OPTIMISERS);
    md.push_str(&polygons::section(&c.polygons));
    md.push_str(&pipeline::section(&c.pipeline));
    md
}

fn render(set: &mut Outputs, results: &std::path::Path, c: &Computed) -> Result<()> {
    let spec = &c.spec;
    let svg =
        crate::studies::ltc_error_map::ltc_error_heatmap(&c.main, "LTC fit: relative L2 error")?;
    set.put(&results.join("ltc-error.svg"), svg.as_bytes());
    set.put(&results.join("ltc-ggx.md"), markdown(c).as_bytes());
    let t = tables(spec, &c.main);
    let poly = &c.polygons;
    let json = crate::results::ltc::Ggx {
        spec: spec.clone(),
        command: crate::results::command(&spec.name),
        preset: c.preset.name().into(),
        grid: c.main.grid,
        layout: "table[j][i] = [a, b, c, d, norm, fresnel]; j = θ index (t = √(1 − cos θ) = j/(n−1)), i = roughness index (r = √α = i/(n−1)); M⁻¹ ∝ [[a, 0, c], [0, 1, 0], [b, 0, d]]".into(),
        table: t.table,
        table_f16: t.table_f16.unwrap_or_default(),
        held_out: c.held,
        held_out_cells: crate::results::ltc::HeldCells::of(&c.main),
        edge_approximations: poly.edge_approximations.clone(),
        degenerate: poly.degenerate_rows(),
        polygons: poly.polygon_rows(),
        pipeline: pipeline::result(&c.pipeline),
        sphere_horizon: poly.sphere_horizon,
        bilinear_pass: c.bilinear,
        between: c.between.clone(),
    };
    crate::results::put_named(set, results, &spec.name, &json)
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        render(set, results, self)
    }

    fn outcome(&self) -> FitOutcome {
        let st = &self.held;
        FitOutcome::judged(
            &self.spec,
            st.l2.max.value,
            format!(
                "{}×{} table: held-out rel. L2 mean {}, max {}",
                self.pl.n,
                self.pl.n,
                st.l2.mean.pct(2),
                st.l2.max.pct(1)
            ),
        )
    }
}

crate::study::study! {
    /// The GGX LTC table study, as the registry holds it.
    LtcGgx = "ltc-ggx", after [], on request false, params Plan, computes compute
}

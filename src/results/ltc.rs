//! The LTC table results (results/fits/ltc-ggx.json and the lobe tables ltc-sheen*,
//! ltc-diffuse*): the table every reader shades with, its held-out figures and the GGX
//! study's polygon checks. The one reader of a fitted table is [`table`].

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::integrate::{Figure, Quad};
use crate::ltc::fit::Grid;
use crate::ltc::held::Stats;
use crate::ltc::smooth::BilinearPass;
use crate::ltc::table::{FittedTable, MAX_SIDE};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Columns j of cells i, each [a, b, c, d, norm, fresnel] (seed 005's M⁻¹ entries, the
/// BRDF's albedo and its Fresnel share).
pub type Columns = Vec<Vec<[f64; 6]>>;

/// The table part of every LTC table result: what code generation, the engine files,
/// the renderer and the shading pipeline read.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Tables {
    pub spec: FitSpec,
    pub table: Columns,
    /// The binary16 storage chosen by the fit (every value a binary16 number), same
    /// layout; absent in a file without one (storage then rounds to nearest).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table_f16: Option<Columns>,
}

/// The held-out figures of an LTC table result, and for the GGX table its polygon checks
/// (absent in the lobe tables).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    pub spec: FitSpec,
    pub command: String,
    pub held_out: Stats,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere_horizon: Option<SphereHorizon>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub edge_approximations: Vec<EdgeApproximation>,
}

pub use super::between::Located;

/// results/fits/ltc-ggx.json: the GGX table, its held-out figures and every section's
/// measures. The lobe-table results share its first part ([`Tables`], [`Summary`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Ggx {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub grid: Grid,
    pub layout: String,
    /// table[j][i] = [a, b, c, d, norm, fresnel].
    pub table: Columns,
    /// The binary16 storage of the table (every value a binary16 number), same layout.
    pub table_f16: Columns,
    pub held_out: Stats,
    /// Every cell's held-out figures (the f64 cell).
    pub held_out_cells: HeldCells,
    pub edge_approximations: Vec<EdgeApproximation>,
    pub degenerate: Vec<Degenerate>,
    pub polygons: Vec<PolygonRow>,
    pub pipeline: Pipeline,
    pub sphere_horizon: SphereHorizon,
    /// The bilinear-aware refit.
    pub bilinear_pass: BilinearPass,
    /// The error between cells, from a calibrated sample of squares.
    pub between: crate::results::between::Between,
}

/// The held-out relative L2 and L1 of every cell of a table (its f64 cell), each
/// [value, error bar]: what a reader compares cell by cell.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct HeldCells {
    pub layout: String,
    pub l2: Vec<Vec<Option<[f64; 2]>>>,
    pub l1: Vec<Vec<Option<[f64; 2]>>>,
}

impl HeldCells {
    /// The figures of a judged table (`ltc::held::judge_table`); `None` where a cell has
    /// none (a singular one, or one not judged).
    pub fn of(t: &crate::ltc::fit::Table) -> HeldCells {
        let grid = |l1: bool| {
            t.cells
                .iter()
                .map(|col| {
                    col.iter()
                        .map(|c| {
                            c.held
                                .and_then(|h| h.f64)
                                .map(|e| if l1 { e.l1 } else { e.l2 })
                                .map(|b| [b.value, b.error])
                        })
                        .collect()
                })
                .collect()
        };
        HeldCells {
            layout: "[j][i] = [value, error] (null where singular)".into(),
            l2: grid(false),
            l1: grid(true),
        }
    }
}

/// results/fits/ltc-ggx-optimisers.json (on request): the optimiser and metric variants
/// on a sub-grid, the floor of a single LTC, and the table's fitting route against the
/// reference route cell by cell.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Optimisers {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub variants: Vec<Variant>,
    pub floor: Vec<FloorCell>,
    pub reference: RouteComparison,
    /// The fingerprint (`FittedTable::fingerprint`) of the published GGX table the study
    /// read (its floor and route comparison index its cells), when it ran; `None` in a
    /// file from before it was kept.
    #[serde(default)]
    pub table_fingerprint: Option<String>,
}

impl super::ResultFile for Optimisers {
    const NAME: &'static str = super::names::LTC_GGX_OPTIMISERS;
}

/// The published table against the same pipeline (bilinear pass, storage) with the
/// reference fitting route, cell by cell, on held-out integrals.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RouteComparison {
    /// The reference route in words, and the table's.
    pub reference: String,
    pub table: String,
    /// Mean held-out relative L2 of each, within the mean of its cells' bars.
    pub reference_mean: Figure<Quad>,
    pub table_mean: Figure<Quad>,
    /// Mean of (table − reference) per cell, within the mean of the summed bars.
    pub mean_change: Figure<Quad>,
    /// Cells where the table is worse / better than the reference by more than the sum
    /// of the two figures' bars (each bar bounds its figure, so such a difference is
    /// certain); of those worse, how many by more than 0.01 and 0.1 points, and the
    /// largest difference (as a fraction).
    pub worse: usize,
    pub worse_by_001pt: usize,
    pub worse_by_01pt: usize,
    pub largest_excess: f64,
    pub better: usize,
    pub cells: usize,
}

/// results/fits/ltc-work.json (on request): the LTC tables' accuracy against their
/// fitting work — each published route on other training draws, cheaper routes judged
/// against that spread (`ltc::spread`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LtcWork {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub tables: Vec<TableWork>,
}

impl super::ResultFile for LtcWork {
    const NAME: &'static str = super::names::LTC_WORK;
}

/// One published table's part of the work study.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TableWork {
    /// The table's file (results/fits/<table>.json).
    pub table: String,
    /// The fingerprint (`FittedTable::fingerprint`) of the table read.
    pub table_fingerprint: String,
    /// The published route's polish in words (the anisotropic table, which has none: its
    /// whole route).
    pub polish: String,
    /// The published route's nodes (absent: moving samples, the reference fitter's). On
    /// any other, the first draw is the reference refitted at the published offset, and
    /// the published table is the route at the published settings on these nodes.
    #[serde(default)]
    pub published_nodes: crate::ltc::fit::Nodes,
    /// The reference's draws (moving samples), the one at the published offset first.
    pub draws: Vec<WorkRow>,
    /// Each cheaper route with its verdict.
    pub routes: Vec<(WorkRow, crate::ltc::spread::Verdict)>,
}

/// One fitted table of the work study: its route and training draw, the mean held-out
/// relative L2 of its f64 cells, and its fit's work and cubic-stage iterations per cell
/// (`None` for the published table, read rather than refitted).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WorkRow {
    pub samples: usize,
    pub max_iters: u64,
    /// Whether the cubic stage measured its trials on fixed nodes
    /// (`ltc::fit::Method::FixedNodes`) rather than on samples of each trial.
    #[serde(default)]
    pub fixed_nodes: bool,
    /// Whether the L2 polish and the bilinear pass did too (`Method::FixedNodesAll`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub fixed_all: bool,
    pub offset: f64,
    pub mean: Figure<Quad>,
    /// The mean held-out relative L2 between cells (the table interpolated at the squares'
    /// centres, `studies::ltc_between`, as the table's own study judges it: every square
    /// or a sample ± its s.e.); `None` for the published table, whose study reports it.
    #[serde(default)]
    pub between_l2: Option<Figure<crate::integrate::StdErr>>,
    /// The judged squares' mean integral bar (the held-out integrals' own error, which a
    /// census's zero s.e. leaves out); `None` where not stored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub between_bar: Option<f64>,
    pub work_per_cell: Option<f64>,
    /// Target evaluations of the fit per cell (`ltc::samples::target_work`).
    #[serde(default)]
    pub target_evals_per_cell: Option<f64>,
    pub iters_per_cell: Option<f64>,
}

impl WorkRow {
    /// The route's nodes, from the two flags the file keeps.
    pub fn nodes(&self) -> crate::ltc::fit::Nodes {
        use crate::ltc::fit::Nodes;
        match (self.fixed_nodes, self.fixed_all) {
            (_, true) => Nodes::FixedAll,
            (true, false) => Nodes::Fixed,
            (false, false) => Nodes::Moving,
        }
    }
}

/// results/fits/ltc-judge-tolerance.json (on request): the held-out judge's accuracy
/// against its work, per published table, at each relative tolerance.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JudgeTolerance {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub tables: Vec<JudgeCurve>,
}

impl super::ResultFile for JudgeTolerance {
    const NAME: &'static str = super::names::LTC_JUDGE_TOLERANCE;
}

/// One table's curve: the cells judged, the tolerance its spec chose, one point per
/// tolerance (the first the reference).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JudgeCurve {
    pub table: String,
    pub cells: usize,
    pub chosen_rel: f64,
    /// The relative L1's tolerance its spec chose (`held_out_l1_rel`).
    pub chosen_l1_rel: f64,
    pub points: Vec<JudgePoint>,
    /// The relative L2 at `chosen_rel`, the relative L1's tolerance swept (`rel` is the
    /// L1's); against the same reference as `points`.
    pub l1_points: Vec<JudgePoint>,
    /// The SHA-256 of results/fits/<table>.json's table part (its cells and its spec's
    /// tolerances) when the study ran (`results::fits_sha256`); `None` in a file from
    /// before it was kept.
    #[serde(default)]
    pub table_sha256: Option<String>,
}

/// The judge at one relative tolerance, over the cells of a curve (the f64 cells' figures).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct JudgePoint {
    pub rel: f64,
    /// Integrand evaluations per cell (all four precisions judged together).
    pub evals_per_cell: f64,
    /// Mean relative L2 within the mean of the cells' bars.
    pub l2_mean: Figure<Quad>,
    /// Mean relative L1 within the mean of the cells' bars.
    pub l1_mean: Figure<Quad>,
    /// The largest bar of any cell's relative L2 or L1.
    pub largest_bar: f64,
    /// The largest |change| of a cell's relative L2 or L1 against the reference tolerance.
    pub largest_change: f64,
    /// Figures (relative L2 and L1 per cell) whose change against the reference exceeds the
    /// two bars together: a bar that failed to bound its figure.
    pub beyond_bars: usize,
    /// Cells whose integrals missed the tolerance within the evaluation budget.
    pub unconverged: usize,
}

/// One optimiser/metric variant and its held-out summary on the sub-grid.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Variant {
    pub fit: String,
    pub stats: Stats,
}

/// A degenerate light and its exact, rational and cubic form factors.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Degenerate {
    pub light: String,
    pub values: Vec<f64>,
}

/// One polygon light at one cell: the Monte Carlo truth ± s.e. beside the LTC with the
/// exact and the rational edge integral.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PolygonRow {
    pub alpha: f64,
    pub theta: f64,
    pub light: String,
    pub mc: Figure,
    pub ltc_exact: f64,
    pub ltc_rational: f64,
}

/// The multi-scale pipeline against brute force (seed 000 §3–4).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Pipeline {
    pub alpha: f64,
    pub views_deg: Vec<f64>,
    pub levels: Vec<PipelineLevel>,
}

/// One mip level of the pipeline study.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PipelineLevel {
    pub level: usize,
    pub cases: usize,
    pub methods: Vec<PipelineMethod>,
}

/// One method's figures at one level.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PipelineMethod {
    pub method: String,
    /// Mean |method/truth − 1| ± s.e. over the sampled footprints (the truth exact to its
    /// bar).
    pub mean_abs_rel: Figure,
    /// Mean method/truth ± s.e.
    pub mean_ratio: Figure,
    /// Σ|method − truth| / Σ truth.
    #[serde(deserialize_with = "super::f64_or_nan")]
    pub energy_weighted_rel: f64,
}

/// One cell of the floor study: the table's held-out error beside the best single LTC.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct FloorCell {
    pub i: usize,
    pub j: usize,
    pub alpha: f64,
    pub theta_deg: f64,
    /// The table's held-out relative L2.
    pub table: crate::integrate::Figure<crate::integrate::Quad>,
    /// The best of the multi-start search, norm = albedo.
    pub global: crate::integrate::Figure<crate::integrate::Quad>,
    /// That shape with the L2-optimal amplitude.
    pub free_amplitude: crate::integrate::Figure<crate::integrate::Quad>,
    /// A*/albedo: the energy that amplitude keeps.
    pub amplitude_over_albedo: f64,
}

impl super::ResultFile for Ggx {
    const NAME: &'static str = super::names::LTC_GGX;
}

/// What a published LTC table file (GGX or a lobe table) holds besides its table that a
/// study refitting it reads.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Published {
    pub spec: FitSpec,
    pub preset: String,
    pub grid: Grid,
    pub held_out_cells: HeldCells,
}

impl Published {
    /// The route its spec names, at the preset it was fitted at.
    pub fn route(&self, name: &str) -> Result<GgxRoute> {
        route_of(&self.spec, &self.preset, name)
    }
    /// The preset it was fitted at (the file `name`) and the keys `P` its spec chose there.
    pub fn chosen<P: crate::fit::spec::Params>(
        &self,
        name: &str,
    ) -> Result<(crate::integrate::Preset, P)> {
        let at = format!("results/fits/{name}.json");
        let preset = crate::integrate::Preset::named(&self.preset, &at)?;
        Ok((preset, self.spec.params(preset)?))
    }
}

/// The route `spec` names at the preset called `preset`, of the file `name`.
fn route_of(spec: &FitSpec, preset: &str, name: &str) -> Result<GgxRoute> {
    let at = format!("results/fits/{name}.json");
    spec.params(crate::integrate::Preset::named(preset, &at)?)
}

/// The published LTC table `name` read back for a study that indexes its cells: the
/// table through the one reader of fitted tables (n × n finite cells), its grid of the
/// same side, and every cell's held-out figure a finite, non-negative pair — never
/// trusted by its shape. Returns the file's keys and the table's fingerprint
/// (`FittedTable::fingerprint`).
pub fn published(results: &Path, name: &str) -> Result<(Published, String)> {
    let (p, _, fingerprint) = published_table(results, name)?;
    Ok((p, fingerprint))
}

/// [`published`] with the table itself, for a study that reads its cells: the file is
/// read and checked once.
pub fn published_table(results: &Path, name: &str) -> Result<(Published, FittedTable, String)> {
    let p: Published = super::require_named(results, name)?;
    let (t, fingerprint) = check_published(results, name, &p.spec, p.grid.n, &p.held_out_cells)?;
    Ok((p, t, fingerprint))
}

/// The published GGX table, checked as [`published`] checks it, with its whole file.
pub fn published_ggx(results: &Path) -> Result<(Ggx, String)> {
    let g: Ggx = super::require(results)?;
    let name = super::names::LTC_GGX;
    let (_, fingerprint) = check_published(results, name, &g.spec, g.grid.n, &g.held_out_cells)?;
    Ok((g, fingerprint))
}

/// [`published`]'s checks of the file `name` (its spec, grid side `n` and held-out
/// cells already read); the table and its fingerprint.
fn check_published(
    results: &Path,
    name: &str,
    spec: &FitSpec,
    n: usize,
    held: &HeldCells,
) -> Result<(FittedTable, String)> {
    let t = table(results, name)?;
    let bad = |what: String| {
        Err(Error::InvalidArgument(format!(
            "results/fits/{name}.json: {what}: run `cargo run --release -- regen --only {}`",
            spec.name
        )))
    };
    if t.n != n {
        return bad(format!("a {0}×{0} table under a grid of side {n}", t.n));
    }
    let cells = &held.l2;
    if cells.len() != n || cells.iter().any(|col| col.len() != n) {
        return bad(format!("held_out_cells is not {n}×{n}"));
    }
    if cells
        .iter()
        .flatten()
        .flatten()
        .any(|f| !(f[0].is_finite() && f[1].is_finite() && f[0] >= 0.0 && f[1] >= 0.0))
    {
        return bad("a held-out figure that is not a finite, non-negative pair".into());
    }
    let fingerprint = t.fingerprint();
    Ok((t, fingerprint))
}

/// The route a published LTC table was fitted with: the keys of its spec that the
/// studies refitting it read (the others are the table study's own).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GgxRoute {
    pub samples: usize,
    pub max_iters: u64,
    pub polish: crate::ltc::fit::Polish,
    /// Where its cubic stage measured its trials (a spec without the key: moving).
    #[serde(default)]
    pub nodes: crate::ltc::fit::Nodes,
    /// The held-out figures' tolerance; a spec from before the key judged to the
    /// default.
    #[serde(default = "crate::ltc::lobe_error::Tolerance::default_relative")]
    pub held_out_rel: f64,
    /// The relative L1's own; a spec from before the key judged it to `held_out_rel`.
    #[serde(default)]
    pub held_out_l1_rel: Option<f64>,
}

impl GgxRoute {
    /// The tolerance the published figures were judged to.
    pub fn tolerance(&self) -> crate::ltc::lobe_error::Tolerance {
        let l1 = self.held_out_l1_rel.unwrap_or(self.held_out_rel);
        crate::ltc::lobe_error::Tolerance::figures(self.held_out_rel, l1)
    }
}

impl crate::fit::spec::Params for GgxRoute {
    fn check(&self) -> std::result::Result<(), String> {
        crate::fit::spec::within("samples", self.samples, 2, 128)?;
        crate::fit::spec::within("max_iters", self.max_iters, 1, 100_000)?;
        crate::ltc::lobe_error::Tolerance::check_relative(self.held_out_rel)?;
        match self.held_out_l1_rel {
            Some(r) => crate::ltc::lobe_error::Tolerance::check_relative_l1(r),
            None => Ok(()),
        }
    }
}

impl Ggx {
    /// The route its spec names, at the preset it was fitted at.
    pub fn route(&self) -> Result<GgxRoute> {
        route_of(&self.spec, &self.preset, super::names::LTC_GGX)
    }
}

/// The clipped-sphere horizon correction against exact clipping over random quads.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct SphereHorizon {
    /// Σ|approx − exact| / Σ exact.
    pub energy_weighted_rel: f64,
    pub cases: usize,
    pub off_by_more_than_10pct: usize,
}

/// A production form of the edge integral's θ/sin θ against the exact one.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EdgeApproximation {
    pub form: String,
    /// Largest relative error on x = cos θ ∈ [−1, 0.999999], and where.
    pub max_rel: f64,
    pub at_x: f64,
    /// Largest relative error on x ∈ [−0.99, 1].
    pub max_rel_x_ge_m099: f64,
}

/// Read the table of the LTC result `name` under `results`: an n × n table
/// (2 ≤ n ≤ [`MAX_SIDE`]) of finite numbers whose binary16 storage, if given, holds only
/// binary16 numbers — or a typed error saying what is wrong.
pub fn table(results: &Path, name: &str) -> Result<FittedTable> {
    table_of(name, &super::require_named(results, name)?)
}

/// The table of the LTC result `t` (the file `name`), checked as [`table`] checks it: what
/// a reader of the file gets, for the study that has the result in hand before it is
/// published.
pub fn table_of(name: &str, t: &Tables) -> Result<FittedTable> {
    let bad = |m: &str| Error::InvalidArgument(format!("results/fits/{name}.json: {m}"));
    let (n, cells) = cells_of(&t.table, None, &bad)?;
    let half = match &t.table_f16 {
        None => None,
        Some(h) => {
            let (_, h) = cells_of(h, Some(n), &bad)?;
            let mut out = Vec::with_capacity(h.len());
            for c in h {
                let q = c.map(half::f16::from_f64);
                if q.iter().zip(&c).any(|(a, b)| a.to_f64() != *b) {
                    return Err(bad("table_f16 holds a value that is not a binary16 number"));
                }
                out.push(q);
            }
            Some(out)
        }
    };
    Ok(FittedTable { n, cells, half })
}

/// The cells of a square table of columns, `cells[i + n·j]`, checked: side 2 … MAX_SIDE
/// (`n` when given), every column of that length, every number finite.
fn cells_of(
    table: &Columns,
    n: Option<usize>,
    bad: &dyn Fn(&str) -> Error,
) -> Result<(usize, Vec<[f64; 6]>)> {
    let n = n.unwrap_or(table.len());
    if !(2..=MAX_SIDE).contains(&n) || table.len() != n {
        return Err(bad(&format!(
            "a table of side {}, not 2 … {MAX_SIDE}",
            table.len()
        )));
    }
    let mut cells = vec![[0.0; 6]; n * n];
    for (j, col) in table.iter().enumerate() {
        if col.len() != n {
            return Err(bad("malformed table"));
        }
        for (i, c) in col.iter().enumerate() {
            if c.iter().any(|x| !x.is_finite()) {
                return Err(bad("bad table cell"));
            }
            cells[i + n * j] = *c;
        }
    }
    Ok((n, cells))
}

//! The LTC table results (results/fits/ltc-ggx.json and the lobe tables ltc-sheen*,
//! ltc-diffuse*): the table every reader shades with, its held-out figures and the GGX
//! study's polygon checks. The one reader of a fitted table is [`table`].

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::ltc::aniso_table::{AnisoCell, AnisoGrid, AnisoTable};
use crate::ltc::held::Stats;
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

/// results/fits/ltc-aniso.json: the anisotropic GGX table, its study's summary and its
/// polygon checks.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Aniso {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub grid: AnisoGrid,
    pub layout: String,
    pub cells: Vec<AnisoCell>,
    pub summary: AnisoSummary,
    /// The polygon-light checks, as the report renders them (no other code reads them).
    pub polygons: serde_json::Value,
}

impl super::ResultFile for Aniso {
    const NAME: &'static str = super::names::LTC_ANISO;
}

/// The anisotropic study's summary: the figures other reports quote, typed; the rest as
/// the study wrote it (read only by its own report).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct AnisoSummary {
    pub cells_fitted: usize,
    /// The relative L2 between cells, as shaders interpolate the table.
    pub between_table: MeanMax,
    #[serde(flatten)]
    pub detail: std::collections::BTreeMap<String, serde_json::Value>,
}

/// (mean ± s.e., max) of a set of errors.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct MeanMax {
    /// The mean and its standard error (for a random sample of cases).
    pub mean: crate::integrate::Figure,
    pub max: f64,
    pub count: usize,
}

/// The table part of results/fits/ltc-aniso.json.
#[derive(Deserialize)]
struct AnisoTables {
    grid: AnisoGrid,
    cells: Vec<AnisoCell>,
}

/// The shipped anisotropic table (a typed error if absent or malformed, with every size
/// bounded).
pub fn aniso_table(results: &Path) -> Result<AnisoTable> {
    let name = super::names::LTC_ANISO;
    let t: AnisoTables = super::require_named(results, name)?;
    let bad = |m: &str| Error::InvalidArgument(format!("results/fits/{name}.json: {m}"));
    let grid = t.grid;
    if [grid.n_r, grid.n_phi, grid.n_t]
        .iter()
        .any(|n| !(2..=64).contains(n))
    {
        return Err(bad("a grid side outside 2 … 64"));
    }
    if t.cells.len() != grid.cells() || t.cells.iter().flatten().any(|x| !x.is_finite()) {
        return Err(bad("cells do not match the grid"));
    }
    Ok(AnisoTable {
        grid,
        cells: t.cells,
    })
}

//! results/fits/ltc-aniso.json: the anisotropic GGX table (the one reader is
//! [`aniso_table`]), the study's summary, its design study and its polygon checks.

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::ltc::aniso_table::{AnisoCell, AnisoGrid, AnisoTable};
use serde::{Deserialize, Serialize};
use std::path::Path;

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
    pub summary: Summary,
    /// The polygon-light checks.
    pub polygons: Vec<PolygonRow>,
}

impl super::ResultFile for Aniso {
    const NAME: &'static str = super::names::LTC_ANISO;
}

/// results/fits/ltc-aniso-work.json (on request): the anisotropic table's accuracy
/// against its fitting work — the reference route's draws and the routes judged against
/// their spread (`ltc::spread`), in the LTC work study's shape. Its fingerprint is the
/// published table's (`AnisoTable::fingerprint`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct AnisoWork {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub work: super::ltc::TableWork,
}

impl super::ResultFile for AnisoWork {
    const NAME: &'static str = super::names::LTC_ANISO_WORK;
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
    // a norm (the lobe's albedo, index 7) of 0 or below would scale every lookup to
    // nothing and divide the held-out figures by it
    if let Some(k) = t.cells.iter().position(|c| !(c[7] > 0.0)) {
        return Err(bad(&format!(
            "cell {k} has a norm {} that is not positive",
            t.cells[k][7]
        )));
    }
    Ok(AnisoTable {
        grid,
        cells: t.cells,
    })
}

/// A row of the per-anisotropy tables.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Bin {
    pub label: String,
    pub ours: MeanMax,
    pub iso_geo: MeanMax,
    pub iso_max: MeanMax,
}

/// A predicted table size.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Prediction {
    pub size: [usize; 4],
    pub texels: usize,
    pub bytes_f16: usize,
    /// Predicted RMS relative L2 between cells.
    pub predicted_mean: f64,
    /// Whether a dimension's penalty was extrapolated (h² beyond the study's finest).
    pub extrapolated: bool,
}

/// Everything the report shows.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    pub fit_rms: f64,
    pub between_rms: f64,
    pub cells_fitted: usize,
    pub cells: Bin,
    pub between_table: MeanMax,
    pub between_table_f16: MeanMax,
    pub between_iso_geo: MeanMax,
    pub between_iso_max: MeanMax,
    pub by_anisotropy: Vec<Bin>,
    pub design: Design,
    pub predictions: Vec<Prediction>,
    /// The largest error bar of any held-out figure of a cell or a case.
    pub bar_max: f64,
    /// Relative L1 of the table: at its cells (mean / max) and between them.
    pub cells_l1: MeanMax,
    pub between_table_l1: MeanMax,
}
/// The interpolation penalty of one dimension at one resolution.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Penalty {
    pub dim: usize,
    /// Nodes over the dimension's whole range.
    pub n: usize,
    /// Mean held-out relative L2 at the dropped nodes, interpolated linearly from the kept
    /// ones (entries and norm), over every line of this dimension.
    pub interpolated: f64,
    /// Mean held-out relative L2 of the fits at the same nodes.
    pub fitted: f64,
}

/// The design study's output.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Design {
    pub bases: Vec<[f64; 4]>,
    pub penalties: Vec<Penalty>,
    /// The largest error bar of any held-out figure of the study.
    pub bar_max: f64,
}
/// One case: a point of the 4D domain.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Case {
    pub ax: f64,
    pub ay: f64,
    pub phi: f64,
    pub theta: f64,
}

/// One polygon check: a case, the table's lookup there × the quad, against MC of the true
/// lobe, and the isotropic table at √(α_x α_y) × the same quad.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PolygonRow {
    pub case: Case,
    pub albedo: f64,
    pub check: crate::ltc::polygon::PolygonCheck,
    pub iso_geo_exact: f64,
}

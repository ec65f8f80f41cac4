//! results/fits/filters.json: the footprint-filter study (seed 003, seed 004 §3.2) —
//! per filter summaries, the fitted constants the generated code carries, and the
//! survey's numbers, and the per-map, per-level and screen tables the report renders.

use crate::fit::spec::FitSpec;
use crate::integrate::Figure;
use crate::survey::em::EmLog;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Filters {
    pub spec: FitSpec,
    pub command: String,
    /// Per filter id (GGX) or `beckmann:<id>`: mean L2 ± s.e.
    pub summary: BTreeMap<String, FilterSummary>,
    pub by_level_note: String,
    pub map_filters: Vec<String>,
    pub by_level: Vec<LevelRow>,
    pub preset: String,
    pub plan: crate::filters::plan::Plan,
    pub maps: Vec<MapRows>,
    pub screen: Vec<ScreenRow>,
    pub fitted: Vec<FittedConstant>,
    pub survey: Summary,
}

impl Filters {
    /// The fitted constant of `family` for `ndf` ("GGX" or "Beckmann").
    pub fn fitted(&self, family: &str, ndf: &str) -> Option<&FittedConstant> {
        self.fitted
            .iter()
            .find(|f| f.family == family && f.ndf == ndf)
    }
}

/// One (mip level, map, NDF, map filter): the mean L2 and energy errors over the level's
/// footprints, α and views.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LevelRow {
    pub level: usize,
    /// Index into [`Filters::map_filters`].
    pub map: usize,
    pub ndf: String,
    pub filter: usize,
    pub l2: Figure,
    pub energy: Figure,
}

/// One map's table: per map filter, its aggregate per NDF.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MapRows {
    pub map: String,
    pub filters: Vec<FilterRow>,
}

/// One filter's row of a map's table.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FilterRow {
    pub filter: String,
    pub by_ndf: Vec<NdfAgg>,
}

/// An aggregate over one NDF's cases.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct NdfAgg {
    pub ndf: String,
    pub all: Agg,
}

/// One screen-space kernel under one pixel footprint and NDF.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ScreenRow {
    pub pixel: String,
    pub ndf: String,
    pub kernel: String,
    pub all: Agg,
}

/// One filter's mean lobe L2 error over its cases.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FilterSummary {
    pub name: String,
    pub l2: Figure,
    /// Which cases: the map cases or the Gaussian-pixel screen cases.
    pub study: String,
}

/// A constant fitted on the training cases, judged on the held-out ones.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FittedConstant {
    pub family: String,
    pub ndf: String,
    pub constant: f64,
    pub train_mean_l2: f64,
    pub held_out: Agg,
}

/// Mean ± standard error over cases (NaNs skipped), plus extremes.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Agg {
    pub cases: usize,
    /// The energy bias (∫ filtered / ∫ truth − 1).
    pub energy: Figure,
    #[serde(deserialize_with = "super::f64_or_nan")]
    pub energy_abs_mean: f64,
    /// The lobe's relative L2 error.
    pub l2: Figure,
    #[serde(deserialize_with = "super::f64_or_nan")]
    pub l2_max: f64,
    /// The peak's relative error.
    pub peak: Figure,
    /// Largest Monte Carlo standard error of any single case's L2 (sampling noise).
    #[serde(deserialize_with = "super::f64_or_nan")]
    pub l2_mc_se_max: f64,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RowSummary {
    pub name: String,
    pub family: String,
    pub params: Option<usize>,
    pub all: Agg,
    pub ggx: Agg,
    pub beckmann: Agg,
    pub by_map: Vec<Agg>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Verdict {
    pub map: String,
    pub budget: usize,
    pub best: String,
    pub best_params: usize,
    pub l2: Figure,
    pub runner_up: String,
    /// Paired difference runner-up − best over the map's cases.
    pub margin: Figure,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LevelPair {
    pub level: usize,
    pub recomputed: Figure,
    pub mipped: Figure,
    pub cost: Figure,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct AlignmentRow {
    pub map: String,
    /// Per merged K: fraction of matched pairs that could not be aligned.
    pub tan_misaligned: Vec<f64>,
    pub vmf_misaligned: Vec<f64>,
    /// Tan, 4 lobes MIP-mapped minus EM per footprint, over footprints with a misaligned
    /// pair and over those without, with the number of footprints.
    pub tan_cost_misaligned: (Figure, usize),
    pub tan_cost_aligned: (Figure, usize),
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RuleOfThumb {
    pub exponent: f64,
    pub rule: f64,
    pub needed: Vec<Option<usize>>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
/// results/filters-survey.md's numbers: every representation's row, the verdicts per budget and
/// the diagnostics of the survey's pitfalls.
pub struct Summary {
    pub maps: Vec<String>,
    pub rows: Vec<RowSummary>,
    pub verdicts: Vec<Verdict>,
    pub schilling: Vec<LevelPair>,
    pub alignment: Vec<AlignmentRow>,
    pub em: EmLog,
    pub fournier_fit_l2: Vec<(usize, Figure)>,
    pub fournier_iters: Vec<(usize, f64)>,
    pub olano_north_z_err_max: f64,
    pub vmf_terms_max: usize,
    pub rule_of_thumb: Vec<RuleOfThumb>,
    pub rule_eps: Vec<f64>,
}

impl super::ResultFile for Filters {
    const NAME: &'static str = super::names::FILTERS;
}

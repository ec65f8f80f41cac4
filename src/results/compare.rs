//! results/ltc-compare.json: our GGX table against a shipped one (three.js's, Bevy's) as
//! shaders sample them, written by `ltc-compare` and summarised in results/ltc-ggx.md.

use crate::error::Result;
use crate::ltc::lobe_error::{LobeError, Spread};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The file.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LtcCompare {
    pub command: String,
    pub source: Option<String>,
    pub bevy_source: Option<String>,
    /// Whose norms the comparison used.
    pub norms: String,
    /// The held-out mean relative L2 of our table when the comparison ran (identifies
    /// the table it was made against).
    pub ours_table_mean_l2: f64,
    /// The fingerprint of our table when the comparison ran (`FittedTable::fingerprint`;
    /// absent in a file written before it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ours_table_fingerprint: Option<String>,
    pub convention: String,
    /// Per place ("three.js FloatType cells", …).
    pub summary: Vec<(String, Summary)>,
    /// Every cell and square of each way an engine uploads both tables.
    pub forms: Vec<Form>,
}

/// Both tables' held-out figures at one place (`None` where a table is singular there or
/// leaves it out).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Pair {
    pub ours: Option<LobeError>,
    pub shipped: Option<LobeError>,
    /// The relative L2 as earlier versions estimated it (48² + 48² stratified samples,
    /// a biased ratio of sums; NaN where not judged), kept to say what changed.
    #[serde(deserialize_with = "super::f64_or_nan")]
    pub ours_sampled: f64,
    #[serde(deserialize_with = "super::f64_or_nan")]
    pub shipped_sampled: f64,
}

/// One way an engine uploads both tables, judged at its reachable places.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Form {
    pub name: String,
    /// What the engine's path holds: ours / the shipped table.
    pub holds: String,
    /// The smallest perceptual roughness its shader reads.
    pub r_min: f64,
    /// cells[i + n·j]
    pub cells: Vec<Pair>,
    /// squares[i + (n − 1)·j]: the square with corners (i, j) and (i + 1, j + 1)
    pub squares: Vec<Pair>,
}

/// Over the places where both tables are judged: each figure's spread, and how many
/// places ours is better, tied or worse by more than both error bars.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Summary {
    pub count: usize,
    pub ours_l2: Spread,
    pub shipped_l2: Spread,
    pub ours_l1: Spread,
    pub shipped_l1: Spread,
    /// Places where ours is lower by more than the two error bars together (relative L2).
    pub ours_better: usize,
    /// Places where ours is higher by more than the two error bars together.
    pub ours_worse: usize,
    /// The earlier sampled estimate: its means and its "ours no worse" count (ours ≤
    /// shipped × 1.001), over the same places.
    pub sampled_ours_mean: f64,
    pub sampled_shipped_mean: f64,
    pub sampled_no_worse: usize,
}

/// Read results/ltc-compare.json: `None` when absent, a typed error when malformed.
pub fn read(results: &Path) -> Result<Option<LtcCompare>> {
    super::read_typed(
        &results.join("ltc-compare.json"),
        "a comparison",
        "rerun `ltc-compare`",
    )
}

/// Our table from results/fits/ltc-ggx.json in the shipped layout.
pub fn ours(results: &Path) -> Result<crate::ltc::compare::Shipped> {
    Ok(crate::ltc::compare::of_table(&super::ltc::table(
        results,
        super::names::LTC_GGX,
    )?))
}

/// The held-out mean relative L2 of our table as recorded in results/fits/ltc-ggx.json
/// (identifies the table a comparison was made against).
pub fn ours_mean_l2(results: &Path) -> Result<f64> {
    let s: super::ltc::Summary = super::require_named(results, super::names::LTC_GGX)?;
    Ok(s.held_out.l2.mean.value)
}

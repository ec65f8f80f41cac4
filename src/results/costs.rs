//! results/costs.json: criterion's ns per evaluation of the filters, the kernels, the
//! LTC polygon forms and fits and the tensor queries, written by `bench-report` and read
//! by `scene` (what it chooses from) and the reports that quote a cost.

use crate::error::Result;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Costs {
    /// What the numbers are.
    #[serde(rename = "_note", default)]
    pub note: String,
    /// ns per evaluation, by `group/function[/param]`.
    #[serde(flatten)]
    pub ns: BTreeMap<String, f64>,
}

impl Costs {
    /// The cost measured under `key`, if any.
    pub fn get(&self, key: &str) -> Option<f64> {
        self.ns.get(key).copied()
    }

    /// The 95 % confidence interval of the cost under `key` (criterion's, kept as
    /// `key/lo` and `key/hi`); the point itself where no interval was kept.
    pub fn interval(&self, key: &str) -> Option<(f64, f64)> {
        let mean = self.get(key)?;
        match (
            self.get(&format!("{key}/lo")),
            self.get(&format!("{key}/hi")),
        ) {
            (Some(lo), Some(hi)) if lo <= mean && mean <= hi => Some((lo, hi)),
            _ => Some((mean, mean)),
        }
    }
}

/// Where the costs live under `results`.
pub fn path(results: &Path) -> PathBuf {
    results.join("costs.json")
}

/// Read results/costs.json: `None` when absent, a typed error when it is not a map of
/// numbers.
pub fn read(results: &Path) -> Result<Option<Costs>> {
    super::read_typed(
        &path(results),
        "a map of costs",
        "run `cargo run --release -- bench-report`",
    )
}

/// Add results/costs.json to the output set `out` (keys sorted, as every result).
pub fn put(set: &mut crate::io::Outputs, results: &Path, costs: &Costs) -> Result<()> {
    set.put(path(results), super::json_text("costs", costs)?);
    Ok(())
}

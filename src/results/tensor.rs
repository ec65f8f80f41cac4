//! results/fits/tensor.json: CP compression of P-NDF image blocks (seed 002 §4) at
//! several ranks per map, unconstrained and non-negative.

use crate::fit::spec::FitSpec;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Tensor {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub rows: Vec<Row>,
}

impl super::ResultFile for Tensor {
    const NAME: &'static str = super::names::TENSOR;
}

/// One (map, rank): the relative reconstruction error ‖T − T̂‖/‖T‖ over its clusters,
/// the storage ratio and the ALS iterations, for CP-ALS and non-negative CP.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Row {
    pub map: String,
    pub rank: usize,
    pub clusters: usize,
    pub mean_rel_error: f64,
    pub max_rel_error: f64,
    pub nonnegative_mean_rel_error: f64,
    pub nonnegative_max_rel_error: f64,
    /// Stored numbers / tensor entries.
    pub compression: f64,
    pub mean_iterations: f64,
    pub nonnegative_mean_iterations: f64,
    /// Runs that stopped at the iteration cap.
    pub runs_at_cap: usize,
}

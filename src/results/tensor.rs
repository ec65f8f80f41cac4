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

/// One geometric-limit wavelength: the distance of the wave image to the slope image.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LimitPoint {
    pub lambda: f64,
    pub dx: f64,
    pub patch: usize,
    pub tv: f64,
}

/// One CP rank of the wave-optics RGB blocks.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RankRow {
    pub rank: usize,
    pub rel_error: f64,
    pub iterations: usize,
    /// Stored values over all images' values, and over the non-empty blocks' values.
    pub ratio_all: f64,
    pub ratio_nonempty: f64,
}

/// results/fits/tensor-wave.json: seed 002's wave-optics NDF images checked (FFT, energy,
/// geometric limit, colour) and CP-compressed.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WaveResult {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    /// Largest |FFT − direct| over the nodes checked, relative to the image's peak.
    pub fft_vs_direct: f64,
    /// Largest |∫D* dψ − window energy| (relative) and |∫D* dψ − 1| over the σ_c, λ checked.
    pub parseval: f64,
    pub energy_vs_one: f64,
    pub limit: Vec<LimitPoint>,
    /// The slope image's quadrature bar (TV distance between spacings ds and 2 ds).
    pub limit_bar: f64,
    /// Least-squares slope of ln TV against ln λ.
    pub limit_rate: f64,
    /// (magnification, chroma): Σ (max − min channel) / Σ mean channel.
    pub chroma: Vec<(f64, f64)>,
    /// Footprints, blocks stacked (non-empty of all) and the CP per rank.
    pub images: usize,
    pub blocks: usize,
    pub blocks_all: usize,
    pub ranks: Vec<RankRow>,
}

impl super::ResultFile for WaveResult {
    const NAME: &'static str = super::names::TENSOR_WAVE;
}

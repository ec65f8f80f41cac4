//! results/fits/tensor-envsg.json: seed 002 §5.4's environment lighting by spherical
//! Gaussians — the SG fit of an environment, and the prefiltered NDF query (Eq 8–9)
//! against point sampling and the quadrature truth.

use crate::fit::spec::FitSpec;
use crate::integrate::{Figure, Quad};
use crate::tensor::envsg::Sg;
use serde::{Deserialize, Serialize};

/// The SG fit of the environment: its lobes and ‖env − SGs‖/‖env‖ with the environment
/// sampled at two resolutions (the procedural sky at w × h and 2w × 2h; a user's map at
/// its own and averaged 2×2).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SgFit {
    /// The environment fitted, in words.
    pub environment: String,
    pub lobes: Vec<Sg>,
    pub rel_error: [f64; 2],
    pub resolutions: [(usize, usize); 2],
}

/// One (ε, scale) of the prefiltered estimator on one case. Relative figures are over
/// the case's reference I.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Row {
    pub eps: f64,
    pub scale: f64,
    /// Smallest and largest query side over the lighting's lobes (pixels).
    pub q: (usize, usize),
    /// (mean − I)/I ± s.e. (the reference's quadrature bar is far below it).
    pub bias: Figure,
    /// Var(point) / Var(prefiltered), ± its delta-method error (independent samples).
    pub var_ratio: Figure,
    /// Unbiased relative MSE of a 16-sample pixel: ((mean − I)² − s.e.² + Var/16)/I².
    pub mse16: Figure,
}

/// One footprint under one lighting.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Case {
    pub footprint: String,
    pub lighting: String,
    /// I by the midpoint rule at 16² points per pixel, ± its distance to 8² points.
    pub reference: Figure<Quad>,
    /// The point-query estimator: (mean − I)/I ± s.e. and its relative MSE at 16 samples.
    pub point_bias: Figure,
    pub point_mse16: Figure,
    pub rows: Vec<Row>,
}

/// The mean over every case of one (ε, scale)'s relative MSE at 16 samples.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Trade {
    pub eps: f64,
    pub scale: f64,
    pub mse16: Figure,
}

/// Seed 002 Fig 11's comparison on a flat patch: one pixel per footprint of a grid over the
/// map, lit by the fitted sky, at `spp` samples per pixel.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Picture {
    /// Pixels per side (footprints every `stride` texels), samples per pixel, and the
    /// prefilter's (ε, scale).
    pub side: usize,
    pub stride: usize,
    pub spp: usize,
    pub eps: f64,
    pub scale: f64,
    /// Row-major images: the quadrature truth, the point query and the prefiltered query.
    pub reference: Vec<f64>,
    pub point: Vec<f64>,
    pub prefiltered: Vec<f64>,
    /// Σ (image − truth)² / Σ truth² over the pixels of these images, as the mean over
    /// pixels of (image − truth)²/mean(truth²) ± its s.e. (independent pixels).
    pub rel_mse_point: Figure,
    pub rel_mse_prefiltered: Figure,
}

/// Fig 11's claim ("much lower noise", no visible bias) at the paper's (ε 0.3, scale 0.5):
/// over the cases where the square exceeds one pixel for some lobe, the smallest and
/// largest variance ratio, and the bias range over every case; the verdict.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Fig11 {
    pub var_ratio: (f64, f64),
    pub bias: (f64, f64),
    /// Cases whose bias lies beyond 2 % and 3 s.e.
    pub visible_bias: usize,
    pub verdict: String,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EnvSg {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub fit: SgFit,
    /// The CP's relative error on the footprints' images (what every estimator reads).
    pub cp_rel_error: f64,
    pub samples: usize,
    pub cases: Vec<Case>,
    pub point_mse16: Figure,
    pub trade: Vec<Trade>,
    pub picture: Picture,
    pub fig11: Fig11,
}

impl super::ResultFile for EnvSg {
    const NAME: &'static str = super::names::TENSOR_ENVSG;
}

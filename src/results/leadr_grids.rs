//! results/fits/leadr-grids.json: LEADR's N×N slope grids (seed 001 §3.4–3.5), error
//! against N for three grid families, the spacing scan at N = 5 and the artificial
//! micronormal at a silhouette.

use crate::fit::spec::FitSpec;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LeadrGrids {
    pub spec: FitSpec,
    pub command: String,
    pub rows: Vec<Row>,
    /// (h, specular RMS, diffuse RMS) on the training set at N = 5.
    pub h_scan_n5: Vec<(f64, f64, f64)>,
    /// The fitted uniform spacing at N = 5 (the generated code's constant).
    pub fitted_h_n5: f64,
    pub artificial_micronormal: Micronormal,
}

/// One grid size N: the fitted spacing and each family's held-out error per lobe.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Row {
    pub n: usize,
    pub fitted_h: f64,
    pub specular: Families,
    pub diffuse: Families,
}

/// The held-out relative error (RMS, max) of each grid family.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Families {
    pub paper: (f64, f64),
    pub fitted: (f64, f64),
    pub gauss_hermite: (f64, f64),
}

/// The visible fraction at a silhouette without and with the artificial micronormal
/// (`None`: without it the estimate is undefined).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Micronormal {
    pub without: Option<f64>,
    pub with: f64,
}

impl super::ResultFile for LeadrGrids {
    const NAME: &'static str = super::names::LEADR_GRIDS;
}

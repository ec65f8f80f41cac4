//! What fits/filters.toml sets for the footprint study: the sizes of the map and screen
//! studies, bounded when the spec is read.

use serde::{Deserialize, Serialize};

/// What fits/filters.toml sets: the sizes of the map and screen studies.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Side of the procedural normal maps (a power of two).
    pub map_size: usize,
    /// Mip levels whose footprints are studied.
    pub levels: Vec<usize>,
    pub footprints_per_level: usize,
    /// Base roughness of the map study.
    pub alphas: Vec<f64>,
    /// Views (θ, φ) in degrees.
    pub views_deg: Vec<(f64, f64)>,
    /// Light samples per case.
    pub samples: usize,
    /// (base α, κ in rad/px) pairs of the screen study (κ/α ≤ 8).
    pub screen_pairs: Vec<(f64, f64)>,
    /// Anisotropy ratios of the screen study's curvature.
    pub anisotropy: Vec<f64>,
    pub screen_views_deg: Vec<f64>,
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::{all_within, power_of_two, within};
        power_of_two("map_size", self.map_size, 8, 4096)?;
        let top = self.map_size.trailing_zeros() as usize;
        all_within("levels", &self.levels, 1, top, 16)?;
        within("footprints_per_level", self.footprints_per_level, 1, 10_000)?;
        all_within("alphas", &self.alphas, 1e-3, 1.0, 16)?;
        let thetas: Vec<f64> = self.views_deg.iter().map(|v| v.0).collect();
        all_within("views_deg (θ)", &thetas, 0.0, 89.0, 32)?;
        let phis: Vec<f64> = self.views_deg.iter().map(|v| v.1).collect();
        all_within("views_deg (φ)", &phis, -360.0, 360.0, 32)?;
        within("samples", self.samples, 16, 1 << 20)?;
        let a: Vec<f64> = self.screen_pairs.iter().map(|p| p.0).collect();
        all_within("screen_pairs (α)", &a, 1e-3, 1.0, 64)?;
        let k: Vec<f64> = self.screen_pairs.iter().map(|p| p.1).collect();
        all_within("screen_pairs (κ)", &k, 0.0, 10.0, 64)?;
        all_within("anisotropy", &self.anisotropy, 1e-3, 1.0, 16)?;
        all_within("screen_views_deg", &self.screen_views_deg, 0.0, 89.0, 32)
    }
}

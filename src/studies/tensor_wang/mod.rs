//! `regen --only tensor-wang`: seed 002 §5.5's constant storage by Wang tiles (the model in
//! `tensor::wang`), fits/tensor-wang.toml.
//!
//! - **Tiles:** sixteen, cut from a procedural example by the diamond construction with
//!   minimum-error cuts; their seams measured on a synthesised map against straight cuts
//!   and against the same tiles laid out with their colours ignored.
//! - **Implicit = explicit (Fig 14):** every footprint centre of the stride grid whose
//!   window lies inside an explicit region of `region`² tiles, at each level and at each of
//!   the `regions` (some of them 2^36 tiles from the origin): the sum of the tiles'
//!   precomputed images against the brute-force P-NDF (Eq 2) of the explicit map.
//! - **Compression:** the tiles' images CP-compressed per tile (seed 002 §4.2) and queried
//!   by point queries (Eq 6), against the same brute force.
//! - **Storage:** the tiles' values against an explicit map's, for areas up to the paper's
//!   100K² deer map.

use crate::error::Result;
use crate::io::Outputs;
use crate::study::FitOutcome;
use std::path::Path;

mod compute;
mod report;

use compute::{compute, Computed, Params};

impl crate::study::Computed for Computed {
    /// Passed when every implicit image equals the explicit one within the spec's
    /// tolerance (relative to the image's peak).
    fn outcome(&self) -> FitOutcome {
        let worst = self
            .result
            .levels
            .iter()
            .map(|l| l.worst)
            .fold(0.0, f64::max);
        FitOutcome::judged(
            &self.spec,
            worst,
            format!(
                "Wang tiles: implicit = explicit to {worst:.1e} of the peak over {} footprints; {} values stored for any area",
                self.result.levels.iter().map(|l| l.footprints).sum::<usize>(),
                self.result.tile_values
            ),
        )
    }

    fn render(&self, set: &mut Outputs, results: &Path) -> Result<()> {
        set.put(results.join("tensor-wang.svg"), report::svg(self)?);
        set.put(results.join("tensor-wang.md"), report::markdown(self));
        crate::results::put(set, results, &self.result)
    }
}

crate::study::study! {
    /// Seed 002 §5.5: seconds at its default preset.
    TensorWang = "tensor-wang", after [], on request true, params Params, computes compute
}

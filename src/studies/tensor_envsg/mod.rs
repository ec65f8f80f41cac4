//! `regen --only tensor-envsg`: seed 002 §5.4's environment lighting by spherical
//! Gaussians (the model in `tensor::envsg`), fits/tensor-envsg.toml.
//!
//! - **Environment:** a procedural sky (sun, sky, ground) fitted by a greedy sum of SGs
//!   with non-negative amplitudes; the fit's relative L2 at two samplings of the sky.
//! - **Prefiltering (Eq 8–9):** two footprints of a glinty map (CP-compressed images, read
//!   as a renderer reads them) under single SGs of several bandwidths and under the fitted
//!   sky: the reflected radiance by quadrature, by the point-query estimator and by the
//!   prefiltered one over a grid of ε and scale, each with its bias ± s.e., its variance
//!   against the point query's and its relative MSE at 16 samples.

use crate::error::Result;
use crate::io::Outputs;
use crate::study::FitOutcome;
use std::path::Path;

mod compute;
mod report;

use compute::{compute, Computed, Params};

impl crate::study::Computed for Computed {
    /// Passed when the point-query estimator, unbiased by construction, agrees with the
    /// quadrature truth in every case (within 4 s.e. plus the quadrature bar).
    fn outcome(&self) -> FitOutcome {
        let worst = self
            .result
            .cases
            .iter()
            .map(|c| {
                c.point_bias.value.abs()
                    / (4.0 * c.point_bias.error + c.reference.error / c.reference.value)
            })
            .fold(0.0, f64::max);
        FitOutcome::judged(
            &self.spec,
            worst,
            format!(
                "SG prefiltering over {} cases: the point query agrees with the quadrature (worst {:.2} of its 4-s.e. band); sky fit {:.2} %",
                self.result.cases.len(),
                worst,
                100.0 * self.result.fit.rel_error[1]
            ),
        )
    }

    fn render(&self, set: &mut Outputs, results: &Path) -> Result<()> {
        set.put(results.join("tensor-envsg.svg"), report::svg(self)?);
        set.put(
            results.join("tensor-envsg-picture.svg"),
            report::picture_svg(self)?,
        );
        set.put(results.join("tensor-envsg.md"), report::markdown(self));
        crate::results::put(set, results, &self.result)
    }
}

crate::study::study! {
    /// Seed 002 §5.4: seconds at its default preset.
    TensorEnvSg = "tensor-envsg", after [], on request true, params Params, computes compute
}

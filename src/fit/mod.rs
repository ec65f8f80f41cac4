//! Fit specifications (fits/*.toml) and the `regen` driver.
//!
//! A spec names the model form, the domain, the training and held-out points, the
//! metric, the optimiser and its settings, the seed and the tolerance on held-out error.
//! `regen` runs every spec (or `--only NAME`), writes results/fits/<name>.json and the
//! fit's report, and fails loudly when a held-out error misses its tolerance.

pub mod spec;

use crate::error::Result;
use crate::integrate::Preset;
use std::path::Path;

/// What one fit produced.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FitOutcome {
    pub name: String,
    pub held_out_max_rel: f64,
    pub tolerance: f64,
    pub passed: bool,
    pub summary: String,
}

/// Run the fits whose name contains `only` (all when None).
pub fn regen(
    fits_dir: &Path,
    results: &Path,
    only: Option<&str>,
    preset: Preset,
) -> Result<Vec<FitOutcome>> {
    let specs = spec::load_dir(fits_dir)?;
    let mut out = Vec::new();
    for s in specs
        .iter()
        .filter(|s| only.is_none_or(|o| s.name.contains(o)))
    {
        let o = match s.name.as_str() {
            "leadr-grids" => crate::leadr::regen(s, results)?,
            "smith-lambda" => crate::microfacet::lambda_fit::regen(s, results)?,
            "multiscale-convolution" => {
                crate::multiscale::regen_convolution::run(s, &specs, results, preset)?
            }
            _ => crate::multiscale::regen::run(s, results, preset)?,
        };
        out.push(o);
    }
    if out.is_empty() {
        return Err(crate::error::Error::InvalidArgument(format!(
            "no fit spec in '{}' matches {:?}",
            fits_dir.display(),
            only
        )));
    }
    Ok(out)
}

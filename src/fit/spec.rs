//! Fit specification files (TOML). Unknown keys are rejected with an error naming them.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// α domain of a fit.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    pub alpha_min: f64,
    pub alpha_max: f64,
}

/// How many points, and how they are placed.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Points {
    pub points: usize,
    pub spacing: String,
}

/// Optimiser and its settings.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Optimiser {
    pub method: String,
    #[serde(default)]
    pub max_iters: Option<u64>,
    #[serde(default)]
    pub tolerance: Option<f64>,
}

/// Held-out error budget.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerance {
    pub max_rel: f64,
}

/// One fit specification.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FitSpec {
    pub name: String,
    pub description: String,
    pub model: String,
    pub terms: usize,
    pub domain: Domain,
    pub training: Points,
    pub held_out: Points,
    pub metric: String,
    pub optimiser: Optimiser,
    /// The baseline refit of the paper's form.
    pub baseline_optimiser: Optimiser,
    pub table_entries: usize,
    pub seed: u64,
    pub tolerance: Tolerance,
}

impl FitSpec {
    /// Parse and validate a spec; errors name the file and the offending key.
    pub fn parse(text: &str, origin: &str) -> Result<FitSpec> {
        let s: FitSpec =
            toml::from_str(text).map_err(|e| Error::InvalidArgument(format!("{origin}: {e}")))?;
        let bad = |m: String| Err(Error::InvalidArgument(format!("{origin}: {m}")));
        if !(s.domain.alpha_min > 0.0
            && s.domain.alpha_max > s.domain.alpha_min
            && s.domain.alpha_max.is_finite())
        {
            return bad(format!(
                "domain: need 0 < alpha_min < alpha_max, got {:?}",
                s.domain
            ));
        }
        if s.training.points < s.terms + 2 || s.held_out.points < 2 {
            return bad("training.points must exceed terms + 1 and held_out.points ≥ 2".into());
        }
        if !(s.tolerance.max_rel > 0.0) {
            return bad("tolerance.max_rel must be > 0".into());
        }
        if s.table_entries < 2 {
            return bad("table_entries must be ≥ 2".into());
        }
        Ok(s)
    }
}

/// Every *.toml in `dir`, sorted by file name.
pub fn load_dir(dir: &Path) -> Result<Vec<FitSpec>> {
    let io = |e: std::io::Error| Error::Io {
        path: dir.display().to_string(),
        msg: e.to_string(),
    };
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .map_err(io)?
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|f| {
            let t = std::fs::read_to_string(f).map_err(|e| Error::Io {
                path: f.display().to_string(),
                msg: e.to_string(),
            })?;
            FitSpec::parse(&t, &f.display().to_string())
        })
        .collect()
}

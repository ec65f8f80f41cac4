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

/// Per-axis point counts of a 2D fit (log-spaced over the domain on both axes).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Grid {
    /// Grid on which every metric is fitted by quadrature (expensive: ~1 s per point).
    pub metric_points: usize,
    /// Dense grid for closed-form targets (training; held-out is offset by half a step).
    pub dense_points: usize,
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
    /// Number of fitted coefficients (model-specific; default 0).
    #[serde(default)]
    pub terms: usize,
    pub domain: Domain,
    pub training: Points,
    pub held_out: Points,
    pub metric: String,
    pub optimiser: Optimiser,
    /// The baseline refit of the paper's form.
    pub baseline_optimiser: Optimiser,
    /// Lookup-table size, for fits that also ship a table (default 0: none).
    #[serde(default)]
    pub table_entries: usize,
    /// Two-parameter grids, for fits over (α_mi, α_me) (default: none).
    #[serde(default)]
    pub grid: Option<Grid>,
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
        if s.table_entries == 1 {
            return bad("table_entries must be 0 (no table) or ≥ 2".into());
        }
        if let Some(g) = &s.grid {
            if g.metric_points < 2 || g.dense_points < 4 {
                return bad(format!(
                    "grid: need metric_points ≥ 2 and dense_points ≥ 4, got {g:?}"
                ));
            }
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

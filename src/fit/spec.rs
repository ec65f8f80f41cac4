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
    /// Number of coefficients of a second branch (the α > 1 branch of the α_me fit;
    /// default 0).
    #[serde(default)]
    pub terms_large: usize,
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

/// Upper bounds on what a spec may ask for (fits/README.md lists them). Generic bounds hold
/// for every spec; a study that reads a key more expensively has tighter ones.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    pub terms: usize,
    pub points: usize,
    pub table_entries: usize,
    pub max_iters: u64,
    pub alpha_min: f64,
    pub alpha_max: f64,
    pub grid_metric_points: usize,
    pub grid_dense_points: usize,
}

/// Bounds for every spec.
pub const GENERIC_LIMITS: Limits = Limits {
    terms: 64,
    points: 1_000_000,
    table_entries: 1 << 20,
    max_iters: 10_000_000,
    alpha_min: 1e-12,
    alpha_max: 1e12,
    grid_metric_points: 64,
    grid_dense_points: 4096,
};

/// Most spec files read from one directory.
pub const MAX_SPEC_FILES: usize = 256;

/// Largest spec file read, in bytes, and the longest text value.
pub const MAX_SPEC_BYTES: u64 = 1 << 20;
pub const MAX_TEXT_CHARS: usize = 4096;

/// The bounds of the study that reads spec `name` (the generic ones, tightened where a
/// study's cost grows with a key: the α_me fit, the overall-roughness grid, the Λ refit
/// and the LTC table).
pub fn limits_for(name: &str) -> Limits {
    let g = GENERIC_LIMITS;
    match name {
        "multiscale-alpha-me" => Limits {
            terms: 16,
            points: 200_000,
            table_entries: 1 << 16,
            max_iters: 1_000_000,
            alpha_min: 1e-8,
            alpha_max: 1e4,
            ..g
        },
        "multiscale-convolution" => Limits {
            terms: 16,
            points: 2_000,
            // the quadrature metrics' domain (multiscale::overall::QUAD_DOMAIN)
            alpha_min: 1e-3,
            alpha_max: 3.0,
            grid_metric_points: 16,
            grid_dense_points: 400,
            ..g
        },
        "smith-lambda" => Limits {
            terms: 16,
            points: 100_000,
            max_iters: 100_000,
            alpha_min: 1e-6,
            alpha_max: 1e3,
            ..g
        },
        "ltc-ggx" | "ltc-sheen" | "ltc-diffuse" | "ltc-aniso" => Limits {
            terms: 4,
            points: 16_384,
            max_iters: 100_000,
            alpha_min: 1e-6,
            alpha_max: 1.0,
            ..g
        },
        _ => g,
    }
}

impl FitSpec {
    /// Parse and validate a spec; errors name the file and the offending key, and every
    /// count, size, iteration cap and domain is checked against [`limits_for`] its name.
    pub fn parse(text: &str, origin: &str) -> Result<FitSpec> {
        let s: FitSpec = toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
        s.validate(origin)?;
        Ok(s)
    }

    /// Check every key against its bounds.
    pub fn validate(&self, origin: &str) -> Result<()> {
        let s = self;
        let lim = limits_for(&s.name);
        let bad = |m: String| Err(Error::InvalidArgument(format!("{origin}: {m}")));
        for (key, v) in [
            ("name", &s.name),
            ("description", &s.description),
            ("model", &s.model),
            ("metric", &s.metric),
            ("training.spacing", &s.training.spacing),
            ("held_out.spacing", &s.held_out.spacing),
            ("optimiser.method", &s.optimiser.method),
            ("baseline_optimiser.method", &s.baseline_optimiser.method),
        ] {
            if v.chars().count() > MAX_TEXT_CHARS {
                return bad(format!("{key} is longer than {MAX_TEXT_CHARS} characters"));
            }
        }
        let (lo, hi) = (s.domain.alpha_min, s.domain.alpha_max);
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
            return bad(format!(
                "domain: need 0 < alpha_min < alpha_max, both finite, got alpha_min = {lo:e}, alpha_max = {hi:e}"
            ));
        }
        if lo < lim.alpha_min {
            return bad(format!(
                "domain.alpha_min = {lo:e} is below the limit {:e} for '{}'",
                lim.alpha_min, s.name
            ));
        }
        if hi > lim.alpha_max {
            return bad(format!(
                "domain.alpha_max = {hi:e} exceeds the limit {:e} for '{}'",
                lim.alpha_max, s.name
            ));
        }
        for (key, v, cap) in [
            ("terms", s.terms, lim.terms),
            ("terms_large", s.terms_large, lim.terms),
            ("training.points", s.training.points, lim.points),
            ("held_out.points", s.held_out.points, lim.points),
            ("table_entries", s.table_entries, lim.table_entries),
        ] {
            if v > cap {
                return bad(format!(
                    "{key} = {v} exceeds the limit {cap} for '{}'",
                    s.name
                ));
            }
        }
        if s.training.points < s.terms + s.terms_large + 2 {
            return bad(format!(
                "training.points = {} must exceed terms + terms_large + 1 = {}",
                s.training.points,
                s.terms + s.terms_large + 1
            ));
        }
        if s.held_out.points < 2 {
            return bad(format!(
                "held_out.points = {} must be ≥ 2",
                s.held_out.points
            ));
        }
        if !(s.tolerance.max_rel > 0.0 && s.tolerance.max_rel.is_finite()) {
            return bad(format!(
                "tolerance.max_rel must be finite and > 0, got {:e}",
                s.tolerance.max_rel
            ));
        }
        if s.table_entries == 1 {
            return bad("table_entries must be 0 (no table) or ≥ 2, got 1".into());
        }
        for (key, o) in [
            ("optimiser", &s.optimiser),
            ("baseline_optimiser", &s.baseline_optimiser),
        ] {
            if let Some(it) = o.max_iters {
                if it == 0 || it > lim.max_iters {
                    return bad(format!(
                        "{key}.max_iters = {it} must lie in [1, {}] for '{}'",
                        lim.max_iters, s.name
                    ));
                }
            }
            if let Some(t) = o.tolerance {
                if !(t > 0.0 && t.is_finite() && t < 1.0) {
                    return bad(format!("{key}.tolerance must lie in (0, 1), got {t:e}"));
                }
            }
        }
        if let Some(g) = &s.grid {
            if g.metric_points < 2 || g.metric_points > lim.grid_metric_points {
                return bad(format!(
                    "grid.metric_points = {} must lie in [2, {}]",
                    g.metric_points, lim.grid_metric_points
                ));
            }
            if g.dense_points < 4 || g.dense_points > lim.grid_dense_points {
                return bad(format!(
                    "grid.dense_points = {} must lie in [4, {}]",
                    g.dense_points, lim.grid_dense_points
                ));
            }
        }
        // what each study itself needs
        match s.name.as_str() {
            "multiscale-alpha-me" => {
                if s.terms == 0 || s.terms_large == 0 {
                    return bad(format!(
                        "terms and terms_large must be ≥ 1 for '{}', got {} and {}",
                        s.name, s.terms, s.terms_large
                    ));
                }
                if s.table_entries < 2 {
                    return bad(format!(
                        "table_entries = {} must be ≥ 2 for '{}'",
                        s.table_entries, s.name
                    ));
                }
                if !(lo < 1.0 && hi > 1.0) {
                    return bad(format!(
                        "domain must contain α = 1 (both branches are pinned there), got [{lo:e}, {hi:e}]"
                    ));
                }
            }
            "multiscale-convolution" if s.grid.is_none() => {
                return bad(format!("'{}' needs a grid table", s.name));
            }
            "multiscale-convolution" | "smith-lambda" if s.terms == 0 => {
                return bad(format!("terms must be ≥ 1 for '{}'", s.name));
            }
            _ => {}
        }
        Ok(())
    }
}

/// Read one spec file, refusing files over [`MAX_SPEC_BYTES`] before reading them.
pub fn load_file(f: &Path) -> Result<FitSpec> {
    let io = |e: std::io::Error| Error::Io {
        path: f.display().to_string(),
        msg: e.to_string(),
    };
    let meta = std::fs::metadata(f).map_err(io)?;
    if meta.len() > MAX_SPEC_BYTES {
        return Err(Error::InvalidArgument(format!(
            "{}: {} bytes exceeds the {MAX_SPEC_BYTES}-byte limit for a fit spec",
            f.display(),
            meta.len()
        )));
    }
    let t = std::fs::read_to_string(f).map_err(io)?;
    FitSpec::parse(&t, &f.display().to_string())
}

/// A TOML parse error as one line: toml's messages span several lines (a source
/// excerpt), so keep the first, with the line it points at.
pub fn toml_error(origin: &str, text: &str, e: &toml::de::Error) -> Error {
    let first = e
        .message()
        .lines()
        .next()
        .unwrap_or("malformed TOML")
        .to_string();
    let at = e
        .span()
        .map(|r| {
            let line = text[..r.start.min(text.len())].matches('\n').count() + 1;
            format!(" (line {line})")
        })
        .unwrap_or_default();
    Error::InvalidArgument(format!("{origin}: {first}{at}"))
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
    if files.len() > MAX_SPEC_FILES {
        return Err(Error::InvalidArgument(format!(
            "{}: {} spec files, more than {MAX_SPEC_FILES}",
            dir.display(),
            files.len()
        )));
    }
    files.iter().map(|f| load_file(f)).collect()
}

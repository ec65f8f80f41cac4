//! Study specifications (fits/*.toml): a header every study shares and the study's own
//! typed parameters.
//!
//! ```toml
//! name = "smith-lambda"            # the study that reads it
//! seed = 0
//! tolerance = { max_rel = 1e-4 }   # the held-out figure the run is judged by
//!
//! [params]                         # the default preset: every number the study reads
//! points = 600
//!
//! [quick]                          # keys of [params] set or replaced at --preset quick
//! points = 60
//! ```
//!
//! `[precise]` does the same for `--preset precise`. Each study declares its parameter
//! struct (a [`Params`]): serde rejects a key it does not read and names it, a missing key
//! is named too, and [`Params::check`] bounds every value. [`FitSpec::params`] merges the
//! preset's table over `[params]`, parses and checks; the driver checks every preset of
//! every spec before anything runs. The prose that used to sit in the spec (the model, the
//! metric, the optimiser) lives in each study's module doc.

use crate::error::{Error, Result};
use crate::integrate::Preset;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Held-out error budget.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerance {
    pub max_rel: f64,
}

/// One study's specification: the shared header and its raw parameter tables (typed by
/// the study through [`FitSpec::params`]).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FitSpec {
    pub name: String,
    pub seed: u64,
    pub tolerance: Tolerance,
    /// Every number the study reads, at the default preset.
    #[serde(default)]
    pub params: toml::Table,
    /// Keys of `params` replaced at the quick preset.
    #[serde(default, skip_serializing_if = "toml::Table::is_empty")]
    pub quick: toml::Table,
    /// Keys of `params` replaced at the precise preset.
    #[serde(default, skip_serializing_if = "toml::Table::is_empty")]
    pub precise: toml::Table,
    /// Where it was read from (for messages; not part of the spec).
    #[serde(skip)]
    pub origin: String,
}

/// A study's typed parameters: what `[params]` (merged with the preset's table) holds.
/// Deserialize with `#[serde(deny_unknown_fields)]`, so a key the study does not read is
/// an error.
pub trait Params: DeserializeOwned + Serialize {
    /// Every value within its bounds; the error names the key and the bound.
    fn check(&self) -> std::result::Result<(), String>;
}

/// `key`'s value `v` lies in `[lo, hi]` (both finite for floats; NaN fails).
pub fn within<T: PartialOrd + std::fmt::Display>(
    key: &str,
    v: T,
    lo: T,
    hi: T,
) -> std::result::Result<(), String> {
    if v >= lo && v <= hi {
        Ok(())
    } else {
        Err(format!("{key} = {v} must lie in [{lo}, {hi}]"))
    }
}

/// Every element of the list `key` lies in `[lo, hi]`, and the list holds 1…`max_len`
/// elements.
pub fn all_within<T: PartialOrd + std::fmt::Display + Copy>(
    key: &str,
    v: &[T],
    lo: T,
    hi: T,
    max_len: usize,
) -> std::result::Result<(), String> {
    if v.is_empty() || v.len() > max_len {
        return Err(format!(
            "{key} holds {} values; it needs 1 … {max_len}",
            v.len()
        ));
    }
    v.iter()
        .enumerate()
        .try_for_each(|(i, &x)| within(&format!("{key}[{i}]"), x, lo, hi))
}

/// `key`'s value is a power of two in `[lo, hi]`.
pub fn power_of_two(key: &str, v: usize, lo: usize, hi: usize) -> std::result::Result<(), String> {
    within(key, v, lo, hi)?;
    if v.is_power_of_two() {
        Ok(())
    } else {
        Err(format!("{key} = {v} must be a power of two"))
    }
}

/// `whole` (key `kw`) splits into blocks of `block` (key `kb`), at least one.
pub fn splits(kw: &str, whole: usize, kb: &str, block: usize) -> std::result::Result<(), String> {
    if block > 0 && whole >= block && whole % block == 0 {
        Ok(())
    } else {
        Err(format!(
            "{kw} = {whole} must split into {kb} = {block} blocks"
        ))
    }
}

/// An α range `[lo, hi]` (keys `alpha_min`, `alpha_max`) inside `[min, max]`, with lo < hi.
pub fn alpha_range(lo: f64, hi: f64, min: f64, max: f64) -> std::result::Result<(), String> {
    within("alpha_min", lo, min, max)?;
    within("alpha_max", hi, min, max)?;
    if lo < hi {
        Ok(())
    } else {
        Err(format!(
            "alpha_min = {lo:e} must be below alpha_max = {hi:e}"
        ))
    }
}

/// Most spec files read from one directory.
pub const MAX_SPEC_FILES: usize = 256;

/// Largest spec file read, in bytes.
pub const MAX_SPEC_BYTES: u64 = 1 << 20;

impl FitSpec {
    /// Parse and check the header; errors name the file and the offending key. The
    /// parameters are checked by the study that reads them ([`FitSpec::params`]).
    pub fn parse(text: &str, origin: &str) -> Result<FitSpec> {
        let mut s: FitSpec = toml::from_str(text).map_err(|e| toml_error(origin, text, &e))?;
        s.origin = origin.to_string();
        s.validate()?;
        Ok(s)
    }

    fn bad(&self, m: String) -> Error {
        let origin = if self.origin.is_empty() {
            format!("spec '{}'", self.name)
        } else {
            self.origin.clone()
        };
        Error::InvalidArgument(format!("{origin}: {m}"))
    }

    /// The header's own checks.
    pub fn validate(&self) -> Result<()> {
        if self.name.is_empty() || self.name.chars().count() > 64 {
            return Err(self.bad("name must hold 1 … 64 characters".into()));
        }
        let t = self.tolerance.max_rel;
        if !(t > 0.0 && t.is_finite()) {
            return Err(self.bad(format!(
                "tolerance.max_rel must be finite and > 0, got {t:e}"
            )));
        }
        Ok(())
    }

    /// The parameters at `preset` of the spec `text` this build compiled in from `file`:
    /// what commands that run a study's measurements on a user's input read.
    pub fn compiled_params<P: Params>(text: &str, file: &str, preset: Preset) -> Result<P> {
        FitSpec::parse(text, &format!("{file} (compiled in)"))?.params(preset)
    }

    /// The study's parameters at `preset`: `[params]` with the preset's table over it,
    /// parsed into `P` and checked. Errors name the file, the table and the key.
    pub fn params<P: Params>(&self, preset: Preset) -> Result<P> {
        let (table, over) = match preset {
            Preset::Quick => ("[params] + [quick]", &self.quick),
            Preset::Precise => ("[params] + [precise]", &self.precise),
            Preset::Default => ("[params]", &toml::Table::new()),
        };
        let mut t = self.params.clone();
        for (k, v) in over {
            t.insert(k.clone(), v.clone());
        }
        let p: P = toml::Value::Table(t)
            .try_into()
            .map_err(|e: toml::de::Error| {
                let m = e
                    .message()
                    .lines()
                    .next()
                    .unwrap_or("malformed")
                    .to_string();
                self.bad(format!("{table}: {m}"))
            })?;
        p.check().map_err(|m| self.bad(format!("{table}: {m}")))?;
        Ok(p)
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

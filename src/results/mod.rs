//! The fit results on disk: results/fits/<name>.json, written by each study and read by
//! the code generator, the reports and the scenes. One place for the path and the format,
//! and one type per file ([`ResultFile`]), shared by its writer and every reader: a reader
//! never looks a number up by a string path, and a file that does not parse as its type
//! (malformed, another study's, an older layout) is a typed error, never "absent".

use crate::error::{Error, Result};
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

pub mod alpha_me;
pub mod between;
pub mod compare;
pub mod costs;
pub mod envsg;
pub mod filters;
pub mod index;
pub mod leadr_grids;
pub mod lobe_cross;
pub mod ltc;
pub mod ltc_aniso;
pub mod ltc_compact;
pub mod render;
pub mod smith_lambda;
pub mod tensor;
pub mod wang;

/// The type of one results/fits file. `NAME` is its spec's name (the file's stem);
/// the spec it embeds must carry that name, so another study's file is refused.
pub trait ResultFile: serde::Serialize + DeserializeOwned {
    const NAME: &'static str;
}

/// The command that writes the result `name`.
pub fn command(name: &str) -> String {
    format!("cargo run --release -- regen --only {name}")
}

/// Read results/fits/<T::NAME>.json as its type: `None` when the file does not exist,
/// a typed error when it is malformed, another study's or of another layout.
pub fn read<T: ResultFile>(results: &Path) -> Result<Option<T>> {
    read_named(results, T::NAME)
}

/// [`read`], for a type several files share (the LTC lobe tables): the file `name`.
pub fn read_named<T: DeserializeOwned>(results: &Path, name: &str) -> Result<Option<T>> {
    let path = fit_path(results, name);
    let Some(v) = read_json(&path)? else {
        return Ok(None);
    };
    let bad = |what: String| {
        Error::InvalidArgument(format!(
            "{}: {what}; run `{}`",
            crate::error::quoted(&path.display().to_string()),
            command(name)
        ))
    };
    // the one place a result is looked into by key: whose spec wrote it. A study writes
    // the file of its own name and, for variant tables, files named `<its name>-…`
    // (ltc-sheen writes ltc-sheen-neubelt)
    match v
        .get("spec")
        .and_then(|s| s.get("name"))
        .and_then(|n| n.as_str())
    {
        Some(n) if written_by(name, n) => {}
        Some(n) => {
            return Err(bad(format!(
                "written by the study {}, not by {name}'s",
                crate::error::quoted(n)
            )))
        }
        None => return Err(bad("not a fit result (it names no spec)".into())),
    }
    serde_json::from_value(v).map(Some).map_err(|e| {
        bad(format!(
            "not a {name} result as this version writes it ({e})"
        ))
    })
}

/// Whether the study `study` writes the result file `name`: its own, or a variant
/// `<study>-…` of it.
fn written_by(name: &str, study: &str) -> bool {
    name == study
        || name
            .strip_prefix(study)
            .is_some_and(|rest| rest.starts_with('-'))
}

/// [`read`], where the result must exist: a missing file is an error naming the command.
pub fn require<T: ResultFile>(results: &Path) -> Result<T> {
    require_named(results, T::NAME)
}

/// [`require`] for the file `name` of a shared type.
pub fn require_named<T: DeserializeOwned>(results: &Path, name: &str) -> Result<T> {
    read_named(results, name)?.ok_or_else(|| {
        Error::InvalidArgument(format!(
            "{} is missing: run `{}`",
            crate::error::quoted(&fit_path(results, name).display().to_string()),
            command(name)
        ))
    })
}

/// The SHA-256 (lower-case hex) of what the readers of the result file `name` read of it
/// as it is now ([`published_sha256`]): what a study that reads a published result records
/// of it, so that a test can tell when it went stale.
pub fn fits_sha256(results: &Path, name: &str) -> Result<String> {
    published_sha256(&fit_path(results, name))
}

/// The keys of a published LTC table file (results/fits/, a `table` or the anisotropic
/// `cells`) that its readers read: the spec (its tolerances), the preset, the grid and the
/// stored tables. Everything else in such a file (held-out figures, the report's sections)
/// is what the study said about the table.
pub const TABLE_KEYS: [&str; 7] = [
    "spec",
    "preset",
    "grid",
    "layout",
    "table",
    "table_f16",
    "cells",
];

/// The SHA-256 (lower-case hex) of what a reader reads of the published file at `path`: for
/// an LTC table file, its [`TABLE_KEYS`] (serialised as one JSON object, keys sorted), so
/// that a study restating its report figures leaves the consumers of its table current;
/// for any other file, every byte. A typed error naming the file when it cannot be read,
/// or when it is a table file (`.json`) that does not parse.
pub fn published_sha256(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(crate::io::io_err(path))?;
    if path.extension().and_then(|e| e.to_str()) != Some("json") {
        return Ok(crate::io::sha256_hex(&bytes));
    }
    let v: serde_json::Value = serde_json::from_slice(&bytes).map_err(|e| {
        Error::InvalidArgument(format!(
            "{}: not JSON ({e})",
            crate::error::quoted(&path.display().to_string())
        ))
    })?;
    let Some(obj) = v
        .as_object()
        .filter(|o| o.contains_key("table") || o.contains_key("cells"))
    else {
        return Ok(crate::io::sha256_hex(&bytes));
    };
    // keys sorted whatever the file's order (and whatever serde_json's map keeps)
    let part: std::collections::BTreeMap<&str, &serde_json::Value> = obj
        .iter()
        .filter(|(k, _)| TABLE_KEYS.contains(&k.as_str()))
        .map(|(k, v)| (k.as_str(), v))
        .collect();
    let text = serde_json::to_vec(&part).map_err(|e| Error::InvalidArgument(e.to_string()))?;
    Ok(crate::io::sha256_hex(&text))
}

/// A number that may have been written as `null` (serde_json writes a NaN or an infinity
/// so): the one reader, shared with [`crate::integrate::Figure`].
pub use crate::integrate::estimate::f64_or_nan;

/// Read the JSON file `path` as `T`: `None` when absent, a typed error naming the file,
/// `what` it should be and how to rewrite it (`redo`) when it does not parse as `T`.
pub fn read_typed<T: DeserializeOwned>(path: &Path, what: &str, redo: &str) -> Result<Option<T>> {
    let Some(v) = read_json(path)? else {
        return Ok(None);
    };
    serde_json::from_value(v).map(Some).map_err(|e| {
        Error::InvalidArgument(format!(
            "{}: not {what} as this version writes it ({e}); {redo}",
            crate::error::quoted(&path.display().to_string())
        ))
    })
}

/// Add results/fits/<T::NAME>.json to the output set `out`.
pub fn put<T: ResultFile>(set: &mut crate::io::Outputs, results: &Path, value: &T) -> Result<()> {
    put_named(set, results, T::NAME, value)
}

/// A study's report, its plot and its typed result: results/NAME.md, results/NAME.svg and
/// results/fits/NAME.json, NAME the result's.
pub fn put_report<T: ResultFile>(
    set: &mut crate::io::Outputs,
    results: &Path,
    md: &str,
    svg: &str,
    value: &T,
) -> Result<()> {
    set.put(results.join(format!("{}.md", T::NAME)), md.as_bytes());
    set.put(results.join(format!("{}.svg", T::NAME)), svg.as_bytes());
    put(set, results, value)
}

/// The names of the result files (results/fits/<name>.json), one per fit spec: readers
/// name a result through these, never through a string of their own.
pub mod names {
    pub const FILTERS: &str = "filters";
    pub const LTC_ANISO: &str = "ltc-aniso";
    pub const LTC_ANISO_WORK: &str = "ltc-aniso-work";
    pub const LTC_COMPACT: &str = "ltc-compact";
    pub const RENDER: &str = "render";
    pub const RENDER_TRUTH_WORK: &str = "render-truth-work";
    pub const LEADR_GRIDS: &str = "leadr-grids";
    pub const LTC_GGX: &str = "ltc-ggx";
    pub const LTC_GGX_OPTIMISERS: &str = "ltc-ggx-optimisers";
    pub const LTC_LOBE_CROSS: &str = "ltc-lobe-cross";
    pub const LTC_WORK: &str = "ltc-work";
    pub const LTC_JUDGE_TOLERANCE: &str = "ltc-judge-tolerance";
    pub const LTC_BETWEEN_SAMPLE: &str = "ltc-between-sample";
    pub const MULTISCALE_ALPHA_ME: &str = "multiscale-alpha-me";
    pub const MULTISCALE_CONVOLUTION: &str = "multiscale-convolution";
    pub const SMITH_LAMBDA: &str = "smith-lambda";
    pub const TENSOR: &str = "tensor";
    pub const TENSOR_ENVSG: &str = "tensor-envsg";
    pub const TENSOR_WANG: &str = "tensor-wang";
    pub const TENSOR_WAVE: &str = "tensor-wave";
}

/// Where the result of the fit `name` lives under `results`.
pub fn fit_path(results: &Path, name: &str) -> PathBuf {
    results.join("fits").join(format!("{name}.json"))
}

/// Add results/fits/<name>.json to the output set `out`. A typed result is first turned
/// into a JSON value, so its keys are written sorted whatever the struct's field order.
pub fn put_named<T: serde::Serialize + ?Sized>(
    set: &mut crate::io::Outputs,
    results: &Path,
    name: &str,
    value: &T,
) -> Result<()> {
    set.put(fit_path(results, name), json_text(name, value)?);
    Ok(())
}

/// A value as this program writes JSON: through a JSON value (keys sorted), pretty.
pub fn json_text<T: serde::Serialize + ?Sized>(what: &str, value: &T) -> Result<String> {
    let value = serde_json::to_value(value)
        .map_err(|e| crate::error::Error::InvalidArgument(format!("{what}: {e}")))?;
    Ok(serde_json::to_string_pretty(&value).expect("a JSON value serialises"))
}

/// Read any JSON file of results/: `None` when absent, a typed error when unreadable or
/// malformed.
pub fn read_json(path: &Path) -> Result<Option<serde_json::Value>> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => {
            return Err(crate::error::Error::Io {
                path: path.display().to_string(),
                msg: e.to_string(),
            })
        }
    };
    serde_json::from_str(&text).map(Some).map_err(|e| {
        crate::error::Error::InvalidArgument(format!(
            "{}: not a well-formed result ({e})",
            crate::error::quoted(&path.display().to_string())
        ))
    })
}

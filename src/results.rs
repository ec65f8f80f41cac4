//! The fit results on disk: results/fits/<name>.json, written by each study and read by
//! the code generator, the reports and the scenes. One place for the path and the format.

use crate::error::Result;
use std::path::{Path, PathBuf};

/// The names of the result files (results/fits/<name>.json), one per fit spec: readers
/// name a result through these, never through a string of their own.
pub mod names {
    pub const FILTERS: &str = "filters";
    pub const LTC_ANISO: &str = "ltc-aniso";
    pub const RENDER: &str = "render";
    pub const LEADR_GRIDS: &str = "leadr-grids";
    pub const LTC_GGX: &str = "ltc-ggx";
    pub const MULTISCALE_ALPHA_ME: &str = "multiscale-alpha-me";
    pub const MULTISCALE_CONVOLUTION: &str = "multiscale-convolution";
    pub const SMITH_LAMBDA: &str = "smith-lambda";
    pub const TENSOR: &str = "tensor";
}

/// Where the result of the fit `name` lives under `results`.
pub fn fit_path(results: &Path, name: &str) -> PathBuf {
    results.join("fits").join(format!("{name}.json"))
}

/// Write results/fits/<name>.json atomically (into the open output set, if any).
/// A typed result is first turned into a JSON value, so its keys are written sorted
/// whatever the struct's field order.
pub fn write_result<T: serde::Serialize + ?Sized>(
    results: &Path,
    name: &str,
    value: &T,
) -> Result<()> {
    let value = serde_json::to_value(value)
        .map_err(|e| crate::error::Error::InvalidArgument(format!("result {name}: {e}")))?;
    crate::io::write_atomic(
        &fit_path(results, name),
        serde_json::to_string_pretty(&value)
            .expect("a JSON value serialises")
            .as_bytes(),
    )
}

/// Read results/fits/<name>.json: `None` when it does not exist (the study has not been
/// run), a typed error when it exists but cannot be read or is not JSON — a malformed
/// result is never taken for an absent one (a file of the open output set reads as its
/// pending contents).
pub fn read_result(results: &Path, name: &str) -> Result<Option<serde_json::Value>> {
    read_json(&fit_path(results, name))
}

/// Read any JSON file of results/ (costs.json, ltc-compare.json, …) as [`read_result`]
/// reads a fit's: `None` when absent, a typed error when unreadable or malformed.
pub fn read_json(path: &Path) -> Result<Option<serde_json::Value>> {
    let text = match crate::io::read_to_string(path) {
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

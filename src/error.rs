//! Typed errors. Every fallible public routine returns [`Result`]; nothing in the
//! library panics on bad user input and nothing returns a silent NaN.

use thiserror::Error;

/// Errors raised by the workbench.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// A roughness parameter was not a finite number in the supported range
    /// [`crate::microfacet::roughness::ALPHA_MIN`, `ALPHA_MAX`] (α⁴ must be a normal f64).
    #[error("roughness must be a finite number in [1e-75, 1e75], got {0:e}")]
    InvalidRoughness(f64),
    /// A parameter that must be finite was NaN or infinite.
    #[error("{what} must be finite, got {value:e}")]
    NonFinite { what: &'static str, value: f64 },
    /// A roughness matrix (or any matrix that must be SPD) was not symmetric positive definite.
    #[error("matrix is not symmetric positive definite: {0}")]
    NotSpd(String),
    /// A direction lies at or below the horizon where the routine requires the upper hemisphere.
    #[error("direction '{what}' is at or below the horizon (z = {z:e}); this routine needs z > 0")]
    BelowHorizon { what: &'static str, z: f64 },
    /// A direction had zero, NaN or infinite length.
    #[error("direction '{what}' has zero or non-finite length")]
    DegenerateDirection { what: &'static str },
    /// sobol_burley supports at most 2^16 points per scrambled sequence.
    #[error("QMC: at most {max} points per Owen-scrambled Sobol sequence (sobol_burley limit), asked for {asked}; use more replicates instead")]
    QmcTooManyPoints { max: u64, asked: u64 },
    /// Any other argument outside its documented domain.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// File-system failure, with the path involved.
    #[error("I/O error on '{path}': {msg}")]
    Io { path: String, msg: String },
    /// A shard set that cannot stand in for one run (missing, duplicated, foreign, corrupt).
    #[error("shards: {0}")]
    Shard(String),
    /// Not a failure: a study run as one shard stops after its sharded map, and the driver
    /// writes the shard file (`crate::memo`).
    #[error("shard computed; the study stops here")]
    ShardDone,
}

/// Crate-wide result type.
pub type Result<T> = std::result::Result<T, Error>;

/// Reject NaN and infinities with a typed error naming the parameter.
pub fn finite(what: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::NonFinite { what, value })
    }
}

/// A user's string as it may appear in a one-line message: quoted, with control
/// characters, quotes and backslashes escaped (Rust's debug form), so a message that
/// echoes it stays one line.
pub fn quoted(s: &str) -> String {
    format!("{s:?}")
}

/// A message as the CLI prints it: control characters (a newline echoed from user text,
/// a carriage return, an escape sequence) are written escaped, so whatever a message
/// quotes, it stays one line.
pub fn one_line(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_default().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

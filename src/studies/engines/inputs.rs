//! What an engine check was judged on: every file under results/ that the harnesses loaded
//! or the judge read, with the SHA-256 of what they read of it when it was judged (of an
//! LTC table file its table and spec, `results::published_sha256`; of any other file every
//! byte). The engines themselves run only where Chromium, the Bevy harness and an adapter
//! are, so their figures cannot be redone everywhere; the digests can be checked
//! everywhere, and a table refitted after the check names the report it left stale
//! ([`stale`]).

use crate::error::Result;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One input file (relative to results/) and the SHA-256 of what was read of it
/// (`results::published_sha256`, lower-case hex).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputDigest {
    pub file: String,
    pub sha256: String,
}

pub use crate::io::sha256_hex;

/// The digests of `files` (relative to `results`), in the order given.
pub fn digests(results: &Path, files: &[&str]) -> Result<Vec<InputDigest>> {
    files
        .iter()
        .map(|f| {
            Ok(InputDigest {
                file: (*f).to_string(),
                sha256: crate::results::published_sha256(&results.join(f))?,
            })
        })
        .collect()
}

/// The recorded inputs whose file under `results` is missing or no longer has the recorded
/// digest, each as one line; empty when the check is current.
pub fn stale(results: &Path, recorded: &[InputDigest]) -> Vec<String> {
    recorded
        .iter()
        .filter_map(
            |d| match crate::results::published_sha256(&results.join(&d.file)) {
                Err(e) => Some(format!("{}: {e}", d.file)),
                // the recorded digest is read back from a report: shortened by characters,
                // whatever it holds
                Ok(now) if now != d.sha256 => Some(format!(
                    "{} changed since the check (sha256 {} recorded, {} now)",
                    d.file,
                    d.sha256.chars().take(12).collect::<String>(),
                    &now[..12]
                )),
                Ok(_) => None,
            },
        )
        .collect()
}

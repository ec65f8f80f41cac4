//! The result cache: one JSON file per map under `DIR/<study>/<key>.json`, where the key
//! hashes the code version, the spec, the preset, the study's inputs and the map's label,
//! size and place in the study. A cache entry is only ever read back under the same key,
//! checked again on reading (format, key, label, item count); anything else is a miss.
//! Every entry carries the SHA-256 of its content (`memo::seal`): an entry that fails the
//! check is discarded with one line on stderr and the map is computed again.
//! Entries are written atomically and outside any output set (the cache is not a result).

use serde::{de::DeserializeOwned, Serialize};
use std::path::{Path, PathBuf};

/// The format of an entry (version 2: sealed by its SHA-256).
pub const FORMAT: &str = "ndfbench-cache/2";

/// The largest cache entry read back (bytes); a bigger file is a miss.
pub const MAX_ENTRY_BYTES: u64 = 1 << 30;

/// A cache directory (by default `target/ndfbench-cache`).
#[derive(Clone, Debug)]
pub struct Cache {
    pub dir: PathBuf,
}

impl Cache {
    pub fn new(dir: &Path) -> Cache {
        Cache {
            dir: dir.to_path_buf(),
        }
    }
    /// Where the entry `key` of `study` lives.
    pub fn path(&self, study: &str, key: &str) -> PathBuf {
        self.dir.join(study).join(format!("{key}.json"))
    }
}

/// The entry at `path` if it is the one for (`key`, `label`, `n`).
pub fn load<T: DeserializeOwned>(path: &Path, key: &str, label: &str, n: usize) -> Option<Vec<T>> {
    if std::fs::metadata(path).ok()?.len() > MAX_ENTRY_BYTES {
        return None;
    }
    let text = std::fs::read_to_string(path).ok()?;
    let corrupt = |why: &str| {
        eprintln!(
            "cache: entry {} {why}; discarded, computing it again",
            crate::error::quoted(&path.display().to_string())
        );
        let _ = std::fs::remove_file(path);
    };
    let v: serde_json::Value = match serde_json::from_str(&text) {
        Ok(v) => v,
        Err(_) => {
            corrupt("is not JSON");
            return None;
        }
    };
    let v = match super::seal::open(v) {
        Ok(v) => v,
        Err(why) => {
            corrupt(&why);
            return None;
        }
    };
    let Ok(e) = serde_json::from_value::<Entry>(v) else {
        corrupt("is not a cache entry");
        return None;
    };
    if e.format != FORMAT || e.key != key || e.label != label || e.items != n {
        return None;
    }
    let items: Vec<T> = serde_json::from_value(e.values).ok()?;
    (items.len() == n).then_some(items)
}

/// A cache entry: which map and key it answers, how many items, and their values
/// (sealed with the SHA-256 of its content).
#[derive(Serialize, serde::Deserialize)]
struct Entry {
    format: String,
    key: String,
    label: String,
    items: usize,
    values: serde_json::Value,
}

/// Store `values` under `key` (best effort: a value that cannot be stored exactly, or a
/// directory that cannot be written, leaves no entry and is said on stderr).
pub fn store<T: Serialize + DeserializeOwned>(path: &Path, key: &str, label: &str, values: &[T]) {
    let entry = super::shards::exact_json(label, values).map(|vals| {
        super::seal::seal(
            serde_json::to_value(Entry {
                format: FORMAT.into(),
                key: key.into(),
                label: label.into(),
                items: values.len(),
                values: vals,
            })
            .unwrap_or_default(),
        )
    });
    let res = entry.and_then(|e| {
        let text = serde_json::to_string(&e).unwrap_or_default();
        crate::io::write_atomic(path, text.as_bytes())
    });
    if let Err(e) = res {
        eprintln!("cache: not stored: {e}");
    }
}

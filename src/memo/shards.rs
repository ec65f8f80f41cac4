//! Shard files and the checks that let a set of them stand in for one run.
//!
//! `regen --only STUDY --shard K/N` computes the items `i ≡ K (mod N)` of the study's first
//! map and writes `STUDY.shard-K-of-N.json`: the study, the code version, the hashes of the
//! spec and of the inputs, the preset, the map's label and size, and the items with their
//! indices. `merge` reads a set of them and accepts it only when it is complete and
//! consistent: one study, one code version, one spec, one input set, one preset, one N,
//! every K from 0 to N − 1 exactly once, each file holding exactly its own indices. Every
//! refusal is a typed error naming the file (or the missing shard); nothing is written.

use crate::error::{Error, Result};
use serde::{de::DeserializeOwned, Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The file format's name and version.
pub const FORMAT: &str = "ndfbench-shard/2";
/// Bounds on what a shard file may claim.
pub const MAX_SHARDS: usize = 4096;
pub const MAX_ITEMS: usize = 1 << 24;
pub const MAX_FILE_BYTES: u64 = 1 << 31;

/// Items of one map: computed by one shard, or (after [`load_set`]) by all of them.
#[derive(Clone, Debug, Default)]
pub struct Part {
    pub label: String,
    pub items_total: usize,
    pub indices: Vec<usize>,
    pub values: Vec<serde_json::Value>,
    pub seconds: f64,
}

impl Part {
    /// The items as the map's type, in index order; the map must be the one the shards
    /// were made of.
    pub fn into_items<T: DeserializeOwned>(self, label: &str, n: usize) -> Result<Vec<T>> {
        if self.label != label || self.items_total != n {
            return Err(Error::Shard(format!(
                "the shards hold map '{}' ({} items) but this study's first map is '{label}' ({n} items)",
                self.label, self.items_total
            )));
        }
        let mut slots: Vec<Option<T>> = (0..n).map(|_| None).collect();
        for (i, v) in self.indices.into_iter().zip(self.values) {
            let t = serde_json::from_value(v)
                .map_err(|e| Error::Shard(format!("map '{label}' item {i}: {e}")))?;
            if let Some(s) = slots.get_mut(i) {
                *s = Some(t);
            }
        }
        slots
            .into_iter()
            .enumerate()
            .map(|(i, s)| s.ok_or_else(|| Error::Shard(format!("map '{label}': item {i} missing"))))
            .collect()
    }
}

/// What identifies a run: a shard belongs to a set only if all of it agrees.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Identity {
    pub study: String,
    pub code: String,
    pub spec: String,
    pub inputs: String,
    pub preset: String,
}

/// One shard file.
#[derive(Serialize, Deserialize)]
struct ShardFile {
    format: String,
    #[serde(flatten)]
    id: Identity,
    shard: usize,
    of: usize,
    label: String,
    items_total: usize,
    /// Wall clock of this shard's map (reported by `merge`, never part of a result).
    seconds: f64,
    items: Vec<(usize, serde_json::Value)>,
}

/// The file name of shard `k` of `n` of `study`.
pub fn file_name(study: &str, k: usize, n: usize) -> String {
    format!("{study}.shard-{k}-of-{n}.json")
}

/// Write what shard `k` of `n` computed into `dir`; returns the path.
pub fn write(dir: &Path, id: &Identity, k: usize, n: usize, part: Part) -> Result<PathBuf> {
    let path = dir.join(file_name(&id.study, k, n));
    let f = ShardFile {
        format: FORMAT.into(),
        id: id.clone(),
        shard: k,
        of: n,
        label: part.label,
        items_total: part.items_total,
        seconds: part.seconds,
        items: part.indices.into_iter().zip(part.values).collect(),
    };
    let v = serde_json::to_value(&f).map_err(|e| Error::Shard(e.to_string()))?;
    let text =
        serde_json::to_string(&super::seal::seal(v)).map_err(|e| Error::Shard(e.to_string()))?;
    crate::io::write_atomic(&path, text.as_bytes())?;
    Ok(path)
}

/// Parse a `K/N` shard argument (0 ≤ K < N ≤ [`MAX_SHARDS`]).
pub fn parse_spec(s: &str) -> Result<(usize, usize)> {
    let bad = || {
        Error::Shard(format!(
            "--shard '{s}': expected K/N with 0 ≤ K < N ≤ {MAX_SHARDS}"
        ))
    };
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n): (usize, usize) = (
        k.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || k >= n || n > MAX_SHARDS {
        return Err(bad());
    }
    Ok((k, n))
}

/// The shard files named by `paths` (files, or directories whose `*.shard-*-of-*.json`
/// files are taken), sorted.
pub fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let rd = std::fs::read_dir(p).map_err(|e| Error::Io {
                path: p.display().to_string(),
                msg: e.to_string(),
            })?;
            for e in rd.flatten() {
                let name = e.file_name().to_string_lossy().to_string();
                if name.contains(".shard-") && name.ends_with(".json") && !name.starts_with('.') {
                    out.push(e.path());
                }
            }
        } else {
            out.push(p.clone());
        }
    }
    out.sort();
    out.dedup();
    if out.is_empty() {
        return Err(Error::Shard("no shard files given".into()));
    }
    Ok(out)
}

fn read_one(path: &Path) -> Result<ShardFile> {
    let name = crate::error::one_line(&path.display().to_string());
    let meta = std::fs::metadata(path).map_err(|e| Error::Shard(format!("shard '{name}': {e}")))?;
    if meta.len() > MAX_FILE_BYTES {
        return Err(Error::Shard(format!(
            "shard '{name}': {} bytes, more than {MAX_FILE_BYTES}",
            meta.len()
        )));
    }
    let text =
        std::fs::read_to_string(path).map_err(|e| Error::Shard(format!("shard '{name}': {e}")))?;
    let v: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| Error::Shard(format!("shard '{name}' is not a shard file: {e}")))?;
    // the format first, so a file of another format says so before its seal is checked
    #[derive(serde::Deserialize)]
    struct Format {
        format: Option<serde_json::Value>,
    }
    let format = serde_json::from_value::<Format>(v.clone())
        .ok()
        .and_then(|f| f.format);
    if format.as_ref().and_then(|f| f.as_str()) != Some(FORMAT) {
        return Err(Error::Shard(format!(
            "shard '{name}': format {}, expected '{FORMAT}'",
            format.map_or("none".into(), |f| f.to_string())
        )));
    }
    let v = super::seal::open(v).map_err(|why| {
        Error::Shard(format!("shard '{name}' is corrupt: {why}; nothing written"))
    })?;
    let f: ShardFile = serde_json::from_value(v)
        .map_err(|e| Error::Shard(format!("shard '{name}' is not a shard file: {e}")))?;
    if f.format != FORMAT {
        return Err(Error::Shard(format!(
            "shard '{name}': format '{}', expected '{FORMAT}'",
            f.format
        )));
    }
    if f.of == 0 || f.of > MAX_SHARDS || f.shard >= f.of || f.items_total > MAX_ITEMS {
        return Err(Error::Shard(format!(
            "shard '{name}': claims shard {} of {} with {} items (bounds: N ≤ {MAX_SHARDS}, items ≤ {MAX_ITEMS})",
            f.shard, f.of, f.items_total
        )));
    }
    let own: Vec<usize> = (f.shard..f.items_total).step_by(f.of).collect();
    if f.items.iter().map(|(i, _)| *i).ne(own.iter().copied()) {
        return Err(Error::Shard(format!(
            "shard '{name}': its items are not exactly shard {}/{}'s ({} held, {} expected)",
            f.shard,
            f.of,
            f.items.len(),
            own.len()
        )));
    }
    Ok(f)
}

/// The study and preset of the first shard file among `paths` (the rest are checked
/// against it by [`load_set`]).
pub fn peek(paths: &[PathBuf]) -> Result<(String, String)> {
    let files = expand(paths)?;
    let f = read_one(&files[0])?;
    Ok((f.id.study, f.id.preset))
}

fn which_differs(a: &Identity, b: &Identity) -> &'static str {
    if a.study != b.study {
        "study"
    } else if a.code != b.code {
        "code version"
    } else if a.spec != b.spec {
        "spec hash"
    } else if a.inputs != b.inputs {
        "input hash"
    } else {
        "preset"
    }
}

/// Read and check a set of shard files against this run's identity; the merged items.
pub fn load_set(paths: &[PathBuf], expect: &Identity) -> Result<Part> {
    let files = expand(paths)?;
    let mut seen: Vec<Option<PathBuf>> = Vec::new();
    let mut n_of: Option<(usize, PathBuf)> = None;
    let mut merged = Part::default();
    let mut pairs: Vec<(usize, serde_json::Value)> = Vec::new();
    for p in &files {
        let f = read_one(p)?;
        let name = p.display();
        if f.id != *expect {
            let what = which_differs(&f.id, expect);
            return Err(Error::Shard(format!(
                "shard '{name}' is foreign: its {what} differs from this run's (study '{}', preset {})",
                expect.study, expect.preset
            )));
        }
        match &n_of {
            None => {
                n_of = Some((f.of, p.clone()));
                seen = vec![None; f.of];
                merged.label = f.label.clone();
                merged.items_total = f.items_total;
            }
            Some((n, first))
                if *n != f.of || merged.label != f.label || merged.items_total != f.items_total =>
            {
                return Err(Error::Shard(format!(
                    "shard '{name}' is foreign: one of {} shards of map '{}' ({} items), but '{}' is one of {n} of '{}' ({} items)",
                    f.of, f.label, f.items_total, first.display(), merged.label, merged.items_total
                )));
            }
            Some(_) => {}
        }
        if let Some(prev) = &seen[f.shard] {
            return Err(Error::Shard(format!(
                "shard {}/{} is duplicated: '{}' and '{name}'",
                f.shard,
                f.of,
                prev.display()
            )));
        }
        seen[f.shard] = Some(p.clone());
        merged.seconds += f.seconds;
        pairs.extend(f.items);
    }
    let missing: Vec<String> = seen
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_none())
        .map(|(k, _)| format!("{k}/{}", seen.len()))
        .collect();
    if !missing.is_empty() {
        return Err(Error::Shard(format!(
            "shard {} of study '{}' missing ({} of {} files given)",
            missing.join(", "),
            expect.study,
            files.len(),
            seen.len()
        )));
    }
    pairs.sort_by_key(|(i, _)| *i);
    (merged.indices, merged.values) = pairs.into_iter().unzip();
    Ok(merged)
}

/// The JSON text of `values`, checked to parse back to the same text (so to the same bits).
pub(crate) fn exact_json<T: Serialize + DeserializeOwned>(
    label: &str,
    values: &[T],
) -> Result<serde_json::Value> {
    let text = serde_json::to_string(values)
        .map_err(|e| Error::InvalidArgument(format!("map '{label}': not serialisable: {e}")))?;
    let back: Vec<T> = serde_json::from_str(&text).map_err(|e| {
        Error::InvalidArgument(format!(
            "map '{label}': its items do not survive JSON (NaN or infinity?): {e}"
        ))
    })?;
    let again = serde_json::to_string(&back).unwrap_or_default();
    if again != text {
        return Err(Error::InvalidArgument(format!(
            "map '{label}': its items change through JSON; they cannot be stored exactly"
        )));
    }
    serde_json::from_str(&text).map_err(|e| Error::InvalidArgument(format!("map '{label}': {e}")))
}

//! Memoised parallel maps: the one place where a study's heavy, embarrassingly parallel
//! work runs, so that the driver can run it whole, from a cache, one shard at a time, or
//! from merged shards — with the same bits every time.
//!
//! A study calls [`map`] with a label, an item count and a pure function of the item's
//! index. What happens depends on the [`Scope`] the driver installed on the study's thread:
//!
//! - none, or [`Mode::Plain`]: every item is computed (rayon), as a plain `par_iter` would;
//! - [`Mode::Cache`]: each map is looked up under the hash of the code its study reaches
//!   ([`deps`]), the spec, the preset, the inputs and the map's place in the study
//!   ([`cache`]); a miss computes and stores it;
//! - [`Mode::Shard`]: only the items `i ≡ k (mod n)` of the study's *first* map are
//!   computed; they go into the scope ([`Part`]) and the study stops with
//!   [`Error::ShardDone`], which the driver turns into a shard file ([`shards`]);
//! - [`Mode::Merge`]: the first map's items come from a checked, complete set of shards;
//!   everything after it is computed as usual.
//!
//! Why the bits agree: every item is a pure function of its index, the items are put back
//! in index order, and what is stored goes through JSON text that is checked, on the way
//! out, to parse back to the same text (shortest round-trip decimals, `float_roundtrip`
//! parsing: one text per f64, so equal text is equal bits).
//!
//! What a map's function may read: the spec, the preset and the results of the studies
//! its study follows (`Study::after`), which are what the key hashes. Nothing else.

pub mod cache;
pub mod deps;
pub mod seal;
pub mod shards;

use crate::error::{Error, Result};
use rayon::prelude::*;
use serde::{de::DeserializeOwned, Serialize};
use std::cell::RefCell;

use shards::exact_json;
pub use shards::Part;

/// The build's code version (SHA-256 of the sources, the manifest and the lock file).
pub const CODE_HASH: &str = env!("NDFB_CODE_HASH");

include!(concat!(env!("OUT_DIR"), "/unit_hashes.rs"));

/// The code version of the module `module_path` (as `module_path!()` gives it): the hash
/// of the files its unit reaches ([`deps`]), or the whole build's [`CODE_HASH`] for a
/// module outside any unit.
pub fn code_hash_of(module_path: &str) -> &'static str {
    let rel = module_path.split("::").skip(1).collect::<Vec<_>>();
    let file = format!("src/{}.rs", rel.join("/"));
    deps::unit_of(&file)
        .and_then(|u| UNIT_HASHES.iter().find(|(n, _)| *n == u).map(|(_, h)| *h))
        .unwrap_or(CODE_HASH)
}

/// How a study's maps run.
pub enum Mode {
    /// Compute every item.
    Plain,
    /// Look every map up in the cache; compute and store on a miss.
    Cache(cache::Cache),
    /// Compute shard `k` of `n` of the first map, then stop.
    Shard { k: usize, n: usize },
    /// The first map's items from merged shards.
    Merge(Part),
}

/// What one map did.
#[derive(Clone, Debug, serde::Serialize)]
pub struct MapLog {
    pub label: String,
    pub items: usize,
    /// Items computed here (0 on a cache hit or when merged).
    pub computed: usize,
    pub source: &'static str,
    pub seconds: f64,
}

/// The context of one study's run: who it is, the hash of what it depends on, the mode.
pub struct Scope {
    pub study: String,
    /// Hex SHA-256 of the code, the spec, the preset and the inputs ([`key`]).
    pub key: String,
    pub mode: Mode,
    ordinal: usize,
    /// In shard mode: what this shard computed.
    pub part: Option<Part>,
    pub log: Vec<MapLog>,
}

impl Scope {
    pub fn new(study: &str, key: String, mode: Mode) -> Scope {
        Scope {
            study: study.to_string(),
            key,
            mode,
            ordinal: 0,
            part: None,
            log: Vec::new(),
        }
    }
}

thread_local! {
    static SCOPE: RefCell<Option<Scope>> = const { RefCell::new(None) };
}

/// Run `f` with `scope` installed on this thread (the one that runs the study), and give
/// the scope back with what the maps did. A scope already installed is restored after.
pub fn run_in<R>(scope: Scope, f: impl FnOnce() -> R) -> (R, Scope) {
    let prev = SCOPE.with_borrow_mut(|s| s.replace(scope));
    let r = f();
    let scope = SCOPE
        .with_borrow_mut(|s| std::mem::replace(s, prev))
        .expect("the scope installed above");
    (r, scope)
}

/// Hex SHA-256 of the parts, each framed by its length.
pub fn key(parts: &[&[u8]]) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    for p in parts {
        h.update((p.len() as u64).to_le_bytes());
        h.update(p);
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// What this call of [`map`] does, decided while the scope is borrowed.
enum Step {
    Plain,
    Cached(std::path::PathBuf, String),
    Shard(usize, usize),
    Merged(Part),
}

fn compute<T: Send, F: Fn(usize) -> Result<T> + Sync>(
    idx: &[usize],
    f: &F,
    label: &str,
) -> Result<Vec<T>> {
    let study = SCOPE.with_borrow(|s| s.as_ref().map(|s| s.study.clone()));
    let pr = crate::progress::Progress::new(
        match study {
            Some(s) => format!("{s}: {label}"),
            None => label.to_string(),
        },
        idx.len() as u64,
    );
    idx.par_iter()
        .map(|&i| {
            let r = f(i);
            pr.inc(1);
            r
        })
        .collect()
}

/// The items `f(0), …, f(n − 1)` of the map `label`, in index order; see the module doc
/// for what the installed scope does with them. `f` must be a pure function of the index.
pub fn map<T, F>(label: &str, n: usize, f: F) -> Result<Vec<T>>
where
    T: Serialize + DeserializeOwned + Send,
    F: Fn(usize) -> Result<T> + Sync,
{
    let step = SCOPE.with_borrow_mut(|s| {
        let Some(s) = s.as_mut() else {
            return Step::Plain;
        };
        let ordinal = s.ordinal;
        s.ordinal += 1;
        match &mut s.mode {
            Mode::Plain => Step::Plain,
            Mode::Cache(c) => {
                let k = key(&[
                    s.key.as_bytes(),
                    &ordinal.to_le_bytes(),
                    label.as_bytes(),
                    &n.to_le_bytes(),
                ]);
                Step::Cached(c.path(&s.study, &k), k)
            }
            Mode::Shard { k, n } if ordinal == 0 => Step::Shard(*k, *n),
            Mode::Shard { .. } => Step::Plain,
            Mode::Merge(p) if ordinal == 0 => Step::Merged(std::mem::take(p)),
            Mode::Merge(_) => Step::Plain,
        }
    });
    let clock = std::time::Instant::now();
    let all: Vec<usize> = (0..n).collect();
    let (out, computed, source) = match step {
        Step::Plain => (compute(&all, &f, label)?, n, "computed"),
        Step::Cached(path, k) => match cache::load::<T>(&path, &k, label, n) {
            Some(v) => (v, 0, "cache hit"),
            None => {
                let v = compute(&all, &f, label)?;
                cache::store(&path, &k, label, &v);
                (v, n, "cache miss, stored")
            }
        },
        Step::Shard(k, of) => {
            let own: Vec<usize> = (k..n).step_by(of).collect();
            let v = compute(&own, &f, label)?;
            let values = exact_json(label, &v)?;
            let seconds = clock.elapsed().as_secs_f64();
            let computed = own.len();
            SCOPE.with_borrow_mut(|s| {
                if let Some(s) = s.as_mut() {
                    s.part = Some(Part {
                        label: label.to_string(),
                        items_total: n,
                        indices: own,
                        values: match values {
                            serde_json::Value::Array(a) => a,
                            _ => Vec::new(),
                        },
                        seconds,
                    });
                    s.log.push(MapLog {
                        label: label.to_string(),
                        items: n,
                        computed,
                        source: "shard",
                        seconds,
                    });
                }
            });
            return Err(Error::ShardDone);
        }
        Step::Merged(part) => (part.into_items(label, n)?, 0, "merged shards"),
    };
    let seconds = clock.elapsed().as_secs_f64();
    SCOPE.with_borrow_mut(|s| {
        if let Some(s) = s.as_mut() {
            s.log.push(MapLog {
                label: label.to_string(),
                items: n,
                computed,
                source,
                seconds,
            });
        }
    });
    Ok(out)
}

/// [`map`] over a slice: item `i` is `f(&items[i])`. The items must themselves be a pure
/// function of what the key hashes (the spec, the preset, the inputs).
pub fn map_items<I, T, F>(label: &str, items: &[I], f: F) -> Result<Vec<T>>
where
    I: Sync,
    T: Serialize + DeserializeOwned + Send,
    F: Fn(&I) -> Result<T> + Sync,
{
    map(label, items.len(), |i| f(&items[i]))
}

/// The memoised map as the [`crate::parmap::ParMap`] a model takes: [`map`] under the
/// installed scope (cached, sharded or merged), plain without one.
#[derive(Clone, Copy, Debug, Default)]
pub struct Memo;

impl crate::parmap::ParMap for Memo {
    fn map<T, F>(&self, label: &str, n: usize, f: F) -> Result<Vec<T>>
    where
        T: Serialize + DeserializeOwned + Send,
        F: Fn(usize) -> Result<T> + Sync,
    {
        map(label, n, f)
    }
}

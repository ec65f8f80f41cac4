//! The one interface a model runs its parallel work through: a pure map over the indices
//! `0..n`, its items back in index order. The model says *what* each item is; the caller
//! says *how* the map runs — [`Plain`] here (rayon, nothing kept), or the driver's
//! memoised map (`memo::Memo`: cached, sharded across processes, merged), which gives the
//! same bits. Models take a `&impl ParMap` and never name the driver.

use crate::error::Result;
use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::Serialize;

/// How a pure indexed map is run. `f` must be a pure function of its index; `label`
/// names the map (progress lines, cache keys).
pub trait ParMap: Sync {
    fn map<T, F>(&self, label: &str, n: usize, f: F) -> Result<Vec<T>>
    where
        T: Serialize + DeserializeOwned + Send,
        F: Fn(usize) -> Result<T> + Sync;

    /// [`ParMap::map`] over a slice: item `i` is `f(&items[i])`.
    fn map_items<I, T, F>(&self, label: &str, items: &[I], f: F) -> Result<Vec<T>>
    where
        I: Sync,
        T: Serialize + DeserializeOwned + Send,
        F: Fn(&I) -> Result<T> + Sync,
    {
        self.map(label, items.len(), |i| f(&items[i]))
    }
}

/// Rayon over the indices, back in index order, the first error returned; nothing kept.
#[derive(Clone, Copy, Debug, Default)]
pub struct Plain;

impl ParMap for Plain {
    fn map<T, F>(&self, _label: &str, n: usize, f: F) -> Result<Vec<T>>
    where
        T: Serialize + DeserializeOwned + Send,
        F: Fn(usize) -> Result<T> + Sync,
    {
        (0..n).into_par_iter().map(|i| f(i)).collect()
    }
}

//! The one reader of a fitted LTC table (results/fits/<name>.json, the `table` array of
//! columns j of cells i, each [a, b, c, d, norm, fresnel]). Code generation, the
//! comparison with a shipped table and the shading pipeline all read it through here.

use crate::error::{Error, Result};
use std::path::Path;

/// A fitted table: `cells[i + n·j]` = [a, b, c, d, norm, fresnel] at roughness index i
/// (r = √α = i/(n − 1)) and view index j (t = √(1 − cos θ) = j/(n − 1)).
#[derive(Clone, Debug, PartialEq)]
pub struct FittedTable {
    pub n: usize,
    pub cells: Vec<[f64; 6]>,
}

/// Largest table side read from a file.
pub const MAX_SIDE: usize = 1024;

impl FittedTable {
    /// Cell (i, j).
    pub fn cell(&self, i: usize, j: usize) -> &[f64; 6] {
        &self.cells[i + self.n * j]
    }
}

/// Read the table of the fit `name` under `results`: an n × n table (2 ≤ n ≤ 1024) of
/// finite numbers, or a typed error saying what is wrong.
pub fn read(results: &Path, name: &str) -> Result<FittedTable> {
    let bad = |m: &str| Error::InvalidArgument(format!("results/fits/{name}.json: {m}"));
    let v = crate::results::read_result(results, name).ok_or_else(|| {
        Error::InvalidArgument(format!(
            "results/fits/{name}.json missing or malformed: run `cargo run --release -- regen --only ltc`"
        ))
    })?;
    let table = v["table"].as_array().ok_or_else(|| bad("no table"))?;
    let n = table.len();
    if !(2..=MAX_SIDE).contains(&n) {
        return Err(bad(&format!("a table of side {n}, not 2 … {MAX_SIDE}")));
    }
    let mut cells = vec![[0.0; 6]; n * n];
    for (j, col) in table.iter().enumerate() {
        let col = col
            .as_array()
            .filter(|c| c.len() == n)
            .ok_or_else(|| bad("malformed table"))?;
        for (i, c) in col.iter().enumerate() {
            for k in 0..6 {
                cells[i + n * j][k] = c[k]
                    .as_f64()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| bad("bad table cell"))?;
            }
        }
    }
    Ok(FittedTable { n, cells })
}

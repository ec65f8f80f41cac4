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
    /// The binary16 table chosen for storage (`table_f16`: per cell the f16 neighbours
    /// of the f64 entries that minimise the fit's error), in the same layout; `None` for
    /// a file without one (then f16 storage rounds to nearest).
    pub half: Option<Vec<[half::f16; 6]>>,
}

/// Largest table side read from a file.
pub const MAX_SIDE: usize = 1024;

impl FittedTable {
    /// Cell (i, j).
    pub fn cell(&self, i: usize, j: usize) -> &[f64; 6] {
        &self.cells[i + self.n * j]
    }
    /// The binary16 entries of cell `k` (= i + n·j) as stored in every f16 file.
    pub fn half_cell(&self, k: usize) -> [half::f16; 6] {
        match &self.half {
            Some(h) => h[k],
            None => self.cells[k].map(half::f16::from_f64),
        }
    }
}

/// Read an n × n table of cells [f64; 6] from a JSON array of columns (`what` names it
/// in errors).
fn cells_of(
    v: &serde_json::Value,
    n: Option<usize>,
    bad: &dyn Fn(&str) -> Error,
) -> Result<(usize, Vec<[f64; 6]>)> {
    let table = v.as_array().ok_or_else(|| bad("no table"))?;
    let n = n.unwrap_or(table.len());
    if !(2..=MAX_SIDE).contains(&n) || table.len() != n {
        return Err(bad(&format!(
            "a table of side {}, not 2 … {MAX_SIDE}",
            table.len()
        )));
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
    Ok((n, cells))
}

/// Read the table of the fit `name` under `results`: an n × n table (2 ≤ n ≤ 1024) of
/// finite numbers, or a typed error saying what is wrong.
pub fn read(results: &Path, name: &str) -> Result<FittedTable> {
    let bad = |m: &str| Error::InvalidArgument(format!("results/fits/{name}.json: {m}"));
    let v = crate::results::read_result(results, name)?.ok_or_else(|| {
        Error::InvalidArgument(format!(
            "results/fits/{name}.json missing or malformed: run `cargo run --release -- regen --only ltc-ggx`"
        ))
    })?;
    let (n, cells) = cells_of(&v["table"], None, &bad)?;
    let half = if v.get("table_f16").is_some() {
        let (_, h) = cells_of(&v["table_f16"], Some(n), &bad)?;
        let mut out = Vec::with_capacity(h.len());
        for c in h {
            let q = c.map(half::f16::from_f64);
            if q.iter().zip(&c).any(|(a, b)| a.to_f64() != *b) {
                return Err(bad("table_f16 holds a value that is not a binary16 number"));
            }
            out.push(q);
        }
        Some(out)
    } else {
        None
    };
    Ok(FittedTable { n, cells, half })
}

impl FittedTable {
    /// The table interpolated bilinearly at (α, cos θ) as a GPU's linear, clamp-to-edge
    /// sampler reads the texture at uv = ((r, t)(n − 1) + ½)/n: texel coordinates
    /// x = r(n − 1), y = t(n − 1) with r = √α, t = √(1 − cos θ) (α and cos θ clamped to
    /// [0, 1]). `half`: the binary16 entries as stored in every f16 file, else the f64
    /// table. The f64 reference of the WGSL lookup (codegen/lut.rs).
    pub fn bilinear(&self, alpha: f64, cos_theta: f64, half: bool) -> [f64; 6] {
        let n = self.n;
        let r = alpha.clamp(0.0, 1.0).sqrt();
        let t = (1.0 - cos_theta.clamp(0.0, 1.0)).sqrt();
        bilinear(n, r, t, |i, j| {
            let k = i + n * j;
            if half {
                self.half_cell(k).map(|h| h.to_f64())
            } else {
                self.cells[k]
            }
        })
    }
}

/// The bilinear lookup engines do in an n×n table (n ≥ 2) at (r, t) ∈ [0, 1]²: texel
/// centres at (i, j)/(n − 1) (uv = (r, t)·(n − 1)/n + 0.5/n), the four texels around the
/// point weighted linearly, clamped at the edges; `at(i, j)` gives a texel.
pub fn bilinear<const K: usize>(
    n: usize,
    r: f64,
    t: f64,
    at: impl Fn(usize, usize) -> [f64; K],
) -> [f64; K] {
    let (x, y) = (
        r.clamp(0.0, 1.0) * (n - 1) as f64,
        t.clamp(0.0, 1.0) * (n - 1) as f64,
    );
    let (i0, j0) = (
        (x.floor() as usize).min(n - 2),
        (y.floor() as usize).min(n - 2),
    );
    let (fx, fy) = (x - i0 as f64, y - j0 as f64);
    let (c00, c10, c01, c11) = (
        at(i0, j0),
        at(i0 + 1, j0),
        at(i0, j0 + 1),
        at(i0 + 1, j0 + 1),
    );
    std::array::from_fn(|c| {
        (c00[c] * (1.0 - fx) + c10[c] * fx) * (1.0 - fy) + (c01[c] * (1.0 - fx) + c11[c] * fx) * fy
    })
}

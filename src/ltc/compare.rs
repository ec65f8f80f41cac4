//! Comparison of our GGX LTC table with the widely shipped one:
//! selfshadow/ltc_code `fit/results/ltc.js`, also shipped by three.js as LTC_MAT_1 /
//! LTC_MAT_2 in RectAreaLightTexturesLib.js (index (r + n·t)·4 + c; LTC_MAT_1 holds the
//! production M⁻¹ (a, b, c, d), LTC_MAT_2 (norm, fresnel, …)). The file is read from the
//! path the user gives (`ltc-compare --shipped FILE`); nothing of it is committed.
//!
//! Both tables are judged against the true BRDF under the same metrics, per cell, on the
//! same held-out sample sets, at the same (α = r², θ = acos(1 − t²)) with θ clamped to
//! 89.99°. The shipped fit used α_min = 1e-5 at r = 0; ours uses the spec's α_min, so
//! the r = 0 row is reported separately.

use crate::error::{Error, Result};
use crate::ltc::fit::{inverse_from_production, metrics};
use crate::ltc::target::GgxTarget;
use crate::ltc::LtcDist;
use serde::Serialize;
use std::path::Path;

/// Extract the numeric array assigned to `name` (`name = [ … ]` or `name: [ … ]`) from
/// JS/JSON text. Tolerates `- 4.2e-07` (a space after the sign), as in the shipped files.
pub fn js_array(text: &str, name: &str) -> Result<Vec<f64>> {
    // the first occurrence of `name` followed by `=` or `:` and then `[` (a mention in a
    // comment or a string is skipped)
    let open = text
        .match_indices(name)
        .find_map(|(at, _)| {
            let rest = text[at + name.len()..].trim_start();
            let rest = rest.strip_prefix('=').or_else(|| rest.strip_prefix(':'))?;
            let body = rest.trim_start();
            body.starts_with('[').then(|| text.len() - body.len())
        })
        .ok_or_else(|| {
            Error::InvalidArgument(format!(
                "no array named '{name}' (`{name} = [ … ]` or `{name}: [ … ]`) in the file"
            ))
        })?;
    let close = text[open..]
        .find(']')
        .map(|i| open + i)
        .ok_or_else(|| Error::InvalidArgument(format!("array '{name}' is not closed")))?;
    text[open + 1..close]
        .split(',')
        .map(|t| t.chars().filter(|c| !c.is_whitespace()).collect::<String>())
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<f64>()
                .map_err(|e| Error::InvalidArgument(format!("array '{name}': '{t}': {e}")))
        })
        .collect()
}

/// A table in the shipped layout: n×n cells of (a, b, c, d) and (norm, fresnel).
#[derive(Clone, Debug)]
pub struct Shipped {
    pub n: usize,
    pub mat: Vec<[f64; 4]>,
    pub mag: Vec<[f64; 2]>,
}

impl Shipped {
    pub fn parse(text: &str, mat_name: &str, mag_name: &str) -> Result<Shipped> {
        let m1 = js_array(text, mat_name)?;
        let m2 = js_array(text, mag_name)?;
        if m1.len() % 4 != 0 || m1.len() != m2.len() {
            return Err(Error::InvalidArgument(format!(
                "'{mat_name}' has {} numbers and '{mag_name}' {}: expected two equal multiples of 4",
                m1.len(),
                m2.len()
            )));
        }
        let cells = m1.len() / 4;
        let n = (cells as f64).sqrt().round() as usize;
        if n * n != cells || n < 2 {
            return Err(Error::InvalidArgument(format!(
                "{cells} cells is not an n×n table"
            )));
        }
        Ok(Shipped {
            n,
            mat: m1.chunks(4).map(|c| [c[0], c[1], c[2], c[3]]).collect(),
            mag: m2.chunks(4).map(|c| [c[0], c[1]]).collect(),
        })
    }
    /// Only the M⁻¹ array; the norms are taken from `norms` (ours: the BRDF's albedo by
    /// quadrature), so that the comparison isolates the fitted matrices.
    pub fn parse_mat_with_norms(text: &str, mat_name: &str, norms: &Shipped) -> Result<Shipped> {
        let m1 = js_array(text, mat_name)?;
        if m1.len() != 4 * norms.n * norms.n {
            return Err(Error::InvalidArgument(format!(
                "'{mat_name}' has {} numbers: expected 4 × {}² = {}",
                m1.len(),
                norms.n,
                4 * norms.n * norms.n
            )));
        }
        Ok(Shipped {
            n: norms.n,
            mat: m1.chunks(4).map(|c| [c[0], c[1], c[2], c[3]]).collect(),
            mag: norms.mag.clone(),
        })
    }
    /// (production inverse, norm) of cell (r index i, t index j).
    pub fn cell(&self, i: usize, j: usize) -> ([f64; 4], f64) {
        let k = i + self.n * j;
        (self.mat[k], self.mag[k][0])
    }
}

/// Per-cell comparison.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CellCmp {
    pub i: usize,
    pub j: usize,
    pub alpha: f64,
    pub theta_deg: f64,
    pub ours_l2: f64,
    pub shipped_l2: f64,
    pub ours_cubic: f64,
    pub shipped_cubic: f64,
}

/// Error of one production-form cell against the BRDF (relative L2, cubic).
pub fn cell_error(
    inv: &[f64; 4],
    norm: f64,
    alpha: f64,
    theta: f64,
    n: usize,
) -> Result<(f64, f64)> {
    let m = inverse_from_production(inv)
        .try_inverse()
        .ok_or_else(|| Error::InvalidArgument("singular LTC inverse in the table".into()))?;
    let ltc = LtcDist::new(m)?;
    let t = GgxTarget::new(alpha, theta)?;
    let (c, l2) = metrics(&t, &ltc, norm, n, 0.25);
    Ok((l2, c))
}

/// The error a shader sees between table cells: the production inverse bilinearly
/// interpolated (as a GPU samples the texture) at the centre of the square with corners
/// (i, j) and (i + 1, j + 1), judged against the BRDF there with its exact norm (by
/// quadrature, so only the interpolated matrix is tested). `None` when a corner is
/// missing (NaN). Relative L2.
pub fn midpoint_error(t: &Shipped, i: usize, j: usize, n_samples: usize) -> Result<Option<f64>> {
    let n = t.n;
    if i + 1 >= n || j + 1 >= n {
        return Ok(None);
    }
    let corners = [
        t.mat[i + n * j],
        t.mat[i + 1 + n * j],
        t.mat[i + n * (j + 1)],
        t.mat[i + 1 + n * (j + 1)],
    ];
    if corners.iter().flatten().any(|v| !v.is_finite()) {
        return Ok(None);
    }
    let inv: [f64; 4] = std::array::from_fn(|k| corners.iter().map(|c| c[k]).sum::<f64>() / 4.0);
    let r = (i as f64 + 0.5) / (n - 1) as f64;
    let tt = (j as f64 + 0.5) / (n - 1) as f64;
    let alpha = r * r;
    let theta = (1.0 - tt * tt).clamp(0.0, 1.0).acos();
    let (norm, _, _) = GgxTarget::new(alpha, theta)?.norm_quad(1e-8);
    cell_error(&inv, norm, alpha, theta, n_samples).map(|(l2, _)| Some(l2))
}

/// Compare two tables of the same size (ours from results/fits/ltc-ggx.json).
pub fn compare(ours: &Shipped, shipped: &Shipped, n_samples: usize) -> Result<Vec<CellCmp>> {
    use rayon::prelude::*;
    if ours.n != shipped.n {
        return Err(Error::InvalidArgument(format!(
            "table sizes differ: ours {}×{}, shipped {}×{}",
            ours.n, ours.n, shipped.n, shipped.n
        )));
    }
    let n = ours.n;
    // cells the file leaves out (NaN) are skipped
    let present: Vec<usize> = (0..n * n)
        .filter(|&k| shipped.mat[k].iter().all(|v| v.is_finite()) && shipped.mag[k][0].is_finite())
        .collect();
    present
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % n, k / n);
            let r = i as f64 / (n - 1) as f64;
            let t = j as f64 / (n - 1) as f64;
            let alpha = (r * r).max(1e-5);
            let theta = (1.0 - t * t).clamp(0.0, 1.0).acos();
            let (oi, on) = ours.cell(i, j);
            let (si, sn) = shipped.cell(i, j);
            let (ol, oc) = cell_error(&oi, on, alpha, theta, n_samples)?;
            let (sl, sc) = cell_error(&si, sn, alpha, theta, n_samples)?;
            Ok(CellCmp {
                i,
                j,
                alpha,
                theta_deg: theta.to_degrees(),
                ours_l2: ol,
                shipped_l2: sl,
                ours_cubic: oc,
                shipped_cubic: sc,
            })
        })
        .collect()
}

/// Our table from results/fits/ltc-ggx.json in the shipped layout.
pub fn ours(results: &Path) -> Result<Shipped> {
    let t = super::table::read(results, "ltc-ggx")?;
    Ok(Shipped {
        n: t.n,
        mat: t.cells.iter().map(|c| [c[0], c[1], c[2], c[3]]).collect(),
        mag: t.cells.iter().map(|c| [c[4], c[5]]).collect(),
    })
}

/// The held-out mean relative L2 of our table as recorded in results/fits/ltc-ggx.json
/// (identifies the table a comparison was made against).
pub fn ours_mean_l2(results: &Path) -> Result<f64> {
    crate::results::read_result(results, "ltc-ggx")
        .and_then(|v| v["held_out"]["mean_l2"].as_f64())
        .ok_or_else(|| {
            Error::InvalidArgument("results/fits/ltc-ggx.json has no held_out.mean_l2".into())
        })
}

/// Smoothness: mean absolute second difference of each parameter along both axes,
/// relative to its range.
pub fn roughness_of_table(t: &Shipped) -> [f64; 4] {
    let n = t.n;
    let mut out = [0.0; 4];
    for (k, o) in out.iter_mut().enumerate() {
        let range = t
            .mat
            .iter()
            .map(|c| c[k].abs())
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max)
            .max(1e-300);
        let mut s = 0.0;
        let mut cnt = 0.0f64;
        // second differences wherever all three cells are present (NaN = left out)
        let mut add = |d: f64| {
            if d.is_finite() {
                s += d.abs();
                cnt += 1.0;
            }
        };
        for j in 0..n {
            for i in 1..n - 1 {
                let v = |ii: usize| t.mat[ii + n * j][k];
                add(v(i - 1) - 2.0 * v(i) + v(i + 1));
            }
        }
        for i in 0..n {
            for j in 1..n - 1 {
                let v = |jj: usize| t.mat[i + n * jj][k];
                add(v(j - 1) - 2.0 * v(j) + v(j + 1));
            }
        }
        *o = s / cnt.max(1.0) / range;
    }
    out
}

/// Largest shipped-table file read.
pub const MAX_SHIPPED_BYTES: u64 = 16 << 20;

/// Run the comparison and write `out`/ltc-compare.md; returns a one-line summary.
pub fn run(
    shipped_path: &Path,
    mat: &str,
    mag: &str,
    norm_ours: bool,
    source: Option<&str>,
    results: &Path,
    out: &Path,
) -> Result<String> {
    let io = |e: std::io::Error| Error::Io {
        path: shipped_path.display().to_string(),
        msg: e.to_string(),
    };
    // three.js's RectAreaLightTexturesLib.js is ~0.5 MB; anything far larger is not a table
    let len = std::fs::metadata(shipped_path).map_err(io)?.len();
    if len > MAX_SHIPPED_BYTES {
        return Err(Error::InvalidArgument(format!(
            "ltc-compare: {} is {len} bytes, over the {MAX_SHIPPED_BYTES}-byte limit for a shipped table",
            shipped_path.display()
        )));
    }
    let text = std::fs::read_to_string(shipped_path).map_err(io)?;
    let ours = ours(results)?;
    let shipped = if norm_ours {
        Shipped::parse_mat_with_norms(&text, mat, &ours)?
    } else {
        Shipped::parse(&text, mat, mag)?
    };
    let cmp = compare(&ours, &shipped, 48)?;
    let inner: Vec<&CellCmp> = cmp
        .iter()
        .filter(|c| c.i > 0 && c.ours_l2.is_finite() && c.shipped_l2.is_finite())
        .collect();
    if inner.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "ltc-compare: {} has no cell that can be compared (every cell is NaN, or only the r = 0 column is given); nothing written",
            shipped_path.display()
        )));
    }
    let mean =
        |f: &dyn Fn(&CellCmp) -> f64| inner.iter().map(|c| f(c)).sum::<f64>() / inner.len() as f64;
    let worse: Vec<&&CellCmp> = inner
        .iter()
        .filter(|c| c.ours_l2 > c.shipped_l2 * 1.001)
        .collect();
    let mut md = format!(
        "# Our GGX LTC table against the shipped one\n\nWritten by `cargo run --release -- ltc-compare --shipped {}`. Both tables judged against the cosine-weighted GGX BRDF (height-correlated G2, F = 1) at the same cells, on the same held-out 48×48 + 48×48 sample sets. {}Norms: {}. Cells compared (r > 0; cells the file leaves as NaN are skipped): {} of {}.\n\n| | ours | shipped |\n|---|---|---|\n| mean relative L2 | {:.2} % | {:.2} % |\n| max relative L2 | {:.1} % | {:.1} % |\n| mean cubic metric | {:.3e} | {:.3e} |\n| smoothness (mean abs(Δ²) / range of a, b, c, d) | {:?} | {:?} |\n\nOurs no worse (relative L2, 0.1 % slack) in {} of {} cells.\n\n",
        shipped_path.display(),
        source.map(|s| format!("Source of the file: {s}. ")).unwrap_or_default(),
        if norm_ours { "ours for both (the BRDF albedo by quadrature, error ≤ 1e-9), so only the fitted matrices differ" } else { "each table's own" },
        inner.len(),
        ours.n * (ours.n - 1),
        100.0 * mean(&|c| c.ours_l2),
        100.0 * mean(&|c| c.shipped_l2),
        100.0 * inner.iter().map(|c| c.ours_l2).fold(0.0, f64::max),
        100.0 * inner.iter().map(|c| c.shipped_l2).fold(0.0, f64::max),
        mean(&|c| c.ours_cubic),
        mean(&|c| c.shipped_cubic),
        roughness_of_table(&ours).map(|x| (x * 1e4).round() / 1e4),
        roughness_of_table(&shipped).map(|x| (x * 1e4).round() / 1e4),
        inner.len() - worse.len(),
        inner.len()
    );
    md.push_str("## Per view angle (rows of the table)\n\n| t index | θ | cells | ours: mean L2 | shipped: mean L2 | ours: max L2 | shipped: max L2 | ours no worse |\n|---|---|---|---|---|---|---|---|\n");
    let mut rows: Vec<usize> = inner.iter().map(|c| c.j).collect();
    rows.dedup();
    for j in rows {
        let row: Vec<&&CellCmp> = inner.iter().filter(|c| c.j == j).collect();
        let m = row.len() as f64;
        md.push_str(&format!(
            "| {j} | {:.2}° | {} | {:.2} % | {:.2} % | {:.1} % | {:.1} % | {} |\n",
            row[0].theta_deg,
            row.len(),
            100.0 * row.iter().map(|c| c.ours_l2).sum::<f64>() / m,
            100.0 * row.iter().map(|c| c.shipped_l2).sum::<f64>() / m,
            100.0 * row.iter().map(|c| c.ours_l2).fold(0.0, f64::max),
            100.0 * row.iter().map(|c| c.shipped_l2).fold(0.0, f64::max),
            row.iter()
                .filter(|c| c.ours_l2 <= c.shipped_l2 * 1.001)
                .count()
        ));
    }
    // between cells: bilinear interpolation at square centres where both rows are present
    let squares: Vec<(usize, usize)> = (0..ours.n - 1)
        .flat_map(|j| (1..ours.n - 1).map(move |i| (i, j)))
        .filter(|&(i, j)| {
            [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
                .iter()
                .all(|&(a, b)| shipped.mat[a + ours.n * b].iter().all(|v| v.is_finite()))
        })
        .collect();
    let mids: Vec<(f64, f64)> = {
        use rayon::prelude::*;
        squares
            .par_iter()
            .map(|&(i, j)| {
                Ok((
                    midpoint_error(&ours, i, j, 48)?.unwrap_or(f64::NAN),
                    midpoint_error(&shipped, i, j, 48)?.unwrap_or(f64::NAN),
                ))
            })
            .collect::<Result<_>>()?
    };
    if !mids.is_empty() {
        let m = mids.len() as f64;
        md.push_str(&format!(
            "\n## Between cells (what a shader sees)\n\nThe production inverse bilinearly interpolated at the centre of each square of four present cells ({} squares), judged against the BRDF there (exact norm by quadrature): mean relative L2 ours {:.2} %, shipped {:.2} %; max ours {:.1} %, shipped {:.1} %; ours no worse (0.1 % slack) in {} of {}.\n",
            mids.len(),
            100.0 * mids.iter().map(|x| x.0).sum::<f64>() / m,
            100.0 * mids.iter().map(|x| x.1).sum::<f64>() / m,
            100.0 * mids.iter().map(|x| x.0).fold(0.0, f64::max),
            100.0 * mids.iter().map(|x| x.1).fold(0.0, f64::max),
            mids.iter().filter(|x| x.0 <= x.1 * 1.001).count(),
            mids.len()
        ));
    }
    md.push_str("\n## Corners\n\n| α | θ | ours L2 | shipped L2 |\n|---|---|---|---|\n");
    let n = ours.n;
    // r = 0 is left out: the shipped fit put α_min = 1e-5 there, ours the spec's 1e-4
    for (i, j) in [(1usize, 0usize), (1, n - 1), (n - 1, 0), (n - 1, n - 1)] {
        if let Some(c) = cmp.iter().find(|c| c.i == i && c.j == j) {
            md.push_str(&format!(
                "| {:.2e} | {:.2}° | {:.2} % | {:.2} % |\n",
                c.alpha,
                c.theta_deg,
                100.0 * c.ours_l2,
                100.0 * c.shipped_l2
            ));
        }
    }
    // how much worse, under the relative L2 and under the cubic metric both fits minimise
    let ratio = |c: &CellCmp| c.ours_l2 / c.shipped_l2.max(1e-300);
    let cubic_worse = inner
        .iter()
        .filter(|c| c.ours_cubic > c.shipped_cubic * 1.001)
        .count();
    let worse1 = inner.iter().filter(|c| ratio(c) > 1.01).count();
    let worse5 = inner.iter().filter(|c| ratio(c) > 1.05).count();
    let better5 = inner.iter().filter(|c| ratio(c) < 1.0 / 1.05).count();
    md.push_str(&format!(
        "\nOurs worse in relative L2 by more than 0.1 %: {} cells; by more than 1 %: {worse1}; by more than 5 %: {worse5}. Ours better by more than 5 %: {better5}. Under the cubic metric (the one both fits minimise), ours worse by more than 0.1 % in {cubic_worse} of {} cells.\n\nWorst cells for ours (ratio ours/shipped, relative L2):\n",
        worse.len(),
        inner.len()
    ));
    let mut by_ratio: Vec<&&CellCmp> = worse.clone();
    by_ratio.sort_by(|a, b| ratio(b).total_cmp(&ratio(a)));
    for c in by_ratio.iter().take(15) {
        md.push_str(&format!(
            "- α = {:.3e}, θ = {:.2}°: ours {:.2} %, shipped {:.2} % (×{:.3}); cubic ours {:.3e}, shipped {:.3e}\n",
            c.alpha,
            c.theta_deg,
            100.0 * c.ours_l2,
            100.0 * c.shipped_l2,
            ratio(c),
            c.ours_cubic,
            c.shipped_cubic
        ));
    }
    crate::io::write_atomic(&out.join("ltc-compare.md"), md.as_bytes())?;
    crate::io::write_atomic(
        &out.join("ltc-compare.json"),
        serde_json::to_string(&serde_json::json!({"command": format!("cargo run --release -- ltc-compare --shipped {}", shipped_path.display()), "source": source, "norms": if norm_ours { "ours" } else { "shipped" }, "ours_table_mean_l2": ours_mean_l2(results)?, "cell_columns": ["i", "j", "alpha", "theta_deg", "ours_l2", "shipped_l2", "ours_cubic", "shipped_cubic"], "cells": cmp.iter().map(|c| [c.i as f64, c.j as f64, c.alpha, c.theta_deg, c.ours_l2, c.shipped_l2, c.ours_cubic, c.shipped_cubic].map(|x| format!("{x:.5e}").parse::<f64>().unwrap_or(x))).collect::<Vec<_>>()}))
            .expect("json")
            .as_bytes(),
    )?;
    Ok(format!(
        "wrote {}: ours no worse in {} of {} cells; mean L2 ours {:.2} % vs shipped {:.2} %",
        out.join("ltc-compare.md").display(),
        inner.len() - worse.len(),
        inner.len(),
        100.0 * mean(&|c| c.ours_l2),
        100.0 * mean(&|c| c.shipped_l2)
    ))
}

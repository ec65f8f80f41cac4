//! Comparison of our GGX LTC table with the widely shipped one:
//! selfshadow/ltc_code `fit/results/ltc.js`, also shipped by three.js as LTC_MAT_1 /
//! LTC_MAT_2 in RectAreaLightTexturesLib.js (index (r + n·t)·4 + c; LTC_MAT_1 holds the
//! production M⁻¹ (a, b, c, d), LTC_MAT_2 (norm, fresnel, …)). The file is read from the
//! path the user gives (`ltc-compare --shipped FILE`); nothing of it is committed.
//!
//! Both tables are judged against the true BRDF by the same held-out figures
//! (`ltc::lobe_error`: converged integrals with their error bars), per cell, at the same
//! (α = r², θ = acos(1 − t²)) with θ clamped to 89.99°. The shipped fit used α_min = 1e-5 at r = 0; ours uses the spec's α_min, so
//! the r = 0 row is reported separately.

use crate::error::{Error, Result};
use crate::ltc::fit::inverse_from_production;
use crate::ltc::lobe_error::{judge, LobeError, Tolerance};
use crate::ltc::target::{GgxTarget, LtcTarget};

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
    /// The one validation of a table read from outside (three.js's module, Bevy's KTX2, a
    /// selfshadow file): it must hold at least one cell whose matrix is finite, below 1e30
    /// and invertible, with a positive finite norm; `what` names the file in the error.
    pub fn check_comparable(&self, what: &str) -> Result<()> {
        let ok = self.mat.iter().zip(&self.mag).any(|(m, g)| {
            m.iter()
                .chain(&g[..1])
                .all(|v| v.is_finite() && v.abs() < 1e30)
                && (m[0] * m[3] - m[1] * m[2]).abs() > 0.0
                && g[0] > 0.0
        });
        if ok {
            Ok(())
        } else {
            Err(crate::error::Error::InvalidArgument(format!(
                "ltc-compare: {} has no cell that can be compared (no finite, invertible matrix with a positive norm); nothing written",
                crate::error::quoted(what)
            )))
        }
    }

    /// (production inverse, norm) of cell (r index i, t index j).
    pub fn cell(&self, i: usize, j: usize) -> ([f64; 4], f64) {
        let k = i + self.n * j;
        (self.mat[k], self.mag[k][0])
    }
}

/// The held-out error (`ltc::lobe_error`) of one production-form cell against the GGX
/// BRDF at (α, θ); `None` where the matrix is singular.
pub fn cell_error(inv: &[f64; 4], norm: f64, alpha: f64, theta: f64) -> Result<Option<LobeError>> {
    let t = GgxTarget::new(alpha, theta)?;
    let (albedo, _, _) = t.albedo(1e-8);
    Ok(cell_error_of(&t, albedo, &[(*inv, norm)], Tolerance::default())[0])
}

/// The held-out errors of production-form entries (a, b, c, d) with amplitudes against
/// any target whose integral is ≈ `albedo`, judged in one cubature to `tol`.
pub fn cell_error_of<T: LtcTarget + ?Sized>(
    t: &T,
    albedo: f64,
    entries: &[([f64; 4], f64)],
    tol: Tolerance,
) -> Vec<Option<LobeError>> {
    let inv: Vec<_> = entries
        .iter()
        .map(|(p, amp)| (inverse_from_production(p), *amp))
        .collect();
    judge(t, albedo, &inv, tol)
}

/// The entries a shader reads at the centre of the square with corners (i, j) and
/// (i + 1, j + 1) of a table: both textures interpolated bilinearly (each corner ¼).
/// `None` when the square is outside the table or a corner is missing (NaN).
pub fn square_entries(t: &Shipped, i: usize, j: usize) -> Option<([f64; 4], f64)> {
    let n = t.n;
    if i + 1 >= n || j + 1 >= n {
        return None;
    }
    let ks = [
        i + n * j,
        i + 1 + n * j,
        i + n * (j + 1),
        i + 1 + n * (j + 1),
    ];
    if ks.iter().any(|&k| {
        t.mat[k]
            .iter()
            .chain(&t.mag[k][..1])
            .any(|v| !v.is_finite())
    }) {
        return None;
    }
    let inv: [f64; 4] = std::array::from_fn(|c| ks.iter().map(|&k| t.mat[k][c]).sum::<f64>() / 4.0);
    let norm = ks.iter().map(|&k| t.mag[k][0]).sum::<f64>() / 4.0;
    Some((inv, norm))
}

/// The error a shader sees between table cells: the table interpolated at the centre of
/// square (i, j) ([`square_entries`]), judged against `target(α, θ)` there (α =
/// max(r², `alpha_min`) as the table's cells are) with the table's interpolated norm;
/// with the lobe's albedo there, judged to `tol`. `None` when a corner is missing or the
/// interpolated matrix is singular.
pub fn midpoint_error_of<T: LtcTarget>(
    t: &Shipped,
    (i, j): (usize, usize),
    alpha_min: f64,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    tol: Tolerance,
) -> Result<(Option<LobeError>, f64)> {
    let (lobe, albedo) = square_lobe(t.n, (i, j), alpha_min, target)?;
    Ok((square_error_of(t, (i, j), &lobe, albedo, tol), albedo))
}

/// The first half of [`midpoint_error_of`]: the lobe at the centre of square (i, j) of an
/// `n`×`n` table (α = max(r², `alpha_min`)) and its albedo.
pub fn square_lobe<T: LtcTarget>(
    n: usize,
    (i, j): (usize, usize),
    alpha_min: f64,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
) -> Result<(T, f64)> {
    let (alpha, theta) = square_centre(n, (i, j), alpha_min);
    let lobe = target(alpha, theta)?;
    let (albedo, _, _) = lobe.albedo(1e-8);
    Ok((lobe, albedo))
}

/// (α, θ in radians) at the centre of square (i, j) of an `n`×`n` table in (r = √α,
/// t = √(1 − cos θ)), α = max(r², `alpha_min`).
pub fn square_centre(n: usize, (i, j): (usize, usize), alpha_min: f64) -> (f64, f64) {
    let r = (i as f64 + 0.5) / (n - 1) as f64;
    let tt = (j as f64 + 0.5) / (n - 1) as f64;
    (
        (r * r).max(alpha_min),
        (1.0 - tt * tt).clamp(0.0, 1.0).acos(),
    )
}

/// The second half of [`midpoint_error_of`]: the table interpolated at the centre of
/// square (i, j) judged against `lobe` (of albedo `albedo`) to `tol`.
pub fn square_error_of<T: LtcTarget>(
    t: &Shipped,
    (i, j): (usize, usize),
    lobe: &T,
    albedo: f64,
    tol: Tolerance,
) -> Option<LobeError> {
    let entries = square_entries(t, i, j)?;
    cell_error_of(lobe, albedo, &[entries], tol)[0]
}

/// The roughness and view of grid coordinates (r, t) in the shipped convention
/// (α = max(r², 1e-5), θ from t = √(1 − cos θ)).
pub fn alpha_theta(r: f64, t: f64) -> (f64, f64) {
    ((r * r).max(1e-5), (1.0 - t * t).clamp(0.0, 1.0).acos())
}

/// Our table as its binary16 files hold it, in the shipped layout.
pub fn stored_half(table: &super::table::FittedTable) -> Shipped {
    let cell = |k: usize| table.half_cell(k).map(|x| x.to_f64());
    Shipped {
        n: table.n,
        mat: (0..table.n * table.n)
            .map(|k| {
                let h = cell(k);
                [h[0], h[1], h[2], h[3]]
            })
            .collect(),
        mag: (0..table.n * table.n)
            .map(|k| {
                let h = cell(k);
                [h[4], h[5]]
            })
            .collect(),
    }
}

/// A fitted table in the shipped layout (f64 entries).
pub fn of_table(t: &super::table::FittedTable) -> Shipped {
    Shipped {
        n: t.n,
        mat: t.cells.iter().map(|c| [c[0], c[1], c[2], c[3]]).collect(),
        mag: t.cells.iter().map(|c| [c[4], c[5]]).collect(),
    }
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

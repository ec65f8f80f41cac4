//! results/fits/ltc-compact.json (on request): LTC tables as compact Chebyshev series
//! (`ltc::compact`), each judged by the exact held-out lobe error after rebuilding and
//! binary16 storage (the texture an engine's start-up code would fill) and as a
//! texture-free per-pixel form, beside the full table and the shipped one.

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::ltc::compact::Compact;
use crate::ltc::lobe_error::Spread;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The file.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LtcCompact {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    /// Every `every`-th cell and square along each axis was judged.
    pub every: usize,
    /// The held-out figures' relative tolerance.
    pub held_out_rel: f64,
    pub families: Vec<CompactFamily>,
}

impl super::ResultFile for LtcCompact {
    const NAME: &'static str = super::names::LTC_COMPACT;
}

/// One table's curve.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CompactFamily {
    /// The table's result file (results/fits/<table>.json).
    pub table: String,
    /// Its side n.
    pub n: usize,
    /// Its coefficients as stored (n² cells × 6 channels).
    pub full_coefficients: usize,
    /// The full table's stored binary16 entries at the judged places (bilinear at the
    /// squares).
    pub full: Judged,
    /// The shipped table at the same places (results/ltc-compare.json; GGX only, when
    /// that file exists): per engine path.
    pub shipped: Vec<ShippedPath>,
    pub forms: Vec<CompactForm>,
    /// The form the goal picks (the fewest coefficients meeting it), else `None`.
    pub chosen: Option<usize>,
    /// The chosen form's series, else the most accurate rebuild's.
    pub series: Compact,
    /// The form a shader with no texture runs: the lowest texture-free mean within the
    /// spec's coefficient budget (`texture_free_form`), with its series; `None` when no
    /// form is within the budget.
    #[serde(default)]
    pub texture_free: Option<TextureFree>,
    /// The polygon lights of the table's own study (its Monte Carlo truth), where that
    /// study has them (GGX, and both sheen tables from their study's report).
    #[serde(default)]
    pub polygons: Option<PolygonSet>,
    /// The fingerprint (`FittedTable::fingerprint`) of the table the family was fitted
    /// to, when the study ran: a table refitted since leaves this file, and the shaders
    /// and drop-ins written from it, stale (`None` in a file from before it was kept).
    #[serde(default)]
    pub table_fingerprint: Option<String>,
}

/// The polygon lights of results/fits/ltc-ggx.json (four cells × the quads of
/// `ltc::polygon::check_lights`, Monte Carlo truth ± s.e.) shaded through each form: the
/// form's (a, b, c, d, norm) at the cell's (α, θ), norm × the exact LTC integral.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PolygonSet {
    /// Per row: α, θ, the light, the truth.
    pub truth: Vec<(f64, f64, String, crate::integrate::Figure)>,
    /// The full table's stored binary16 entries, read bilinearly.
    pub full: PolygonFigures,
    /// Per form (in `forms`' order): rebuilt (binary16, bilinear) and texture-free (f32).
    pub rebuilt: Vec<PolygonFigures>,
    pub texture_free: Vec<PolygonFigures>,
}

/// One form over the polygon rows.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PolygonFigures {
    /// The shaded value per row.
    pub values: Vec<f64>,
    /// The mean over rows of (value − truth)², estimated without bias as the mean of
    /// (value − MC)² − s.e.², ± its standard error.
    pub mse: crate::integrate::Figure,
}

/// Held-out relative L2 over the judged cells and squares.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Judged {
    pub cells: Spread,
    pub squares: Spread,
}

/// The shipped table along one engine path, at the places judged.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ShippedPath {
    pub path: String,
    pub r_min: f64,
    pub shipped: Judged,
    /// The full table over the same places (those the path reaches).
    pub ours_full: Judged,
    /// The full table against the shipped one there: places better, tied, worse (beyond
    /// both bars).
    #[serde(default)]
    pub full_vs_shipped: [usize; 3],
}

/// One compact form (a transform set and a degree).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CompactForm {
    /// The transform set's name ("raw", "log").
    pub transforms: String,
    pub p: usize,
    pub coefficients: usize,
    /// Rebuilt at the texel centres, stored as the nearest binary16, read bilinearly.
    pub rebuilt: Judged,
    /// Evaluated per pixel in f32 at the place itself.
    pub texture_free: Judged,
    /// Places (cells + squares) where the rebuild is worse than the full table by more
    /// than both bars.
    pub rebuilt_worse_than_full: usize,
    /// Per shipped path (same order as `CompactFamily::shipped`): the places where the
    /// rebuild is better, tied, worse than the shipped table (beyond both bars).
    pub rebuilt_vs_shipped: Vec<[usize; 3]>,
    /// The largest |f32 form − f64 series| / max(|f64|, 1e-3) of any channel over a
    /// 257² grid of (r, t).
    pub f32_rel_error: f64,
    /// For a form refined by the lobe error (`ltc::compact_fit`): what that fit did.
    #[serde(default)]
    pub lobe_fit: Option<crate::ltc::compact_fit::Trace>,
}

/// A family's texture-free pick: the form's index in `forms` and its series.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TextureFree {
    pub form: usize,
    pub series: Compact,
}

/// The form a shader with no texture should run: among the forms of at most
/// `max_coefficients`, the lowest mean of the texture-free cells' and squares' means
/// (ties to the first); `None` when none is within the budget.
pub fn texture_free_form(forms: &[CompactForm], max_coefficients: usize) -> Option<usize> {
    let mean = |f: &CompactForm| {
        0.5 * (f.texture_free.cells.mean.value + f.texture_free.squares.mean.value)
    };
    (0..forms.len())
        .filter(|&k| forms[k].coefficients <= max_coefficients)
        .min_by(|&a, &b| mean(&forms[a]).total_cmp(&mean(&forms[b])))
}

/// The form a family's `series` holds: the chosen one, else the lowest rebuilt mean at
/// the cells (ties to the first).
pub fn series_form(forms: &[CompactForm], chosen: Option<usize>) -> Option<usize> {
    chosen.or_else(|| {
        (0..forms.len()).min_by(|&a, &b| {
            forms[a]
                .rebuilt
                .cells
                .mean
                .value
                .total_cmp(&forms[b].rebuilt.cells.mean.value)
        })
    })
}

/// The GGX family's series of results/fits/ltc-compact.json and its table side, or `None`
/// when the on-request study has not written that file (then there is no compact table to
/// generate code from or to judge). A series that fails its check, or a side outside
/// 2..=`MAX_SIDE`, is a typed error.
pub fn ggx_series(results: &Path) -> Result<Option<(Compact, usize)>> {
    let Some((r, path)) = read_file(results)? else {
        return Ok(None);
    };
    let f = r
        .families
        .into_iter()
        .find(|f| f.table == super::names::LTC_GGX)
        .ok_or_else(|| Error::InvalidArgument(format!("{}: no GGX family", path.display())))?;
    f.series.check()?;
    if !(2..=crate::ltc::table::MAX_SIDE).contains(&f.n) {
        return Err(Error::InvalidArgument(format!(
            "{}: a GGX table of side {} (2..={})",
            path.display(),
            f.n,
            crate::ltc::table::MAX_SIDE
        )));
    }
    Ok(Some((f.series, f.n)))
}

/// results/fits/ltc-compact.json and its path, or `None` when the on-request study has not
/// written it; a file that does not parse is a typed error naming it.
pub fn read_file(results: &Path) -> Result<Option<(LtcCompact, std::path::PathBuf)>> {
    let path = results.join("fits/ltc-compact.json");
    if !path.is_file() {
        return Ok(None);
    }
    let r: LtcCompact = super::require(results)
        .map_err(|e| Error::InvalidArgument(format!("{}: {e}", path.display())))?;
    Ok(Some((r, path)))
}

/// A family's texture-free pick of results/fits/ltc-compact.json: its series and a
/// description ("log, lobe-fit p = 12 (864 coefficients)"), or `None` when the file is
/// absent or was written before the study picked one. A family the file lacks, a pick
/// naming a form it does not hold, or a series that fails its check, is a typed error.
pub fn texture_free_series(results: &Path, table: &str) -> Result<Option<(Compact, String)>> {
    match read_file(results)? {
        Some((r, path)) => texture_free_in(&r, table, &path),
        None => Ok(None),
    }
}

/// [`texture_free_series`] from a file already read (`path` names it in errors).
pub fn texture_free_in(
    r: &LtcCompact,
    table: &str,
    path: &Path,
) -> Result<Option<(Compact, String)>> {
    let f = r
        .families
        .iter()
        .find(|f| f.table == table)
        .ok_or_else(|| Error::InvalidArgument(format!("{}: no {table} family", path.display())))?;
    let Some(tf) = &f.texture_free else {
        return Ok(None);
    };
    let form = f.forms.get(tf.form).ok_or_else(|| {
        Error::InvalidArgument(format!(
            "{}: {table}'s texture-free pick names form {} of {}",
            path.display(),
            tf.form,
            f.forms.len()
        ))
    })?;
    tf.series.check()?;
    if form.p != tf.series.p {
        return Err(Error::InvalidArgument(format!(
            "{}: {table}'s texture-free series has p = {}, its form p = {}",
            path.display(),
            tf.series.p,
            form.p
        )));
    }
    let desc = format!(
        "{} p = {} ({} coefficients)",
        form.transforms, form.p, form.coefficients
    );
    Ok(Some((tf.series.clone(), desc)))
}

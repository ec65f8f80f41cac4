//! `ltc-compare`: our GGX LTC table against the shipped one, as each engine uploads and
//! samples them (`ltc::upload`): three.js's FloatType and HalfFloatType textures (its
//! truncating `toHalfFloat`, roughness ≥ 0.045) and Bevy's `ltc.ktx2` (RGBA16F, the full
//! roughness range), at every texel centre ("cells") and every square centre (the
//! bilinear lookup halfway between four texels), each judged against the GGX BRDF by the
//! held-out integrals of `ltc::lobe_error` (relative L2 and L1 ± their error bars).
//! Compute ([`compare_all`]) → report ([`markdown`], [`heatmaps`]) → files ([`run`]).

mod compute;
mod render;

use compute::{compare_all, half_counts, norm_ratios, Tables};
pub use compute::{summaries, summarise, Form, FormSummary, Pair};

use crate::error::{Error, Result};
use crate::ltc::compare::{of_table, stored_half, Shipped};
use crate::ltc::lobe_error::Tolerance;
use crate::ltc::upload;
use render::{half_section, heatmaps, markdown, norms_section};
use std::path::Path;

pub use crate::results::compare::Summary;

/// Largest shipped-table file read.
pub const MAX_SHIPPED_BYTES: u64 = 16 << 20;

/// What `ltc-compare` reads.
pub struct Inputs<'a> {
    /// three.js's RectAreaLightTexturesLib.js (or any JS/JSON text with the two arrays).
    pub shipped: &'a Path,
    pub mat: &'a str,
    pub mag: &'a str,
    /// Our norms for both tables (compares the matrices only).
    pub norm_ours: bool,
    pub source: Option<&'a str>,
    /// Bevy's ltc.ktx2, when given.
    pub bevy: Option<&'a Path>,
}

fn read_capped(path: &Path, cap: u64) -> Result<Vec<u8>> {
    let io = |e: std::io::Error| Error::Io {
        path: path.display().to_string(),
        msg: e.to_string(),
    };
    let len = std::fs::metadata(path).map_err(io)?.len();
    if len > cap {
        return Err(Error::InvalidArgument(format!(
            "ltc-compare: {} is {len} bytes, over the {cap}-byte limit for a shipped table",
            crate::error::quoted(&path.display().to_string())
        )));
    }
    std::fs::read(path).map_err(io)
}

/// Run the comparison into `set` (`out`/ltc-compare.{md,json,svg}, ltc-compare-rows.svg);
/// returns a one-line summary.
pub fn run(
    set: &mut crate::io::Outputs,
    inp: &Inputs,
    results: &Path,
    out: &Path,
) -> Result<String> {
    let bytes = read_capped(inp.shipped, MAX_SHIPPED_BYTES)?;
    let text = String::from_utf8(bytes).map_err(|_| {
        Error::InvalidArgument(format!(
            "ltc-compare: {} is not UTF-8 text",
            crate::error::quoted(&inp.shipped.display().to_string())
        ))
    })?;
    let table = crate::results::ltc::table(results, crate::results::names::LTC_GGX)?;
    let ours = of_table(&table);
    let ours_f16 = stored_half(&table);
    let shipped = if inp.norm_ours {
        Shipped::parse_mat_with_norms(&text, inp.mat, &ours)?
    } else {
        Shipped::parse(&text, inp.mat, inp.mag)?
    };
    if shipped.n != ours.n {
        return Err(Error::InvalidArgument(format!(
            "ltc-compare: table sizes differ: ours {}×{}, shipped {}×{}",
            ours.n, ours.n, shipped.n, shipped.n
        )));
    }
    shipped.check_comparable(&inp.shipped.display().to_string())?;
    let bevy = match inp.bevy {
        Some(p) => {
            let b = upload::bevy_ktx2(&read_capped(p, upload::MAX_KTX2_BYTES as u64)?)?;
            b.check_comparable(&p.display().to_string())?;
            if b.n != ours.n {
                return Err(Error::InvalidArgument(format!(
                    "ltc-compare: Bevy's table is {}×{}, ours {}×{}",
                    b.n, b.n, ours.n, ours.n
                )));
            }
            Some(if inp.norm_ours {
                Shipped {
                    mag: ours.mag.clone(),
                    ..b
                }
            } else {
                b
            })
        }
        None => None,
    };
    let tables = Tables {
        ours_f32: upload::f32_table(&ours),
        ours_f16: ours_f16.clone(),
        three_f32: upload::f32_table(&shipped),
        three_f16: upload::three_half_table(&shipped),
        bevy,
    };
    let forms = compare_all(&tables)?;
    let n = ours.n;
    let sums = summaries(n, &forms);
    // the same after judging: a path on which no place could be judged is no comparison
    for (f, fs) in forms.iter().zip(&sums) {
        if fs.cells.count == 0 {
            return Err(Error::InvalidArgument(format!(
                "ltc-compare: on the {} path no cell of the two tables could be judged (no finite lobe with a positive norm on both sides); nothing written",
                f.name
            )));
        }
    }
    let command = format!(
        "cargo run --release -- ltc-compare --shipped {}{}",
        inp.shipped.display(),
        inp.bevy
            .map(|p| format!(" --bevy {}", p.display()))
            .unwrap_or_default()
    );
    let tol = Tolerance::default();
    let header = format!(
        "# Our GGX LTC table against the shipped one, as engines upload and sample them\n\nWritten by `{command}`. {}Both tables judged against the cosine-weighted GGX BRDF (height-correlated G2, F = 1) with {}, by the held-out integrals of `ltc::lobe_error` (each figure ± its error bar; tolerance {:e} relative or {:e} absolute). Grid convention of both: α = max(r², 1e-5) at texel (i, j), r = i/63, t = j/63 (the shipped grid's r = 0 column is α = 1e-5, and so is ours). Both engines sample at uv = (r, √(1 − N·V))·63/64 + 0.5/64 with bilinear filtering, so a texel centre reads one cell and a square's centre the mean of its four corners (both textures: the matrix and the norm); three.js clamps the perceptual roughness to ≥ {} before the lookup and never reads the first three columns, Bevy reads the whole table.\n\n",
        inp.source.map(|s| format!("Source of the file: {s}. ")).unwrap_or_default(),
        if inp.norm_ours { "our norms for both (only the fitted matrices differ)" } else { "each table's own norm" },
        tol.rel,
        tol.abs,
        upload::THREE_MIN_ROUGHNESS,
    );
    let mut md = markdown(n, &forms, &sums, &header);
    md.push_str(&half_section(&half_counts(
        &shipped,
        &tables.three_f16,
        tables.bevy.as_ref(),
    )));
    md.push_str(&norms_section(&norm_ratios(&ours, &shipped, &forms[0])));
    let (heat, rows) = heatmaps(n, &forms, &sums)?;
    let json = crate::results::compare::LtcCompare {
        command: command.clone(),
        source: inp.source.map(str::to_string),
        bevy_source: inp.bevy.map(|p| p.display().to_string()),
        norms: if inp.norm_ours {
            "ours"
        } else {
            "each table's own"
        }
        .into(),
        ours_table_mean_l2: crate::results::compare::ours_mean_l2(results)?,
        ours_table_fingerprint: Some(table.fingerprint()),
        convention: "α = max(r², 1e-5); uv = (r, t)·63/64 + 0.5/64, bilinear; three.js: r ≥ 0.045"
            .into(),
        summary: forms
            .iter()
            .zip(&sums)
            .flat_map(|(f, fs)| {
                [
                    (format!("{} cells", f.name), fs.cells.clone()),
                    (format!("{} squares", f.name), fs.squares.clone()),
                ]
            })
            .collect(),
        forms,
    };
    set.put(&out.join("ltc-compare.md"), md.as_bytes());
    set.put(&out.join("ltc-compare.svg"), heat.as_bytes());
    set.put(&out.join("ltc-compare-rows.svg"), rows.as_bytes());
    set.put(
        &out.join("ltc-compare.json"),
        serde_json::to_string(&json)
            .map_err(|e| Error::InvalidArgument(format!("ltc-compare: json: {e}")))?
            .as_bytes(),
    );
    let (c, s) = (&sums[0].cells, &sums[0].squares);
    Ok(format!(
        "wrote {}: three.js FloatType cells: ours better in {}, worse in {} of {}, mean rel. L2 ours {} vs shipped {}; squares: better in {}, worse in {} of {}, mean {} vs {}",
        out.join("ltc-compare.md").display(),
        c.ours_better,
        c.ours_worse,
        c.count,
        c.ours_l2.mean.pct(2),
        c.shipped_l2.mean.pct(2),
        s.ours_better,
        s.ours_worse,
        s.count,
        s.ours_l2.mean.pct(2),
        s.shipped_l2.mean.pct(2)
    ))
}

//! `ltc-compare`: our GGX LTC table against the shipped one, as each engine uploads and
//! samples them (`ltc::upload`): three.js's FloatType and HalfFloatType textures (its
//! truncating `toHalfFloat`, roughness ≥ 0.045) and Bevy's `ltc.ktx2` (RGBA16F, the full
//! roughness range), at every texel centre ("cells") and every square centre (the
//! bilinear lookup halfway between four texels), each judged against the GGX BRDF by the
//! held-out integrals of `ltc::lobe_error` (relative L2 and L1 ± their error bars).
//! Compute ([`compare_all`]) → report ([`markdown`], [`heatmaps`]) → files ([`run`]).

use super::compare::{cell_error_of, square_entries, Shipped};
use super::compare_render::{half_section, heatmaps, markdown, norms_section};
use super::lobe_error::{Bounded, LobeError, Spread};
use super::upload;
use crate::error::{Error, Result};
use crate::ltc::target::{GgxTarget, LtcTarget};
use serde::Serialize;
use std::path::Path;

/// Both tables' held-out figures at one place (`None` where a table is singular there or
/// leaves it out).
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize)]
pub struct Pair {
    pub ours: Option<LobeError>,
    pub shipped: Option<LobeError>,
    /// The relative L2 as earlier versions estimated it (48² + 48² stratified samples,
    /// a biased ratio of sums; NaN where not judged), kept to say what changed.
    pub ours_sampled: f64,
    pub shipped_sampled: f64,
}

/// One way an engine uploads both tables, judged at its reachable places.
#[derive(Clone, Debug, Serialize)]
pub struct Form {
    pub name: &'static str,
    /// What the engine's path holds: ours / the shipped table.
    pub holds: &'static str,
    /// The smallest perceptual roughness its shader reads.
    pub r_min: f64,
    /// cells[i + n·j]
    pub cells: Vec<Pair>,
    /// squares[i + (n − 1)·j]: the square with corners (i, j) and (i + 1, j + 1)
    pub squares: Vec<Pair>,
}

/// The roughness and view of grid coordinates (r, t) in the shipped convention
/// (α = max(r², 1e-5), θ from t = √(1 − cos θ)).
pub fn alpha_theta(r: f64, t: f64) -> (f64, f64) {
    ((r * r).max(1e-5), (1.0 - t * t).clamp(0.0, 1.0).acos())
}

/// The entries every table holds at one place (cell or square centre): the same place in
/// every table, `None` where a table leaves it out.
fn entries_at(t: &Shipped, square: bool, i: usize, j: usize) -> Option<([f64; 4], f64)> {
    if square {
        square_entries(t, i, j)
    } else {
        let k = i + t.n * j;
        let e = (t.mat[k], t.mag[k][0]);
        (e.0.iter().all(|v| v.is_finite()) && e.1.is_finite()).then_some(e)
    }
}

/// The tables an engine may hold, in the order of [`TABLES`].
struct Tables {
    ours_f32: Shipped,
    ours_f16: Shipped,
    three_f32: Shipped,
    three_f16: Shipped,
    bevy: Option<Shipped>,
}

/// The held-out figures of every table at a place, and the earlier sampled estimate.
type Judged = ([Option<LobeError>; 5], [f64; 5]);

/// Every place of every table, judged in one cubature per place.
fn judge_places(tables: &Tables, square: bool) -> Result<Vec<Judged>> {
    let n = tables.ours_f32.n;
    let w = if square { n - 1 } else { n };
    let off = if square { 0.5 } else { 0.0 };
    let list: [Option<&Shipped>; 5] = [
        Some(&tables.ours_f32),
        Some(&tables.ours_f16),
        Some(&tables.three_f32),
        Some(&tables.three_f16),
        tables.bevy.as_ref(),
    ];
    let label = format!(
        "ltc-compare {} {n}²",
        if square { "squares" } else { "cells" }
    );
    crate::memo::map(&label, w * w, |k| {
        let (i, j) = (k % w, k / w);
        let r = (i as f64 + off) / (n - 1) as f64;
        let (alpha, theta) = alpha_theta(r, (j as f64 + off) / (n - 1) as f64);
        let t = GgxTarget::new(alpha, theta)?;
        let (albedo, _, _) = t.albedo(1e-8);
        // three.js never reads below its roughness clamp
        let reachable = |q: usize| q < 2 || q == 4 || r >= upload::THREE_MIN_ROUGHNESS;
        let places: Vec<(usize, ([f64; 4], f64))> = list
            .iter()
            .enumerate()
            .filter(|(q, _)| reachable(*q))
            .filter_map(|(q, t)| t.and_then(|t| entries_at(t, square, i, j)).map(|e| (q, e)))
            .collect();
        let e = cell_error_of(
            &t,
            albedo,
            &places.iter().map(|(_, e)| *e).collect::<Vec<_>>(),
        );
        let mut out = [None; 5];
        let mut sampled = [f64::NAN; 5];
        for ((q, entries), e) in places.iter().zip(e) {
            out[*q] = e;
            sampled[*q] = crate::ltc::fit::production_metrics(&t, &entries.0, entries.1, 48, 0.25)
                .map_or(f64::NAN, |m| m.1);
        }
        Ok((out, sampled))
    })
}

/// Every cell and square of both tables in each engine's upload.
fn compare_all(tables: &Tables) -> Result<Vec<Form>> {
    crate::report::stage("ltc-compare: cells");
    let cells = judge_places(tables, false)?;
    crate::report::stage("ltc-compare: squares");
    let squares = judge_places(tables, true)?;
    let n = tables.ours_f32.n;
    let pick = |v: &[Judged], ours: usize, theirs: usize, r_min: f64, w: usize, off: f64| {
        v.iter()
            .enumerate()
            .map(|(k, (e, sm))| {
                let r = ((k % w) as f64 + off) / (n - 1) as f64;
                if r < r_min {
                    Pair {
                        ours: None,
                        shipped: None,
                        ours_sampled: f64::NAN,
                        shipped_sampled: f64::NAN,
                    }
                } else {
                    Pair {
                        ours: e[ours],
                        shipped: e[theirs],
                        ours_sampled: sm[ours],
                        shipped_sampled: sm[theirs],
                    }
                }
            })
            .collect::<Vec<_>>()
    };
    let mut forms = vec![
        Form {
            name: "three.js FloatType",
            holds: "ours: our table in f32 (ltc_ggx.js); shipped: LTC_MAT_1/2 as Float32Array",
            r_min: upload::THREE_MIN_ROUGHNESS,
            cells: pick(&cells, 0, 2, upload::THREE_MIN_ROUGHNESS, n, 0.0),
            squares: pick(&squares, 0, 2, upload::THREE_MIN_ROUGHNESS, n - 1, 0.5),
        },
        Form {
            name: "three.js HalfFloatType",
            holds: "ours: our stored binary16 table (ltc_ggx_*_f16.bin); shipped: DataUtils.toHalfFloat of LTC_MAT_1/2 (truncated)",
            r_min: upload::THREE_MIN_ROUGHNESS,
            cells: pick(&cells, 1, 3, upload::THREE_MIN_ROUGHNESS, n, 0.0),
            squares: pick(&squares, 1, 3, upload::THREE_MIN_ROUGHNESS, n - 1, 0.5),
        },
    ];
    if tables.bevy.is_some() {
        forms.push(Form {
            name: "Bevy ltc.ktx2",
            holds: "ours: our stored binary16 table (ltc_ggx.ktx2); shipped: bevy_pbr's embedded ltc.ktx2 (RGBA16F, zstd)",
            r_min: 0.0,
            cells: pick(&cells, 1, 4, 0.0, n, 0.0),
            squares: pick(&squares, 1, 4, 0.0, n - 1, 0.5),
        });
    }
    Ok(forms)
}

pub use crate::results::compare::Summary;

pub(super) fn worse(a: &Bounded, b: &Bounded) -> bool {
    a.value - a.error > b.value + b.error
}

pub fn summarise<'a>(v: impl Iterator<Item = &'a Pair>) -> Summary {
    let pairs: Vec<&Pair> = v
        .filter(|p| p.ours.is_some() && p.shipped.is_some())
        .collect();
    let both: Vec<(&LobeError, &LobeError)> = pairs
        .iter()
        .filter_map(|p| Some((p.ours.as_ref()?, p.shipped.as_ref()?)))
        .collect();
    let sampled: Vec<(f64, f64)> = pairs
        .iter()
        .map(|p| (p.ours_sampled, p.shipped_sampled))
        .filter(|x| x.0.is_finite() && x.1.is_finite())
        .collect();
    let ms = sampled.len().max(1) as f64;
    Summary {
        count: both.len(),
        ours_l2: Spread::of(both.iter().map(|p| Some(&p.0.l2))),
        shipped_l2: Spread::of(both.iter().map(|p| Some(&p.1.l2))),
        ours_l1: Spread::of(both.iter().map(|p| Some(&p.0.l1))),
        shipped_l1: Spread::of(both.iter().map(|p| Some(&p.1.l1))),
        ours_better: both.iter().filter(|p| worse(&p.1.l2, &p.0.l2)).count(),
        ours_worse: both.iter().filter(|p| worse(&p.0.l2, &p.1.l2)).count(),
        sampled_ours_mean: sampled.iter().map(|x| x.0).sum::<f64>() / ms,
        sampled_shipped_mean: sampled.iter().map(|x| x.1).sum::<f64>() / ms,
        sampled_no_worse: sampled.iter().filter(|x| x.0 <= x.1 * 1.001).count(),
    }
}

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

/// Run the comparison and write `out`/ltc-compare.{md,json,svg} and ltc-compare-rows.svg;
/// returns a one-line summary.
pub fn run(inp: &Inputs, results: &Path, out: &Path) -> Result<String> {
    let bytes = read_capped(inp.shipped, MAX_SHIPPED_BYTES)?;
    let text = String::from_utf8(bytes).map_err(|_| {
        Error::InvalidArgument(format!(
            "ltc-compare: {} is not UTF-8 text",
            crate::error::quoted(&inp.shipped.display().to_string())
        ))
    })?;
    let table = crate::results::ltc::table(results, crate::results::names::LTC_GGX)?;
    let ours = super::compare::of_table(&table);
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
    // the same after judging: a path on which no place could be judged is no comparison
    for f in &forms {
        if summarise(f.cells.iter()).count == 0 {
            return Err(Error::InvalidArgument(format!(
                "ltc-compare: on the {} path no cell of the two tables could be judged (no finite lobe with a positive norm on both sides); nothing written",
                f.name
            )));
        }
    }
    let n = ours.n;
    let command = format!(
        "cargo run --release -- ltc-compare --shipped {}{}",
        inp.shipped.display(),
        inp.bevy
            .map(|p| format!(" --bevy {}", p.display()))
            .unwrap_or_default()
    );
    let tol = super::lobe_error::Tolerance::default();
    let header = format!(
        "# Our GGX LTC table against the shipped one, as engines upload and sample them\n\nWritten by `{command}`. {}Both tables judged against the cosine-weighted GGX BRDF (height-correlated G2, F = 1) with {}, by the held-out integrals of `ltc::lobe_error` (each figure ± its error bar; tolerance {:e} relative or {:e} absolute). Grid convention of both: α = max(r², 1e-5) at texel (i, j), r = i/63, t = j/63 (the shipped grid's r = 0 column is α = 1e-5, and so is ours). Both engines sample at uv = (r, √(1 − N·V))·63/64 + 0.5/64 with bilinear filtering, so a texel centre reads one cell and a square's centre the mean of its four corners (both textures: the matrix and the norm); three.js clamps the perceptual roughness to ≥ {} before the lookup and never reads the first three columns, Bevy reads the whole table.\n\n",
        inp.source.map(|s| format!("Source of the file: {s}. ")).unwrap_or_default(),
        if inp.norm_ours { "our norms for both (only the fitted matrices differ)" } else { "each table's own norm" },
        tol.rel,
        tol.abs,
        upload::THREE_MIN_ROUGHNESS,
    );
    let mut md = markdown(n, &forms, &header);
    md.push_str(&half_section(
        &shipped,
        &tables.three_f16,
        tables.bevy.as_ref(),
    ));
    md.push_str(&norms_section(&ours, &shipped, &forms[0]));
    let (heat, rows) = heatmaps(n, &forms)?;
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
        convention: "α = max(r², 1e-5); uv = (r, t)·63/64 + 0.5/64, bilinear; three.js: r ≥ 0.045"
            .into(),
        summary: forms
            .iter()
            .flat_map(|f| {
                [
                    (format!("{} cells", f.name), summarise(f.cells.iter())),
                    (format!("{} squares", f.name), summarise(f.squares.iter())),
                ]
            })
            .collect(),
        forms: &forms,
    };
    crate::io::write_atomic(&out.join("ltc-compare.md"), md.as_bytes())?;
    crate::io::write_atomic(&out.join("ltc-compare.svg"), heat.as_bytes())?;
    crate::io::write_atomic(&out.join("ltc-compare-rows.svg"), rows.as_bytes())?;
    crate::io::write_atomic(
        &out.join("ltc-compare.json"),
        serde_json::to_string(&json)
            .map_err(|e| Error::InvalidArgument(format!("ltc-compare: json: {e}")))?
            .as_bytes(),
    )?;
    let c = summarise(forms[0].cells.iter());
    let s = summarise(forms[0].squares.iter());
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

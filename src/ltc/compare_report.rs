//! `ltc-compare`: our GGX LTC table against the shipped one, as each engine uploads and
//! samples them (`ltc::upload`): three.js's FloatType and HalfFloatType textures (its
//! truncating `toHalfFloat`, roughness ≥ 0.045) and Bevy's `ltc.ktx2` (RGBA16F, the full
//! roughness range), at every texel centre ("cells") and every square centre (the
//! bilinear lookup halfway between four texels), each judged against the GGX BRDF by the
//! held-out integrals of `ltc::lobe_error` (relative L2 and L1 ± their error bars).
//! Compute ([`compare_all`]) → report ([`markdown`], [`heatmaps`]) → files ([`run`]).

use super::compare::{cell_error_of, square_entries, Shipped};
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

/// Every place of every table, judged in one cubature per place.
fn judge_places(tables: &Tables, square: bool) -> Result<Vec<[Option<LobeError>; 5]>> {
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
        for ((q, _), e) in places.iter().zip(e) {
            out[*q] = e;
        }
        Ok(out)
    })
}

/// Every cell and square of both tables in each engine's upload.
fn compare_all(tables: &Tables) -> Result<Vec<Form>> {
    crate::report::stage("ltc-compare: cells");
    let cells = judge_places(tables, false)?;
    crate::report::stage("ltc-compare: squares");
    let squares = judge_places(tables, true)?;
    let n = tables.ours_f32.n;
    let pick = |v: &[[Option<LobeError>; 5]],
                ours: usize,
                theirs: usize,
                r_min: f64,
                w: usize,
                off: f64| {
        v.iter()
            .enumerate()
            .map(|(k, e)| {
                let r = ((k % w) as f64 + off) / (n - 1) as f64;
                if r < r_min {
                    Pair {
                        ours: None,
                        shipped: None,
                    }
                } else {
                    Pair {
                        ours: e[ours],
                        shipped: e[theirs],
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

/// Over the places where both tables are judged: each figure's spread, and how many
/// places ours is better, tied or worse by more than both error bars.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Summary {
    pub count: usize,
    pub ours_l2: Spread,
    pub shipped_l2: Spread,
    pub ours_l1: Spread,
    pub shipped_l1: Spread,
    /// Places where ours is lower by more than the two error bars together (relative L2).
    pub ours_better: usize,
    /// Places where ours is higher by more than the two error bars together.
    pub ours_worse: usize,
}

fn worse(a: &Bounded, b: &Bounded) -> bool {
    a.value - a.error > b.value + b.error
}

pub fn summarise<'a>(v: impl Iterator<Item = &'a Pair>) -> Summary {
    let both: Vec<(&LobeError, &LobeError)> = v
        .filter_map(|p| Some((p.ours.as_ref()?, p.shipped.as_ref()?)))
        .collect();
    Summary {
        count: both.len(),
        ours_l2: Spread::of(both.iter().map(|p| Some(&p.0.l2))),
        shipped_l2: Spread::of(both.iter().map(|p| Some(&p.1.l2))),
        ours_l1: Spread::of(both.iter().map(|p| Some(&p.0.l1))),
        shipped_l1: Spread::of(both.iter().map(|p| Some(&p.1.l1))),
        ours_better: both.iter().filter(|p| worse(&p.1.l2, &p.0.l2)).count(),
        ours_worse: both.iter().filter(|p| worse(&p.0.l2, &p.1.l2)).count(),
    }
}

/// The markdown report.
pub fn markdown(n: usize, forms: &[Form], header: &str) -> String {
    let mut md = header.to_string();
    md.push_str("## Summary\n\nRelative L2 ‖f − norm·γ_M‖/‖f‖ and relative L1 ∫|f − norm·γ_M|/∫f of each table as the engine holds it, mean over the places the engine reaches, ± the mean error bar; \"better\" and \"worse\" count the places where the two tables' relative L2 differ by more than their two error bars together (the rest are tied).\n\n| engine path | where | count | ours: rel. L2 | shipped: rel. L2 | ours: rel. L1 | shipped: rel. L1 | ours better / tied / worse | rows t ≥ 56: ours L2 | rows t ≥ 56: shipped L2 |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for f in forms {
        for (what, v, w) in [
            ("cells", &f.cells, n),
            ("squares (bilinear)", &f.squares, n - 1),
        ] {
            let s = summarise(v.iter());
            let g = summarise(
                v.iter()
                    .enumerate()
                    .filter(|(k, _)| 63 * (k / w) >= 56 * (n - 1))
                    .map(|x| x.1),
            );
            md.push_str(&format!(
                "| {} | {what} | {} | {} | {} | {} | {} | {} / {} / {} | {} | {} |\n",
                f.name,
                s.count,
                s.ours_l2.mean.pct(2),
                s.shipped_l2.mean.pct(2),
                s.ours_l1.mean.pct(2),
                s.shipped_l1.mean.pct(2),
                s.ours_better,
                s.count - s.ours_better - s.ours_worse,
                s.ours_worse,
                g.ours_l2.mean.pct(2),
                g.shipped_l2.mean.pct(2)
            ));
        }
    }
    md.push_str("\nWhat each path holds:\n\n");
    for f in forms {
        md.push_str(&format!(
            "- **{}** (perceptual roughness ≥ {}): {}.\n",
            f.name, f.r_min, f.holds
        ));
    }
    md.push_str("\nHeat maps (three.js FloatType cells; r = √α across, t = √(1 − cos θ) down, normal incidence at the top; grey: not reached): ![compare](ltc-compare.svg) Mean relative L2 per view row: ![rows](ltc-compare-rows.svg)\n\n");
    // per row, every path's cells
    md.push_str("## Per row j (view; t = j/63), cells, relative L2\n\n| j |");
    for f in forms {
        md.push_str(&format!(" {} ours | {} shipped |", f.name, f.name));
    }
    md.push_str("\n|---|");
    for _ in forms {
        md.push_str("---|---|");
    }
    md.push('\n');
    for j in 0..n {
        md.push_str(&format!("| {j} |"));
        for f in forms {
            let s = summarise(f.cells[n * j..n * (j + 1)].iter());
            md.push_str(&format!(
                " {} | {} |",
                s.ours_l2.mean.pct(2),
                s.shipped_l2.mean.pct(2)
            ));
        }
        md.push('\n');
    }
    md.push('\n');
    for f in forms {
        for (what, v, w) in [("cells", &f.cells, n), ("squares", &f.squares, n - 1)] {
            let mut bad: Vec<(usize, &LobeError, &LobeError)> = v
                .iter()
                .enumerate()
                .filter_map(|(k, p)| Some((k, p.ours.as_ref()?, p.shipped.as_ref()?)))
                .filter(|(_, o, s)| worse(&o.l2, &s.l2))
                .collect();
            bad.sort_by(|a, b| {
                (b.1.l2.value / b.2.l2.value.max(1e-300))
                    .total_cmp(&(a.1.l2.value / a.2.l2.value.max(1e-300)))
            });
            md.push_str(&format!("## Worst {what} for ours, {} (ratio ours/shipped of the relative L2; {} places worse beyond the error bars)\n\n| i | j | α | θ | ours | shipped | ratio |\n|---|---|---|---|---|---|---|\n", f.name, bad.len()));
            let off = if what == "cells" { 0.0 } else { 0.5 };
            for (k, o, s) in bad.iter().take(12) {
                let (i, j) = (k % w, k / w);
                let (al, th) = alpha_theta(
                    (i as f64 + off) / (n - 1) as f64,
                    (j as f64 + off) / (n - 1) as f64,
                );
                md.push_str(&format!(
                    "| {i} | {j} | {al:.3e} | {:.2}° | {} | {} | ×{:.3} |\n",
                    th.to_degrees(),
                    o.l2.pct(2),
                    s.l2.pct(2),
                    o.l2.value / s.l2.value
                ));
            }
            md.push('\n');
        }
    }
    md
}

/// The shipped norms against our albedo (by quadrature, error ≤ 1e-9): over the table,
/// and at the cells where the shipped table is better.
pub fn norms_section(ours: &Shipped, shipped: &Shipped, f32_cells: &Form) -> String {
    let ratio = |k: usize| shipped.mag[k][0] / ours.mag[k][0];
    let all: Vec<f64> = (0..ours.mat.len())
        .map(ratio)
        .filter(|r| r.is_finite())
        .collect();
    let better: Vec<usize> = f32_cells
        .cells
        .iter()
        .enumerate()
        .filter(|(_, p)| match (&p.ours, &p.shipped) {
            (Some(o), Some(s)) => worse(&o.l2, &s.l2),
            _ => false,
        })
        .map(|(k, _)| k)
        .collect();
    let worse_r: Vec<f64> = better
        .iter()
        .map(|&k| ratio(k))
        .filter(|r| r.is_finite())
        .collect();
    let stats = |v: &[f64]| {
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        let med = s.get(s.len() / 2).copied().unwrap_or(f64::NAN);
        let mean_abs = v.iter().map(|r| (r - 1.0).abs()).sum::<f64>() / v.len().max(1) as f64;
        (
            s.first().copied().unwrap_or(f64::NAN),
            med,
            s.last().copied().unwrap_or(f64::NAN),
            mean_abs,
            v.iter().filter(|r| **r < 1.0).count(),
        )
    };
    let (a0, a1, a2, a3, _) = stats(&all);
    let (w0, w1, w2, w3, wl) = stats(&worse_r);
    format!(
        "## The shipped norms against the albedo

The norm channel is the lobe's energy: a light covering the whole hemisphere returns exactly it. Ours is the albedo by quadrature (error ≤ 1e-9). Shipped norm / albedo over all {} cells: min {a0:.4}, median {a1:.4}, max {a2:.4}, mean |ratio − 1| = {:.2} %. At the {} cells where the shipped table is better beyond the error bars (three.js FloatType): min {w0:.4}, median {w1:.4}, max {w2:.4}, mean |ratio − 1| = {:.2} %; {wl} of them carry less energy than the BRDF: a lower norm lowers the L2 error of a lobe shape that cannot follow the BRDF's tail (results/ltc.md, the floor with an L2-optimal amplitude), and ours keeps the energy exact.\n\n",
        all.len(),
        100.0 * a3,
        worse_r.len(),
        100.0 * w3,
    )
}

/// How three.js's and Bevy's binary16 tables relate to round-to-nearest of the shipped
/// numbers.
fn half_section(shipped: &Shipped, three_f16: &Shipped, bevy: Option<&Shipped>) -> String {
    let values = |t: &Shipped| -> Vec<f64> { t.mat.iter().flatten().copied().collect::<Vec<_>>() };
    let src = values(shipped);
    let nearest: Vec<f64> = src
        .iter()
        .map(|x| half::f16::from_f64(*x).to_f64())
        .collect();
    let three = values(three_f16);
    let below = three.iter().zip(&nearest).filter(|(a, b)| a != b).count();
    let mut md = format!(
        "## Which binary16 table\n\n\"The shipped table in f16\" is two tables. three.js's `DataUtils.toHalfFloat` truncates: {below} of the {} numbers of LTC_MAT_1 sit one binary16 step below round-to-nearest (toward zero). ",
        src.len()
    );
    match bevy {
        Some(b) => {
            let bv = values(b);
            let same_nearest = bv.iter().zip(&nearest).filter(|(a, b)| a == b).count();
            let same_three = bv.iter().zip(&three).filter(|(a, b)| a == b).count();
            md.push_str(&format!(
                "Bevy's embedded ltc.ktx2 holds {same_nearest} of its {} matrix values equal to round-to-nearest of the same numbers and {same_three} equal to three.js's truncation.\n\n",
                bv.len()
            ));
        }
        None => {
            md.push_str("Bevy's ltc.ktx2 was not given (`--bevy`): its path is not compared.\n\n")
        }
    }
    md
}

/// ltc-compare.svg (ours, shipped, log10 ratio; three.js FloatType cells) and
/// ltc-compare-rows.svg.
pub fn heatmaps(n: usize, forms: &[Form]) -> Result<(String, String)> {
    use crate::report::plot::{heatmap_svg, loglog_svg, HeatPanel, Panel, Series};
    let x: Vec<f64> = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
    let l2 = |e: &Option<LobeError>| e.map_or(f64::NAN, |e| e.l2.value);
    let grid = |f: &dyn Fn(&Pair) -> f64| -> Vec<Vec<f64>> {
        (0..n)
            .map(|j| (0..n).map(|i| f(&forms[0].cells[i + n * j])).collect())
            .collect()
    };
    let panel = |title: &str, values: Vec<Vec<f64>>, range: (f64, f64), colour: &str| HeatPanel {
        title: title.into(),
        x: x.clone(),
        y: x.clone(),
        values,
        log_range: range,
        x_label: "r = √α".into(),
        y_label: "t = √(1 − cos θ)  (t = 0: normal incidence, top)".into(),
        log_axes: false,
        y_down: true,
        colour_label: colour.into(),
    };
    let heat = heatmap_svg(
        &[
            panel(
                "ours (f32)",
                grid(&|p| l2(&p.ours).max(1e-8)),
                (-4.0, 0.0),
                "log10 relative L2",
            ),
            panel(
                "shipped (f32)",
                grid(&|p| l2(&p.shipped).max(1e-8)),
                (-4.0, 0.0),
                "log10 relative L2",
            ),
            panel(
                "ours / shipped (below 0: ours better)",
                grid(&|p| l2(&p.ours) / l2(&p.shipped)),
                (-1.0, 1.0),
                "log10(ours / shipped)",
            ),
        ],
        1500,
        560,
    )?;
    let row = |f: &Form, ours: bool| Series {
        name: format!("{} {}", if ours { "ours" } else { "shipped" }, f.name),
        points: (1..n)
            .filter_map(|j| {
                let s = summarise(f.cells[n * j..n * (j + 1)].iter());
                let v = if ours { s.ours_l2 } else { s.shipped_l2 }.mean.value;
                v.is_finite()
                    .then_some((j as f64 / (n - 1) as f64, v.max(1e-6)))
            })
            .collect(),
    };
    let rows = loglog_svg(
        &[Panel {
            title: "mean relative L2 per view row (cells)".into(),
            x_label: "t = √(1 − cos θ)".into(),
            y_label: "mean relative L2".into(),
            series: forms
                .iter()
                .flat_map(|f| [row(f, true), row(f, false)])
                .collect(),
        }],
        900,
        560,
    )?;
    Ok((heat, rows))
}

/// results/ltc-compare.json.
#[derive(Serialize)]
struct CompareJson<'a> {
    command: String,
    source: Option<&'a str>,
    bevy_source: Option<String>,
    norms: &'static str,
    ours_table_mean_l2: f64,
    convention: &'static str,
    summary: Vec<(String, Summary)>,
    forms: &'a [Form],
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
    let table = super::table::read(results, crate::results::names::LTC_GGX)?;
    let ours = super::compare::of_table(&table);
    let ours_f16 = Shipped {
        n: table.n,
        mat: (0..table.n * table.n)
            .map(|k| {
                let h = table.half_cell(k);
                [h[0], h[1], h[2], h[3]].map(|x| x.to_f64())
            })
            .collect(),
        mag: (0..table.n * table.n)
            .map(|k| {
                let h = table.half_cell(k);
                [h[4], h[5]].map(|x| x.to_f64())
            })
            .collect(),
    };
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
    // a table with no cell whose matrix is finite and invertible cannot be compared
    let comparable = shipped.mat.iter().zip(&shipped.mag).any(|(m, g)| {
        m.iter()
            .chain(&g[..1])
            .all(|v| v.is_finite() && v.abs() < 1e30)
            && (m[0] * m[3] - m[1] * m[2]).abs() > 0.0
            && g[0] > 0.0
    });
    if !comparable {
        return Err(Error::InvalidArgument(format!(
            "ltc-compare: {} has no cell that can be compared (no finite, invertible matrix with a positive norm); nothing written",
            crate::error::quoted(&inp.shipped.display().to_string())
        )));
    }
    let bevy = match inp.bevy {
        Some(p) => {
            let b = upload::bevy_ktx2(&read_capped(p, upload::MAX_KTX2_BYTES as u64)?)?;
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
    let json = CompareJson {
        command: command.clone(),
        source: inp.source,
        bevy_source: inp.bevy.map(|p| p.display().to_string()),
        norms: if inp.norm_ours {
            "ours"
        } else {
            "each table's own"
        },
        ours_table_mean_l2: super::compare::ours_mean_l2(results)?,
        convention: "α = max(r², 1e-5); uv = (r, t)·63/64 + 0.5/64, bilinear; three.js: r ≥ 0.045",
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

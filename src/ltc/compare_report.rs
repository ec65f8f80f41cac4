//! `ltc-compare`: our GGX LTC table against a shipped one, as a shader samples them —
//! each table with its own norm, stored in f32 (three.js `FloatType`) and in f16
//! (three.js `HalfFloatType`, Bevy's RGBA16F KTX2: the shipped table rounded to nearest,
//! ours as stored), judged cell by cell and square by square (bilinear interpolation of
//! both textures at each square's centre), per row, per column, with the worst cells.
//! Compute ([`compare_all`]) → report ([`markdown`], [`heatmaps`]) → files ([`run`]).

use super::compare::{cell_error, Shipped};
use crate::error::{Error, Result};
use rayon::prelude::*;
use serde::Serialize;
use std::path::Path;

/// Relative L2 errors of the two tables at one place (NaN where a table leaves it out).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Pair {
    pub ours: f64,
    pub shipped: f64,
}

/// Both tables at one storage precision.
#[derive(Clone, Debug, Serialize)]
pub struct AtPrecision {
    pub precision: &'static str,
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

fn quantised(t: &Shipped, half: bool) -> Shipped {
    let q = |x: f64| {
        if half {
            half::f16::from_f64(x).to_f64()
        } else {
            x as f32 as f64
        }
    };
    Shipped {
        n: t.n,
        mat: t.mat.iter().map(|c| c.map(q)).collect(),
        mag: t.mag.iter().map(|c| c.map(q)).collect(),
    }
}

/// Relative L2 at the centre of square (i, j) of a table: both textures interpolated
/// bilinearly (the centre weighs each corner ¼), the table's own norm. NaN when a corner
/// is missing or the interpolated matrix is singular.
fn square_error(t: &Shipped, i: usize, j: usize, n_samples: usize) -> f64 {
    let n = t.n;
    let ks = [
        i + n * j,
        i + 1 + n * j,
        i + n * (j + 1),
        i + 1 + n * (j + 1),
    ];
    if ks
        .iter()
        .any(|&k| t.mat[k].iter().chain(&t.mag[k]).any(|v| !v.is_finite()))
    {
        return f64::NAN;
    }
    let inv: [f64; 4] = std::array::from_fn(|c| ks.iter().map(|&k| t.mat[k][c]).sum::<f64>() / 4.0);
    let norm = ks.iter().map(|&k| t.mag[k][0]).sum::<f64>() / 4.0;
    let (alpha, theta) = alpha_theta(
        (i as f64 + 0.5) / (n - 1) as f64,
        (j as f64 + 0.5) / (n - 1) as f64,
    );
    cell_error(&inv, norm, alpha, theta, n_samples)
        .map(|e| e.0)
        .unwrap_or(f64::NAN)
}

fn cell_l2(t: &Shipped, i: usize, j: usize, n_samples: usize) -> f64 {
    let k = i + t.n * j;
    if t.mat[k].iter().chain(&t.mag[k]).any(|v| !v.is_finite()) {
        return f64::NAN;
    }
    let (alpha, theta) = alpha_theta(i as f64 / (t.n - 1) as f64, j as f64 / (t.n - 1) as f64);
    cell_error(&t.mat[k], t.mag[k][0], alpha, theta, n_samples)
        .map(|e| e.0)
        .unwrap_or(f64::NAN)
}

fn pairs(
    ours: &Shipped,
    shipped: &Shipped,
    places: &[(usize, usize)],
    f: &(dyn Fn(&Shipped, usize, usize) -> f64 + Sync),
) -> Vec<Pair> {
    places
        .par_iter()
        .map(|&(i, j)| Pair {
            ours: f(ours, i, j),
            shipped: f(shipped, i, j),
        })
        .collect()
}

/// Every cell and square of both tables at f32 and f16. `ours_f16` is our stored
/// binary16 table; the shipped one is rounded to nearest (as three.js does).
pub fn compare_all(
    ours: &Shipped,
    ours_f16: &Shipped,
    shipped: &Shipped,
    n_samples: usize,
) -> Result<Vec<AtPrecision>> {
    if ours.n != shipped.n {
        return Err(Error::InvalidArgument(format!(
            "table sizes differ: ours {}×{}, shipped {}×{}",
            ours.n, ours.n, shipped.n, shipped.n
        )));
    }
    let n = ours.n;
    let cells: Vec<(usize, usize)> = (0..n * n).map(|k| (k % n, k / n)).collect();
    let squares: Vec<(usize, usize)> = (0..(n - 1) * (n - 1))
        .map(|k| (k % (n - 1), k / (n - 1)))
        .collect();
    let mut out = Vec::new();
    for (precision, o, s) in [
        ("f32", quantised(ours, false), quantised(shipped, false)),
        ("f16", ours_f16.clone(), quantised(shipped, true)),
    ] {
        crate::report::stage(&format!("ltc-compare: {precision} cells and squares"));
        out.push(AtPrecision {
            precision,
            cells: pairs(&o, &s, &cells, &|t, i, j| cell_l2(t, i, j, n_samples)),
            squares: pairs(&o, &s, &squares, &|t, i, j| {
                square_error(t, i, j, n_samples)
            }),
        });
    }
    Ok(out)
}

/// Mean, max and "ours no worse" (0.1 % slack) over the places where both are finite.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Summary {
    pub count: usize,
    pub ours_mean: f64,
    pub shipped_mean: f64,
    pub ours_max: f64,
    pub shipped_max: f64,
    pub ours_no_worse: usize,
}

pub fn summarise<'a>(v: impl Iterator<Item = &'a Pair>) -> Summary {
    let both: Vec<&Pair> = v
        .filter(|p| p.ours.is_finite() && p.shipped.is_finite())
        .collect();
    let m = both.len().max(1) as f64;
    Summary {
        count: both.len(),
        ours_mean: both.iter().map(|p| p.ours).sum::<f64>() / m,
        shipped_mean: both.iter().map(|p| p.shipped).sum::<f64>() / m,
        ours_max: both.iter().map(|p| p.ours).fold(0.0, f64::max),
        shipped_max: both.iter().map(|p| p.shipped).fold(0.0, f64::max),
        ours_no_worse: both.iter().filter(|p| p.ours <= p.shipped * 1.001).count(),
    }
}

fn pct(x: f64) -> String {
    format!("{:.2} %", 100.0 * x)
}

/// The markdown report.
pub fn markdown(n: usize, all: &[AtPrecision], header: &str) -> String {
    let mut md = header.to_string();
    md.push_str("## Summary (relative L2 ‖f − norm·γ_M‖/‖f‖ on held-out 48×48 + 48×48 sample sets)\n\n| precision | where | count | ours: mean | shipped: mean | ours: max | shipped: max | ours no worse (0.1 % slack) | rows t ≥ 56: ours | rows t ≥ 56: shipped |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for a in all {
        for (what, v, w) in [
            ("cells", &a.cells, n),
            ("squares (bilinear)", &a.squares, n - 1),
        ] {
            let s = summarise(v.iter());
            let g = summarise(
                v.iter()
                    .enumerate()
                    .filter(|(k, _)| k / w >= 56)
                    .map(|x| x.1),
            );
            md.push_str(&format!(
                "| {} | {what} | {} | {} | {} | {} | {} | {} of {} | {} | {} |\n",
                a.precision,
                s.count,
                pct(s.ours_mean),
                pct(s.shipped_mean),
                pct(s.ours_max),
                pct(s.shipped_max),
                s.ours_no_worse,
                s.count,
                pct(g.ours_mean),
                pct(g.shipped_mean)
            ));
        }
    }
    md.push_str("\nHeat maps (r = √α across, t = √(1 − cos θ) down, normal incidence at the top): ![compare](ltc-compare.svg) Mean error per row: ![rows](ltc-compare-rows.svg)\n\n");
    // per row and per column, f32 and f16 cells
    for (axis, label) in [
        (1usize, "row j (view; t = j/63)"),
        (0, "column i (roughness; r = i/63)"),
    ] {
        md.push_str(&format!("## Per {label}\n\n| index | f32 ours | f32 shipped | f32 ours no worse | f16 ours | f16 shipped | f16 ours no worse | squares f32 ours | squares f32 shipped |\n|---|---|---|---|---|---|---|---|---|\n"));
        for x in 0..n {
            let sel = |k: usize, w: usize| if axis == 1 { k / w == x } else { k % w == x };
            let line = |v: &[Pair], w: usize| {
                summarise(
                    v.iter()
                        .enumerate()
                        .filter(|(k, _)| x < w && sel(*k, w))
                        .map(|p| p.1),
                )
            };
            let (c32, c16, s32) = (
                line(&all[0].cells, n),
                line(&all[1].cells, n),
                line(&all[0].squares, n - 1),
            );
            md.push_str(&format!(
                "| {x} | {} | {} | {} of {} | {} | {} | {} of {} | {} | {} |\n",
                pct(c32.ours_mean),
                pct(c32.shipped_mean),
                c32.ours_no_worse,
                c32.count,
                pct(c16.ours_mean),
                pct(c16.shipped_mean),
                c16.ours_no_worse,
                c16.count,
                if s32.count > 0 {
                    pct(s32.ours_mean)
                } else {
                    "—".into()
                },
                if s32.count > 0 {
                    pct(s32.shipped_mean)
                } else {
                    "—".into()
                },
            ));
        }
        md.push('\n');
    }
    for a in all {
        for (what, v, w) in [("cells", &a.cells, n), ("squares", &a.squares, n - 1)] {
            let mut worst: Vec<(usize, &Pair)> = v
                .iter()
                .enumerate()
                .filter(|(_, p)| {
                    p.ours.is_finite() && p.shipped.is_finite() && p.ours > p.shipped * 1.001
                })
                .collect();
            worst.sort_by(|a, b| {
                (b.1.ours / b.1.shipped.max(1e-300))
                    .total_cmp(&(a.1.ours / a.1.shipped.max(1e-300)))
            });
            md.push_str(&format!("## Worst {what} for ours, {} (ratio ours/shipped; {} worse by more than 0.1 %)\n\n| i | j | α | θ | ours | shipped | ratio |\n|---|---|---|---|---|---|---|\n", a.precision, worst.len()));
            let off = if what == "cells" { 0.0 } else { 0.5 };
            for (k, p) in worst.iter().take(12) {
                let (i, j) = (k % w, k / w);
                let (al, th) = alpha_theta(
                    (i as f64 + off) / (n - 1) as f64,
                    (j as f64 + off) / (n - 1) as f64,
                );
                md.push_str(&format!(
                    "| {i} | {j} | {al:.3e} | {:.2}° | {} | {} | ×{:.3} |\n",
                    th.to_degrees(),
                    pct(p.ours),
                    pct(p.shipped),
                    p.ours / p.shipped
                ));
            }
            md.push('\n');
        }
    }
    md
}

/// The shipped norms against our albedo (by quadrature, error ≤ 1e-9): over the table,
/// and at the cells where the shipped table is better.
pub fn norms_section(ours: &Shipped, shipped: &Shipped, f32_cells: &AtPrecision) -> String {
    let ratio = |k: usize| shipped.mag[k][0] / ours.mag[k][0];
    let all: Vec<f64> = (0..ours.mat.len())
        .map(ratio)
        .filter(|r| r.is_finite())
        .collect();
    let worse: Vec<f64> = f32_cells
        .cells
        .iter()
        .enumerate()
        .filter(|(_, p)| p.ours.is_finite() && p.shipped.is_finite() && p.ours > p.shipped * 1.001)
        .map(|(k, _)| ratio(k))
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
    let (w0, w1, w2, w3, wl) = stats(&worse);
    // how much worse, at the worse cells whose norm is not below the albedo
    let mut others: Vec<f64> = f32_cells
        .cells
        .iter()
        .enumerate()
        .filter(|(k, p)| {
            p.ours.is_finite()
                && p.shipped.is_finite()
                && p.ours > p.shipped * 1.001
                && ratio(*k) >= 1.0
        })
        .map(|(_, p)| p.ours / p.shipped)
        .collect();
    others.sort_by(f64::total_cmp);
    let others_median = others.get(others.len() / 2).copied().unwrap_or(f64::NAN);
    format!(
        "## The shipped norms against the albedo

The norm channel is the lobe's energy: a light covering the whole hemisphere returns exactly it. Ours is the albedo by quadrature (error ≤ 1e-9; an independent Monte Carlo of the Schlick-weighted BRDF in tests/textures.rs agrees). Shipped norm / albedo over all {} cells: min {a0:.4}, median {a1:.4}, max {a2:.4}, mean |ratio − 1| = {:.2} %. At the {} cells where the shipped table is better (f32): min {w0:.4}, median {w1:.4}, max {w2:.4}, mean |ratio − 1| = {:.2} %. {wl} of them carry less energy than the BRDF: a lower norm lowers the L2 error of a lobe shape that cannot follow the BRDF's tail (results/ltc.md, the floor with an L2-optimal amplitude), and ours keeps the energy exact. At the other {} the shipped error is lower by a median factor ×{:.3} (ours/shipped).\n\n",
        all.len(),
        100.0 * a3,
        worse.len(),
        100.0 * w3,
        others.len(),
        others_median,
    )
}

/// ltc-compare.svg (ours, shipped, log10 ratio; f32 cells) and ltc-compare-rows.svg.
pub fn heatmaps(n: usize, all: &[AtPrecision]) -> Result<(String, String)> {
    use crate::report::plot::{heatmap_svg, loglog_svg, HeatPanel, Panel, Series};
    let x: Vec<f64> = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
    let grid = |f: &dyn Fn(&Pair) -> f64| -> Vec<Vec<f64>> {
        (0..n)
            .map(|j| (0..n).map(|i| f(&all[0].cells[i + n * j])).collect())
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
                grid(&|p| p.ours.max(1e-8)),
                (-4.0, 0.0),
                "log10 relative L2",
            ),
            panel(
                "shipped (f32)",
                grid(&|p| p.shipped.max(1e-8)),
                (-4.0, 0.0),
                "log10 relative L2",
            ),
            panel(
                "ours / shipped (below 0: ours better)",
                grid(&|p| p.ours / p.shipped),
                (-1.0, 1.0),
                "log10(ours / shipped)",
            ),
        ],
        1500,
        560,
    )?;
    let row = |a: &AtPrecision, ours: bool| Series {
        name: format!("{} {}", if ours { "ours" } else { "shipped" }, a.precision),
        points: (1..n)
            .map(|j| {
                let s = summarise(a.cells[n * j..n * (j + 1)].iter());
                (
                    j as f64 / (n - 1) as f64,
                    if ours { s.ours_mean } else { s.shipped_mean }.max(1e-6),
                )
            })
            .collect(),
    };
    let rows = loglog_svg(
        &[Panel {
            title: "mean relative L2 per view row (cells)".into(),
            x_label: "t = √(1 − cos θ)".into(),
            y_label: "mean relative L2".into(),
            series: vec![
                row(&all[0], true),
                row(&all[0], false),
                row(&all[1], true),
                row(&all[1], false),
            ],
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
    norms: &'static str,
    ours_table_mean_l2: f64,
    convention: &'static str,
    summary: Vec<(String, Summary)>,
    cell_columns: [&'static str; 6],
    cells: Vec<[f64; 6]>,
    square_columns: [&'static str; 6],
    squares: Vec<[f64; 6]>,
}

fn sig5(x: f64) -> f64 {
    format!("{x:.5e}").parse::<f64>().unwrap_or(x)
}

/// Largest shipped-table file read.
pub const MAX_SHIPPED_BYTES: u64 = 16 << 20;

/// Run the comparison and write `out`/ltc-compare.{md,json,svg} and ltc-compare-rows.svg;
/// returns a one-line summary.
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
    // three.js's RectAreaLightTexturesLib.js is ~0.3 MB; anything far larger is not a table
    let len = std::fs::metadata(shipped_path).map_err(io)?.len();
    if len > MAX_SHIPPED_BYTES {
        return Err(Error::InvalidArgument(format!(
            "ltc-compare: {} is {len} bytes, over the {MAX_SHIPPED_BYTES}-byte limit for a shipped table",
            shipped_path.display()
        )));
    }
    let text = std::fs::read_to_string(shipped_path).map_err(io)?;
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
    let shipped = if norm_ours {
        Shipped::parse_mat_with_norms(&text, mat, &ours)?
    } else {
        Shipped::parse(&text, mat, mag)?
    };
    if !shipped
        .mat
        .iter()
        .zip(&shipped.mag)
        .any(|(m, g)| m.iter().chain(g).all(|v| v.is_finite()))
    {
        return Err(Error::InvalidArgument(format!(
            "ltc-compare: {} has no cell that can be compared (every cell is NaN); nothing written",
            shipped_path.display()
        )));
    }
    let all = compare_all(&ours, &ours_f16, &shipped, 48)?;
    let n = ours.n;
    let command = format!(
        "cargo run --release -- ltc-compare --shipped {}",
        shipped_path.display()
    );
    let header = format!(
        "# Our GGX LTC table against the shipped one, as a shader samples them\n\nWritten by `{command}`. {}Both tables judged against the cosine-weighted GGX BRDF (height-correlated G2, F = 1) on the same held-out sample sets, with {}. Grid convention of both: α = max(r², 1e-5) (the shipped grid's r = 0 column is α = 1e-5, and so is ours). f32: both tables rounded to f32 (three.js `FloatType`). f16: the shipped table rounded to nearest binary16 (three.js `HalfFloatType`), ours as stored in its f16 files (results/textures/, `table_f16`). Squares: both textures interpolated bilinearly at the square's centre (the matrix and the norm), judged against the BRDF at the centre's (α, θ).\n\n",
        source.map(|s| format!("Source of the file: {s}. ")).unwrap_or_default(),
        if norm_ours { "our norms for both (only the fitted matrices differ)" } else { "each table's own norm" },
    );
    let mut md = markdown(n, &all, &header);
    md.push_str(&norms_section(&ours, &shipped, &all[0]));
    let (heat, rows) = heatmaps(n, &all)?;
    let row = |k: usize, w: usize, a: &Pair, b: &Pair| {
        [
            (k % w) as f64,
            (k / w) as f64,
            a.ours,
            a.shipped,
            b.ours,
            b.shipped,
        ]
        .map(sig5)
    };
    let json = CompareJson {
        command: command.clone(),
        source,
        norms: if norm_ours {
            "ours"
        } else {
            "each table's own"
        },
        ours_table_mean_l2: super::compare::ours_mean_l2(results)?,
        convention:
            "α = max(r², 1e-5); squares: bilinear interpolation of both textures at the centre",
        summary: all
            .iter()
            .flat_map(|a| {
                [
                    (format!("{} cells", a.precision), summarise(a.cells.iter())),
                    (
                        format!("{} squares", a.precision),
                        summarise(a.squares.iter()),
                    ),
                ]
            })
            .collect(),
        cell_columns: [
            "i",
            "j",
            "ours_f32",
            "shipped_f32",
            "ours_f16",
            "shipped_f16",
        ],
        cells: (0..n * n)
            .map(|k| row(k, n, &all[0].cells[k], &all[1].cells[k]))
            .collect(),
        square_columns: [
            "i",
            "j",
            "ours_f32",
            "shipped_f32",
            "ours_f16",
            "shipped_f16",
        ],
        squares: (0..(n - 1) * (n - 1))
            .map(|k| row(k, n - 1, &all[0].squares[k], &all[1].squares[k]))
            .collect(),
    };
    crate::io::write_atomic(&out.join("ltc-compare.md"), md.as_bytes())?;
    crate::io::write_atomic(&out.join("ltc-compare.svg"), heat.as_bytes())?;
    crate::io::write_atomic(&out.join("ltc-compare-rows.svg"), rows.as_bytes())?;
    crate::io::write_atomic(
        &out.join("ltc-compare.json"),
        serde_json::to_string(&serde_json::to_value(&json).expect("json"))
            .expect("json")
            .as_bytes(),
    )?;
    let c = summarise(all[0].cells.iter());
    let s = summarise(all[0].squares.iter());
    Ok(format!(
        "wrote {}: f32 cells: ours no worse in {} of {}, mean ours {} vs shipped {}; squares: ours no worse in {} of {}, mean {} vs {}",
        out.join("ltc-compare.md").display(),
        c.ours_no_worse,
        c.count,
        pct(c.ours_mean),
        pct(c.shipped_mean),
        s.ours_no_worse,
        s.count,
        pct(s.ours_mean),
        pct(s.shipped_mean)
    ))
}

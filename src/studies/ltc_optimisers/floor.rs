//! How far a single LTC per cell can go: the floor under the table's error. On a spread
//! of cells (the corners, every ninth row and column, and the grazing rows), a global
//! search — every combination of three offsets per fit parameter (`STEPS`) around the
//! table's solution, each fitted under the relative L2 and chosen by a validation set —
//! gives the best energy-exact LTC (norm = the albedo), and the L2-optimal amplitude
//! A* = ∫f·γ/∫γ² of that shape (on the training set) gives the floor when the norm may
//! trade energy for shape. Every error is the held-out figure of
//! `ltc::lobe_error` (converged integrals, ± their error bars).

use crate::error::Result;
use crate::integrate::mc::Strategy;
use crate::integrate::{Figure, Quad};
use crate::ltc::fit::{fit_cell, matrix, metrics, params_to_m, turn, Method, Metric};
use crate::ltc::lobe_error::{judge, Tolerance};
use crate::ltc::target::GgxTarget;
use crate::ltc::target::LtcTarget;
use crate::ltc::LtcDist;
use crate::report::table::Table as MdTable;

pub use crate::results::ltc::FloorCell;
use crate::results::ltc::Ggx;

/// One published cell: where it sits, its production inverse and its norm.
struct Published {
    alpha: f64,
    theta: f64,
    inv: [f64; 4],
    norm: f64,
}

/// The L2-optimal amplitude of an LTC shape against the target on the training set.
fn best_amplitude(t: &GgxTarget, ltc: &LtcDist, n: usize) -> f64 {
    let (mut fg, mut gg) = (0.0, 0.0);
    for a in 0..n {
        for b in 0..n {
            let u = [(a as f64 + 0.5) / n as f64, (b as f64 + 0.5) / n as f64];
            for l in [ltc.sample(u), t.sample(u)].into_iter().flatten() {
                let (f, pb) = t.eval(&l);
                let g = ltc.eval(&l);
                if g + pb > 0.0 {
                    fg += f * g / (g + pb);
                    gg += g * g / (g + pb);
                }
            }
        }
    }
    if gg > 0.0 {
        fg / gg
    } else {
        0.0
    }
}

fn floor_of(c: &Published, i: usize, j: usize, n: usize, max_iters: u64) -> Result<FloorCell> {
    let t = GgxTarget::new(c.alpha, c.theta)?;
    let (_, _, _, zm) = t.moments(32);
    // the fit parameters of the published lobe (its axis turned by φ from the mean
    // direction); a cell they cannot carry starts from the isotropic lobe of its α
    let (m11, m22, m13, phi) = crate::ltc::fit::params_from_production(&c.inv, &zm)
        .unwrap_or((c.alpha, c.alpha, 0.0, 0.0));
    let dist = |p: &[f64; 4]| {
        let (m11, m22, m13) = params_to_m(p);
        LtcDist::new(matrix(m11, m22, m13, &turn(&zm, p[3]))).ok()
    };
    let on = |p: &[f64; 4], norm: f64, k: usize, off: f64| {
        dist(p)
            .map(|l| metrics(&t, &l, norm, k, off).1)
            .filter(|x| x.is_finite())
            .unwrap_or(f64::INFINITY)
    };
    // the table's own lobe, straight from its production inverse (the fit parameters
    // cannot always carry it: a bilinear-pass cell may need m13/m11 beyond the fit's box)
    let table_ltc = crate::ltc::fit::inverse_from_production(&c.inv)
        .try_inverse()
        .and_then(|m| LtcDist::new(m).ok());
    let table_val = table_ltc
        .as_ref()
        .map(|l| metrics(&t, l, c.norm, n + 7, 0.37).1)
        .filter(|x| x.is_finite())
        .unwrap_or(f64::INFINITY);
    let base = [m11.ln(), m22.ln(), m13 / m11, phi];
    let mut best: (f64, Option<[f64; 4]>) = (table_val, None);
    for d0 in STEPS[0] {
        for d1 in STEPS[1] {
            for d2 in STEPS[2] {
                let s = [base[0] + d0, base[1] + d1, base[2] + d2, base[3]];
                let (q, _) = fit_cell(
                    &t,
                    &zm,
                    c.norm,
                    &s,
                    n,
                    Metric::L2,
                    Method::NelderMead,
                    max_iters,
                )?;
                let v = on(&q, c.norm, n + 7, 0.37);
                if v < best.0 {
                    best = (v, Some(q));
                }
            }
        }
    }
    let shape = match best.1 {
        Some(q) => dist(&q),
        None => table_ltc,
    };
    let amp = shape
        .as_ref()
        .map(|l| best_amplitude(&t, l, n))
        .unwrap_or(c.norm);
    let table_inv = crate::ltc::fit::inverse_from_production(&c.inv);
    let shape_inv = shape
        .as_ref()
        .and_then(|l| l.matrix().try_inverse())
        .unwrap_or(table_inv);
    let held = judge(
        &t,
        c.norm,
        &[(table_inv, c.norm), (shape_inv, c.norm), (shape_inv, amp)],
        Tolerance::default(),
    );
    let none = Figure::<Quad>::new(f64::INFINITY, f64::INFINITY);
    let l2 = |k: usize| held[k].map(|e| e.l2).unwrap_or(none);
    Ok(FloorCell {
        i,
        j,
        alpha: c.alpha,
        theta_deg: c.theta.to_degrees(),
        table: l2(0),
        global: l2(1),
        free_amplitude: l2(2),
        amplitude_over_albedo: amp / c.norm,
    })
}

/// The starts around the table's fit parameters: offsets of (ln m11, ln m22, m13/m11), every
/// combination.
const STEPS: [[f64; 3]; 3] = [[-1.0, 0.0, 1.0], [-1.5, 0.0, 1.0], [-0.5, 0.0, 0.5]];

/// The sampled columns and rows on a 64-wide grid (scaled to the table's), the rows
/// denser where the view grazes.
const COLS_64: [usize; 8] = [0, 9, 18, 27, 36, 45, 54, 63];
const ROWS_64: [usize; 9] = [0, 9, 18, 27, 36, 45, 56, 60, 63];

/// Whether row `j` of an `n`-row table is a grazing one: t ≥ 56/63.
fn grazing(j: usize, n: usize) -> bool {
    63 * j >= 56 * (n - 1)
}

/// The sampled cells: the columns and rows above, scaled to the grid.
pub(super) fn compute(ggx: &Ggx, n: usize, max_iters: u64) -> Result<Vec<FloorCell>> {
    let g = ggx.grid.n;
    let scale = |x: usize| (x * (g - 1) + 31) / 63;
    let mut cols: Vec<usize> = COLS_64.map(scale).to_vec();
    let mut rows: Vec<usize> = ROWS_64.map(scale).to_vec();
    cols.dedup();
    rows.dedup();
    let picks: Vec<(usize, usize)> = rows
        .iter()
        .flat_map(|&j| cols.iter().map(move |&i| (i, j)))
        .collect();
    crate::memo::map_items("ltc floor cells", &picks, |&(i, j)| {
        let e = ggx.table[j][i];
        let c = Published {
            alpha: ggx.grid.alpha(i),
            theta: ggx.grid.theta(j),
            inv: [e[0], e[1], e[2], e[3]],
            norm: e[4],
        };
        floor_of(&c, i, j, n, max_iters)
    })
}

/// The implied floors: the table's mean over all cells and over its grazing rows, and
/// the change of each search against the table (mean, s.e.) over the sampled cells.
pub(super) struct Summary {
    /// The sampled columns and rows, and the rows among them that graze.
    cols: Vec<usize>,
    rows: Vec<usize>,
    grazing_rows: Vec<usize>,
    /// Starts per cell.
    starts: usize,
    table_mean: f64,
    grazing_mean: f64,
    /// [global over all, free amplitude over all, global over grazing, free over grazing].
    changes: [Figure; 4],
    /// The largest error bar of any figure.
    bar: f64,
    /// The range of A*/albedo.
    amplitude: (f64, f64),
}

/// The implied floors of the table's mean (`table_mean`, its held-out relative L2) and
/// of its grazing rows.
pub(super) fn summarise(cells: &[FloorCell], ggx: &Ggx) -> Summary {
    let grid_n = ggx.grid.n;
    let table_mean = ggx.held_out.l2.mean.value;
    let grazing_rows = |j: usize| grazing(j, grid_n);
    let unique = |f: fn(&FloorCell) -> usize| {
        let mut v: Vec<usize> = cells.iter().map(f).collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    let rows = unique(|c| c.j);
    let grazing: Vec<f64> = ggx
        .held_out_cells
        .l2
        .iter()
        .enumerate()
        .filter(|(j, _)| grazing_rows(*j))
        .flat_map(|(_, col)| col.iter().flatten().map(|b| b[0]))
        .collect();
    let d = |f: &dyn Fn(&FloorCell) -> f64, only_graze: bool| {
        Figure::mean_of(
            &cells
                .iter()
                .filter(|c| !only_graze || grazing_rows(c.j))
                .map(|c| f(c) - c.table.value)
                .collect::<Vec<_>>(),
        )
    };
    Summary {
        cols: unique(|c| c.i),
        grazing_rows: rows.iter().copied().filter(|&j| grazing_rows(j)).collect(),
        rows,
        starts: STEPS.iter().map(|s| s.len()).product(),
        table_mean,
        grazing_mean: grazing.iter().sum::<f64>() / grazing.len().max(1) as f64,
        changes: [
            d(&|c| c.global.value, false),
            d(&|c| c.free_amplitude.value, false),
            d(&|c| c.global.value, true),
            d(&|c| c.free_amplitude.value, true),
        ],
        bar: cells
            .iter()
            .flat_map(|c| [c.table.error, c.global.error, c.free_amplitude.error])
            .fold(0.0, f64::max),
        amplitude: (
            cells
                .iter()
                .map(|c| c.amplitude_over_albedo)
                .fold(f64::INFINITY, f64::min),
            cells
                .iter()
                .map(|c| c.amplitude_over_albedo)
                .fold(0.0, f64::max),
        ),
    }
}

/// "0, 9, 18": a list of indices.
fn list(v: &[usize]) -> String {
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The markdown section: per sampled cell and the implied floors of the table's mean and
/// of its grazing rows.
pub(super) fn section(cells: &[FloorCell], s: &Summary) -> String {
    let (table_mean, grazing_mean, bar) = (s.table_mean, s.grazing_mean, s.bar);
    let [g_all, f_all, g_gr, f_gr] = s.changes;
    let mut md = format!(
        "## The floor of a single LTC per cell\n\nOn {} cells (columns {}; rows {}, the grazing ones {}), the table's own lobe and {} starts around its fit parameters, each fitted under the relative L2 (Nelder–Mead), the best chosen on a validation set; then the L2-optimal amplitude A* = ∫f·γ/∫γ² of that shape. Held-out relative L2 (converged integrals; the largest error bar of any figure below is {:.1e}, as a fraction), change against the table (mean ± s.e. over the sampled cells) and the floor it implies:\n\n",
        cells.len(),
        list(&s.cols),
        list(&s.rows),
        list(&s.grazing_rows),
        s.starts,
        bar,
    );
    let change = |d: Figure, base: f64| {
        format!("{} → {:.2} %", d.points_signed(2), 100.0 * (base + d.value))
    };
    let graze = format!(
        "rows t ≥ {}",
        s.grazing_rows.first().map_or("—".into(), |j| j.to_string())
    );
    let mut t = MdTable::new(["", "all cells", graze.as_str()]);
    t.row([
        "the table (energy-exact: norm = albedo)".to_string(),
        format!("{:.2} %", 100.0 * table_mean),
        format!("{:.2} %", 100.0 * grazing_mean),
    ]);
    t.row([
        format!("best of {} starts, norm = albedo", s.starts),
        change(g_all, table_mean),
        change(g_gr, grazing_mean),
    ]);
    t.row([
        "that shape with the L2-optimal amplitude".to_string(),
        change(f_all, table_mean),
        change(f_gr, grazing_mean),
    ]);
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\nA*/albedo over the sampled cells: {:.3} … {:.3} (the energy an L2-optimal norm gives away).\n\n",
        s.amplitude.0, s.amplitude.1,
    ));
    let starts = format!("{} starts", s.starts);
    let mut t = MdTable::new([
        "i",
        "j",
        "α",
        "θ",
        "table",
        starts.as_str(),
        "+ L2-optimal amplitude",
        "A*/albedo",
    ]);
    for c in cells {
        t.row([
            c.i.to_string(),
            c.j.to_string(),
            format!("{:.2e}", c.alpha),
            format!("{:.1}°", c.theta_deg),
            c.table.pct(2),
            c.global.pct(2),
            c.free_amplitude.pct(2),
            format!("{:.3}", c.amplitude_over_albedo),
        ]);
    }
    md.push_str(&t.to_string());
    md.push('\n');
    md
}

//! The held-out figures of a fitted table (`ltc::lobe_error`, converged integrals with
//! their error bars): every cell in each precision it is stored in, summarised; and the
//! sampled estimate earlier versions printed, kept only to say what changed.

use crate::error::Result;
use crate::ltc::fit::{inverse_from_production, production_metrics, Cell, Table};
use crate::ltc::lobe_error::{judge, Held, LobeError, Spread, Tolerance};
use crate::ltc::target::LtcTarget;
use crate::parmap::ParMap;
use serde::Serialize;

/// The held-out figures of every cell of a table in every precision it is stored in
/// (`Cell::held`): one cubature per cell judges the f64 cell, its f32 and
/// round-to-nearest binary16 roundings and its stored binary16 cell (`Cell::half`)
/// against `target(α, θ)`. One θ column per item of the caller's map.
pub fn judge_table<T: LtcTarget>(
    pm: &impl ParMap,
    table: &mut Table,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    tol: Tolerance,
) -> Result<()> {
    let cols = &table.cells;
    let label = format!(
        "held-out figures {}² (tolerance {:e})",
        table.grid.n, tol.rel
    );
    let held: Vec<Vec<Held>> = pm.map(&label, cols.len(), |j| {
        cols[j]
            .iter()
            .map(|c| {
                let t = target(c.alpha, c.theta)?;
                let full = [c.inv[0], c.inv[1], c.inv[2], c.inv[3], c.norm];
                let stored = [c.half[0], c.half[1], c.half[2], c.half[3], c.half[4]];
                let e = judge(&t, c.norm, &precisions(full, stored), tol);
                Ok(Held {
                    f64: e[0],
                    f32: e[1],
                    f16_nearest: e[2],
                    f16: e[3],
                })
            })
            .collect()
    })?;
    for (col, h) in table.cells.iter_mut().zip(held) {
        for (c, h) in col.iter_mut().zip(h) {
            c.held = Some(h);
        }
    }
    Ok(())
}

/// The four precisions a table's cell is judged in, as (M⁻¹, norm): the f64 entries
/// `full` (a, b, c, d, norm), their f32 and round-to-nearest binary16 roundings, and the
/// stored binary16 entries `stored`, in the order of [`Held`]'s fields.
pub fn precisions(full: [f64; 5], stored: [f64; 5]) -> [(nalgebra::Matrix3<f64>, f64); 4] {
    let f32v = full.map(|x| x as f32 as f64);
    let near = full.map(|x| half::f16::from_f64(x).to_f64());
    [full, f32v, near, stored].map(|v| (inverse_from_production(&[v[0], v[1], v[2], v[3]]), v[4]))
}

/// The held-out error of a fitted table over its cells (the f64 cells).
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize)]
pub struct Stats {
    /// Relative L2 ‖f − norm·γ_M‖/‖f‖: mean and largest, each ± its error bar.
    pub l2: Spread,
    /// Relative L1 ∫|f − norm·γ_M|/∫f.
    pub l1: Spread,
    /// (α, θ in degrees) of the cell with the largest relative L2.
    pub worst_cell: (f64, f64),
    /// Cells whose held-out integrals met their tolerance / all cells judged.
    pub converged: usize,
    pub cells: usize,
    pub mean_iters: f64,
}

/// The held-out errors of every cell of `t` (`judge_table` first), summarised.
pub fn held_out_stats(t: &Table) -> Stats {
    let cells: Vec<&Cell> = t.cells.iter().flatten().collect();
    let figs: Vec<Option<LobeError>> = cells.iter().map(|c| c.held.and_then(|h| h.f64)).collect();
    let l2 = Spread::of(figs.iter().map(|e| e.as_ref().map(|e| &e.l2)));
    let l1 = Spread::of(figs.iter().map(|e| e.as_ref().map(|e| &e.l1)));
    let worst = cells
        .get(l2.argmax)
        .map(|c| (c.alpha, c.theta.to_degrees()))
        .unwrap_or((f64::NAN, f64::NAN));
    Stats {
        l2,
        l1,
        worst_cell: worst,
        converged: figs.iter().flatten().filter(|e| e.converged).count(),
        cells: cells.len(),
        mean_iters: cells.iter().map(|c| c.iters as f64).sum::<f64>() / cells.len().max(1) as f64,
    }
}

/// What the held-out figure was before it became an integral: the relative L2 as a ratio
/// of sums over an n×n + n×n stratified sample set per cell (offset ¼), which is biased
/// low (the square root of a ratio of noisy sums). Kept only to say, in the reports,
/// what changed: mean and largest over the cells of `t`, and the cells where it falls
/// below the integral's value by more than the integral's error bar.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Sampled {
    pub n: usize,
    pub mean: f64,
    pub max: f64,
    pub below: usize,
    pub cells: usize,
}

/// [`Sampled`] of a judged table against `target(α, θ)`.
pub fn sampled_estimate<T: LtcTarget>(
    pm: &impl ParMap,
    t: &Table,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    n: usize,
) -> Result<Sampled> {
    let cells: Vec<&Cell> = t.cells.iter().flatten().collect();
    let v: Vec<f64> = pm.map_items("sampled estimate (earlier method)", &cells, |c| {
        Ok(
            production_metrics(&target(c.alpha, c.theta)?, &c.inv, c.norm, n, 0.25)
                .map_or(f64::NAN, |m| m.1),
        )
    })?;
    let ok: Vec<(f64, &Cell)> = v
        .into_iter()
        .zip(cells)
        .filter(|x| x.0.is_finite())
        .collect();
    let m = ok.len().max(1) as f64;
    Ok(Sampled {
        n,
        mean: ok.iter().map(|x| x.0).sum::<f64>() / m,
        max: ok.iter().map(|x| x.0).fold(0.0, f64::max),
        below: ok
            .iter()
            .filter(|(s, c)| c.l2().is_some_and(|b| *s < b.value - b.error))
            .count(),
        cells: ok.len(),
    })
}

impl Sampled {
    /// One sentence for a report.
    pub fn sentence(&self, exact_mean: f64) -> String {
        format!(
            "Earlier versions printed a sampled estimate instead (the square root of a ratio of sums over {n}×{n} + {n}×{n} stratified samples per cell, biased low, without an error bar): on this same table it gives mean {:.2} % and max {:.1} %, {:+.2} points from the integrals' mean, and lies below the integral by more than its error bar in {} of {} cells.",
            100.0 * self.mean,
            100.0 * self.max,
            100.0 * (self.mean - exact_mean),
            self.below,
            self.cells,
            n = self.n
        )
    }
}

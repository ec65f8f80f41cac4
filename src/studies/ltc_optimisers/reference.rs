//! The table's fitting route against the reference route: the same grid, warm starts,
//! bilinear pass (`ltc::smooth`) and held-out integrals (`ltc::held`), only the per-cell
//! fit differs — the reference runs Nelder–Mead on the cubic metric out to its cap and
//! polishes with Nelder–Mead on the L2. Compared cell by cell against the published
//! table's own held-out figures.

use crate::error::Result;
use crate::integrate::{Figure, Quad};
use crate::ltc::fit::{fit_table, Method, Metric, Polish};
use crate::ltc::held::judge_table;
use crate::ltc::lobe_error::{Change, Tolerance};
use crate::ltc::smooth::bilinear_pass;
use crate::ltc::target::GgxTarget;
use crate::memo::Memo;
use crate::results::ltc::{Ggx, RouteComparison};

/// Fit the reference table on the published table's grid (`samples`² per technique,
/// ≤ `iters` Nelder–Mead iterations per stage), judge it to the published figures'
/// tolerance `tol` and compare; `table` names the published table's route.
pub(super) fn compare(
    ggx: &Ggx,
    samples: usize,
    iters: u64,
    tol: Tolerance,
    table: String,
) -> Result<RouteComparison> {
    let grid = ggx.grid;
    let pb = crate::progress::Progress::new("ltc reference route", (grid.n * grid.n) as u64);
    let mut t = fit_table(
        &Memo,
        grid,
        &GgxTarget::new,
        samples,
        Metric::Cubic,
        Method::NelderMead,
        iters,
        Polish::NelderMead,
        &|| pb.inc(1),
    )?;
    pb.finish();
    bilinear_pass(&Memo, &mut t, &GgxTarget::new, samples)?;
    judge_table(&Memo, &mut t, &GgxTarget::new, tol)?;
    let pairs: Vec<Option<(Figure<Quad>, Figure<Quad>)>> = t
        .cells
        .iter()
        .zip(&ggx.held_out_cells.l2)
        .flat_map(|(rc, tc)| {
            rc.iter().zip(tc).map(|(r, c)| {
                let r = r.held.and_then(|h| h.f64).map(|e| e.l2)?;
                let c = c.map(|c| Figure::<Quad>::new(c[0], c[1]))?;
                Some((r, c))
            })
        })
        .collect();
    let change = Change::of(pairs.iter().copied(), 1e-3);
    // a difference beyond the sum of the two bars is certain: each bar bounds its figure
    let beyond = |d: f64, r: &Figure<Quad>, c: &Figure<Quad>| d > r.error + c.error;
    let worse: Vec<f64> = pairs
        .iter()
        .flatten()
        .map(|(r, c)| (c.value - r.value, r, c))
        .filter(|(d, r, c)| beyond(*d, r, c))
        .map(|(d, _, _)| d)
        .collect();
    let better = pairs
        .iter()
        .flatten()
        .filter(|(r, c)| beyond(r.value - c.value, r, c))
        .count();
    let both: Vec<&(Figure<Quad>, Figure<Quad>)> = pairs.iter().flatten().collect();
    Ok(RouteComparison {
        reference: format!(
            "Nelder–Mead (≤ {iters} iterations per stage) on the cubic metric, then {}",
            Polish::NelderMead.describe(samples)
        ),
        table,
        reference_mean: Figure::mean_bounded(&both.iter().map(|p| p.0).collect::<Vec<_>>()),
        table_mean: Figure::mean_bounded(&both.iter().map(|p| p.1).collect::<Vec<_>>()),
        mean_change: change.mean,
        worse: worse.len(),
        worse_by_001pt: worse.iter().filter(|d| **d > 1e-4).count(),
        worse_by_01pt: worse.iter().filter(|d| **d > 1e-3).count(),
        largest_excess: worse.iter().copied().fold(0.0, f64::max),
        better,
        cells: both.len(),
    })
}

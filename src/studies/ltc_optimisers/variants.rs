//! The optimiser and metric variants of the GGX table's fit on a sub-grid: each route
//! fits the whole sub-grid (warm starts as the table's) and is judged by the same
//! held-out integrals (`ltc::held`).

use crate::error::Result;
use crate::ltc::fit::{fit_table, Grid, Method, Metric, Polish};
use crate::ltc::held::{held_out_stats as stats, judge_table, Stats};
use crate::ltc::lobe_error::Tolerance;
use crate::ltc::target::GgxTarget;
use crate::memo::Memo;
use crate::report::table::Table as MdTable;

/// The routes, in this order: name, metric, optimiser and L2 polish (after a cubic fit).
const ROUTES: [(&str, Metric, Method, Polish); 5] = [
    (
        "Nelder–Mead, cubic metric, Nelder–Mead L2 polish (the reference route)",
        Metric::Cubic,
        Method::NelderMead,
        Polish::NelderMead,
    ),
    (
        "Nelder–Mead, cubic metric, Levenberg–Marquardt L2 polish, φ held",
        Metric::Cubic,
        Method::NelderMead,
        Polish::LevenbergMarquardtTurnHeld,
    ),
    (
        "Nelder–Mead, L2 metric",
        Metric::L2,
        Method::NelderMead,
        Polish::NelderMead,
    ),
    (
        "L-BFGS (central differences), cubic metric, Nelder–Mead L2 polish",
        Metric::Cubic,
        Method::Lbfgs,
        Polish::NelderMead,
    ),
    (
        "Levenberg–Marquardt on fixed nodes, relative L2",
        Metric::L2,
        Method::LevenbergMarquardt,
        Polish::NelderMead,
    ),
];

/// Every route fitted over `grid` with `samples`² samples per technique and `iters`
/// iterations, judged; each name with its held-out summary.
pub(super) fn measure(grid: Grid, samples: usize, iters: u64) -> Result<Vec<(String, Stats)>> {
    let pb = crate::progress::Progress::new(
        "ltc optimiser variants",
        (ROUTES.len() * grid.n * grid.n) as u64,
    );
    let mut rows = Vec::with_capacity(ROUTES.len());
    for (name, metric, method, polish) in ROUTES {
        let mut t = fit_table(
            &Memo,
            grid,
            &GgxTarget::new,
            samples,
            metric,
            method,
            iters,
            polish,
            &|| pb.inc(1),
        )?;
        judge_table(&Memo, &mut t, &GgxTarget::new, Tolerance::default())?;
        rows.push((name.to_string(), stats(&t)));
    }
    pb.finish();
    Ok(rows)
}

/// The rows as the result file holds them.
pub(super) fn rows(rows: &[(String, Stats)]) -> Vec<crate::results::ltc::Variant> {
    rows.iter()
        .map(|(name, s)| crate::results::ltc::Variant {
            fit: name.clone(),
            stats: *s,
        })
        .collect()
}

pub(super) fn section(sub: usize, iters: u64, rows: &[(String, Stats)]) -> String {
    let mut md = format!(
        "## Optimisers and metrics ({sub}×{sub} sub-grid, held-out errors)\n\nEvery route with at most {iters} iterations per stage (the polish: half of them for Nelder–Mead).\n\n"
    );
    let mut t = MdTable::new([
        "fit",
        "mean rel. L2",
        "max rel. L2",
        "mean rel. L1",
        "max rel. L1",
        "mean iterations",
    ]);
    for (name, s) in rows {
        t.row([
            name.to_string(),
            s.l2.mean.pct(2),
            s.l2.max.pct(1),
            s.l1.mean.pct(2),
            s.l1.max.pct(1),
            format!("{:.0}", s.mean_iters),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\nThe cubic metric weighs the peak (|f − f_ltc|³ grows like α⁻⁶ near the mirror direction), the L2 metric the whole lobe; both are training metrics (Monte Carlo sums on the fit's sample set), and every fit is judged by the same held-out integrals. A collapsed L-BFGS cell (a line-search failure or a jump into the metric's spurious basin of very wide LTCs, which the cubic metric has when the start is off by ~2× at tiny α) keeps its warm start, so the table stays continuous. Levenberg–Marquardt (`ltc::gauss_newton`) minimises the relative L2 on fixed nodes — n×n stratified points per technique, drawn once from the target's sampler and the start LTC with fixed balance weights, then redrawn once from the fitted LTC — so its objective is smooth and it needs tens of iterations where Nelder–Mead needs hundreds; alone, from the warm-start chain, it can leave a narrow lobe's basin (φ runs off at tiny α), which is why the table uses it only as a polish after the cubic stage. Iterations count the cubic stage (or the single route), not the polish.\n\n");
    md
}

//! The tables the two work studies' reports share (results/ltc-work.md for the tables
//! fitted by Nelder–Mead, results/ltc-aniso-work.md for the anisotropic one): a table's
//! reference draws against each other, the columns every judged route shows, and the
//! bounds of `ltc::spread`'s rule. Formats only.

use crate::ltc::spread::Verdict;
use crate::report::table::Table as MdTable;
use crate::results::ltc::{TableWork, WorkRow};

/// A row's mean relative L2 between cells in percent: ± its s.e. where sampled, ± the
/// judged squares' mean bar where all were (a census has no s.e.).
pub fn between(r: &WorkRow) -> String {
    let Some(b) = r.between_l2 else {
        return "(its study's report)".into();
    };
    match (b.error > 0.0, r.between_bar) {
        (true, _) => format!("{:.3} % ± {:.3} (s.e.)", 100.0 * b.value, 100.0 * b.error),
        (false, Some(q)) => format!("{:.3} ± {:.3} %", 100.0 * b.value, 100.0 * q),
        (false, None) => format!("{:.3} %", 100.0 * b.value),
    }
}

/// A count per cell in millions (none: a published table, read and not refitted).
pub fn millions(w: Option<f64>) -> String {
    w.map_or("(published, not refitted)".into(), |w| {
        format!("{:.3}", w / 1e6)
    })
}

/// The reference's draws, each against the envelope of the others (the leave-one-out
/// statistics the first route's verdict holds); `mean` heads the mean column.
pub fn draws_table(t: &TableWork, mean: &str) -> String {
    let mut d = MdTable::new([
        "training offset",
        mean,
        "between cells: mean rel. L2",
        "work per cell (M)",
        "target evaluations per cell (M)",
        "mean iterations",
        "cells above the others",
        "sum above (points)",
        "largest (points)",
        "cells below the others",
    ]);
    let leave_out = t
        .routes
        .first()
        .map(|r| r.1.reference.clone())
        .unwrap_or_default();
    for (k, r) in t.draws.iter().enumerate() {
        let e = leave_out.get(k).copied().unwrap_or_default();
        d.row([
            format!("{}", r.offset),
            r.mean.pct(3),
            between(r),
            millions(r.work_per_cell),
            millions(r.target_evals_per_cell),
            r.iters_per_cell.map_or("—".into(), |i| format!("{i:.0}")),
            e.above.to_string(),
            format!("{:.3}", 100.0 * e.excess),
            format!("{:.3}", 100.0 * e.largest),
            e.below.to_string(),
        ]);
    }
    d.to_string()
}

/// The routes table's headers: samples, cap, the nodes column (`nodes`), then
/// [`route_cells`]'s (`mean` heads the mean column).
pub fn route_headers<'a>(nodes: &'a str, mean: &'a str) -> [&'a str; 15] {
    [
        "samples",
        "cap",
        nodes,
        "work per cell (M)",
        "work / reference",
        "target evaluations per cell (M)",
        "target evaluations / reference",
        mean,
        "between cells: mean rel. L2",
        "cells above",
        "sum above (points)",
        "largest (points)",
        "cells below",
        "surplus above",
        "no worse",
    ]
}

/// The reference route's (work, target evaluations) per cell: the means over its
/// refitted draws.
pub fn reference_counts(t: &TableWork) -> (f64, f64) {
    let mean = |f: &dyn Fn(&WorkRow) -> Option<f64>| {
        let v: Vec<f64> = t.draws.iter().filter_map(f).collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    (
        mean(&|r| r.work_per_cell),
        mean(&|r| r.target_evals_per_cell),
    )
}

/// `x / of` to two decimals, or a dash.
pub fn ratio(x: Option<f64>, of: f64) -> String {
    x.filter(|_| of > 0.0)
        .map_or("—".into(), |x| format!("{:.2}", x / of))
}

/// One route's row, given its nodes in words: samples, cap, nodes, its counts against
/// the reference's `(work, target evaluations)` and its verdict's statistics.
pub fn route_cells(
    row: &WorkRow,
    v: &Verdict,
    nodes: String,
    (w0, e0): (f64, f64),
) -> [String; 15] {
    let largest = v.candidate.iter().map(|e| e.largest).fold(0.0, f64::max);
    let below = v.candidate.iter().map(|e| e.below as f64).sum::<f64>() / v.candidate.len() as f64;
    [
        format!("{}²", row.samples),
        row.max_iters.to_string(),
        nodes,
        millions(row.work_per_cell),
        ratio(row.work_per_cell, w0),
        millions(row.target_evals_per_cell),
        ratio(row.target_evals_per_cell, e0),
        row.mean.pct(3),
        between(row),
        format!("{:.1}", v.candidate_above),
        format!("{:.3}", 100.0 * v.candidate_excess),
        format!("{:.3}", 100.0 * largest),
        format!("{below:.1}"),
        format!("{:.1}", v.candidate_surplus),
        if v.no_worse { "yes" } else { "no" }.into(),
    ]
}

/// The rule's bounds from the draws, in a sentence (`cells` names what was counted).
pub fn bounds(t: &TableWork, cells: &str) -> String {
    t.routes.first().map_or(String::new(), |(_, v)| {
        format!(
            "\nBounds (one-sided 95 % prediction from the {} draws, over {} {cells}): mean rel. L2 ≤ {:.3} %, cells above ≤ {:.1}, sum above ≤ {:.3} points, surplus above ≤ {:.1}. ",
            v.reference.len(),
            v.cells,
            100.0 * v.mean_bound,
            v.above_bound,
            100.0 * v.excess_bound,
            v.surplus_bound,
        )
    })
}

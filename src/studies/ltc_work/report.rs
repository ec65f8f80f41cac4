//! results/ltc-work.md: per table, the reference's spread and the cheaper routes against it.

use crate::integrate::Preset;
use crate::ltc::fit::Nodes;
use crate::report::table::Table as MdTable;
use crate::results::ltc::{LtcWork, TableWork, WorkRow};
use crate::studies::ltc_work_tables::{
    bounds, draws_table, reference_counts, route_cells, route_headers,
};

pub(super) fn markdown(o: &LtcWork, preset: Preset) -> String {
    let mut md = format!(
        "# LTC tables: accuracy against fitting work\n\nWritten by `{}` (preset {}) from `fits/{}.toml`, on request (the main job leaves it out). For each LTC table the main job fits by Nelder–Mead, it reads the published table and its route, refits the reference (the route's settings with the reference fitter's trials on moving samples) on other draws of its training samples (the strata offset; a table published on moving samples is the draw at 0.5: the same work, another draw; one published on fixed nodes is a route below, and the reference is refitted at 0.5 too), and fits cheaper routes; every table goes through the same bilinear pass, binary16 storage and held-out integrals (relative L2 of the f64 cell, ± its bar). The diffuse table is left out: its route is already cut to 20 iterations with a Levenberg–Marquardt polish, whose evaluations the work count does not see.\n\n**The rule** (`ltc::spread`). The judge's bars (~1e-5 relative) measure the integrals, not the fit: a draw of the same route moves hundreds of cells by far more, both ways. So each draw is set against the envelope of the others (their largest error per cell), and counts the cells where it lands above that envelope beyond both bars, their sum and largest difference, and the cells where it lands below the others' smallest. The surplus is a draw's cells above less its cells below: a fresh draw is as often below the others as above, so a route a little worse almost everywhere shows as a surplus. A route is set against the same envelopes, one per left-out draw, and its statistics are the means over them. It is **no worse** when its cells above, sum above, surplus and mean rel. L2 (less its bar) are each within the one-sided 95 % prediction bound of the draws' own (mean + t₀.₉₅·s·√(1 + 1/R) over the R draws, Student's t with R − 1 degrees of freedom): a fresh draw fails each bound about one time in twenty. Work: the fit's trial-LTC sample evaluations per cell (cubic stages and polish), in millions; a count, not a clock. Target evaluations: the fit's evaluations of the BRDF lobe per cell, in millions, also a count: a moving-sample trial evaluates the lobe at each of its LTC half's samples, so the lobe (two powers and an exponential per value for the sheen, GGX's D and Λ) is most of a trial's cost. A route with fixed nodes (`ltc::fit::Method::FixedNodes`) measures the cubic stage's trials on nodes drawn once per stage — the LTC half from the stage's start, with the balance weights of the two techniques that drew them — so its trials evaluate no lobe; the L2 polish stays the published one. A route with fixed nodes in every stage (`Method::FixedNodesAll`) also measures the L2 polish's trials on nodes drawn once from the cubic solution, twice as many per axis as the cubic stage's (`ltc::polish::FIXED_POLISH_SCALE`; a cell whose polished lobe the fixed and the moving estimate disagree on by more than 1.2×, or that captures nothing, relative L2 ≥ 0.9, is polished again on moving samples), and the bilinear pass's on nodes drawn once per place from the table's entries there before the pass (the pass's keep-or-revert test stays on moving samples); the pass's evaluations are in neither count. A route with the reference's settings and moving nodes is a check: its cells are the first draw's, bit for bit; and where the table was published on fixed nodes, the route with its settings on those nodes is the published table. The cheapest route no worse is ranked by target evaluations, which a fit's CPU time follows (a fixed-node trial evaluates no lobe; its trial-LTC evaluations are cheap).\n\n",
        o.command,
        preset.name(),
        o.spec.name,
    );
    for t in &o.tables {
        md.push_str(&table_section(t));
    }
    md
}

fn table_section(t: &TableWork) -> String {
    let d0 = &t.draws[0];
    let fingerprint = &t.table_fingerprint[..t.table_fingerprint.len().min(16)];
    let published = match t.published_nodes {
        Nodes::Moving => format!(
            "The published route is the reference's (table fingerprint {fingerprint})"
        ),
        n => format!(
            "The published table (fingerprint {fingerprint}) is the route below at these settings with {}; the reference is refitted at the published offset 0.5 (the first draw)",
            nodes_words(n)
        ),
    };
    let mut md = format!(
        "## {}\n\nThe reference route (the reference fitter, trials on moving samples): {}² stratified samples per technique, Nelder–Mead ≤ {} iterations per stage on the cubic metric, then {}. {published}.\n\n",
        t.table, d0.samples, d0.max_iters, t.polish,
    );
    md.push_str(&draws_table(t, "mean rel. L2"));
    md.push('\n');
    md.push_str(&routes_table(t));
    md
}

fn routes_table(t: &TableWork) -> String {
    let counts = reference_counts(t);
    let mut r = MdTable::new(route_headers("cubic stage's nodes", "mean rel. L2"));
    for (row, v) in &t.routes {
        let nodes = format!(
            "{}{}",
            match row.nodes() {
                Nodes::FixedAll => "fixed, and in the polish and the bilinear pass",
                Nodes::Fixed => "fixed",
                Nodes::Moving => "moving",
            },
            if published_row(t, row) {
                " (the published table)"
            } else {
                ""
            }
        );
        r.row(route_cells(row, v, nodes, counts));
    }
    let mut md = r.to_string();
    md.push_str(&bounds(t, "cells"));
    md.push_str(&verdict(t, counts.1));
    md
}

/// Whether a route is the published table's: the published settings on its nodes, where
/// those are not the reference's moving samples.
fn published_row(t: &TableWork, r: &WorkRow) -> bool {
    let d0 = &t.draws[0];
    t.published_nodes != Nodes::Moving
        && r.nodes() == t.published_nodes
        && (r.samples, r.max_iters) == (d0.samples, d0.max_iters)
}

/// A route's nodes in words, after "with".
fn nodes_words(n: Nodes) -> &'static str {
    match n {
        Nodes::FixedAll => "fixed nodes in every stage (cubic, polish, bilinear pass)",
        Nodes::Fixed => "fixed nodes in the cubic stage",
        Nodes::Moving => "moving samples",
    }
}

/// The cheapest route no worse than the reference, in a sentence. Cheapest by target
/// evaluations per cell: a fixed-node trial evaluates no lobe, so the lobe's evaluations,
/// not the trial LTC's, are what a fit's CPU time follows.
fn verdict(t: &TableWork, e0: f64) -> String {
    let d0 = &t.draws[0];
    // cheaper by its settings: no more samples or iterations than the reference route,
    // and fewer of one or fixed nodes (the reference's own settings on moving samples are
    // a check, not a candidate)
    let cheaper = |r: &WorkRow| {
        r.samples <= d0.samples
            && r.max_iters <= d0.max_iters
            && ((r.samples, r.max_iters) != (d0.samples, d0.max_iters) || r.fixed_nodes)
    };
    let e = |r: &WorkRow| r.target_evals_per_cell.unwrap_or(f64::INFINITY);
    let cheapest = t
        .routes
        .iter()
        .filter(|(r, v)| v.no_worse && cheaper(r))
        .min_by(|a, b| e(&a.0).total_cmp(&e(&b.0)));
    match cheapest {
        Some((r, _)) => format!(
            "The cheapest route no worse than the reference, by target evaluations: {}² samples, ≤ {} iterations per stage, with {}, {:.2}× the reference's target evaluations{}.\n\n",
            r.samples,
            r.max_iters,
            nodes_words(r.nodes()),
            e(r) / e0,
            if published_row(t, r) {
                " (the published table)"
            } else {
                ""
            }
        ),
        None => "No cheaper route is no worse than the reference: among these routes, the reference route's work is what its accuracy needs.\n\n".into(),
    }
}

#[cfg(test)]
mod tests {
    use crate::integrate::Preset;
    use crate::results::ltc::LtcWork;
    use std::path::Path;

    /// results/ltc-work.md is its JSON rendered by this code: a renderer changed without
    /// the (35-minute) rerun leaves the committed report stale, and this fails.
    #[test]
    fn the_committed_report_is_its_file_rendered() {
        let w = crate::results::read::<LtcWork>(Path::new("results"))
            .unwrap()
            .expect("results/fits/ltc-work.json");
        let preset = Preset::named(&w.preset, "results/fits/ltc-work.json").unwrap();
        let md = std::fs::read_to_string("results/ltc-work.md").unwrap();
        assert!(
            super::markdown(&w, preset) == md,
            "results/ltc-work.md is not results/fits/ltc-work.json rendered now (regen --only ltc-work)"
        );
    }
}

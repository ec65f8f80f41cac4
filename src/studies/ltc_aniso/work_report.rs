//! results/ltc-aniso-work.md: the anisotropic table's reference draws and the routes
//! judged against their spread. Formats only.

use crate::integrate::Preset;
use crate::ltc::fit::Nodes;
use crate::report::table::Table as MdTable;
use crate::results::ltc::WorkRow;
use crate::results::ltc_aniso::AnisoWork;
use crate::studies::ltc_work_tables::{
    bounds, draws_table, ratio, reference_counts, route_cells, route_headers,
};

pub(super) fn markdown(o: &AnisoWork, preset: Preset) -> String {
    let w = &o.work;
    let fingerprint = &w.table_fingerprint[..w.table_fingerprint.len().min(16)];
    let mut md = format!(
        "# Anisotropic LTC table: accuracy against fitting work\n\nWritten by `{}` (preset {}) from `fits/{}.toml`, on request (the main job leaves it out). It reads the published anisotropic table (results/fits/ltc-aniso.json, fingerprint {fingerprint}; its route: {}) and refits its reference route (the published samples and cap, three starts per cell, the reference fitter's trials on moving samples: each trial draws the LTC half of its samples) on other draws of its training samples (the strata offset; the draw at the published offset 0.5 is refitted too{}), then fits each route below on the published draw. A route with fixed nodes (`ltc::aniso::Route`) measures its trials on nodes drawn once from each start, twice the samples per axis (`ltc::polish::FIXED_POLISH_SCALE`), weighted by the balance heuristic of the two techniques that drew them, so no trial evaluates the lobe; a cell whose fitted lobe the fixed and the moving estimate (validation set) disagree on by more than 1.2×, or that captures nothing (relative L2 ≥ 0.9), is fitted again on moving samples (`ltc::polish::fixed_fit_holds`). Every fit is judged as results/ltc-aniso.md judges the table: each fitted cell's held-out relative L2 (its own norm, ± its bar) and the table between cells at the study's random cases (mean ± s.e.).\n\n**The rule** (`ltc::spread`, as results/ltc-work.md states it): each draw is set against the envelope of the others per fitted cell, counting the cells it lands above beyond both bars, their sum and largest difference, and the cells below; a route is set against the same envelopes, and is **no worse** when its cells above, sum above, surplus (above less below) and mean (less its bar) are each within the one-sided 95 % prediction bound of the draws' own. Work: trial-LTC sample evaluations per cell over its three starts, in millions; target evaluations: the lobe's evaluations per cell, in millions (a moving-sample trial evaluates the lobe at each LTC-half sample; a fixed-node fit only where it draws its nodes). Counts, not clocks.\n\n",
        o.command,
        preset.name(),
        o.spec.name,
        w.polish,
        match w.published_nodes {
            Nodes::Moving => ": the published table itself, bit for bit",
            _ => "; the published table, fitted on fixed nodes, is the route below at its settings on those nodes",
        },
    );
    md.push_str(&draws_table(w, "mean rel. L2 (fitted cells)"));
    md.push('\n');
    md.push_str(&routes(o));
    md
}

fn routes(o: &AnisoWork) -> String {
    let w = &o.work;
    let (w0, e0) = reference_counts(w);
    let d0 = &w.draws[0];
    let published = |r: &WorkRow| {
        w.published_nodes != Nodes::Moving
            && r.nodes() != Nodes::Moving
            && (r.samples, r.max_iters) == (d0.samples, d0.max_iters)
    };
    let mut t = MdTable::new(route_headers("nodes", "mean rel. L2 (fitted cells)"));
    for (row, v) in &w.routes {
        let nodes = format!(
            "{}{}",
            if row.nodes() == Nodes::Moving {
                "moving"
            } else {
                "fixed"
            },
            if published(row) {
                " (the published table)"
            } else {
                ""
            }
        );
        t.row(route_cells(row, v, nodes, (w0, e0)));
    }
    let mut md = t.to_string();
    md.push_str(&bounds(w, "fitted cells"));
    let cheapest = w
        .routes
        .iter()
        // the route at the reference's own settings on moving samples is a check, not a
        // cheaper route
        .filter(|(r, _)| {
            r.nodes() != Nodes::Moving || (r.samples, r.max_iters) != (d0.samples, d0.max_iters)
        })
        .filter(|(r, v)| v.no_worse && r.target_evals_per_cell.unwrap_or(f64::INFINITY) < e0)
        .min_by(|a, b| {
            let e = |r: &WorkRow| r.target_evals_per_cell.unwrap_or(f64::INFINITY);
            e(&a.0).total_cmp(&e(&b.0))
        });
    md.push_str(&match cheapest {
        Some((r, _)) => format!(
            "The cheapest route no worse than the reference, by target evaluations: {}² samples, ≤ {} iterations per start, {} nodes, {}× the reference's target evaluations{}; and {}× its trial-LTC evaluations{}.\n",
            r.samples,
            r.max_iters,
            if r.nodes() == Nodes::Moving { "moving" } else { "fixed" },
            ratio(r.target_evals_per_cell, e0),
            if published(r) { " (the published table)" } else { "" },
            ratio(r.work_per_cell, w0),
            if r.nodes() == Nodes::Moving {
                ""
            } else {
                " (a fixed-node trial evaluates the LTC at twice the samples per axis, four times as many nodes, and the lobe nowhere: target evaluations rank this fit's cost only where the lobe dominates a trial)"
            }
        ),
        None => "No route with fewer target evaluations than the reference is no worse.\n".into(),
    });
    md
}

#[cfg(test)]
mod tests {
    /// results/ltc-aniso-work.md is its JSON rendered by this code: a renderer change
    /// without the study's rerun fails here.
    #[test]
    fn the_committed_report_is_its_file_rendered() {
        let r = std::path::Path::new("results");
        let Some(w) = crate::results::read::<crate::results::ltc_aniso::AnisoWork>(r).unwrap()
        else {
            panic!("results/fits/ltc-aniso-work.json is missing");
        };
        let preset = crate::integrate::Preset::named(&w.preset, "ltc-aniso-work.json").unwrap();
        let md = std::fs::read_to_string(r.join("ltc-aniso-work.md")).unwrap();
        assert!(
            super::markdown(&w, preset) == md,
            "results/ltc-aniso-work.md is not its JSON rendered (regen --only ltc-aniso-work)"
        );
    }
}

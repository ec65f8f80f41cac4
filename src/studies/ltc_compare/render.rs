//! The rendering of `ltc-compare` (`studies::ltc_compare`): the markdown report and the heat
//! maps of a comparison already computed. Formats only.

use super::compute::{Form, FormSummary, HalfCounts, NormRatios, Pair, GRAZING, SAMPLED_SIDE};
use crate::error::Result;
use crate::ltc::compare::alpha_theta;
use crate::ltc::lobe_error::LobeError;
use crate::report::table::Table;

/// The markdown report.
pub fn markdown(n: usize, forms: &[Form], sums: &[FormSummary], header: &str) -> String {
    let mut md = header.to_string();
    md.push_str("## Summary\n\nRelative L2 ‖f − norm·γ_M‖/‖f‖ and relative L1 ∫|f − norm·γ_M|/∫f of each table as the engine holds it, mean over the places the engine reaches, ± the mean error bar; \"better\" and \"worse\" count the places where the two tables' relative L2 differ by more than their two error bars together (the rest are tied).\n\n");
    let graze = format!("rows t ≥ {}/{}", GRAZING.0, GRAZING.1);
    let mut t = Table::new([
        "engine path".to_string(),
        "where".into(),
        "count".into(),
        "ours: rel. L2".into(),
        "shipped: rel. L2".into(),
        "ours: rel. L1".into(),
        "shipped: rel. L1".into(),
        "ours better / tied / worse".into(),
        format!("{graze}: ours L2"),
        format!("{graze}: shipped L2"),
    ]);
    for (f, fs) in forms.iter().zip(sums) {
        for (what, s, g) in [
            ("cells", &fs.cells, &fs.cells_grazing),
            ("squares (bilinear)", &fs.squares, &fs.squares_grazing),
        ] {
            t.row([
                f.name.to_string(),
                what.to_string(),
                s.count.to_string(),
                s.ours_l2.mean.pct(2),
                s.shipped_l2.mean.pct(2),
                s.ours_l1.mean.pct(2),
                s.shipped_l1.mean.pct(2),
                format!(
                    "{} / {} / {}",
                    s.ours_better,
                    s.count - s.ours_better - s.ours_worse,
                    s.ours_worse
                ),
                g.ours_l2.mean.pct(2),
                g.shipped_l2.mean.pct(2),
            ]);
        }
    }
    md.push_str(&t.to_string());
    md.push_str(&format!("\nWhat changed with exact figures: earlier versions estimated the relative L2 by a ratio of sums over {SAMPLED_SIDE}² + {SAMPLED_SIDE}² stratified samples per place (biased low, no error bar) and counted \"ours no worse\" within 0.1 %. The same estimate on the same places:\n\n"));
    let mut t = Table::new([
        "engine path",
        "where",
        "sampled: ours",
        "sampled: shipped",
        "sampled: ours no worse",
        "integrals: ours better or tied",
    ]);
    for (f, fs) in forms.iter().zip(sums) {
        for (what, s) in [("cells", &fs.cells), ("squares", &fs.squares)] {
            t.row([
                f.name.to_string(),
                what.to_string(),
                format!("{:.2} %", 100.0 * s.sampled_ours_mean),
                format!("{:.2} %", 100.0 * s.sampled_shipped_mean),
                format!("{} of {}", s.sampled_no_worse, s.count),
                format!("{} of {}", s.count - s.ours_worse, s.count),
            ]);
        }
    }
    md.push_str(&t.to_string());
    md.push_str("\nWhat each path holds:\n\n");
    for f in forms {
        md.push_str(&format!(
            "- **{}** (perceptual roughness ≥ {}): {}.\n",
            f.name, f.r_min, f.holds
        ));
    }
    md.push_str("\nHeat maps (three.js FloatType cells; r = √α across, t = √(1 − cos θ) down, normal incidence at the top; grey: not reached): ![compare](ltc-compare.svg) Mean relative L2 per view row: ![rows](ltc-compare-rows.svg)\n\n");
    // per row, every path's cells
    md.push_str(&format!(
        "## Per row j (view; t = j/{}), cells, relative L2\n\n",
        n - 1
    ));
    let mut t = Table::new(
        std::iter::once("j".to_string()).chain(
            forms
                .iter()
                .flat_map(|f| [format!("{} ours", f.name), format!("{} shipped", f.name)]),
        ),
    );
    for j in 0..n {
        t.row(
            std::iter::once(j.to_string()).chain(sums.iter().flat_map(|fs| {
                let s = &fs.rows[j];
                [s.ours_l2.mean.pct(2), s.shipped_l2.mean.pct(2)]
            })),
        );
    }
    md.push_str(&t.to_string());
    md.push('\n');
    for (f, fs) in forms.iter().zip(sums) {
        for (what, bad, w) in [
            ("cells", &fs.worse_cells, n),
            ("squares", &fs.worse_squares, n - 1),
        ] {
            md.push_str(&format!("## Worst {what} for ours, {} (ratio ours/shipped of the relative L2; {} places worse beyond the error bars)\n\n", f.name, bad.len()));
            let mut t = Table::new(["i", "j", "α", "θ", "ours", "shipped", "ratio"]);
            let off = if what == "cells" { 0.0 } else { 0.5 };
            for (k, o, s) in bad.iter().take(12) {
                let (i, j) = (k % w, k / w);
                let (al, th) = alpha_theta(
                    (i as f64 + off) / (n - 1) as f64,
                    (j as f64 + off) / (n - 1) as f64,
                );
                t.row([
                    i.to_string(),
                    j.to_string(),
                    format!("{al:.3e}"),
                    format!("{:.2}°", th.to_degrees()),
                    o.l2.pct(2),
                    s.l2.pct(2),
                    format!("×{:.3}", o.l2.value / s.l2.value),
                ]);
            }
            md.push_str(&t.to_string());
            md.push('\n');
        }
    }
    md
}

/// The shipped norms against our albedo (by quadrature, error ≤ 1e-9): over the table,
/// and at the cells where the shipped table is better.
pub fn norms_section(r: &NormRatios) -> String {
    let (a, w) = (&r.all, &r.where_shipped_better);
    format!(
        "## The shipped norms against the albedo

The norm channel is the lobe's energy: a light covering the whole hemisphere returns exactly it. Ours is the albedo by quadrature (error ≤ 1e-9). Shipped norm / albedo over all {} cells: min {:.4}, median {:.4}, max {:.4}, mean |ratio − 1| = {:.2} %. At the {} cells where the shipped table is better beyond the error bars (three.js FloatType): min {:.4}, median {:.4}, max {:.4}, mean |ratio − 1| = {:.2} %; {} of them carry less energy than the BRDF: a lower norm lowers the L2 error of a lobe shape that cannot follow the BRDF's tail (results/ltc-ggx.md, the floor with an L2-optimal amplitude), and ours keeps the energy exact.\n\n",
        a.count,
        a.min,
        a.median,
        a.max,
        100.0 * a.mean_abs_dev,
        w.count,
        w.min,
        w.median,
        w.max,
        100.0 * w.mean_abs_dev,
        w.below_one,
    )
}

/// How three.js's and Bevy's binary16 tables relate to round-to-nearest of the shipped
/// numbers.
pub(super) fn half_section(h: &HalfCounts) -> String {
    let mut md = format!(
        "## Which binary16 table\n\n\"The shipped table in f16\" is two tables. three.js's `DataUtils.toHalfFloat` truncates: {} of the {} numbers of LTC_MAT_1 sit one binary16 step below round-to-nearest (toward zero). ",
        h.three_below_nearest, h.values
    );
    match h.bevy {
        Some((n, same_nearest, same_three)) => {
            md.push_str(&format!(
                "Bevy's embedded ltc.ktx2 holds {same_nearest} of its {n} matrix values equal to round-to-nearest of the same numbers and {same_three} equal to three.js's truncation.\n\n",
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
pub fn heatmaps(n: usize, forms: &[Form], sums: &[FormSummary]) -> Result<(String, String)> {
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
    let row = |f: &Form, fs: &FormSummary, ours: bool| Series {
        name: format!("{} {}", if ours { "ours" } else { "shipped" }, f.name),
        points: (1..n)
            .filter_map(|j| {
                let s = &fs.rows[j];
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
                .zip(sums)
                .flat_map(|(f, fs)| [row(f, fs, true), row(f, fs, false)])
                .collect(),
        }],
        900,
        560,
    )?;
    Ok((heat, rows))
}

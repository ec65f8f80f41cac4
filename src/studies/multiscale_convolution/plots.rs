//! The plots of the overall-α study: slices of α(α_mi, α_me) and maps of each model's
//! error over the held-out grid.

use super::compute::{models, Computed};
use crate::error::Result;
use crate::multiscale::alpha_me::held_out_alphas;
use crate::multiscale::overall::{alpha_moment, eq7, improved, sum_of_squares};
use crate::report::plot::{loglog_svg, Panel, Series};
use std::path::Path;

/// Write results/multiscale-convolution{,-maps}.svg; returns the markdown that shows them.
pub(super) fn write(set: &mut crate::io::Outputs, c: &Computed, results: &Path) -> Result<String> {
    let Computed {
        lo,
        hi,
        ref held_axis,
        ref ci,
        ..
    } = *c;
    let models = models(c);
    let product2 = |x: f64, y: f64| c.product(x, y);
    let mut md = String::new();
    // slices plot
    let slices: Vec<Panel> = [0.03, 0.3, 1.0]
        .iter()
        .map(|&mi| {
            let ys = held_out_alphas(60, lo, hi);
            let curve =
                |f: &dyn Fn(f64, f64) -> f64| ys.iter().map(|&y| (y, f(mi, y))).collect::<Vec<_>>();
            let mut series: Vec<Series> = vec![Series {
                name: "moment (closed form)".into(),
                points: curve(&|x, y| alpha_moment(x, y).unwrap_or(f64::NAN)),
            }];
            for (name, f) in models
                .iter()
                .filter(|m| m.0 != "Eq 7 form, refitted (linear LS)")
            {
                series.push(Series {
                    name: name.to_string(),
                    points: curve(f.as_ref()),
                });
            }
            Panel {
                title: format!("α_mi = {mi}"),
                x_label: "α_me".into(),
                y_label: "overall α".into(),
                series,
            }
        })
        .collect();
    let svg = loglog_svg(&slices, 1500, 520)?;
    set.put(&results.join("multiscale-convolution.svg"), svg.as_bytes());
    md.push_str("![slices of the overall α](multiscale-convolution.svg)\n\n");
    // maps on the held-out grid: the target surface and each model's relative error
    let map = |f: &dyn Fn(f64, f64) -> f64| -> Vec<Vec<f64>> {
        held_axis
            .iter()
            .map(|&y| held_axis.iter().map(|&x| f(x, y)).collect())
            .collect()
    };
    let rel = |f: &dyn Fn(f64, f64) -> f64| {
        map(&|x, y| {
            let a = alpha_moment(x, y).unwrap_or(f64::NAN);
            ((f(x, y) - a) / a).abs()
        })
    };
    let heat = |title: &str, values: Vec<Vec<f64>>, r: (f64, f64)| crate::report::plot::HeatPanel {
        title: title.to_string(),
        x: held_axis.clone(),
        y: held_axis.clone(),
        values,
        log_range: r,
        x_label: "α_mi".into(),
        y_label: "α_me".into(),
        log_axes: true,
        y_down: false,
        colour_label: format!("log10 {title}"),
    };
    let maps = crate::report::plot::heatmap_svg(
        &[
            heat(
                "α (unclipped moment)",
                map(&|x, y| alpha_moment(x, y).unwrap_or(f64::NAN)),
                (-2.0, 0.5),
            ),
            heat("|rel. error| Eq 7", rel(&eq7), (-5.0, 0.0)),
            heat("|rel. error| α²-sum", rel(&sum_of_squares), (-5.0, 0.0)),
            heat(
                "|rel. error| polynomial",
                rel(&|x, y| improved(&ci, x, y)),
                (-5.0, 0.0),
            ),
            heat("|rel. error| ours", rel(&product2), (-5.0, 0.0)),
        ],
        2000,
        430,
    )?;
    set.put(
        &results.join("multiscale-convolution-maps.svg"),
        maps.as_bytes(),
    );
    md.push_str("Maps over the held-out grid (unclipped-moment target; colour = log10, range in each title; ours degrades only where the target α > 1, outside the α_me fit's domain):\n\n![maps](multiscale-convolution-maps.svg)\n");
    Ok(md)
}

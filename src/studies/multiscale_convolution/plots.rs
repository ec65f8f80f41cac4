//! The plots of the overall-α study: slices of α(α_mi, α_me) and maps of each model's
//! error over the held-out grid (formats the study's [`Judged`] curves and maps only).

use super::judged::Judged;
use crate::error::Result;
use crate::report::plot::{loglog_svg, Panel, Series};
use std::path::Path;

/// results/multiscale-convolution{,-maps}.svg into `set`; returns the markdown that shows
/// them. `held_axis` is the held-out grid the maps lie on.
pub(super) fn write(
    set: &mut crate::io::Outputs,
    j: &Judged,
    held_axis: &[f64],
    results: &Path,
) -> Result<String> {
    let mut md = String::new();
    let slices: Vec<Panel> = j
        .slices
        .iter()
        .map(|(mi, curves)| Panel {
            title: format!("α_mi = {mi}"),
            x_label: "α_me".into(),
            y_label: "overall α".into(),
            series: curves
                .iter()
                .map(|(name, points)| Series {
                    name: name.clone(),
                    points: points.clone(),
                })
                .collect(),
        })
        .collect();
    let svg = loglog_svg(&slices, 1500, 520)?;
    set.put(results.join("multiscale-convolution.svg"), svg);
    md.push_str("![slices of the overall α](multiscale-convolution.svg)\n\n");
    let heat =
        |(title, values, r): &(String, Vec<Vec<f64>>, (f64, f64))| crate::report::plot::HeatPanel {
            title: title.clone(),
            x: held_axis.to_vec(),
            y: held_axis.to_vec(),
            values: values.clone(),
            log_range: *r,
            x_label: "α_mi".into(),
            y_label: "α_me".into(),
            log_axes: true,
            y_down: false,
            colour_label: format!("log10 {title}"),
        };
    let panels: Vec<_> = j.maps.iter().map(heat).collect();
    let maps = crate::report::plot::heatmap_svg(&panels, 2000, 430)?;
    set.put(results.join("multiscale-convolution-maps.svg"), maps);
    md.push_str("Maps over the held-out grid (unclipped-moment target; colour = log10, range in each title; ours degrades only where the target α > 1, outside the α_me fit's domain):\n\n![maps](multiscale-convolution-maps.svg)\n");
    Ok(md)
}

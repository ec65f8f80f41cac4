//! Log–log line plots as SVG (plotters, SVG backend: no system fonts needed).

use crate::error::{Error, Result};
use plotters::prelude::*;

/// One series of (x, y) points.
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// One panel.
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

fn bounds(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v
        .filter(|x| x.is_finite() && *x > 0.0)
        .fold((f64::INFINITY, 0.0f64), |a, x| (a.0.min(x), a.1.max(x)));
    if lo.is_finite() {
        (lo / 2.0, hi * 2.0)
    } else {
        (1e-16, 1.0)
    }
}

/// Render panels side by side into an SVG string (legend in the lower left).
pub fn loglog_svg(panels: &[Panel], width: u32, height: u32) -> Result<String> {
    loglog_svg_legend(panels, width, height, SeriesLabelPosition::LowerLeft)
}

/// [`loglog_svg`] with the legend where the caller's data leaves room.
pub fn loglog_svg_legend(
    panels: &[Panel],
    width: u32,
    height: u32,
    legend: SeriesLabelPosition,
) -> Result<String> {
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (width, height)).into_drawing_area();
        let err = |e: String| Error::InvalidArgument(format!("plot: {e}"));
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let areas = root.split_evenly((1, panels.len().max(1)));
        let palette = [
            RED,
            BLUE,
            GREEN,
            MAGENTA,
            CYAN,
            BLACK,
            RGBColor(255, 140, 0),
            RGBColor(128, 0, 128),
            RGBColor(0, 128, 128),
            RGBColor(139, 69, 19),
            RGBColor(128, 128, 0),
            RGBColor(112, 128, 144),
            RGBColor(220, 20, 60),
            RGBColor(0, 0, 128),
            RGBColor(34, 139, 34),
            RGBColor(255, 105, 180),
            RGBColor(70, 130, 180),
            RGBColor(184, 134, 11),
        ];
        for (area, p) in areas.iter().zip(panels) {
            let (x0, x1) = bounds(p.series.iter().flat_map(|s| s.points.iter().map(|q| q.0)));
            let (y0, y1) = bounds(p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1)));
            let mut chart = ChartBuilder::on(area)
                .caption(&p.title, ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(55)
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(|e| err(e.to_string()))?;
            chart
                .configure_mesh()
                .x_desc(p.x_label.as_str())
                .y_desc(p.y_label.as_str())
                .x_label_formatter(&|x| format!("{x:.0e}"))
                .y_label_formatter(&|y| format!("{y:.0e}"))
                .draw()
                .map_err(|e| err(e.to_string()))?;
            for (k, s) in p.series.iter().enumerate() {
                let c = palette[k % palette.len()];
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|q| q.0 > 0.0 && q.1 > 0.0)
                    .collect();
                chart
                    .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                    .map_err(|e| err(e.to_string()))?
                    .label(s.name.as_str())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 15, y)], c.stroke_width(2))
                    });
                chart
                    .draw_series(pts.iter().map(|q| Circle::new(*q, 3, c.filled())))
                    .map_err(|e| err(e.to_string()))?;
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .position(legend.clone())
                .draw()
                .map_err(|e| err(e.to_string()))?;
        }
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok(buf)
}

/// One heat-map panel: values on a (log-spaced) grid, coloured by log10(value).
pub struct HeatPanel {
    pub title: String,
    /// Grid axes (x = columns, y = rows), positive.
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// values[iy][ix] > 0 (non-positive values drawn grey)
    pub values: Vec<Vec<f64>>,
    /// Colour range in log10 units.
    pub log_range: (f64, f64),
    pub x_label: String,
    pub y_label: String,
    /// Log-scaled axes (positive grid values) or linear ones.
    pub log_axes: bool,
    /// Draw the first row at the top (a table's row order) instead of the bottom.
    pub y_down: bool,
    /// What the colour bar measures (its label, e.g. "log10 relative L2").
    pub colour_label: String,
}

fn viridis_like(t: f64) -> RGBColor {
    // a perceptually ordered dark-blue → green → yellow ramp
    let t = t.clamp(0.0, 1.0);
    let stops = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let x = t * (stops.len() - 1) as f64;
    let i = (x.floor() as usize).min(stops.len() - 2);
    let f = x - i as f64;
    let lerp = |a: f64, b: f64| (a + (b - a) * f).round() as u8;
    RGBColor(
        lerp(stops[i].0, stops[i + 1].0),
        lerp(stops[i].1, stops[i + 1].1),
        lerp(stops[i].2, stops[i + 1].2),
    )
}

/// Render heat-map panels side by side (log-log axes, log10 colour scale given per panel).
pub fn heatmap_svg(panels: &[HeatPanel], width: u32, height: u32) -> Result<String> {
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (width, height)).into_drawing_area();
        let err = |e: String| Error::InvalidArgument(format!("plot: {e}"));
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let areas = root.split_evenly((1, panels.len().max(1)));
        for (whole, p) in areas.iter().zip(panels) {
            // each panel: the map and, at its right, a colour bar in log10 units
            let bar_w = 95.min(whole.dim_in_pixel().0 / 4);
            let (area, bar) = whole.split_horizontally(whole.dim_in_pixel().0 - bar_w);
            colour_bar(&bar, p).map_err(err)?;
            let area = &area;
            // log axes are drawn as linear axes in log10 units, labelled with the values
            // themselves (plotters' log scale labels crowd or vanish over one decade)
            let log = p.log_axes;
            let tr = |v: f64| if log { v.log10() } else { v };
            let edges = |v: &[f64]| -> Vec<f64> {
                let v: Vec<f64> = v.iter().map(|&x| tr(x)).collect();
                let n = v.len();
                let mut e = Vec::with_capacity(n + 1);
                e.push(v[0] - 0.5 * (v[1] - v[0]));
                for i in 0..n - 1 {
                    e.push(0.5 * (v[i] + v[i + 1]));
                }
                e.push(v[n - 1] + 0.5 * (v[n - 1] - v[n - 2]));
                e
            };
            let (ex, ey) = (edges(&p.x), edges(&p.y));
            let title = format!(
                "{} (log10: {:.1} … {:.1})",
                p.title, p.log_range.0, p.log_range.1
            );
            let (x0, x1, y0, y1) = (ex[0], ex[ex.len() - 1], ey[0], ey[ey.len() - 1]);
            // y_down: the axis runs from the last edge (bottom) to the first (top)
            let (y0, y1) = if p.y_down { (y1, y0) } else { (y0, y1) };
            let label = |v: &f64| {
                if log {
                    let x = 10f64.powf(*v);
                    if (1e-3..1e3).contains(&x) {
                        format!("{:.3}", x)
                            .trim_end_matches('0')
                            .trim_end_matches('.')
                            .to_string()
                    } else {
                        format!("{x:.1e}")
                    }
                } else {
                    format!("{v:.2}")
                }
            };
            let mut chart = ChartBuilder::on(area)
                .caption(title.as_str(), ("sans-serif", 14))
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(50)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| err(e.to_string()))?;
            chart
                .configure_mesh()
                .x_desc(p.x_label.as_str())
                .y_desc(p.y_label.as_str())
                .x_labels(5)
                .y_labels(8)
                .x_label_formatter(&label)
                .y_label_formatter(&label)
                .disable_mesh()
                .draw()
                .map_err(|e| err(e.to_string()))?;
            draw_cells(&mut chart, p, &ex, &ey).map_err(err)?;
        }
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok(buf)
}

/// A vertical colour bar for `p`'s log10 range, labelled with `p.colour_label`.
fn colour_bar(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    p: &HeatPanel,
) -> std::result::Result<(), String> {
    let (lo, hi) = p.log_range;
    let mut chart = ChartBuilder::on(area)
        .margin_top(40)
        .margin_bottom(45)
        .margin_right(5)
        .y_label_area_size(45)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .disable_x_axis()
        .disable_mesh()
        .y_desc(p.colour_label.as_str())
        .label_style(("sans-serif", 11))
        .axis_desc_style(("sans-serif", 11))
        .y_label_formatter(&|y| format!("{y:.1}"))
        .draw()
        .map_err(|e| e.to_string())?;
    let n = 64;
    chart
        .draw_series((0..n).map(|k| {
            let a = lo + (hi - lo) * k as f64 / n as f64;
            let b = lo + (hi - lo) * (k + 1) as f64 / n as f64;
            let c = viridis_like((k as f64 + 0.5) / n as f64);
            Rectangle::new([(0.0, a), (1.0, b)], c.filled())
        }))
        .map_err(|e| e.to_string())?;
    Ok(())
}

fn draw_cells<X, Y>(
    chart: &mut ChartContext<'_, SVGBackend<'_>, Cartesian2d<X, Y>>,
    p: &HeatPanel,
    ex: &[f64],
    ey: &[f64],
) -> std::result::Result<(), String>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let (lo, hi) = p.log_range;
    chart
        .draw_series(p.values.iter().enumerate().flat_map(|(iy, row)| {
            row.iter().enumerate().map(move |(ix, &v)| {
                let c = if v > 0.0 {
                    viridis_like((v.log10() - lo) / (hi - lo))
                } else {
                    RGBColor(200, 200, 200)
                };
                Rectangle::new([(ex[ix], ey[iy]), (ex[ix + 1], ey[iy + 1])], c.filled())
            })
        }))
        .map_err(|e| e.to_string())?;
    Ok(())
}

//! The heat map of an LTC table's held-out error over its grid: one picture the GGX
//! table study and the lobe table studies both draw, so it lives beside them rather than
//! in either.

use crate::error::Result;
use crate::ltc::fit::Table;
use crate::report::plot::{heatmap_svg, HeatPanel};

/// The heat-map panel of an LTC table's held-out relative L2 error over (r = √α, t =
/// √(1 − cos θ)), one colour per cell on a log scale from 1e-4 to 1.
pub fn ltc_error_panel(main: &Table, title: &str) -> HeatPanel {
    let n = main.grid.n;
    HeatPanel {
        title: title.into(),
        x: (0..n).map(|i| main.grid.alpha(i).sqrt()).collect(),
        y: (0..n)
            .map(|j| (1.0 - main.grid.theta(j).cos()).max(0.0).sqrt())
            .collect(),
        values: (0..n)
            .map(|j| {
                (0..n)
                    .map(|i| {
                        main.cells[j][i]
                            .l2()
                            .map_or(f64::NAN, |b| b.value)
                            .max(1e-8)
                    })
                    .collect()
            })
            .collect(),
        log_range: (-4.0, 0.0),
        x_label: "r = √α".into(),
        y_label: "t = √(1 − cos θ)  (t = 0: normal incidence, top)".into(),
        log_axes: false,
        y_down: true,
        colour_label: "log10 relative L2 (held out)".into(),
    }
}

/// The heat map of one LTC table's error ([`ltc_error_panel`]).
pub fn ltc_error_heatmap(main: &Table, title: &str) -> Result<String> {
    heatmap_svg(&[ltc_error_panel(main, title)], 720, 620)
}

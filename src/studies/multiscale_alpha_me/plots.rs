//! The plots of the α_me study: the error of every method beyond the fit domain on both
//! sides, and α_me against 1 − ‖b̄‖ (formats only: the curves are computed with the study).

use super::compute::Curves;
use crate::error::Result;
use crate::report::plot::{loglog_svg, Panel, Series};

/// (results/multiscale-alpha-error.svg, results/multiscale-alpha-me.svg).
pub(super) fn render(k: &Curves) -> Result<(String, String)> {
    let series = |v: &[(String, Vec<(f64, f64)>)]| -> Vec<Series> {
        v.iter()
            .map(|(name, points)| Series {
                name: name.clone(),
                points: points.clone(),
            })
            .collect()
    };
    let svg_err = loglog_svg(
        &[
            Panel {
                title: "relative error of α_me(‖b̄‖)".into(),
                x_label: "true α".into(),
                y_label: "|α_fit − α| / α".into(),
                series: series(&k.rel),
            },
            Panel {
                title: "absolute error of paper Eq 5".into(),
                x_label: "true α".into(),
                y_label: "|α_Eq5 − α|".into(),
                series: vec![Series {
                    name: "paper Eq 5".into(),
                    points: k.abs_eq5.clone(),
                }],
            },
        ],
        1400,
        520,
    )?;
    let svg_mrl = loglog_svg(
        &[Panel {
            title: "α_me against 1 − ‖b̄‖ (exact closed form vs fits; Eq 5 is drawn only where positive)".into(),
            x_label: "1 − ‖b̄‖".into(),
            y_label: "α_me".into(),
            series: series(&k.mrl),
        }],
        900,
        560,
    )?;
    Ok((svg_err, svg_mrl))
}

//! The plots of the α_me study: the error of every method beyond the fit domain on both
//! sides, and α_me against 1 − ‖b̄‖.

use super::compute::Computed;
use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::multiscale::alpha_me::{held_out_alphas, paper_form, paper_method};
use crate::multiscale::mrl::{alpha_from_one_minus, alpha_me_paper, mrl_pair};
use crate::report::plot::{loglog_svg, Panel, Series};

/// (results/multiscale-alpha-error.svg, results/multiscale-alpha-me.svg).
pub(super) fn render(spec: &FitSpec, k: &Computed) -> Result<(String, String)> {
    let Computed {
        lo,
        hi,
        ref c,
        ref refit,
        ref table,
        ..
    } = *k;
    // error curves beyond the fit domain on both sides
    let curve: Vec<f64> = held_out_alphas(400, 0.01 * lo, 10.0 * hi);
    let rel = |f: &dyn Fn(f64, f64) -> f64| -> Vec<(f64, f64)> {
        curve
            .iter()
            .map(|&a| {
                let (b, y) = mrl_pair(a);
                (a, ((f(b, y) - a) / a).abs().max(1e-17))
            })
            .collect()
    };
    let abs_curve: Vec<(f64, f64)> = curve
        .iter()
        .map(|&a| {
            let (b, _) = mrl_pair(a);
            (a, (alpha_me_paper(b) - a).abs().max(1e-17))
        })
        .collect();
    let svg_err = loglog_svg(
        &[
            Panel {
                title: "relative error of α_me(‖b̄‖)".into(),
                x_label: "true α".into(),
                y_label: "|α_fit − α| / α".into(),
                series: vec![
                    Series {
                        name: "paper Eq 5".into(),
                        points: rel(&paper_method),
                    },
                    Series {
                        name: "paper form, refitted".into(),
                        points: rel(&|b, _y| paper_form(&refit.params, b)),
                    },
                    Series {
                        name: format!("ours ({} + {} terms)", spec.terms, spec.terms_large),
                        points: rel(&|_b, y| c.eval(y)),
                    },
                    Series {
                        name: format!("table ({} entries)", spec.table_entries),
                        points: rel(&|_b, y| table.eval(y)),
                    },
                ],
            },
            Panel {
                title: "absolute error of paper Eq 5".into(),
                x_label: "true α".into(),
                y_label: "|α_Eq5 − α|".into(),
                series: vec![Series {
                    name: "paper Eq 5".into(),
                    points: abs_curve,
                }],
            },
        ],
        1400,
        520,
    )?;
    let mrl_curve = |f: &dyn Fn(f64, f64) -> f64| -> Vec<(f64, f64)> {
        curve
            .iter()
            .filter_map(|&a| {
                let (b, y) = mrl_pair(a);
                let v = f(b, y);
                (v > 0.0).then_some((y, v))
            })
            .collect()
    };
    let svg_mrl = loglog_svg(
        &[Panel {
            title: "α_me against 1 − ‖b̄‖ (exact closed form vs fits; Eq 5 is drawn only where positive)".into(),
            x_label: "1 − ‖b̄‖".into(),
            y_label: "α_me".into(),
            series: vec![
                Series { name: "exact (closed form inverse)".into(), points: mrl_curve(&|_b, y| alpha_from_one_minus(y).unwrap_or(f64::NAN)) },
                Series { name: "paper Eq 5".into(), points: mrl_curve(&paper_method) },
                Series { name: "ours".into(), points: mrl_curve(&|_b, y| c.eval(y)) },
            ],
        }],
        900,
        560,
    )?;
    Ok((svg_err, svg_mrl))
}

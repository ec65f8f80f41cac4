//! The compact forms under the polygon lights each table's own study checks it with
//! (results/fits/<table>.json: four cells × the four quads of
//! `ltc::polygon::check_lights`, each with its Monte Carlo truth ± s.e.): the full table's
//! binary16 entries read bilinearly, each form rebuilt (binary16, bilinear) and each
//! texture-free form (f32) at the cell's (α, θ), shaded as norm × the exact LTC integral
//! of the polygon. The error per form is the mean squared difference from the truth,
//! estimated without bias (mean of (value − MC)² − s.e.²) with its standard error: no
//! ratio of noisy sums.

use crate::error::Result;
use crate::integrate::Figure;
use crate::ltc::compact::Compact;
use crate::ltc::fit::inverse_from_production;
use crate::ltc::polygon::{check_lights, ltc_integral, EdgeForm};
use crate::ltc::table::FittedTable;
use crate::results::ltc_compact::{PolygonFigures, PolygonSet};

/// The rows' (α, θ, light, truth), and the light's vertices for each.
type Rows = Vec<((f64, f64, String, Figure), Vec<nalgebra::Vector3<f64>>)>;

/// The rows of a table's own polygon checks: the GGX study's `polygons` (θ in radians),
/// or a lobe study's `report.polygons` ((α, θ°, albedo, check)); `None` where the file
/// holds none.
fn rows(results: &std::path::Path, table: &str) -> Result<Option<Rows>> {
    // the polygon rows alone (the file's tables are read by `family` already)
    let checks: Vec<(f64, f64, crate::ltc::polygon::PolygonCheck)> =
        if table == crate::results::names::LTC_GGX {
            #[derive(serde::Deserialize)]
            struct P {
                polygons: Vec<crate::results::ltc::PolygonRow>,
            }
            let g: P = crate::results::require_named(results, table)?;
            g.polygons
                .into_iter()
                .map(|r| {
                    (
                        r.alpha,
                        r.theta,
                        crate::ltc::polygon::PolygonCheck {
                            light: r.light,
                            mc: r.mc,
                            ltc_exact: r.ltc_exact,
                            ltc_rational: r.ltc_rational,
                        },
                    )
                })
                .collect()
        } else {
            #[derive(serde::Deserialize)]
            struct R {
                #[serde(default)]
                polygons: Vec<(f64, f64, f64, crate::ltc::polygon::PolygonCheck)>,
            }
            #[derive(serde::Deserialize)]
            struct P {
                report: R,
            }
            let g: P = crate::results::require_named(results, table)?;
            g.report
                .polygons
                .into_iter()
                .map(|(a, deg, _, c)| (a, deg.to_radians(), c))
                .collect()
        };
    let mut out = Vec::new();
    for (alpha, theta, c) in checks {
        let Some((_, light)) = check_lights(theta).into_iter().find(|(n, _)| *n == c.light) else {
            return Err(crate::error::Error::InvalidArgument(format!(
                "results/fits/{table}.json: a polygon row of unknown light {}",
                crate::error::quoted(&c.light)
            )));
        };
        out.push(((alpha, theta, c.light, c.mc), light.vertices));
    }
    Ok((!out.is_empty()).then_some(out))
}

/// norm × the exact LTC integral of each row's light for the entries `at(α, θ)` gives.
fn figures(rows: &Rows, at: impl Fn(f64, f64) -> [f64; 5]) -> PolygonFigures {
    let values: Vec<f64> = rows
        .iter()
        .map(|((a, th, _, _), v)| {
            let e = at(*a, *th);
            e[4] * ltc_integral(
                &inverse_from_production(&[e[0], e[1], e[2], e[3]]),
                v,
                EdgeForm::Exact,
            )
        })
        .collect();
    let m = values.len().max(1) as f64;
    let (mut sum, mut var) = (0.0, 0.0);
    for (v, ((_, _, _, t), _)) in values.iter().zip(rows) {
        let (d, se) = (v - t.value, t.error);
        sum += d * d - se * se;
        // Var[(v − MC)²] = 4(v − T)²σ² + 2σ⁴ for Gaussian MC error, (v − T) estimated by
        // (v − MC)
        var += 4.0 * d * d * se * se + 2.0 * se.powi(4);
    }
    PolygonFigures {
        values,
        mse: Figure::with_se(sum / m, var.sqrt() / m),
    }
}

/// The set for one table, or `None` where its study has no polygon rows.
pub(super) fn measure(
    results: &std::path::Path,
    table_name: &str,
    table: &FittedTable,
    forms: &[(String, Compact)],
) -> Result<Option<PolygonSet>> {
    let Some(rows) = rows(results, table_name)? else {
        return Ok(None);
    };
    let five = |e: [f64; 6]| [e[0], e[1], e[2], e[3], e[4]];
    let full = figures(&rows, |a, th| five(table.bilinear(a, th.cos(), true)));
    let mut rebuilt = Vec::new();
    let mut texture_free = Vec::new();
    for (_, f) in forms {
        let t = f.rebuild(table.n)?;
        rebuilt.push(figures(&rows, |a, th| five(t.bilinear(a, th.cos(), true))));
        let c32 = f.coeffs_f32();
        texture_free.push(figures(&rows, |a, th| {
            let r = a.clamp(0.0, 1.0).sqrt() as f32;
            let tt = (1.0 - th.cos().clamp(0.0, 1.0)).sqrt() as f32;
            five(f.eval_f32(&c32, r, tt).map(f64::from))
        }));
    }
    Ok(Some(PolygonSet {
        truth: rows.into_iter().map(|(t, _)| t).collect(),
        full,
        rebuilt,
        texture_free,
    }))
}

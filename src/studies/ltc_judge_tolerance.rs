//! `regen --only ltc-judge-tolerance` (on request): the held-out judge's accuracy against
//! its work, the curve each LTC table's spec chooses its `held_out_rel` from.
//!
//! For each table the main job fits (GGX, the Estevez–Kulla sheen, the paper's Burley
//! diffuse; the published files), every `every`-th cell along each axis is judged by
//! `ltc::lobe_error::judge` in the four precisions a table's judge sees (`ltc::held::
//! precisions`) at each relative tolerance of `rels`, the first (the tightest) the
//! reference. Per tolerance:
//!
//! - the work: integrand evaluations per cell (deterministic, unlike a wall clock);
//! - the mean relative L2 of the f64 cells within the mean of their bars, and the largest
//!   bar;
//! - the largest change of a cell's relative L2 or L1 against the reference, and how many
//!   changes exceed the two bars together. Each bar is the cubature's error estimate (a
//!   multiple of the K15 ⊗ K15 − G7 ⊗ G7 difference), not a proof, so this count is the
//!   check that the bars a tolerance reports still bound their figures.
//!
//! The anisotropic GGX table (ltc-aniso) is judged the same way on every `aniso_every`-th
//! fitted cell, its f64 cells only (its study judges one precision).
//!
//! A second curve holds the relative L2's tolerance at the table's own (`held_out_rel`)
//! and sweeps the relative L1's alone (`l1_rels`, the table's `held_out_l1_rel`): |f − g|
//! has kinks where f = g, so at equal tolerances the L1 figure sets most of the work.
//!
//! Writes results/ltc-judge-tolerance.{md,svg} and results/fits/ltc-judge-tolerance.json.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::{Figure, Preset, Quad};
use crate::io::Outputs;
use crate::ltc::lobe_error::{judge, LobeError, Tolerance};
use crate::ltc::lobes::Lobe;
use crate::ltc::target::{GgxTarget, LtcTarget};
use crate::report::table::{Align, Table};
use crate::results::ltc::{JudgeCurve, JudgePoint, JudgeTolerance};
use crate::study::{Ctx, FitOutcome};

/// What fits/ltc-judge-tolerance.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Judge every `every`-th cell along each axis of each table.
    pub every: usize,
    /// The relative tolerances, strictly increasing; the first is the reference.
    pub rels: Vec<f64>,
    /// The relative L1's tolerances of the second curve, strictly increasing (the relative
    /// L2 at the table's `held_out_rel`); judged against the same reference.
    pub l1_rels: Vec<f64>,
    /// Judge every `aniso_every`-th fitted cell of the anisotropic table.
    pub aniso_every: usize,
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        crate::fit::spec::within("every", self.every, 1, 64)?;
        crate::fit::spec::within("aniso_every", self.aniso_every, 1, 4096)?;
        crate::fit::spec::within("rels (its length)", self.rels.len(), 2, 16)?;
        crate::fit::spec::within("l1_rels (its length)", self.l1_rels.len(), 1, 16)?;
        for &r in &self.rels {
            Tolerance::check_relative(r)?;
        }
        for &r in &self.l1_rels {
            Tolerance::check_relative_l1(r)?;
        }
        for (key, v) in [("rels", &self.rels), ("l1_rels", &self.l1_rels)] {
            if !v.windows(2).all(|w| w[0] < w[1]) {
                return Err(format!(
                    "{key} = {v:?} must increase strictly (the first of rels is the reference)"
                ));
            }
        }
        Ok(())
    }
}

/// The keys of a published table's spec this study reads.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
struct Chosen {
    /// A spec from before the key judged to the default tolerance.
    #[serde(default = "crate::ltc::lobe_error::Tolerance::default_relative")]
    held_out_rel: f64,
    /// A spec from before the key judged the relative L1 to `held_out_rel`.
    #[serde(default)]
    held_out_l1_rel: Option<f64>,
}

impl crate::fit::spec::Params for Chosen {
    fn check(&self) -> std::result::Result<(), String> {
        Tolerance::check_relative(self.held_out_rel)?;
        self.held_out_l1_rel
            .map_or(Ok(()), Tolerance::check_relative_l1)
    }
}

/// The tables judged: file name and lobe (`None`: GGX).
const TABLES: [(&str, Option<Lobe>); 3] = [
    ("ltc-ggx", None),
    ("ltc-sheen", Some(Lobe::SheenEstevezKulla)),
    ("ltc-diffuse", Some(Lobe::BurleyPaper)),
];

/// What the study computed.
pub struct Computed {
    result: JudgeTolerance,
}

/// The study: every table's curve.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let pl: Plan = c.params()?;
    let mut tables = Vec::new();
    for (name, lobe) in TABLES {
        crate::report::stage(&format!("regen ltc-judge-tolerance: {name}"));
        tables.push(match lobe {
            None => curve(c.results, name, &GgxTarget::new, &pl)?,
            Some(l) => curve(c.results, name, &move |a, t| l.target(a, t), &pl)?,
        });
    }
    crate::report::stage("regen ltc-judge-tolerance: ltc-aniso");
    tables.push(aniso_curve(c.results, &pl)?);
    Ok(Computed {
        result: JudgeTolerance {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            tables,
        },
    })
}

/// One table's curve (see the module doc).
fn curve<T: LtcTarget>(
    results: &std::path::Path,
    name: &str,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    pl: &Plan,
) -> Result<JudgeCurve> {
    let (p, table, _) = crate::results::ltc::published_table(results, name)?;
    let (_, chosen) = p.chosen::<Chosen>(name)?;
    let (n, grid) = (table.n, p.grid);
    let cells: Vec<(usize, usize)> = (0..n)
        .step_by(pl.every)
        .flat_map(|j| (0..n).step_by(pl.every).map(move |i| (i, j)))
        .collect();
    let judged: Vec<Vec<Option<LobeError>>> = tolerances(pl, &chosen)
        .iter()
        .map(|(tag, tol)| {
            let label = format!("judge tolerance {name} {tag}");
            crate::memo::map_items(&label, &cells, |&(i, j)| {
                let k = i + n * j;
                let e = table.cells[k];
                let full = [e[0], e[1], e[2], e[3], e[4]];
                let stored = match &table.half {
                    Some(h) => std::array::from_fn(|q| h[k][q].to_f64()),
                    None => full.map(|x| half::f16::from_f64(x).to_f64()),
                };
                let t = target(grid.alpha(i), grid.theta(j))?;
                let inv = crate::ltc::held::precisions(full, stored);
                Ok(judge(&t, e[4], &inv, *tol)[0])
            })
        })
        .collect::<Result<_>>()?;
    let sha = crate::results::fits_sha256(results, name)?;
    Ok(assemble(name, cells.len(), &chosen, pl, &judged, sha))
}

/// The tolerances every curve judges, in order: the plan's `rels` (both figures), then its
/// `l1_rels` with the relative L2 at the table's own; each tagged for the memo's label.
fn tolerances(pl: &Plan, chosen: &Chosen) -> Vec<(String, Tolerance)> {
    pl.rels
        .iter()
        .map(|&r| (format!("{r:e}"), Tolerance::relative(r)))
        .chain(pl.l1_rels.iter().map(|&r| {
            (
                format!("{:e} L1 {r:e}", chosen.held_out_rel),
                Tolerance::figures(chosen.held_out_rel, r),
            )
        }))
        .collect()
}

/// A table's two curves from its cells judged at [`tolerances`] (in that order), with the
/// SHA-256 of the table file it judged (`results::fits_sha256`).
fn assemble(
    name: &str,
    cells: usize,
    chosen: &Chosen,
    pl: &Plan,
    judged: &[Vec<Option<LobeError>>],
    table_sha256: String,
) -> JudgeCurve {
    let reference = &judged[0];
    let (overall, l1) = judged.split_at(pl.rels.len());
    let points = pl
        .rels
        .iter()
        .zip(overall)
        .map(|(&rel, v)| point(rel, v, reference))
        .collect();
    let l1_points = pl
        .l1_rels
        .iter()
        .zip(l1)
        .map(|(&rel, v)| point(rel, v, reference))
        .collect();
    JudgeCurve {
        table: name.into(),
        cells,
        chosen_rel: chosen.held_out_rel,
        chosen_l1_rel: chosen.held_out_l1_rel.unwrap_or(chosen.held_out_rel),
        points,
        l1_points,
        table_sha256: Some(table_sha256),
    }
}

/// What a published file holds of the study that wrote it.
#[derive(serde::Deserialize)]
struct PublishedSpec {
    spec: FitSpec,
    preset: String,
}

/// The anisotropic GGX table's curves: every `aniso_every`-th fitted cell (α_x ≥ α_y, the
/// diagonal up to φ = π/4, in the fit's order), its f64 production inverse and norm against its own target (the
/// ltc-aniso study's held-out judge, one precision).
fn aniso_curve(results: &std::path::Path, pl: &Plan) -> Result<JudgeCurve> {
    use crate::ltc::aniso::inverse_of;
    use crate::ltc::aniso::AnisoGgxTarget;
    use crate::ltc::aniso_table::inv7;
    let name = crate::results::names::LTC_ANISO;
    let table = crate::results::ltc_aniso::aniso_table(results)?;
    let p: PublishedSpec = crate::results::require_named(results, name)?;
    let preset = Preset::named(&p.preset, &format!("results/fits/{name}.json"))?;
    let chosen: Chosen = p.spec.params(preset)?;
    let g = table.grid;
    let cells: Vec<(usize, usize, usize, usize)> = g
        .fitted_cells()
        .into_iter()
        .step_by(pl.aniso_every)
        .collect();
    let judged: Vec<Vec<Option<LobeError>>> = tolerances(pl, &chosen)
        .iter()
        .map(|(tag, tol)| {
            let label = format!("judge tolerance {name} {tag}");
            crate::memo::map_items(&label, &cells, |&(ix, iy, k, j)| {
                let c = table.cells[g.index(ix, iy, k, j)];
                let t = AnisoGgxTarget::new(g.alpha(ix), g.alpha(iy), g.theta(j), g.phi(k))?;
                Ok(judge(&t, c[7], &[(inverse_of(&inv7(&c)), c[7])], *tol)[0])
            })
        })
        .collect::<Result<_>>()?;
    let sha = crate::results::fits_sha256(results, name)?;
    Ok(assemble(name, cells.len(), &chosen, pl, &judged, sha))
}

/// One tolerance's figures against the reference's, cell by cell.
fn point(rel: f64, v: &[Option<LobeError>], reference: &[Option<LobeError>]) -> JudgePoint {
    let l2: Vec<Figure<Quad>> = v.iter().flatten().map(|e| e.l2).collect();
    let l1: Vec<Figure<Quad>> = v.iter().flatten().map(|e| e.l1).collect();
    let both = |e: &LobeError| [e.l2, e.l1];
    let mut largest_change: f64 = 0.0;
    let mut beyond_bars = 0;
    for (e, r) in v.iter().zip(reference) {
        if let (Some(e), Some(r)) = (e, r) {
            for (a, b) in both(e).iter().zip(both(r)) {
                let d = (a.value - b.value).abs();
                largest_change = largest_change.max(d);
                beyond_bars += usize::from(d > a.error + b.error);
            }
        }
    }
    // over the cells judged (a singular cell has no figures and no count)
    let cells = v.iter().flatten().count().max(1) as f64;
    JudgePoint {
        rel,
        evals_per_cell: v.iter().flatten().map(|e| e.evals as f64).sum::<f64>() / cells,
        l2_mean: Figure::mean_bounded(&l2),
        l1_mean: Figure::mean_bounded(&l1),
        largest_bar: v
            .iter()
            .flatten()
            .flat_map(|e| both(e).map(|f| f.error))
            .fold(0.0, f64::max),
        largest_change,
        beyond_bars,
        unconverged: v.iter().filter(|e| !e.is_some_and(|e| e.converged)).count(),
    }
}

fn markdown(r: &JudgeTolerance) -> String {
    let mut md = format!(
        "# The held-out judge: accuracy against work\n\nWritten by `{}` (preset {}) from `fits/{}.toml`, on request (the main job leaves it out). Each LTC table's held-out figures are integrals by adaptive cubature (`ltc::lobe_error`) refined until each figure's bar is below a relative tolerance; this is the curve that tolerance is chosen from (each table spec's `held_out_rel`). Per table: the cells of the published file judged (every `every`-th along each axis), in the four precisions its judge sees together (f64, f32, binary16 nearest, the stored binary16; the anisotropic table: every `aniso_every`-th fitted cell, f64 only, as its study judges it, so its evaluations per cell count one precision); the figures are the f64 cells'. Work is integrand evaluations per cell (what the judge's time is proportional to, and deterministic). A change beyond both bars is a cell whose relative L2 or L1 moved from the reference tolerance's by more than the two bars together: the bars are the cubature's error estimates, and this counts where one failed to bound its figure.\n\n![accuracy against work](ltc-judge-tolerance.svg)\n\n",
        r.command, r.preset, r.spec.name
    );
    for c in &r.tables {
        let reference = c.points.first().map_or(f64::NAN, |p| p.evals_per_cell);
        md.push_str(&format!(
            "## {} ({} cells; the table's tolerance {:e})\n\n",
            c.table, c.cells, c.chosen_rel
        ));
        let t = curve_table(&c.points, c.chosen_rel, reference, false);
        md.push_str(&format!("{t}\n"));
        md.push_str(&l1_section(c, reference));
    }
    md
}

/// The second curve of a table: the relative L2 at its tolerance, the relative L1's swept.
fn l1_section(c: &JudgeCurve, reference: f64) -> String {
    let mut md = format!(
        "The relative L1's own tolerance, the relative L2's held at {:e} (the table's `held_out_l1_rel` is {:e}); changes against the same reference:\n\n",
        c.chosen_rel, c.chosen_l1_rel
    );
    let t = curve_table(&c.l1_points, c.chosen_l1_rel, reference, true);
    md.push_str(&format!("{t}\n"));
    md
}

/// One curve as a table: a row per tolerance (the spec's marked), the work against the
/// reference's, the mean figures (the relative L1's first on the L1 curve), the bars and
/// the changes.
fn curve_table(points: &[JudgePoint], chosen: f64, reference: f64, l1: bool) -> Table {
    let mut head = vec![if l1 {
        "L1 tolerance"
    } else {
        "relative tolerance"
    }];
    head.extend(["evaluations per cell", "of the reference's"]);
    if l1 {
        head.push("mean relative L1");
    }
    head.extend([
        "mean relative L2",
        "largest bar (points)",
        "largest change (points)",
        "changes beyond both bars",
        "cells not converged",
    ]);
    let cols = head.len();
    let mut t = Table::new(head);
    for col in 1..cols {
        t = t.align(col, Align::Right);
    }
    for p in points {
        let mark = if p.rel == chosen {
            " (the table's)"
        } else {
            ""
        };
        let mut row = vec![
            format!("{:e}{mark}", p.rel),
            format!("{:.0}", p.evals_per_cell),
            format!("{:.2}", p.evals_per_cell / reference),
        ];
        if l1 {
            row.push(p.l1_mean.pct_fixed(5));
        }
        row.extend([
            p.l2_mean.pct_fixed(5),
            format!("{:.5}", 100.0 * p.largest_bar),
            format!("{:.5}", 100.0 * p.largest_change),
            p.beyond_bars.to_string(),
            p.unconverged.to_string(),
        ]);
        t.row(row);
    }
    t
}

fn plot(r: &JudgeTolerance) -> Result<String> {
    use crate::report::plot::{loglog_svg, Panel, Series};
    let series = |y: &dyn Fn(&JudgePoint) -> f64| -> Vec<Series> {
        r.tables
            .iter()
            .map(|c| Series {
                name: c.table.clone(),
                points: c
                    .points
                    .iter()
                    .map(|p| (p.evals_per_cell, 100.0 * y(p)))
                    .collect(),
            })
            .collect()
    };
    loglog_svg(
        &[
            Panel {
                title: "Bar of the mean relative L2 against work".into(),
                x_label: "integrand evaluations per cell".into(),
                y_label: "mean bar (percentage points)".into(),
                series: series(&|p| p.l2_mean.error),
            },
            Panel {
                title: "Bar of the mean relative L1 against work (L2 at the table's tolerance)"
                    .into(),
                x_label: "integrand evaluations per cell".into(),
                y_label: "mean L1 bar (percentage points)".into(),
                series: r
                    .tables
                    .iter()
                    .map(|c| Series {
                        name: c.table.clone(),
                        points: c
                            .l1_points
                            .iter()
                            .map(|p| (p.evals_per_cell, 100.0 * p.l1_mean.error))
                            .collect(),
                    })
                    .collect(),
            },
            Panel {
                title: "Largest change against the reference tolerance".into(),
                x_label: "integrand evaluations per cell".into(),
                y_label: "largest |change| (percentage points)".into(),
                series: series(&|p| p.largest_change),
            },
        ],
        1800,
        480,
    )
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        let (md, svg) = (markdown(&self.result), plot(&self.result)?);
        crate::results::put_report(set, results, &md, &svg, &self.result)
    }

    fn outcome(&self) -> FitOutcome {
        // at each table's own tolerance: the changes its bars failed to bound
        let at_chosen: Vec<(String, JudgePoint)> = self
            .result
            .tables
            .iter()
            .filter_map(|c| {
                c.points
                    .iter()
                    .find(|p| p.rel == c.chosen_rel)
                    .map(|p| (c.table.clone(), *p))
            })
            .collect();
        FitOutcome::measured(
            &self.result.spec,
            at_chosen
                .iter()
                .map(|p| p.1.largest_change)
                .fold(0.0, f64::max),
            at_chosen
                .iter()
                .map(|(t, p)| {
                    format!(
                        "{t} at {:e}: {:.0} evaluations per cell, {} changes beyond both bars",
                        p.rel, p.evals_per_cell, p.beyond_bars
                    )
                })
                .collect::<Vec<_>>()
                .join("; "),
        )
    }
}

crate::study::study! {
    /// The held-out judge's accuracy against its work, as the registry holds it.
    LtcJudgeTolerance = "ltc-judge-tolerance", after ["ltc-ggx", "ltc-sheen", "ltc-diffuse", "ltc-aniso"], on request true, params Plan, computes compute
}

//! `regen --only ltc-between-sample` (on request): the curve the between-cell sample size
//! is chosen from. For each published LTC table, every visible square is judged
//! (`studies::ltc_between`: the table interpolated at the square's centre as a shader
//! reads it, against the lobe there), which gives the exact means over every square; then
//! the sample the studies draw (the census of the worst cells' squares and the largest
//! corner jumps, and `sample` more at random) is redrawn `redraws` times per size with
//! its own seed, and each draw's estimate (the difference estimator,
//! `ltc_between::stratified_mean`) is set against the exact mean: the share of draws
//! within two of their standard errors, the bias, the mean squared z and the mean s.e.
//! The figures are the squares' own, so the integrals' error cancels from each draw's
//! error: what is measured is the sample's.
//!
//! Writes results/ltc-between-sample.{md,svg} and results/fits/ltc-between-sample.json.

use crate::error::{Error, Result};
use crate::integrate::{Figure, Preset, Quad};
use crate::io::Outputs;
use crate::ltc::lobe_error::Tolerance;
use crate::ltc::lobes::Lobe;
use crate::ltc::target::{GgxTarget, LtcTarget};
use crate::report::table::{Align, Table};
use crate::results::between::{BetweenSample, Calibration, SampleCurve, SamplePoint};
use crate::studies::ltc_between::{self as between, Cells};
use crate::study::{Ctx, FitOutcome};
use rayon::prelude::*;

/// What fits/ltc-between-sample.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// The published tables judged, by file name ([`TABLES`]).
    pub tables: Vec<String>,
    /// The sample sizes (`between_sample`), strictly increasing.
    pub samples: Vec<usize>,
    /// Draws per size.
    pub redraws: usize,
}

/// The tables this study can judge: file name and lobe (`None`: GGX).
const TABLES: [(&str, Option<Lobe>); 5] = [
    ("ltc-ggx", None),
    ("ltc-sheen", Some(Lobe::SheenEstevezKulla)),
    ("ltc-sheen-neubelt", Some(Lobe::SheenNeubelt)),
    ("ltc-diffuse", Some(Lobe::BurleyPaper)),
    ("ltc-diffuse-engines", Some(Lobe::BurleyEngines)),
];

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::within;
        within("tables (its length)", self.tables.len(), 1, TABLES.len())?;
        for t in &self.tables {
            if !TABLES.iter().any(|(n, _)| n == t) {
                let known: Vec<&str> = TABLES.iter().map(|x| x.0).collect();
                return Err(format!("tables: unknown table '{t}' (known: {known:?})"));
            }
        }
        within("samples (its length)", self.samples.len(), 1, 32)?;
        for &m in &self.samples {
            within("samples", m, 1, 1_000_000)?;
        }
        if !self.samples.windows(2).all(|w| w[0] < w[1]) {
            return Err(format!(
                "samples = {:?} must increase strictly",
                self.samples
            ));
        }
        within("redraws", self.redraws, 10, 100_000)
    }
}

/// The keys of a published table's spec this study reads.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
struct Chosen {
    held_out_rel: f64,
    held_out_l1_rel: f64,
    #[serde(default)]
    between_sample: Option<usize>,
}

impl crate::fit::spec::Params for Chosen {
    fn check(&self) -> std::result::Result<(), String> {
        Tolerance::check_relative(self.held_out_rel)?;
        Tolerance::check_relative_l1(self.held_out_l1_rel)?;
        between::check_sample(self.between_sample)
    }
}

/// What the study computed.
pub struct Computed {
    result: BetweenSample,
}

/// The study: every chosen table's curve.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let pl: Plan = c.params()?;
    let mut tables = Vec::new();
    for (name, lobe) in TABLES {
        if !pl.tables.iter().any(|t| t == name) {
            continue;
        }
        crate::report::stage(&format!("regen ltc-between-sample: {name}"));
        tables.push(match lobe {
            None => curve(c.results, name, &GgxTarget::new, &pl)?,
            Some(l) => curve(c.results, name, &move |a, t| l.target(a, t), &pl)?,
        });
    }
    Ok(Computed {
        result: BetweenSample {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            redraws: pl.redraws,
            tables,
        },
    })
}

/// The published table `name` as the sample design reads it, and its spec's choices.
fn cells_of(results: &std::path::Path, name: &str) -> Result<(Cells, Chosen, Preset)> {
    // the table, its grid's side and every cell's L2 figure checked by the one reader
    let (p, table, _) = crate::results::ltc::published_table(results, name)?;
    let (preset, chosen) = p.chosen::<Chosen>(name)?;
    let n = table.n;
    let bad = |what: &str| Error::InvalidArgument(format!("results/fits/{name}.json: {what}"));
    if n < 2 {
        return Err(bad(&format!("a {n}×{n} table has no square")));
    }
    let (l2, l1) = (&p.held_out_cells.l2, &p.held_out_cells.l1);
    let rows_ok = |g: &Vec<Vec<Option<[f64; 2]>>>| g.len() == n && g.iter().all(|r| r.len() == n);
    if !rows_ok(l2) || !rows_ok(l1) {
        return Err(bad(&format!("held_out_cells is not {n}×{n}")));
    }
    let held = (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            match (l2[j][i], l1[j][i]) {
                (Some(a), Some(b)) if a[0].is_finite() && b[0].is_finite() && b[0] >= 0.0 => {
                    Some([a[0], b[0]])
                }
                (None, None) => None,
                _ => Some([f64::NAN; 2]),
            }
        })
        .collect::<Vec<_>>();
    if held.iter().flatten().any(|h| !h[0].is_finite()) {
        return Err(bad(
            "a cell's held-out figures are not finite and non-negative, or only one is given",
        ));
    }
    let cells = Cells {
        n,
        alpha_min: p.grid.alpha_min,
        entries: table
            .cells
            .iter()
            .map(|e| [e[0], e[1], e[2], e[3], e[4]])
            .collect(),
        held,
    };
    Ok((cells, chosen, preset))
}

/// One table's curve (see the module doc).
fn curve<T: LtcTarget>(
    results: &std::path::Path,
    name: &str,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    pl: &Plan,
) -> Result<SampleCurve> {
    let (c, chosen, preset) = cells_of(results, name)?;
    let tol = Tolerance::figures(chosen.held_out_rel, chosen.held_out_l1_rel);
    let albedos = between::square_albedos(&c, target)?;
    let visible: Vec<usize> = (0..c.squares())
        .filter(|&k| albedos[k] >= between::VISIBLE_ALBEDO)
        .collect();
    if visible.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "results/fits/{name}.json: no square's lobe has an albedo of at least {:e}: nothing to judge between cells",
            between::VISIBLE_ALBEDO
        )));
    }
    let errs = between::judge_squares(&c, target, &albedos, &visible, tol)?;
    let fig = between::figures(&c, &visible, &errs);
    let controls = [between::control(&c, false), between::control(&c, true)];
    let spread = |l1: bool| {
        crate::ltc::lobe_error::Spread::of(
            errs.iter()
                .map(|e| e.as_ref().map(|e| if l1 { &e.l1 } else { &e.l2 })),
        )
    };
    let (s2, s1) = (spread(false), spread(true));
    // the exact means as the estimator counts them: a square without a figure adds 0
    let exact = |l1: bool| {
        fig.iter()
            .flatten()
            .map(|f| f[usize::from(l1)])
            .sum::<f64>()
            / visible.len() as f64
    };
    let exact = [exact(false), exact(true)];
    let points = pl
        .samples
        .iter()
        .map(|&m| point(&c, &visible, (&fig, &controls), exact, m, pl.redraws))
        .collect();
    let published_sample = between::sample_for(name, chosen.between_sample, preset);
    Ok(SampleCurve {
        table: name.into(),
        sha256: crate::results::fits_sha256(results, name)?,
        visible: visible.len(),
        without_figure: errs.iter().filter(|e| e.is_none()).count(),
        exact_l2: Figure::<Quad>::new(exact[0], s2.mean.error),
        exact_l1: Figure::<Quad>::new(exact[1], s1.mean.error),
        published_sample,
        points,
    })
}

/// Seed of draw `r`: the studies' seed for the first, then one apart.
fn seed_of(r: usize) -> u64 {
    between::BETWEEN_SEED.wrapping_add(r as u64)
}

/// One sample size over `redraws` draws (in parallel, each a pure function of its index,
/// so the same bits at any thread count).
fn point(
    c: &Cells,
    visible: &[usize],
    (fig, controls): (&[Option<[f64; 2]>], &[Vec<f64>; 2]),
    exact: [f64; 2],
    m: usize,
    redraws: usize,
) -> SamplePoint {
    let base = between::census(c, visible, m);
    let first = between::draw(base.clone(), m, seed_of(0));
    let judged = first.census.len() + first.drawn.len();
    let estimate = |p: &between::Picked, l1: bool| {
        between::stratified_mean(p, fig, &controls[usize::from(l1)], l1)
    };
    let own = [false, true].map(|l1| estimate(&first, l1));
    let draws: Vec<[[f64; 2]; 2]> = (0..redraws)
        .into_par_iter()
        .map(|r| {
            let p = between::draw(base.clone(), m, seed_of(r));
            [false, true].map(|l1| {
                let est = estimate(&p, l1);
                [est.value - exact[usize::from(l1)], est.error]
            })
        })
        .collect();
    let calib = |q: usize| {
        let exact_all = first.rest.is_empty();
        let v = |f: &dyn Fn(f64, f64) -> f64| -> Vec<f64> {
            draws.iter().map(|d| f(d[q][0], d[q][1])).collect()
        };
        let none = Figure::NONE;
        Calibration {
            coverage: if exact_all {
                none
            } else {
                Figure::mean_of(&v(&|e, s| f64::from(u8::from(e.abs() <= 2.0 * s))))
            },
            bias: Figure::mean_of(&v(&|e, _| e)),
            z2: if exact_all {
                none
            } else {
                Figure::mean_of(&v(&|e, s| (e / s).powi(2)))
            },
            se: Figure::mean_of(&v(&|_, s| s)),
        }
    };
    SamplePoint {
        sample: m,
        judged,
        own,
        l2: calib(0),
        l1: calib(1),
    }
}

fn markdown(r: &BetweenSample) -> String {
    let mut md = format!(
        "# The between-cell sample: accuracy against work\n\nWritten by `{}` (preset {}) from `fits/{}.toml`, on request (the main job leaves it out). A table's error between cells is the mean over its squares (where a shader's bilinear lookup lands) of the held-out relative L2 and L1 of the table interpolated at the square's centre against the lobe there (`studies::ltc_between`). The sheen and diffuse studies judge a sample: the squares touching the 16 worst cells and the quarter of the sample where the corners' entries jump most, always, and the rest of the sample at random; the mean over every square is the census's sum plus the difference estimator with the corners' held-out mean as control, ± its standard error. Here every visible square of each published table is judged (the exact means), and the sample is redrawn {} times per size (draw r with seed 0x005eedb7 + r; the first is the studies' own). Per size: the squares judged per draw, the share of draws within 2 s.e. of the exact mean (0.954 when the s.e. is honest and the estimate normal), the mean error (bias), the mean squared z = error/s.e. (1 when the s.e. is honest) and the mean s.e., each ± its s.e. over the draws. A size the rest does not exceed judges every square (exact; no calibration).\n\n![s.e. and coverage against squares judged](ltc-between-sample.svg)\n\n",
        r.command, r.preset, r.spec.name, r.redraws
    );
    for t in &r.tables {
        let published = if t.published_sample == usize::MAX {
            "every square".to_string()
        } else {
            format!("{}", t.published_sample)
        };
        md.push_str(&format!(
            "## {} ({} visible squares{}; its spec draws: {published})\n\nExact means over every visible square: relative L2 {}, relative L1 {} (± the mean of the squares' integral bars).\n\n",
            t.table,
            t.visible,
            if t.without_figure > 0 {
                format!(", {} without a figure", t.without_figure)
            } else {
                String::new()
            },
            t.exact_l2.pct(4),
            t.exact_l1.pct(4)
        ));
        let head = [
            "sample",
            "judged",
            "draw 0 (the studies'): L2 ± s.e.",
            "L2: within 2 s.e.",
            "L2: bias (points)",
            "L2: mean z²",
            "L2: mean s.e. (points)",
            "L1: within 2 s.e.",
            "L1: bias (points)",
            "L1: mean z²",
            "L1: mean s.e. (points)",
        ];
        let mut tab = (1..head.len()).fold(Table::new(head), |t, c| t.align(c, Align::Right));
        for p in &t.points {
            let mut row = vec![p.sample.to_string(), p.judged.to_string(), p.own[0].pct(4)];
            for c in [&p.l2, &p.l1] {
                row.push(c.coverage.pct(1));
                row.push(c.bias.scaled(100.0).sci_signed(1, 1));
                row.push(c.z2.fixed(2));
                row.push(c.se.scaled(100.0).sci(2, 1));
            }
            tab.row(row);
        }
        md.push_str(&tab.to_string());
        md.push('\n');
    }
    md
}

fn plot(r: &BetweenSample) -> Result<String> {
    use crate::report::plot::{loglog_svg, Panel, Series};
    let series = |y: &dyn Fn(&SamplePoint) -> f64| -> Vec<Series> {
        r.tables
            .iter()
            .map(|t| Series {
                name: t.table.clone(),
                points: t
                    .points
                    .iter()
                    .filter(|p| y(p).is_finite() && y(p) > 0.0)
                    .map(|p| (p.judged as f64, y(p)))
                    .collect(),
            })
            .collect()
    };
    loglog_svg(
        &[
            Panel {
                title: "Mean s.e. of the relative L2's mean against work".into(),
                x_label: "squares judged".into(),
                y_label: "mean s.e. (percentage points)".into(),
                series: series(&|p| 100.0 * p.l2.se.value),
            },
            Panel {
                title: "Draws within 2 s.e. of the exact mean (relative L2)".into(),
                x_label: "squares judged".into(),
                y_label: "share of draws (%)".into(),
                series: series(&|p| 100.0 * p.l2.coverage.value),
            },
        ],
        1200,
        480,
    )
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        let (md, svg) = (markdown(&self.result), plot(&self.result)?);
        crate::results::put_report(set, results, &md, &svg, &self.result)
    }

    fn outcome(&self) -> FitOutcome {
        // at each table's own sample size: how far its coverage falls below 0.954
        let summary: Vec<String> = self
            .result
            .tables
            .iter()
            .map(
                |t| match t.points.iter().find(|p| p.sample == t.published_sample) {
                    Some(p) => format!(
                        "{} at {}: L2 within 2 s.e. in {}, mean s.e. {} points",
                        t.table,
                        p.sample,
                        p.l2.coverage.pct(1),
                        p.l2.se.scaled(100.0).fixed(4)
                    ),
                    None => format!(
                        "{}: exact L2 mean {} over {} squares",
                        t.table,
                        t.exact_l2.pct(4),
                        t.visible
                    ),
                },
            )
            .collect();
        let worst = self
            .result
            .tables
            .iter()
            .flat_map(|t| t.points.iter())
            .map(|p| p.l2.bias.value.abs())
            .fold(0.0, f64::max);
        FitOutcome::measured(&self.result.spec, worst, summary.join("; "))
    }
}

crate::study::study! {
    /// The between-cell sample's accuracy against its work, as the registry holds it.
    LtcBetweenSample = "ltc-between-sample", after ["ltc-ggx", "ltc-sheen", "ltc-diffuse"], on request true, params Plan, computes compute
}

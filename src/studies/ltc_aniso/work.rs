//! `regen --only ltc-aniso-work` (on request): the anisotropic table's accuracy against its
//! fitting work. Does its route do more work than its accuracy needs?
//!
//! The published table's route (fits/ltc-aniso.toml as results/fits/ltc-aniso.json
//! records it: samples per axis, Nelder–Mead cap, three starts per cell) is refitted with
//! the reference fitter's trials on moving samples on other draws of its training samples
//! (`draws`, the strata offset; the draw at the published offset 0.5 is refitted too, and
//! where the table was published on moving samples it is that table, bit for bit), and
//! cheaper routes (`routes`: the published samples and cap scaled, on moving samples or on
//! nodes drawn once from each start, `ltc::aniso::Route`) are fitted on the published
//! draw. Every fit is judged as the study judges its table: each fitted cell's held-out
//! relative L2 (`ltc::lobe_error`, at the published tolerance) ± its bar, and the table
//! between cells at the study's random cases (mean ± s.e.). A route is no worse than the
//! reference by `ltc::spread`'s rule, over the fitted cells. Work: the fits' trial-LTC
//! and target evaluations per cell (`ltc::samples`), counts rather than clocks.
//!
//! Writes results/ltc-aniso-work.md and results/fits/ltc-aniso-work.json.

use super::compute::{between, fit_table, Fitted, Params, Plan};
use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::integrate::{Figure, Preset, Quad};
use crate::io::Outputs;
use crate::ltc::fit::{Nodes, TRAIN_OFFSET};
use crate::ltc::spread::{self, Route};
use crate::results::ltc::{TableWork, WorkRow};
use crate::results::ltc_aniso::{Aniso, AnisoWork};
use crate::study::{Ctx, FitOutcome};

/// What fits/ltc-aniso-work.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkPlan {
    /// Training-set strata offsets of the reference's other draws, each in [0, 1),
    /// distinct, none the published one (0.5).
    pub draws: Vec<f64>,
    /// The routes judged against the reference's spread (`max_iters` scales the
    /// published `iters`).
    pub routes: Vec<Route>,
}

impl crate::fit::spec::Params for WorkPlan {
    fn check(&self) -> std::result::Result<(), String> {
        spread::check_plan(&self.draws, &self.routes)
    }
}

/// One fitted table: its row and its cells' held-out figures, in the fitted cells' order.
struct Fit {
    row: WorkRow,
    cells: Vec<Option<Figure<Quad>>>,
}

/// Fit the table by `pl` (its route and training draw), then judge it between cells.
fn fit(iso: &crate::ltc::table::FittedTable, pl: &Plan) -> Result<Fit> {
    let (table, fitted) = fit_table(iso, pl)?;
    let cases = between(iso, &table, pl)?;
    let errs: Vec<f64> = cases
        .iter()
        .map(|c| c.err_table)
        .filter(|x| x.is_finite())
        .collect();
    let per_cell =
        |f: &dyn Fn(&Fitted) -> f64| fitted.iter().map(f).sum::<f64>() / fitted.len().max(1) as f64;
    let cells: Vec<Option<Figure<Quad>>> = fitted
        .iter()
        .map(|f| (f.err.is_finite() && f.bar.is_finite()).then(|| Figure::new(f.err, f.bar)))
        .collect();
    let row = WorkRow {
        samples: pl.samples,
        max_iters: pl.iters,
        fixed_nodes: pl.nodes != Nodes::Moving,
        fixed_all: false,
        offset: pl.train,
        mean: Figure::mean_bounded(&cells.iter().flatten().copied().collect::<Vec<_>>()),
        between_l2: Some(Figure::mean_of(&errs)),
        between_bar: cases.iter().map(|c| c.bar).reduce(f64::max),
        work_per_cell: Some(per_cell(&|f| f.work as f64)),
        target_evals_per_cell: Some(per_cell(&|f| f.target_evals as f64)),
        iters_per_cell: Some(per_cell(&|f| f.iters as f64)),
    };
    Ok(Fit { row, cells })
}

/// What the study computed.
pub struct Computed {
    spec: FitSpec,
    preset: Preset,
    out: AnisoWork,
}

/// The study: the reference's draws, then every route against them.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let wp: WorkPlan = c.params()?;
    let name = crate::results::names::LTC_ANISO;
    let iso = crate::results::ltc::table(c.results, crate::results::names::LTC_GGX)?;
    let a: Aniso = crate::results::require_named(c.results, name)?;
    let at = format!("results/fits/{name}.json");
    let params: Params = a.spec.params(Preset::named(&a.preset, &at)?)?;
    let published = params.plan();
    let fingerprint = crate::results::ltc_aniso::aniso_table(c.results)?.fingerprint();
    let (samples, iters) = (published.samples, published.iters);
    // a table published on fixed nodes is judged as a route: without it among the plan's
    // routes, the study would leave the published table unjudged
    if published.nodes != Nodes::Moving
        && !wp
            .routes
            .iter()
            .any(|r| r.nodes != Nodes::Moving && r.of(samples, iters) == (samples, iters))
    {
        return Err(Error::InvalidArgument(format!(
            "ltc-aniso-work: {at} was fitted with nodes = \"fixed\" and fits/ltc-aniso-work.toml has no route at its settings on fixed nodes ({{ samples = 1.0, max_iters = 1.0, nodes = \"fixed\" }}): the published table would go unjudged"
        )));
    }
    let with = |samples, iters, nodes, train| Plan {
        samples,
        iters,
        nodes,
        train,
        ..published.clone()
    };
    let mut draws = Vec::new();
    for o in std::iter::once(TRAIN_OFFSET).chain(wp.draws.iter().copied()) {
        crate::report::stage(&format!(
            "regen ltc-aniso-work: the reference route on the training draw at offset {o}"
        ));
        draws.push(fit(&iso, &with(samples, iters, Nodes::Moving, o))?);
    }
    let refs: Vec<&spread::Cells> = draws.iter().map(|d| d.cells.as_slice()).collect();
    let mut routes = Vec::with_capacity(wp.routes.len());
    for r in &wp.routes {
        let (s, i) = r.of(samples, iters);
        // one stage: fixed nodes in every stage are fixed nodes
        let nodes = match r.nodes {
            Nodes::Moving => Nodes::Moving,
            Nodes::Fixed | Nodes::FixedAll => Nodes::Fixed,
        };
        let on = if nodes == Nodes::Moving {
            "moving samples"
        } else {
            "fixed nodes"
        };
        crate::report::stage(&format!(
            "regen ltc-aniso-work: {s}² samples, ≤ {i} iterations per start, {on}"
        ));
        let f = fit(&iso, &with(s, i, nodes, TRAIN_OFFSET))?;
        let v = spread::judge(&refs, &f.cells).ok_or_else(|| {
            Error::InvalidArgument("ltc-aniso-work: tables of unequal size".into())
        })?;
        routes.push((f.row, v));
    }
    Ok(Computed {
        spec: c.spec.clone(),
        preset: c.preset,
        out: AnisoWork {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            work: TableWork {
                table: name.into(),
                table_fingerprint: fingerprint,
                // the published route in words (the anisotropic fit has no polish stage)
                polish: route_words(&published),
                published_nodes: published.nodes,
                draws: draws.into_iter().map(|d| d.row).collect(),
                routes,
            },
        },
    })
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        set.put(
            results.join(format!("{}.md", self.spec.name)),
            super::work_report::markdown(&self.out, self.preset).as_bytes(),
        );
        crate::results::put(set, results, &self.out)
    }

    fn outcome(&self) -> FitOutcome {
        let w = &self.out.work;
        let passed = w.routes.iter().filter(|(_, v)| v.no_worse).count();
        FitOutcome::measured(
            &self.spec,
            w.draws.first().map_or(f64::NAN, |d| d.mean.value),
            format!(
                "{passed} of {} routes no worse than the reference's spread",
                w.routes.len()
            ),
        )
    }
}

/// The published route in words, as the result file keeps it: samples, cap and nodes.
fn route_words(pl: &Plan) -> String {
    format!(
        "{}² stratified samples per technique, Nelder–Mead ≤ {} iterations per start from each of three starts, {}",
        pl.samples,
        pl.iters,
        match pl.nodes {
            Nodes::Moving => "trials on moving samples",
            Nodes::Fixed | Nodes::FixedAll => "trials on fixed nodes",
        }
    )
}

//! `regen --only ltc-work` (on request): the LTC tables' accuracy against their fitting
//! work. Does a published route do more work than its accuracy needs?
//!
//! For each table the main job fits by Nelder–Mead (GGX; the sheen lobes of Estevez &
//! Kulla and of Neubelt), read from its published file:
//!
//! - **The reference's spread.** The reference route (the published spec's samples,
//!   iteration cap and polish, with the reference fitter's trials on moving samples) is
//!   refitted on other draws of its training samples (`draws`: the strata offset,
//!   `ltc::fit::fit_table_drawn`; a table published on moving samples is the draw at 0.5,
//!   one published on fixed nodes is a route, and the reference is refitted at 0.5), each
//!   through the same bilinear pass, binary16 storage and held-out integrals
//!   (`ltc::held::judge_table`, at the published tolerance).
//! - **Cheaper routes** (`routes`: the published samples per axis and iteration cap each
//!   scaled, rounded) go through the same steps on the published draw.
//! - **The rule** (`ltc::spread`): a route is no worse when, against the envelope of the
//!   reference's draws with one left out, it lands above that envelope beyond both bars
//!   in no more cells, and by no more in sum, than the worst left-out draw does.
//! - **Work**: the fit's trial-LTC sample evaluations per cell (`ltc::samples::work`, the
//!   cubic stages and a Nelder–Mead polish), a count rather than a clock, so the file is
//!   the same on every machine; the bilinear pass and the storage choice also scale with
//!   samples² but are not counted.
//!
//! The diffuse table is left out: its published route is already cut to 20 iterations
//! with a Levenberg–Marquardt polish, whose evaluations this count does not see.
//!
//! Writes results/ltc-work.md and results/fits/ltc-work.json.

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::integrate::{Figure, Preset, Quad, StdErr};
use crate::io::Outputs;
use crate::ltc::fit::{fit_table_drawn, Cell, Grid, Metric, Nodes, Polish, TRAIN_OFFSET};
use crate::ltc::lobe_error::Tolerance;
use crate::ltc::lobes::Lobe;
use crate::ltc::spread::{self, Route};
use crate::memo::Memo;
use crate::results::ltc::{LtcWork, TableWork, WorkRow};
use crate::study::{Ctx, FitOutcome};

mod report;

/// The tables judged: the file name of each and its lobe.
const TABLES: [(&str, Lobe); 3] = [
    ("ltc-ggx", Lobe::Ggx),
    ("ltc-sheen", Lobe::SheenEstevezKulla),
    ("ltc-sheen-neubelt", Lobe::SheenNeubelt),
];

/// What fits/ltc-work.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Training-set strata offsets of the published routes' refitted draws, each in
    /// [0, 1), distinct, none the published one (0.5).
    pub draws: Vec<f64>,
    /// The routes judged against each reference's spread.
    pub routes: Vec<Route>,
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        spread::check_plan(&self.draws, &self.routes)
    }
}

/// A fitted table's per-cell held-out relative L2 (f64 cell, `[j][i]` flattened) and its
/// work, target evaluations and iterations per cell.
struct Fitted {
    cells: Vec<Option<Figure<Quad>>>,
    /// The mean relative L2 between cells (`ltc_between::measure`).
    between: Option<Figure<StdErr>>,
    /// The judged squares' mean integral bar.
    between_bar: Option<f64>,
    work: Option<f64>,
    target_evals: Option<f64>,
    iters: Option<f64>,
}

/// Fit `grid` of `lobe` by the route (`samples`, `max_iters`, `polish`, the cubic
/// stage's `nodes`) on the training draw `offset`, then the published table's steps:
/// bilinear pass, storage, held-out judge, and the figure between cells (`between`
/// random squares, `ltc_between::sample_for`).
fn fit(
    lobe: Lobe,
    grid: Grid,
    (samples, max_iters, polish, nodes): (usize, u64, Polish, Nodes),
    (offset, between): (f64, usize),
    tol: Tolerance,
) -> Result<Fitted> {
    let target = move |a: f64, t: f64| lobe.target(a, t);
    let label = format!("ltc work fit: {}", lobe.short());
    let pb = crate::progress::Progress::new(label, (grid.n * grid.n) as u64);
    let route = (Metric::Cubic, nodes.method(), max_iters, polish);
    let mut t = fit_table_drawn(&Memo, grid, &target, samples, route, offset, &|| pb.inc(1))?;
    pb.finish();
    crate::ltc::smooth::bilinear_pass(&Memo, &mut t, &target, samples)?;
    crate::ltc::storage::store_table(&Memo, &mut t, &target, samples)?;
    crate::ltc::held::judge_table(&Memo, &mut t, &target, tol)?;
    let between = crate::studies::ltc_between::measure(&t, &target, tol, between)?;
    let all: Vec<&Cell> = t.cells.iter().flatten().collect();
    let per_cell =
        |f: &dyn Fn(&Cell) -> f64| all.iter().map(|c| f(c)).sum::<f64>() / all.len() as f64;
    Ok(Fitted {
        cells: all.iter().map(|c| c.l2()).collect(),
        between: Some(between.mean_l2),
        between_bar: Some(between.judged.l2.mean.error),
        work: Some(per_cell(&|c| c.work as f64)),
        target_evals: Some(per_cell(&|c| c.target_evals as f64)),
        iters: Some(per_cell(&|c| c.iters as f64)),
    })
}

fn row((samples, max_iters): (usize, u64), nodes: Nodes, offset: f64, f: &Fitted) -> WorkRow {
    WorkRow {
        samples,
        max_iters,
        fixed_nodes: nodes != Nodes::Moving,
        fixed_all: nodes == Nodes::FixedAll,
        offset,
        mean: Figure::mean_bounded(&f.cells.iter().flatten().copied().collect::<Vec<_>>()),
        between_l2: f.between,
        between_bar: f.between_bar,
        work_per_cell: f.work,
        target_evals_per_cell: f.target_evals,
        iters_per_cell: f.iters,
    }
}

/// One table's part: the reference's draws, then every route judged against them.
fn table(results: &std::path::Path, name: &str, lobe: Lobe, pl: &Plan) -> Result<TableWork> {
    let (p, fingerprint) = crate::results::ltc::published(results, name)?;
    let route = p.route(name)?;
    // the reference fitter measures its trials on moving samples: where the published
    // route does too, the published table is its draw at the published offset
    let published = (route.nodes == Nodes::Moving).then(|| Fitted {
        cells: p
            .held_out_cells
            .l2
            .iter()
            .flatten()
            .map(|f| f.map(|f| Figure::new(f[0], f[1])))
            .collect(),
        between: None,
        between_bar: None,
        work: None,
        target_evals: None,
        iters: None,
    });
    let (tol, at) = (route.tolerance(), (route.samples, route.max_iters));
    // a table published on fixed nodes is judged as a route: without it among the plan's
    // routes, the study would leave the published table unjudged
    if route.nodes != Nodes::Moving
        && !pl
            .routes
            .iter()
            .any(|r| r.nodes == route.nodes && r.of(at.0, at.1) == at)
    {
        // the spec's spelling ("fixed", "fixed-all")
        let nodes = serde_json::to_string(&route.nodes).unwrap_or_default();
        return Err(Error::InvalidArgument(format!(
            "ltc-work: results/fits/{name}.json was fitted with nodes = {nodes} and fits/ltc-work.toml has no route at its settings on those nodes ({{ samples = 1.0, max_iters = 1.0, nodes = {nodes} }}): the published table would go unjudged"
        )));
    }
    // the squares the table's own study judges between cells, at its published preset
    let preset = Preset::named(&p.preset, &format!("results/fits/{name}.json"))?;
    let between = crate::studies::ltc_between::sample_for(name, None, preset);
    let (mut draws, mut rows) = (Vec::new(), Vec::new());
    // the published table, or the reference refitted at its offset, then the other draws
    let offsets = published.is_none().then_some(TRAIN_OFFSET);
    for o in offsets.into_iter().chain(pl.draws.iter().copied()) {
        crate::report::stage(&format!(
            "regen ltc-work: {name}, the reference route on the training draw at offset {o}"
        ));
        let f = fit(
            lobe,
            p.grid,
            (at.0, at.1, route.polish, Nodes::Moving),
            (o, between),
            tol,
        )?;
        rows.push(row(at, Nodes::Moving, o, &f));
        draws.push(f);
    }
    if let Some(f) = published {
        rows.insert(0, row(at, Nodes::Moving, TRAIN_OFFSET, &f));
        draws.insert(0, f);
    }
    let refs: Vec<&spread::Cells> = draws.iter().map(|d| d.cells.as_slice()).collect();
    let mut routes = Vec::with_capacity(pl.routes.len());
    for r in &pl.routes {
        let (s, i) = r.of(route.samples, route.max_iters);
        let on = match r.nodes {
            Nodes::Moving => "",
            Nodes::Fixed => ", fixed nodes",
            Nodes::FixedAll => ", fixed nodes in every stage",
        };
        crate::report::stage(&format!(
            "regen ltc-work: {name}, {s}² samples, ≤ {i} iterations per stage{on}"
        ));
        let f = fit(
            lobe,
            p.grid,
            (s, i, route.polish, r.nodes),
            (TRAIN_OFFSET, between),
            tol,
        )?;
        let v = spread::judge(&refs, &f.cells).ok_or_else(|| {
            Error::InvalidArgument(format!("ltc-work: {name}: tables of unequal size"))
        })?;
        routes.push((row((s, i), r.nodes, TRAIN_OFFSET, &f), v));
    }
    Ok(TableWork {
        table: name.into(),
        table_fingerprint: fingerprint,
        polish: route.polish.describe(route.samples),
        published_nodes: route.nodes,
        draws: rows,
        routes,
    })
}

/// What the study computed.
pub struct Computed {
    spec: FitSpec,
    preset: Preset,
    out: LtcWork,
}

/// The study: every table's part.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let pl: Plan = c.params()?;
    let tables = TABLES
        .iter()
        .map(|&(name, lobe)| table(c.results, name, lobe, &pl))
        .collect::<Result<Vec<_>>>()?;
    Ok(Computed {
        spec: c.spec.clone(),
        preset: c.preset,
        out: LtcWork {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            tables,
        },
    })
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        set.put(
            results.join(format!("{}.md", self.spec.name)),
            report::markdown(&self.out, self.preset).as_bytes(),
        );
        crate::results::put(set, results, &self.out)
    }

    fn outcome(&self) -> FitOutcome {
        let o = &self.out;
        let routes: usize = o.tables.iter().map(|t| t.routes.len()).sum();
        let passed: usize = o
            .tables
            .iter()
            .map(|t| t.routes.iter().filter(|(_, v)| v.no_worse).count())
            .sum();
        FitOutcome::measured(
            &self.spec,
            o.tables.first().map_or(f64::NAN, |t| t.draws[0].mean.value),
            format!(
                "{passed} of {routes} cheaper routes over {} tables no worse than their reference's spread",
                o.tables.len()
            ),
        )
    }
}

crate::study::study! {
    /// The LTC tables' accuracy against their fitting work, as the registry holds it.
    LtcWorkStudy = "ltc-work", after ["ltc-ggx", "ltc-sheen"], on request true, params Plan, computes compute
}

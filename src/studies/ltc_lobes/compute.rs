//! The sheen and diffuse tables' computation: the lobe families, the plan per preset, each
//! lobe's fit, bilinear pass and binary16 storage.

use crate::error::Result;
use crate::ltc::fit::{fit_table, Grid, Metric, Nodes, Polish, Table};
pub use crate::ltc::lobes::{family, Family};
use crate::ltc::lobes::{Lobe, LobeTarget};
use crate::ltc::smooth::{bilinear_pass, BilinearPass};
use crate::memo::Memo;

/// What fits/ltc-sheen.toml and fits/ltc-diffuse.toml set.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Cells per axis of each table, in (r = √α, t = √(1 − cos θ)).
    pub n: usize,
    /// α = max(r², alpha_min).
    pub alpha_min: f64,
    /// Stratified samples per axis and technique of each cell's fit (held out: twice as
    /// many, offset by a quarter cell).
    pub samples: usize,
    /// Nelder–Mead iteration cap per stage of each cell's cubic fit (the L2 polish is
    /// Levenberg–Marquardt, `ltc::fit::POLISH_ITERS`).
    pub max_iters: u64,
    /// The L2 polish after the cubic stage (`ltc::fit::Polish`).
    pub polish: Polish,
    /// Where the cubic stage's trials are measured (the bilinear pass stays on moving ones)
    /// (`ltc::fit::Nodes`; absent: moving, the reference fitter's).
    #[serde(default)]
    pub nodes: Nodes,
    /// MC samples per technique of the polygon-light checks.
    pub mc: usize,
    /// The held-out figures' relative tolerance (`ltc::lobe_error::Tolerance::relative`),
    /// chosen from the accuracy-against-work curve of the `ltc-judge-tolerance` study.
    pub held_out_rel: f64,
    /// The relative L1's own relative tolerance (`ltc::lobe_error::Tolerance::figures`),
    /// chosen from the same study's L1 curve.
    pub held_out_l1_rel: f64,
    /// Squares the between-cell figures judge at random beyond those judged always
    /// (`ltc_between::pick_squares`); as many as the other squares or more: all of them,
    /// and the means are exact. Absent: `ltc_between::BETWEEN_SAMPLE` at the quick and default presets,
    /// every square at the precise one.
    #[serde(default)]
    pub between_sample: Option<usize>,
}

impl Plan {
    /// The squares judged at random between cells at `preset` (`usize::MAX`: all).
    pub fn between_sample(&self, preset: crate::integrate::Preset) -> usize {
        crate::studies::ltc_between::sample_at(self.between_sample, preset)
    }
    /// The held-out judge's tolerance: `held_out_rel` for the relative L2,
    /// `held_out_l1_rel` for the relative L1.
    pub fn tolerance(&self) -> crate::ltc::lobe_error::Tolerance {
        crate::ltc::lobe_error::Tolerance::figures(self.held_out_rel, self.held_out_l1_rel)
    }
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        crate::ltc::fit::check_table_settings(
            self.n,
            self.alpha_min,
            self.samples,
            self.max_iters,
            self.mc,
        )?;
        crate::ltc::lobe_error::Tolerance::check_relative(self.held_out_rel)?;
        crate::ltc::lobe_error::Tolerance::check_relative_l1(self.held_out_l1_rel)?;
        crate::studies::ltc_between::check_sample(self.between_sample)
    }
}

/// A fitted, bilinear-refitted, binary16-stored table of one lobe.
pub(crate) struct Fitted {
    pub lobe: Lobe,
    pub table: Table,
    pub bilinear: BilinearPass,
}

/// The target constructor of a lobe.
pub(super) fn target_of(lobe: Lobe) -> impl Fn(f64, f64) -> Result<LobeTarget> + Sync {
    move |a, t| lobe.target(a, t)
}

/// Fit one lobe's table: the per-cell fit (cubic metric, the spec's L2 polish), one bilinear pass,
/// the binary16 storage.
pub(super) fn fit_lobe(lobe: Lobe, pl: &Plan) -> Result<Fitted> {
    let grid = Grid {
        n: pl.n,
        alpha_min: pl.alpha_min,
    };
    let iters = pl.max_iters;
    let pb =
        crate::progress::Progress::new(format!("ltc fit: {}", lobe.short()), (pl.n * pl.n) as u64);
    let target = target_of(lobe);
    let mut table = fit_table(
        &Memo,
        grid,
        &target,
        pl.samples,
        Metric::Cubic,
        pl.nodes.method(),
        iters,
        pl.polish,
        &|| pb.inc(1),
    )?;
    pb.finish();
    let bilinear = bilinear_pass(&Memo, &mut table, &target, pl.samples)?;
    crate::ltc::storage::store_table(&Memo, &mut table, &target, pl.samples)?;
    crate::ltc::held::judge_table(&Memo, &mut table, &target, pl.tolerance())?;
    Ok(Fitted {
        lobe,
        table,
        bilinear,
    })
}

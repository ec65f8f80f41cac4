//! The GGX table's computation: the plan per preset, the main table, each cell as the
//! LTC it stands for.

use crate::error::Result;
use crate::ltc::fit::{self, fit_table, Cell, Grid, Metric, Nodes, Polish, Table};
use crate::ltc::target::GgxTarget;
use crate::memo::Memo;
use nalgebra::Matrix3;

/// What fits/ltc-ggx.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Cells per axis of the table, in (r = √α, t = √(1 − cos θ)).
    pub n: usize,
    /// α = max(r², alpha_min).
    pub alpha_min: f64,
    /// Stratified samples per axis and technique of each cell's fit (held out: twice as
    /// many, offset by a quarter cell).
    pub samples: usize,
    /// Nelder–Mead iteration cap per stage of each cell's cubic fit (the L2 polish is
    /// `polish`).
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
    /// The pipeline section: map side, mip levels, footprints per level, and the truth's
    /// relative tolerance.
    pub pipeline_size: usize,
    pub pipeline_levels: Vec<usize>,
    pub pipeline_per_level: usize,
    pub pipeline_tolerance: f64,
    /// Squares the between-cell figures judge at random beyond those judged always
    /// (`studies::ltc_between`); as many as the other squares or more: all of them, and
    /// the means are exact. Absent: every square at every preset. Unlike the sheen and
    /// diffuse tables', this table's errors between cells have a tail no sample of 1024
    /// covers: the squares next to the smallest α (α = max(r², α_min) changes 25-fold
    /// across the first column) and at grazing; measured in fits/ltc-ggx.toml.
    #[serde(default)]
    pub between_sample: Option<usize>,
}

impl Plan {
    /// The squares judged at random between cells at `preset` (`usize::MAX`: all; the
    /// rule is `studies::ltc_between::sample_for`'s).
    pub fn between_sample(&self, preset: crate::integrate::Preset) -> usize {
        crate::studies::ltc_between::sample_for("ltc-ggx", self.between_sample, preset)
    }
    /// The held-out judge's tolerance: `held_out_rel` for the relative L2,
    /// `held_out_l1_rel` for the relative L1.
    pub fn tolerance(&self) -> crate::ltc::lobe_error::Tolerance {
        crate::ltc::lobe_error::Tolerance::figures(self.held_out_rel, self.held_out_l1_rel)
    }
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::{all_within, within};
        crate::ltc::fit::check_table_settings(
            self.n,
            self.alpha_min,
            self.samples,
            self.max_iters,
            self.mc,
        )?;
        crate::fit::spec::power_of_two("pipeline_size", self.pipeline_size, 4, 4096)?;
        let top = self.pipeline_size.trailing_zeros() as usize;
        all_within("pipeline_levels", &self.pipeline_levels, 0, top, 16)?;
        within("pipeline_per_level", self.pipeline_per_level, 1, 1_000)?;
        within("pipeline_tolerance", self.pipeline_tolerance, 1e-9, 0.1)?;
        crate::ltc::lobe_error::Tolerance::check_relative(self.held_out_rel)?;
        crate::ltc::lobe_error::Tolerance::check_relative_l1(self.held_out_l1_rel)?;
        crate::studies::ltc_between::check_sample(self.between_sample)
    }
}

/// The LTC of a cell as (M⁻¹ from the production form, norm).
pub fn cell_ltc(c: &Cell) -> (Matrix3<f64>, f64) {
    (fit::inverse_from_production(&c.inv), c.norm)
}

/// The main table: every cell fitted (`ltc::fit::fit_table`, the spec's route).
pub(super) fn fit_main(pl: &Plan) -> Result<Table> {
    let grid = Grid {
        n: pl.n,
        alpha_min: pl.alpha_min,
    };
    let pb = crate::progress::Progress::new("ltc fit", (pl.n * pl.n) as u64);
    let main = fit_table(
        &Memo,
        grid,
        &GgxTarget::new,
        pl.samples,
        Metric::Cubic,
        pl.nodes.method(),
        pl.max_iters,
        pl.polish,
        &|| pb.inc(1),
    )?;
    pb.finish();
    crate::report::stage("regen ltc-ggx: table fitted; polygon and precision studies next");
    Ok(main)
}

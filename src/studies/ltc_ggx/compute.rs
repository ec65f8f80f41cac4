//! The GGX table's computation: the plan per preset, the main table and the optimiser
//! variants, each cell as the LTC it stands for.

use crate::error::Result;
use crate::ltc::fit::{self, fit_table, Cell, Grid, Method, Metric, Table};
use crate::ltc::held::{self};
use crate::ltc::lobe_error::Tolerance;
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
    /// Nelder–Mead iteration cap per cell (the floor's searches too).
    pub max_iters: u64,
    /// Cells per axis of the sub-grid the optimiser variants are fitted on.
    pub sub: usize,
    /// MC samples per technique of the polygon-light checks.
    pub mc: usize,
    /// The pipeline section: map side, mip levels, footprints per level, and the truth's
    /// relative tolerance.
    pub pipeline_size: usize,
    pub pipeline_levels: Vec<usize>,
    pub pipeline_per_level: usize,
    pub pipeline_tolerance: f64,
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
        within("sub", self.sub, 2, self.n)?;
        crate::fit::spec::power_of_two("pipeline_size", self.pipeline_size, 4, 4096)?;
        let top = self.pipeline_size.trailing_zeros() as usize;
        all_within("pipeline_levels", &self.pipeline_levels, 0, top, 16)?;
        within("pipeline_per_level", self.pipeline_per_level, 1, 1_000)?;
        within("pipeline_tolerance", self.pipeline_tolerance, 1e-9, 0.1)
    }
}

/// The LTC of a cell as (M⁻¹ from the production form, norm).
pub fn cell_ltc(c: &Cell) -> (Matrix3<f64>, f64) {
    (fit::inverse_from_production(&c.inv), c.norm)
}

/// The optimiser and metric variants fitted over the sub-grid, in this order.
const ROUTES: [(&str, Metric, Method); 4] = [
    (
        "Nelder–Mead, cubic metric",
        Metric::Cubic,
        Method::NelderMead,
    ),
    ("Nelder–Mead, L2 metric", Metric::L2, Method::NelderMead),
    (
        "L-BFGS (central differences), cubic metric",
        Metric::Cubic,
        Method::Lbfgs,
    ),
    (
        "Levenberg–Marquardt on fixed nodes, relative L2",
        Metric::L2,
        Method::LevenbergMarquardt,
    ),
];

/// The main table and the optimiser/metric variants on the sub-grid.
pub(super) fn fit_tables(pl: &Plan) -> Result<(Table, Vec<(&'static str, Table)>)> {
    let grid = Grid {
        n: pl.n,
        alpha_min: pl.alpha_min,
    };
    let iters = pl.max_iters;
    let pb = indicatif::ProgressBar::new((pl.n * pl.n + ROUTES.len() * pl.sub * pl.sub) as u64);
    pb.set_message("ltc fit");
    let tick = || pb.inc(1);
    let main = fit_table(
        &Memo,
        grid,
        &GgxTarget::new,
        pl.samples,
        Metric::Cubic,
        Method::NelderMead,
        iters,
        &tick,
    )?;
    let sub = Grid {
        n: pl.sub,
        alpha_min: pl.alpha_min,
    };
    let mut variants: Vec<(&'static str, Table)> = Vec::with_capacity(ROUTES.len());
    for (name, metric, method) in ROUTES {
        let t = fit_table(
            &Memo,
            sub,
            &GgxTarget::new,
            pl.samples,
            metric,
            method,
            iters,
            &tick,
        )?;
        variants.push((name, t));
    }
    pb.finish_and_clear();
    for (_, t) in variants.iter_mut() {
        held::judge_table(&Memo, t, &GgxTarget::new, Tolerance::default())?;
    }
    crate::report::stage("regen ltc-ggx: table fitted; polygon and precision studies next");
    Ok((main, variants))
}

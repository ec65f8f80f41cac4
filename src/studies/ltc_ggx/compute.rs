//! The GGX table's computation: the plan per preset, the main table and the optimiser
//! variants, each cell as the LTC it stands for.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::ltc::fit::{self, fit_table, Cell, Grid, Method, Metric, Table};
use crate::ltc::held::{self};
use crate::ltc::lobe_error::Tolerance;
use crate::ltc::target::GgxTarget;
use crate::memo::Memo;
use nalgebra::Matrix3;

pub(super) struct Plan {
    pub(super) n: usize,
    pub(super) samples: usize,
    pub(super) sub: usize,
    pub(super) mc: usize,
}

pub(super) fn plan(p: Preset) -> Plan {
    match p {
        Preset::Quick => Plan {
            n: 8,
            samples: 12,
            sub: 4,
            mc: 1 << 12,
        },
        Preset::Default => Plan {
            n: 64,
            samples: 24,
            sub: 12,
            mc: 1 << 16,
        },
        Preset::Precise => Plan {
            n: 64,
            samples: 32,
            sub: 16,
            mc: 1 << 18,
        },
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
pub(super) fn fit_tables(spec: &FitSpec, pl: &Plan) -> Result<(Table, Vec<(&'static str, Table)>)> {
    let grid = Grid {
        n: pl.n,
        alpha_min: spec.domain.alpha_min,
    };
    let iters = spec.optimiser.max_iters.unwrap_or(400);
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
        alpha_min: spec.domain.alpha_min,
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

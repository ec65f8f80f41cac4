//! Fitting the GGX LTC table (Heitz, Dupuy, Hill, Neubelt 2016; seed 000 Eq 1).
//!
//! Target: the cosine-weighted GGX BRDF with height-correlated Smith G2 and F = 1,
//! f(l) = D(h)·G2(l, v)/(4 v_z), for a view v = (sin θ, 0, cos θ) and roughness α.
//! Model: f ≈ norm·γ_M(l), γ_M the LTC of the clamped cosine with
//! M = [X Y Z]·[[m11, 0, m13], [0, m22, 0], [0, 0, 1]], Z the BRDF's mean direction,
//! Y = (0, 1, 0), X = Y × Z (the frame of the reference fitter). norm = ∫ f (directional
//! albedo), fresnel = ∫ f·(1 − v·h)⁵ (so that ∫ f·F_Schlick = F0·(norm − fresnel) + fresnel).
//!
//! Metrics (both reported for every table): the reference fitter's
//! Σ|f − f_ltc|³/(p_ltc + p_brdf) over samples drawn from both the LTC and the BRDF (one
//! stratified n×n set each), and the plain L2 error ∫(f − f_ltc)² by the same balance
//! estimator, reported relative to ∫f². Optimisers (argmin): Nelder–Mead, and L-BFGS on
//! central-difference gradients; parameters (ln m11, ln m22, m13/m11) so that α down to
//! 1e-4 has no floor and no sign to flip. The published routes draw half of each trial's
//! samples from the trial LTC itself (`samples::metrics_on`), so every trial evaluates the
//! target; `Method::FixedNodes` measures a stage's trials on nodes drawn once from the
//! stage's start (`samples::FixedNodes`), an unbiased estimator of the same integrals
//! whose trials evaluate no target (judged against the published route in the
//! `ltc-work` study).
//!
//! Production form: M⁻¹ normalised by its middle element, stored as (a, b, c, d) with
//! M⁻¹ ∝ [[a, 0, c], [0, 1, 0], [b, 0, d]] — the layout of the 2016 "journey" talk and the
//! shipped ltc_1 textures (columns (a, 0, b) and (c, 0, d)).

use crate::error::{Error, Result};
use crate::ltc::lobe_error::Held;
use crate::ltc::target::LtcTarget;
use crate::ltc::LtcDist;
use crate::parmap::ParMap;
use nalgebra::Vector3;
use serde::Serialize;

pub use super::objective::Metric;
use super::objective::{ltc_at, Objective};
pub use super::params::{
    inverse_from_production, matrix, params_from_production, params_to_m, production_inverse, turn,
};
use super::polish::FIXED_POLISH_SCALE;
pub use super::polish::{Polish, POLISH_ITERS};
pub use super::samples::{
    metrics, metrics_on, FixedNodes, Nodes, Sets, TargetSamples, TRAIN_OFFSET,
};
pub use super::table::{check_table_settings, Grid};

type V3 = Vector3<f64>;

/// Fitted parameters of one cell.
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize)]
pub struct Cell {
    pub alpha: f64,
    pub theta: f64,
    pub m11: f64,
    pub m22: f64,
    pub m13: f64,
    /// The fitted frame axis (x, z) (Y = (0, 1, 0)): the BRDF's mean direction turned
    /// by `turn` radians about Y.
    pub z_dir: [f64; 2],
    pub turn: f64,
    pub norm: f64,
    /// Quadrature error estimate of `norm`.
    pub norm_se: f64,
    pub fresnel: f64,
    /// Production inverse (a, b, c, d), M⁻¹ normalised by its middle element.
    pub inv: [f64; 4],
    /// The held-out figures of the cell as computed and as stored (`judge_table`; `None`
    /// until then).
    pub held: Option<Held>,
    pub iters: u64,
    /// Trial-LTC sample evaluations of the cell's fit and polish on its sample sets
    /// (`samples::work`; a Levenberg–Marquardt route's own nodes are not counted).
    pub work: u64,
    /// Target evaluations of the cell's fit and polish (`samples::target_work`: its
    /// sample sets, the LTC half of every moving-sample trial, each fixed-node set).
    #[serde(default)]
    pub target_evals: u64,
    /// The binary16 storage of [a, b, c, d, norm, fresnel] (as f64): each entry rounded
    /// to nearest, or the f16 neighbours chosen by `ltc::storage::half_storage`.
    pub half: [f64; 6],
    /// Whether the L2 polish (from the cubic solution) was kept.
    pub polished: bool,
}

impl Cell {
    /// The held-out relative L2 of the f64 cell (`None` until judged).
    pub fn l2(&self) -> Option<crate::integrate::Figure<crate::integrate::Quad>> {
        self.held.and_then(|h| h.f64).map(|e| e.l2)
    }
}

/// Which optimiser.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Method {
    NelderMead,
    Lbfgs,
    /// Levenberg–Marquardt on fixed nodes (`ltc::gauss_newton`): the relative L2 whatever
    /// the metric asked for.
    LevenbergMarquardt,
    /// Nelder–Mead on fixed nodes (`samples::FixedNodes`): each stage draws its LTC half
    /// once from the stage's start instead of from every trial, so a trial evaluates no
    /// target. The L2 polish after a cubic stage stays the reference's (its `Polish`).
    FixedNodes,
    /// [`Method::FixedNodes`] in the cubic stage, and fixed nodes in a Nelder–Mead L2
    /// polish (drawn from the cubic solution) and in the table's bilinear pass
    /// (`ltc::smooth`, which reads the table's method): no trial evaluates the target.
    FixedNodesAll,
}

impl Method {
    /// Whether the cubic stage's trials are measured on fixed nodes.
    fn fixed_stages(self) -> bool {
        matches!(self, Method::FixedNodes | Method::FixedNodesAll)
    }
}

impl Nodes {
    /// The cubic stage's method (`samples::Nodes`).
    pub fn method(self) -> Method {
        match self {
            Nodes::Moving => Method::NelderMead,
            Nodes::Fixed => Method::FixedNodes,
            Nodes::FixedAll => Method::FixedNodesAll,
        }
    }
}

/// One optimiser run from `start` (Nelder–Mead: initial simplex steps `steps`); returns
/// the best parameters and the iterations (a failed L-BFGS line search keeps the start,
/// reported as 0 iterations).
fn optimise<T: LtcTarget + ?Sized>(
    obj: Objective<'_, T>,
    method: Method,
    start: Vec<f64>,
    steps: &[f64],
    max_iters: u64,
) -> Result<(Vec<f64>, u64)> {
    use argmin::core::{Executor, State};
    let err = |e: argmin::core::Error| Error::InvalidArgument(format!("LTC fit: {e}"));
    Ok(match method {
        Method::NelderMead | Method::FixedNodes | Method::FixedNodesAll => {
            use argmin::solver::neldermead::NelderMead;
            let mut simplex = vec![start.clone()];
            for (k, st) in steps.iter().enumerate() {
                let mut q = start.clone();
                q[k] += st;
                simplex.push(q);
            }
            let solver = NelderMead::new(simplex)
                .with_sd_tolerance(1e-12)
                .map_err(err)?;
            let res = Executor::new(obj, solver)
                .configure(|s| s.max_iters(max_iters))
                .run()
                .map_err(err)?;
            (
                res.state().get_best_param().cloned().unwrap_or(start),
                res.state().get_iter(),
            )
        }
        Method::Lbfgs => {
            use argmin::solver::linesearch::MoreThuenteLineSearch;
            use argmin::solver::quasinewton::LBFGS;
            let solver = LBFGS::new(MoreThuenteLineSearch::new(), 5)
                .with_tolerance_grad(1e-14)
                .map_err(err)?
                .with_tolerance_cost(1e-14)
                .map_err(err)?;
            match Executor::new(obj, solver)
                .configure(|s| s.param(start.clone()).max_iters(max_iters))
                .run()
            {
                Ok(res) => (
                    res.state().get_best_param().cloned().unwrap_or(start),
                    res.state().get_iter(),
                ),
                Err(_) => (start, 0),
            }
        }
        // `fit_cell` hands this route to `gauss_newton` before it builds an objective
        Method::LevenbergMarquardt => (start, 0),
    })
}

/// Fit one cell from the start `p0` = (ln m11, ln m22, m13/m11, φ), where φ turns the
/// frame axis about Y away from `z`, the BRDF's mean direction. All four are fitted, the
/// production form's full four degrees of freedom (the reference fitter fixes Z at its
/// estimate of the mean direction, ~1° off the best axis at grazing angles). Returns the
/// fitted parameters (the axis is `turn(z, p[3])`) and the iterations.
#[allow(clippy::too_many_arguments)]
pub fn fit_cell<T: LtcTarget + ?Sized>(
    t: &T,
    z: &V3,
    norm: f64,
    p0: &[f64; 4],
    n: usize,
    metric: Metric,
    method: Method,
    max_iters: u64,
) -> Result<([f64; 4], u64)> {
    if method == Method::LevenbergMarquardt {
        let r = super::gauss_newton::fit_cell_lm(t, z, norm, p0, n, max_iters as usize, false)?;
        return Ok((r.params, r.iters as u64));
    }
    fit_cell_on(t, z, norm, p0, &Sets::new(t, n), metric, method, max_iters)
}

/// [`fit_cell`] on the cell's sample sets drawn beforehand (the Levenberg–Marquardt
/// route draws its own nodes, at the sets' n).
#[allow(clippy::too_many_arguments)]
fn fit_cell_on<T: LtcTarget + ?Sized>(
    t: &T,
    z: &V3,
    norm: f64,
    p0: &[f64; 4],
    sets: &Sets,
    metric: Metric,
    method: Method,
    max_iters: u64,
) -> Result<([f64; 4], u64)> {
    if method == Method::LevenbergMarquardt {
        return fit_cell(t, z, norm, p0, sets.n(), metric, method, max_iters);
    }
    // the fixed-node route: each stage's training and validation nodes from its start (a
    // singular start, which the warm-start chain never hands over, keeps moving samples)
    let nodes_at = |zz: &V3, p: &[f64]| -> Option<(FixedNodes, FixedNodes)> {
        if !method.fixed_stages() {
            return None;
        }
        let start = ltc_at(zz, p)?;
        Some((
            FixedNodes::new(t, &sets.train, &start),
            FixedNodes::new(t, &sets.val, &start),
        ))
    };
    let symmetric = t.view().x.abs() <= 1e-12;
    // 1. the three matrix parameters, the frame turn held at the start's
    let phi0 = if symmetric { 0.0 } else { p0[3] };
    let z1 = turn(z, phi0);
    let q0 = [p0[0], p0[1], p0[2]];
    let nodes1 = nodes_at(&z1, &q0);
    let obj = |z, validation| Objective::on(t, z, norm, metric, sets, nodes1.as_ref(), validation);
    let (b3, i3) = optimise(
        obj(z1, false),
        method,
        q0.to_vec(),
        &[0.1, 0.1, 0.05],
        max_iters,
    )?;
    let p3: [f64; 3] = if b3.iter().any(|x| !x.is_finite())
        || !(obj(z1, false).value(&b3) <= obj(z1, false).value(&q0))
    {
        // a diverged or worse result keeps the start
        q0
    } else {
        [b3[0], b3[1], b3[2]]
    };
    let p3 = [p3[0], p3[1], p3[2], phi0];
    if symmetric {
        return Ok((p3, i3));
    }
    // 2. away from normal incidence (where the lobe is symmetric about Z), all four
    // parameters from that solution; the turn's first step scales with the lobe width.
    // Taken only if it lowers the training metric and a separate validation set's, so the
    // cubic metric's spurious basin of very wide LTCs (tiny α) cannot capture it.
    let nodes2 = nodes_at(z, &p3);
    let obj = |z, validation| Objective::on(t, z, norm, metric, sets, nodes2.as_ref(), validation);
    let (b4, i4) = optimise(
        obj(*z, false),
        method,
        p3.to_vec(),
        &[0.1, 0.1, 0.05, 0.02 * (10.0 * t.width()).min(1.0)],
        max_iters,
    )?;
    let (train, val) = (obj(*z, false), obj(*z, true));
    if b4.iter().all(|x| x.is_finite())
        && train.value(&b4) < train.value(&p3)
        && val.value(&b4) < val.value(&p3)
    {
        return Ok(([b4[0], b4[1], b4[2], b4[3].clamp(-0.5, 0.5)], i3 + i4));
    }
    Ok((p3, i3 + i4))
}

/// The L2 polish of a cell fitted under the cubic metric, by `how`, from that solution
/// `p`. Returns the parameters and whether the polish was kept: where it lowers the
/// validation set's relative L2 (moving samples). On the route with fixed nodes in every
/// stage, Nelder–Mead runs on fixed nodes ([`fixed_polish`]) and again on moving samples
/// where its result fails [`fixed_polish_holds`].
#[allow(clippy::too_many_arguments)]
pub(super) fn polish_l2<T: LtcTarget + ?Sized>(
    t: &T,
    z: &V3,
    norm: f64,
    p: &[f64; 4],
    sets: &Sets,
    (how, method): (Polish, Method),
    max_iters: u64,
) -> Result<([f64; 4], bool)> {
    use super::gauss_newton::fit_cell_lm;
    let n = sets.n();
    let val = Objective {
        t,
        z: *z,
        norm,
        set: &sets.val,
        metric: Metric::L2,
        fixed: None,
    };
    let moving = || -> Result<[f64; 4]> {
        let l2 = Metric::L2;
        Ok(fit_cell_on(t, z, norm, p, sets, l2, Method::NelderMead, max_iters / 2)?.0)
    };
    // the polished lobe's relative L2 on the validation set, where the route measured it
    let (q, at_q) = match how {
        Polish::NelderMead if method == Method::FixedNodesAll => {
            let q = fixed_polish(t, z, norm, p, sets, max_iters / 2)?;
            let at_q = val.value(&q);
            if fixed_polish_holds(t, z, norm, (p, &q, at_q), sets) {
                (q, Some(at_q))
            } else {
                (moving()?, None)
            }
        }
        Polish::NelderMead => (moving()?, None),
        Polish::LevenbergMarquardt | Polish::LevenbergMarquardtTurnHeld => {
            let held = how == Polish::LevenbergMarquardtTurnHeld;
            let mut q = fit_cell_lm(t, z, norm, p, 2 * n, POLISH_ITERS, held)?.params;
            // the route evaluates φ clamped as the objective does; store it so
            q[3] = q[3].clamp(-0.5, 0.5);
            (q, None)
        }
    };
    if q.iter().all(|x| x.is_finite()) && at_q.unwrap_or_else(|| val.value(&q)) < val.value(p) {
        Ok((q, true))
    } else {
        Ok((*p, false))
    }
}

/// The Nelder–Mead polish on fixed nodes from the cubic solution `p`:
/// [`FIXED_POLISH_SCALE`]× the sets' nodes per axis, at the training draw's offset.
fn fixed_polish<T: LtcTarget + ?Sized>(
    t: &T,
    z: &V3,
    norm: f64,
    p: &[f64; 4],
    sets: &Sets,
    max_iters: u64,
) -> Result<[f64; 4]> {
    let wide = Sets::drawn(t, FIXED_POLISH_SCALE * sets.n(), sets.train.offset());
    let l2 = Metric::L2;
    Ok(fit_cell_on(t, z, norm, p, &wide, l2, Method::FixedNodes, max_iters)?.0)
}

/// Whether a fixed-node polish from `p` to `q` (whose relative L2 on the moving samples of
/// the validation set is `moving`) passes both checks: the estimate on fixed nodes drawn
/// from `p` agrees with `moving`, and `q` captures the lobe
/// (`ltc::polish::fixed_fit_holds`).
fn fixed_polish_holds<T: LtcTarget + ?Sized>(
    t: &T,
    z: &V3,
    norm: f64,
    (p, q, moving): (&[f64; 4], &[f64; 4], f64),
    sets: &Sets,
) -> bool {
    let (Some(from), Some(to)) = (ltc_at(z, p), ltc_at(z, q)) else {
        return false;
    };
    super::polish::fixed_fit_holds(t, &sets.val, (&from, &to), norm, moving)
}

/// Both metrics of a production-form cell (a, b, c, d) with amplitude `norm` against the
/// target on the n×n set with offset `off`; `None` where the matrix is singular.
pub fn production_metrics<T: LtcTarget + ?Sized>(
    t: &T,
    inv: &[f64; 4],
    norm: f64,
    n: usize,
    off: f64,
) -> Option<(f64, f64)> {
    production_metrics_on(t, &TargetSamples::new(t, n, off), inv, norm)
}

/// [`production_metrics`] on the target's samples `s` drawn beforehand.
pub fn production_metrics_on<T: LtcTarget + ?Sized>(
    t: &T,
    s: &TargetSamples,
    inv: &[f64; 4],
    norm: f64,
) -> Option<(f64, f64)> {
    let m = inverse_from_production(inv).try_inverse()?;
    let ltc = LtcDist::new(m).ok()?;
    Some(metrics_on(t, s, &ltc, norm))
}

/// The absolute tolerance of a cell's norm and Fresnel share (the albedo integrals).
pub const ALBEDO_TOL: f64 = 1e-9;

/// The fitted table: cells[j][i] for θ index j and α index i.
#[derive(Clone, Debug, Serialize)]
pub struct Table {
    pub grid: Grid,
    pub metric: Metric,
    pub method: Method,
    pub polish: Polish,
    pub samples_per_technique: usize,
    pub cells: Vec<Vec<Cell>>,
}

/// Fit a whole table of `target(α, θ)`: rayon over θ columns; within a column α runs from rough to smooth,
/// each cell starting from its neighbour's solution (the first from the isotropic
/// M = diag(α, α, 1)).
#[allow(clippy::too_many_arguments)]
pub fn fit_table<T: LtcTarget>(
    pm: &impl ParMap,
    grid: Grid,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    n: usize,
    metric: Metric,
    method: Method,
    max_iters: u64,
    polish: Polish,
    progress: &(dyn Fn() + Sync),
) -> Result<Table> {
    let route = (metric, method, max_iters, polish);
    fit_table_drawn(pm, grid, target, n, route, TRAIN_OFFSET, progress)
}

/// [`fit_table`] with every cell's training set drawn at stratum offset `train`
/// (`Sets::drawn`): the same route on another draw of its samples, at the same cost.
/// `route` is (metric, method, iteration cap, polish).
pub fn fit_table_drawn<T: LtcTarget>(
    pm: &impl ParMap,
    grid: Grid,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    n: usize,
    route: (Metric, Method, u64, Polish),
    train: f64,
    progress: &(dyn Fn() + Sync),
) -> Result<Table> {
    let (metric, method, _, polish) = route;
    // one θ column per item of the caller's map
    let label = if train == TRAIN_OFFSET {
        format!(
            "ltc table {}² ({metric:?}, {method:?}, {n}² samples)",
            grid.n
        )
    } else {
        format!(
            "ltc table {}² ({metric:?}, {method:?}, {n}² samples, training offset {train})",
            grid.n
        )
    };
    let cols: Vec<Vec<Cell>> = pm.map(&label, grid.n, |j| {
        fit_column(grid, j, target, n, route, train, progress)
    })?;
    Ok(Table {
        grid,
        metric,
        method,
        polish,
        samples_per_technique: n * n,
        cells: cols,
    })
}

/// One θ column `j` of [`fit_table_drawn`], as the table fits it: α from rough to smooth,
/// each cell from its rougher neighbour's solution (the first from the isotropic
/// M = diag(α, α, 1)), with its moments, albedo, cubic stage, L2 polish and rounded
/// storage; `progress` after each cell. `route` is (metric, method, iteration cap,
/// polish); every cell's training set is drawn at stratum offset `train`. The table's
/// bilinear pass and its chosen binary16 storage come after, over the whole table.
pub fn fit_column<T: LtcTarget>(
    grid: Grid,
    j: usize,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    n: usize,
    (metric, method, max_iters, polish): (Metric, Method, u64, Polish),
    train: f64,
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<Cell>> {
    let theta = grid.theta(j);
    let mut col = Vec::with_capacity(grid.n);
    let mut p = [0.0f64; 4];
    for i in (0..grid.n).rev() {
        let alpha = grid.alpha(i);
        let t = target(alpha, theta)?;
        let (_, _, _, zm) = t.moments(32);
        let (norm, norm_se, fresnel) = t.albedo(ALBEDO_TOL);
        if i == grid.n - 1 {
            p = [alpha.ln(), alpha.ln(), 0.0, 0.0];
        } else {
            // keep the ratios to α and the frame turn of the rougher neighbour
            // (a continuation: neighbouring cells stay in the same basin, so the
            // table stays smooth enough to interpolate)
            let prev = grid.alpha(i + 1);
            p[0] += (alpha / prev).ln();
            p[1] += (alpha / prev).ln();
            // the best axis approaches the mean direction as the lobe narrows
            p[3] *= alpha / prev;
        }
        let sets = Sets::drawn(&t, n, train);
        let (work0, evals0) = (super::samples::work(), super::samples::target_work());
        let (best, iters) = fit_cell_on(&t, &zm, norm, &p, &sets, metric, method, max_iters)?;
        // the warm-start chain carries the primary metric's solution
        p = best;
        let (q, polished) = if metric == Metric::Cubic {
            polish_l2(&t, &zm, norm, &best, &sets, (polish, method), max_iters)?
        } else {
            (best, false)
        };
        let z = turn(&zm, q[3]);
        let (m11, m22, m13) = params_to_m(&q);
        let m = matrix(m11, m22, m13, &z);
        LtcDist::new(m)?;
        let inv = production_inverse(&m)?;
        col.push(Cell {
            alpha,
            theta,
            m11,
            m22,
            m13,
            z_dir: [z.x, z.z],
            turn: q[3],
            norm,
            norm_se,
            fresnel,
            inv,
            held: None,
            iters,
            work: super::samples::work() - work0,
            target_evals: super::samples::target_work() - evals0,
            // round to nearest; a study may choose better (`ltc::storage`)
            half: [inv[0], inv[1], inv[2], inv[3], norm, fresnel]
                .map(|x| half::f16::from_f64(x).to_f64()),
            polished,
        });
        progress();
    }
    col.reverse();
    Ok(col)
}

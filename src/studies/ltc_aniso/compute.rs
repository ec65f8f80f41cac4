//! The anisotropic table's computation: the plan per preset, the per-cell fits from the
//! isotropic table's stretched start, the cases between cells and the polygon rows.

use crate::error::{Error, Result};
use crate::ltc::aniso::{fit_cell_route, mirror_y, rel_l2, AnisoGgxTarget, Inv7, Route};
use crate::ltc::aniso_table::{AnisoCell, AnisoGrid, AnisoTable};
use crate::ltc::fit::Nodes;
use crate::ltc::table::FittedTable;
use crate::ltc::target::LtcTarget;

#[derive(Clone)]
pub(crate) struct Plan {
    pub grid: AnisoGrid,
    pub samples: usize,
    pub iters: u64,
    /// What each fit's trials are measured on (`ltc::aniso::Route`).
    pub nodes: Nodes,
    /// The training set's strata offset (`ltc::fit::TRAIN_OFFSET` for the published
    /// table; the work study draws others).
    pub train: f64,
    /// Nodes of each design-study line.
    pub line: usize,
    /// Random cases between cells.
    pub cases: usize,
    /// MC samples per technique of the polygon checks.
    pub mc: usize,
    /// The held-out judge's tolerance (`held_out_rel`, `held_out_l1_rel`).
    pub tol: crate::ltc::lobe_error::Tolerance,
}

/// What fits/ltc-aniso.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Cells per axis: √α_x and √α_y (n_r), tangent azimuth φ ∈ [0, π/2] (n_phi),
    /// √(1 − cos θ) (n_t).
    pub n_r: usize,
    pub n_phi: usize,
    pub n_t: usize,
    /// α = max(r², alpha_min) on both axes.
    pub alpha_min: f64,
    /// Stratified samples per axis and technique of each cell's fit (held out: twice as
    /// many).
    pub samples: usize,
    /// Nelder–Mead iteration cap per start.
    pub iters: u64,
    /// What the trials are measured on: "moving" (absent: the reference fitter's samples,
    /// the LTC half drawn from each trial) or "fixed" (nodes drawn once from each start,
    /// `ltc::aniso::Route`).
    #[serde(default)]
    pub nodes: Nodes,
    /// Nodes of each design-study line.
    pub line: usize,
    /// Random cases between cells.
    pub cases: usize,
    /// MC samples per technique of the polygon checks.
    pub mc: usize,
    /// The held-out figures' relative tolerances: the relative L2's and the relative L1's
    /// (`ltc::lobe_error::Tolerance::figures`).
    pub held_out_rel: f64,
    pub held_out_l1_rel: f64,
}

impl crate::fit::spec::Params for Params {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::within;
        within("n_r", self.n_r, 2, 32)?;
        within("n_phi", self.n_phi, 2, 32)?;
        within("n_t", self.n_t, 2, 32)?;
        within("alpha_min", self.alpha_min, 1e-6, 0.5)?;
        within("samples", self.samples, 2, 64)?;
        within("iters", self.iters, 1, 100_000)?;
        within("line", self.line, 2, 1_000)?;
        within("cases", self.cases, 1, 100_000)?;
        within("mc", self.mc, 16, 1 << 24)?;
        if self.nodes == Nodes::FixedAll {
            return Err(
                "nodes = \"fixed-all\": the anisotropic fit has one stage; say \"fixed\"".into(),
            );
        }
        crate::ltc::lobe_error::Tolerance::check_relative(self.held_out_rel)?;
        crate::ltc::lobe_error::Tolerance::check_relative_l1(self.held_out_l1_rel)
    }
}

impl Params {
    pub(super) fn plan(&self) -> Plan {
        Plan {
            grid: AnisoGrid {
                n_r: self.n_r,
                n_phi: self.n_phi,
                n_t: self.n_t,
                alpha_min: self.alpha_min,
            },
            samples: self.samples,
            iters: self.iters,
            nodes: self.nodes,
            train: crate::ltc::fit::TRAIN_OFFSET,
            line: self.line,
            cases: self.cases,
            mc: self.mc,
            tol: crate::ltc::lobe_error::Tolerance::figures(
                self.held_out_rel,
                self.held_out_l1_rel,
            ),
        }
    }
}

impl Plan {
    /// How each cell is fitted.
    pub(crate) fn route(&self) -> Route {
        Route {
            samples: self.samples,
            iters: self.iters,
            nodes: self.nodes,
            train: self.train,
        }
    }
}

pub use crate::results::ltc_aniso::{Case, PolygonRow};

/// What one fitted case measured (held-out relative L2).
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Fitted {
    pub case: Case,
    pub inv: Inv7,
    pub norm: f64,
    pub fresnel: f64,
    /// This fit, with its own norm (held-out relative L2, `ltc::lobe_error`).
    pub err: f64,
    /// The same fit's held-out relative L1.
    pub err_l1: f64,
    /// The isotropic table at √(α_x α_y), with its norm: what engines do today.
    pub err_iso_geo: f64,
    /// The isotropic table at max(α_x, α_y), with its norm.
    pub err_iso_max: f64,
    /// The largest error bar of this case's held-out figures.
    pub bar: f64,
    pub iters: u64,
    /// Trial-LTC sample evaluations of the case's fits from every start
    /// (`ltc::samples::work`), and their target evaluations (`ltc::samples::target_work`):
    /// counts, the work study's measure of cost.
    #[serde(default)]
    pub work: u64,
    #[serde(default)]
    pub target_evals: u64,
}

/// The held-out figures (`ltc::lobe_error`) of production inverses with their norms
/// against a target: (relative L2 of each, relative L1 of each, the largest error bar);
/// ∞ where an inverse is singular.
pub(super) fn held_out(
    t: &AnisoGgxTarget,
    albedo: f64,
    cands: &[(Inv7, f64)],
    tol: crate::ltc::lobe_error::Tolerance,
) -> (Vec<f64>, Vec<f64>, f64) {
    use crate::ltc::lobe_error::judge;
    let inv: Vec<_> = cands
        .iter()
        .map(|(p, n)| (crate::ltc::aniso::inverse_of(p), *n))
        .collect();
    let e = judge(t, albedo, &inv, tol);
    let l2 = e
        .iter()
        .map(|e| e.map_or(f64::INFINITY, |e| e.l2.value))
        .collect();
    let l1 = e
        .iter()
        .map(|e| e.map_or(f64::INFINITY, |e| e.l1.value))
        .collect();
    let bar = e
        .iter()
        .flatten()
        .flat_map(|e| [e.l2.error, e.l1.error])
        .fold(0.0, f64::max);
    (l2, l1, bar)
}

/// The isotropic table's (production inverse as Inv7, norm) at (α, θ).
pub(super) fn iso_at(iso: &FittedTable, alpha: f64, theta: f64) -> (Inv7, f64) {
    let c = iso.bilinear(alpha, theta.cos(), false);
    ([c[0], c[1], c[2], c[3], 0.0, 0.0, 0.0], c[4])
}

/// The isotropic cell at √(α_x α_y) stretched toward the tangent: M = M_iso·S with
/// S = R_φ·diag(α_x/ᾱ, α_y/ᾱ, 1)·R_φᵀ in the cosine's frame (the lobe's lateral widths
/// follow the roughness along and across the tangent), as a production inverse.
pub(super) fn stretched(iso_geo: &Inv7, c: &Case) -> Option<Inv7> {
    use nalgebra::Matrix3;
    let g = (c.ax * c.ay).sqrt();
    let (s, co) = c.phi.sin_cos();
    let r = Matrix3::new(co, -s, 0.0, s, co, 0.0, 0.0, 0.0, 1.0);
    let d = Matrix3::new(c.ax / g, 0.0, 0.0, 0.0, c.ay / g, 0.0, 0.0, 0.0, 1.0);
    let stretch = r * d * r.transpose();
    let m = crate::ltc::aniso::inverse_of(iso_geo).try_inverse()? * stretch;
    crate::ltc::aniso::production_of(&m.try_inverse()?)
}

/// Fit one case: Nelder–Mead from each of three starts — the isotropic table at
/// √(α_x α_y), the same stretched toward the tangent, the isotropic table at
/// max(α_x, α_y) — the best on the validation set kept.
pub(crate) fn fit_case(iso: &FittedTable, c: Case, pl: &Plan) -> Result<Fitted> {
    let t = AnisoGgxTarget::new(c.ax, c.ay, c.theta, c.phi)?;
    let (norm, _, fresnel) = t.albedo(1e-7);
    let (start, geo_norm) = iso_at(iso, (c.ax * c.ay).sqrt(), c.theta);
    let (max_inv, max_norm) = iso_at(iso, c.ax.max(c.ay), c.theta);
    let mut starts = vec![start, max_inv];
    if let Some(st) = stretched(&start, &c) {
        starts.insert(1, st);
    }
    let val = |p: &Inv7| rel_l2(&t, p, norm, pl.samples + 7, 0.37);
    use crate::ltc::samples::{target_work, work};
    let (work0, evals0) = (work(), target_work());
    let mut best: Option<(Inv7, u64, f64)> = None;
    for s in &starts {
        let (p, it) = fit_cell_route(&t, s, norm, pl.route())?;
        let v = val(&p);
        if best.as_ref().is_none_or(|b| v < b.2) {
            best = Some((p, it, v));
        }
    }
    let (inv, iters, _) = best.expect("at least one start");
    let (work, target_evals) = (work() - work0, target_work() - evals0);
    let (l2, l1, bar) = held_out(
        &t,
        norm,
        &[(inv, norm), (start, geo_norm), (max_inv, max_norm)],
        pl.tol,
    );
    Ok(Fitted {
        case: c,
        inv,
        norm,
        fresnel,
        err: l2[0],
        err_l1: l1[0],
        err_iso_geo: l2[1],
        err_iso_max: l2[2],
        bar,
        iters,
        work,
        target_evals,
    })
}

/// The table: cells with α_x ≥ α_y fitted (on the diagonal only φ ≤ π/4), the others
/// filled by the symmetry (α_y, α_x, π/2 − φ) = S·(α_x, α_y, φ)·S.
pub(super) fn fit_table(iso: &FittedTable, pl: &Plan) -> Result<(AnisoTable, Vec<Fitted>)> {
    let g = pl.grid;
    let todo = g.fitted_cells();
    let pb = indicatif::ProgressBar::new(todo.len() as u64);
    pb.set_message("ltc-aniso fit");
    let fitted: Vec<Fitted> =
        crate::memo::map_items("ltc-aniso cells", &todo, |&(ix, iy, k, j)| {
            let r = fit_case(
                iso,
                Case {
                    ax: g.alpha(ix),
                    ay: g.alpha(iy),
                    phi: g.phi(k),
                    theta: g.theta(j),
                },
                pl,
            );
            pb.inc(1);
            r
        })?;
    pb.finish_and_clear();
    let mut cells: Vec<Option<AnisoCell>> = vec![None; g.cells()];
    for (&(ix, iy, k, j), f) in todo.iter().zip(&fitted) {
        let c = |p: &Inv7| [p[0], p[1], p[2], p[3], p[4], p[5], p[6], f.norm, f.fresnel];
        cells[g.index(ix, iy, k, j)] = Some(c(&f.inv));
        let mirror = g.index(iy, ix, g.n_phi - 1 - k, j);
        if cells[mirror].is_none() {
            cells[mirror] = Some(c(&mirror_y(&f.inv)));
        }
    }
    let cells = cells
        .into_iter()
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| Error::InvalidArgument("ltc-aniso: a cell was left unfitted".into()))?;
    Ok((AnisoTable { grid: g, cells }, fitted))
}

/// A case between cells: the table (f64 and binary16) against the lobe there, with the
/// interpolated norm, and the isotropic table at √(α_x α_y) and max(α_x, α_y).
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Between {
    pub case: Case,
    pub err_table: f64,
    /// The table's held-out relative L1 there.
    pub err_table_l1: f64,
    pub err_table_f16: f64,
    pub err_iso_geo: f64,
    pub err_iso_max: f64,
    /// The largest error bar of this case's held-out figures.
    pub bar: f64,
}

pub(super) fn between(iso: &FittedTable, table: &AnisoTable, pl: &Plan) -> Result<Vec<Between>> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0);
    let amin = pl.grid.alpha_min;
    let cases: Vec<Case> = (0..pl.cases)
        .map(|_| {
            let (rx, ry): (f64, f64) = (rng.random(), rng.random());
            let t: f64 = rng.random();
            Case {
                ax: (rx * rx).max(amin),
                ay: (ry * ry).max(amin),
                phi: rng.random::<f64>() * std::f64::consts::PI,
                theta: (1.0 - t * t).clamp(0.0, 1.0).acos(),
            }
        })
        .collect();
    let half = table.to_half();
    crate::memo::map_items("ltc-aniso between cells", &cases, |c| {
        let t = AnisoGgxTarget::new(c.ax, c.ay, c.theta, c.phi)?;
        let at = |tb: &AnisoTable| {
            let v = tb.lookup(c.ax, c.ay, c.phi, c.theta.cos());
            (crate::ltc::aniso_table::inv7(&v), v[7])
        };
        let (g, gn) = iso_at(iso, (c.ax * c.ay).sqrt(), c.theta);
        let (m, mn) = iso_at(iso, c.ax.max(c.ay), c.theta);
        let (albedo, _, _) = t.albedo(1e-7);
        // the isotropic table's frame is the view's; its lobe ignores φ entirely
        let (l2, l1, bar) = held_out(
            &t,
            albedo,
            &[at(table), at(&half), (g, gn), (m, mn)],
            pl.tol,
        );
        Ok(Between {
            case: *c,
            err_table: l2[0],
            err_table_l1: l1[0],
            err_table_f16: l2[1],
            err_iso_geo: l2[2],
            err_iso_max: l2[3],
            bar,
        })
    })
}

/// Four anisotropic cases × the four check lights (one straddling the horizon): the
/// shipped table as a shader reads it (binary16, interpolated), the isotropic table at
/// √(α_x α_y), and MC of the true lobe (`mc` samples per technique).
pub(super) fn polygons(
    iso: &FittedTable,
    table: &AnisoTable,
    mc: usize,
) -> Result<Vec<PolygonRow>> {
    use crate::ltc::polygon::{check_cell, ltc_integral, EdgeForm};
    let half = table.to_half();
    let cases = [
        (0.3, 0.03, 0.3, 30.0),
        (0.05, 0.4, 1.0, 55.0),
        (0.6, 0.15, 2.2, 75.0),
        (0.2, 0.1, 0.0, 10.0),
    ];
    let mut out = Vec::new();
    for (ax, ay, phi, deg) in cases {
        let c = Case {
            ax,
            ay,
            phi,
            theta: f64::to_radians(deg),
        };
        let t = AnisoGgxTarget::new(ax, ay, c.theta, phi)?;
        let v = half.lookup(ax, ay, phi, c.theta.cos());
        let minv = crate::ltc::aniso::inverse_of(&crate::ltc::aniso_table::inv7(&v));
        let (g, gn) = iso_at(iso, (ax * ay).sqrt(), c.theta);
        let giso = crate::ltc::aniso::inverse_of(&g);
        let lights = crate::ltc::polygon::check_lights(c.theta);
        for (k, chk) in check_cell(&t, &minv, v[7], c.theta, mc)?
            .into_iter()
            .enumerate()
        {
            out.push(PolygonRow {
                case: c,
                albedo: t.albedo(1e-7).0,
                iso_geo_exact: gn * ltc_integral(&giso, &lights[k].1.vertices, EdgeForm::Exact),
                check: chk,
            });
        }
    }
    Ok(out)
}

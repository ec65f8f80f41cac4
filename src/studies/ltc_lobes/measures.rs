//! The measures of a table family, the GGX table's for each table: held-out
//! relative L2 per cell and the worst cells, the error between cells (the bilinear
//! interpolation a shader samples), what f32 and binary16 storage cost, the albedo by
//! quadrature against Monte Carlo, the polygon integral against MC of the true lobe
//! (a light straddling the horizon included), and the cost of shading one lobe with the
//! other's table. The report (`report`) formats them.

use super::compute::{Fitted, Plan};
use crate::error::Result;
use crate::integrate::{Figure, Quad};
use crate::ltc::fit::{inverse_from_production, Cell, Table};
use crate::ltc::lobe_error::Change;
use crate::ltc::polygon::{check_cell, PolygonCheck};
use crate::ltc::target::LtcTarget;
use crate::memo::Memo;
use serde::Serialize;

/// The side of the stratified Monte Carlo grid the norms are checked against.
pub const NORM_MC_SIDE: usize = 256;
/// The albedo below which a cell is left out of that check (its MC has almost no samples).
pub const NORM_MC_MIN: f64 = 1e-6;

/// One cell, as reported among the worst.
#[derive(Clone, Debug, Serialize)]
pub struct CellRow {
    pub alpha: f64,
    pub theta_deg: f64,
    pub inv: [f64; 4],
    pub norm: f64,
    pub fresnel: f64,
    pub l2: Figure<Quad>,
    pub l1: Figure<Quad>,
}

/// The change of the held-out relative L2 that a storage precision costs, each change
/// ± the sum of the two figures' error bars.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct StorageCost {
    pub mean_change: Figure<Quad>,
    pub largest_change: Figure<Quad>,
    pub at: (f64, f64),
    /// Cells whose stored matrix has a non-positive determinant (a mirrored lobe).
    pub mirrored: usize,
}

/// What the BRDF itself does that engines may not expect.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Facts {
    /// Cells whose albedo (the stored norm) exceeds 1.
    pub albedo_above_one: usize,
    pub albedo_max: f64,
    /// (α, θ°) of the largest albedo.
    pub albedo_max_at: (f64, f64),
    /// The LTC's mass below the horizon, (1 − M_zz/‖M_z·‖)/2 (closed form; a
    /// horizon-clipped shader loses it): mean and largest over the cells.
    pub below_horizon_mean: f64,
    pub below_horizon_max: f64,
    pub below_horizon_at: (f64, f64),
}

/// The smallest normal binary16 number.
const F16_NORMAL_MIN: f64 = 6.103515625e-5;

/// One table's measures.
#[derive(Clone, Debug, Serialize)]
pub struct TableReport {
    pub worst: Vec<CellRow>,
    /// The production inverse interpolated at the centres of the squares between cells.
    pub between: crate::studies::ltc_between::Between,
    /// f32, binary16 to nearest, binary16 as stored.
    pub storage: [StorageCost; 3],
    /// Cells with an albedo below binary16's normal range (left out of `storage`).
    pub storage_left_out: usize,
    /// Largest quadrature error estimate of the norm.
    pub norm_error_max: f64,
    /// Largest |quadrature − MC| in units of the MC standard error over the checked cells.
    pub norm_vs_mc_max_se: f64,
    pub norm_mc_cells: usize,
    /// Cells with an albedo below [`NORM_MC_MIN`], left out of the MC check.
    pub norm_mc_left_out: usize,
    /// (α, θ°, the cell's albedo, the check).
    pub polygons: Vec<(f64, f64, f64, PolygonCheck)>,
    pub facts: Facts,
    /// The earlier sampled estimate of the cells' relative L2, to say what changed.
    pub sampled: crate::ltc::held::Sampled,
}

/// Everything the report shows.
pub struct Report {
    pub main: TableReport,
    pub variant: TableReport,
}

fn flat(t: &Table) -> Vec<&Cell> {
    t.cells.iter().flatten().collect()
}

/// The LTC's mass below the horizon: with (Mω)_z = m·ω (m the third row of M), the
/// clamped cosine's share of the half-space m·ω < 0 is (1 − m_z/|m|)/2.
pub fn below_horizon(inv: &[f64; 4]) -> f64 {
    match inverse_from_production(inv).try_inverse() {
        Some(m) => {
            let r = m.row(2);
            0.5 * (1.0 - r[2] / r.norm())
        }
        None => f64::NAN,
    }
}

fn facts(t: &Table) -> Facts {
    let cells = flat(t);
    let at = |c: &Cell| (c.alpha, c.theta.to_degrees());
    let top = cells
        .iter()
        .max_by(|a, b| a.norm.total_cmp(&b.norm))
        .copied();
    let below: Vec<f64> = cells.iter().map(|c| below_horizon(&c.inv)).collect();
    let k = (0..below.len())
        .max_by(|a, b| below[*a].total_cmp(&below[*b]))
        .unwrap_or(0);
    Facts {
        albedo_above_one: cells.iter().filter(|c| c.norm > 1.0).count(),
        albedo_max: top.map_or(f64::NAN, |c| c.norm),
        albedo_max_at: top.map_or((f64::NAN, f64::NAN), at),
        below_horizon_mean: below.iter().sum::<f64>() / below.len().max(1) as f64,
        below_horizon_max: below.get(k).copied().unwrap_or(f64::NAN),
        below_horizon_at: cells.get(k).map_or((f64::NAN, f64::NAN), |c| at(c)),
    }
}

fn storage_costs(t: &Table) -> [StorageCost; 3] {
    use crate::ltc::lobe_error::Held;
    let cells = flat(t);
    std::array::from_fn(|pick| {
        let change = Change::of(
            cells.iter().map(|c| {
                // an albedo below binary16's normal range is stored as (nearly) nothing
                if c.norm < F16_NORMAL_MIN {
                    return None;
                }
                let Held {
                    f64: Some(a),
                    f32,
                    f16_nearest,
                    f16,
                } = c.held?
                else {
                    return None;
                };
                [f32, f16_nearest, f16][pick].map(|b| (a.l2, b.l2))
            }),
            f64::INFINITY,
        );
        let at = change.argmax.map_or((0.0, 0.0), |k| {
            (cells[k].alpha, cells[k].theta.to_degrees())
        });
        let entries = |c: &Cell| -> [f64; 4] {
            match pick {
                0 => c.inv.map(|x| x as f32 as f64),
                1 => c.inv.map(|x| half::f16::from_f64(x).to_f64()),
                _ => [c.half[0], c.half[1], c.half[2], c.half[3]],
            }
        };
        StorageCost {
            mean_change: change.mean,
            largest_change: change.largest,
            at,
            mirrored: cells
                .iter()
                .filter(|c| {
                    let v = entries(c);
                    !(v[0] * v[3] - v[1] * v[2] > 0.0)
                })
                .count(),
        }
    })
}

fn table_report(f: &Fitted, pl: &Plan, sample: usize) -> Result<TableReport> {
    let t = &f.table;
    let n = t.grid.n;
    let mut cells = flat(t);
    let l2 = |c: &Cell| c.l2().map_or(f64::NAN, |b| b.value);
    cells.sort_by(|a, b| l2(b).total_cmp(&l2(a)));
    let none = Figure::<Quad>::new(f64::NAN, f64::NAN);
    let worst = cells
        .iter()
        .take(6)
        .map(|c| {
            let e = c.held.and_then(|h| h.f64);
            CellRow {
                alpha: c.alpha,
                theta_deg: c.theta.to_degrees(),
                inv: c.inv,
                norm: c.norm,
                fresnel: c.fresnel,
                l2: e.map_or(none, |e| e.l2),
                l1: e.map_or(none, |e| e.l1),
            }
        })
        .collect();
    let target = |a: f64, th: f64| f.lobe.target(a, th);
    let between = crate::studies::ltc_between::measure(t, &target, pl.tolerance(), sample)?;
    let target = |a: f64, th: f64| f.lobe.target(a, th);
    // the norm by quadrature against stratified MC (NORM_MC_SIDE² samples of the lobe's
    // sampler)
    let step = (n / 8).max(1);
    let probe: Vec<&Cell> = (0..n)
        .step_by(step)
        .flat_map(|j| (0..n).step_by(step).map(move |i| (i, j)))
        .map(|(i, j)| &t.cells[j][i])
        .collect();
    let zs: Vec<Option<f64>> = crate::memo::map_items("lobe norm against MC", &probe, |c| {
        let tgt = f.lobe.target(c.alpha, c.theta)?;
        let (m, _, se, _) = tgt.moments(NORM_MC_SIDE);
        // cells whose albedo is below NORM_MC_MIN (sheen seen head-on at the smallest α) are
        // left out: their energy is invisible and their MC has almost no samples
        Ok((c.norm >= NORM_MC_MIN).then(|| (m - c.norm).abs() / se.max(1e-300)))
    })?;
    // polygons: four cells × four lights
    let mut polygons = Vec::new();
    for (ai, tj) in [
        (n / 2, n / 4),
        (n / 4, n / 2),
        (n - 1, 3 * n / 4),
        (n / 8 + 1, n - 1),
    ] {
        let c = &t.cells[tj.min(n - 1)][ai.min(n - 1)];
        let tgt = f.lobe.target(c.alpha, c.theta)?;
        let minv = inverse_from_production(&c.inv);
        for p in check_cell(&tgt, &minv, c.norm, c.theta, pl.mc)? {
            polygons.push((c.alpha, c.theta.to_degrees(), c.norm, p));
        }
    }
    Ok(TableReport {
        worst,
        between,
        storage: storage_costs(t),
        storage_left_out: flat(t).iter().filter(|c| c.norm < F16_NORMAL_MIN).count(),
        norm_error_max: flat(t).iter().map(|c| c.norm_se).fold(0.0, f64::max),
        norm_vs_mc_max_se: zs.iter().flatten().cloned().fold(0.0, f64::max),
        norm_mc_cells: zs.iter().flatten().count(),
        norm_mc_left_out: zs.iter().filter(|z| z.is_none()).count(),
        polygons,
        facts: facts(t),
        sampled: crate::ltc::held::sampled_estimate(&Memo, t, &target, 2 * pl.samples)?,
    })
}

/// All measures of both tables of a family.
pub(super) fn compute(main: &Fitted, variant: &Fitted, pl: &Plan, sample: usize) -> Result<Report> {
    Ok(Report {
        main: table_report(main, pl, sample)?,
        variant: table_report(variant, pl, sample)?,
    })
}

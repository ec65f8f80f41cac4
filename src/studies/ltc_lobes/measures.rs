//! The measures of a table family, the GGX table's for each table: held-out
//! relative L2 per cell and the worst cells, the error between cells (the bilinear
//! interpolation a shader samples), what f32 and binary16 storage cost, the albedo by
//! quadrature against Monte Carlo, the polygon integral against MC of the true lobe
//! (a light straddling the horizon included), and the cost of shading one lobe with the
//! other's table. The report (`report`) formats them.

use super::compute::{Fitted, Plan};
use crate::error::Result;
use crate::integrate::{Figure, Quad, StdErr};
use crate::ltc::compare::{square_centre, square_error_of, square_lobe, Shipped};
use crate::ltc::fit::{inverse_from_production, Cell, Table};
use crate::ltc::lobe_error::{Change, LobeError};
use crate::ltc::polygon::{check_cell, PolygonCheck};
use crate::ltc::target::LtcTarget;
use crate::memo::Memo;
use crate::results::ltc::Located;
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

/// The albedo below which a lobe's relative error is left out of the between-cell means
/// (a ten-thousandth of a white light's energy).
pub const VISIBLE_ALBEDO: f64 = 1e-4;

/// The smallest normal binary16 number.
const F16_NORMAL_MIN: f64 = 6.103515625e-5;

/// One table's measures.
#[derive(Clone, Debug, Serialize)]
pub struct TableReport {
    pub worst: Vec<CellRow>,
    /// The production inverse interpolated at the centres of the squares between cells.
    pub between: Between,
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

/// The table in the shipped layout (for the between-cell measure).
fn as_shipped(t: &Table) -> Shipped {
    let n = t.grid.n;
    Shipped {
        n,
        mat: (0..n * n).map(|k| t.cells[k / n][k % n].inv).collect(),
        mag: (0..n * n)
            .map(|k| [t.cells[k / n][k % n].norm, 0.0])
            .collect(),
    }
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
    let between = measure_between(f, pl, sample)?;
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

/// The seed of the random sample of squares the between-cell figures judge.
const BETWEEN_SEED: u64 = 0x005e_edb7;

/// The cells (by held-out relative L2, worst first) whose squares the between-cell figures
/// always judge, so that the largest error between cells is not left to chance.
pub const BETWEEN_WORST_CELLS: usize = 16;

/// The error between cells: the table interpolated at square centres as a shader reads it,
/// judged against the lobe there.
#[derive(Clone, Debug, Serialize)]
pub struct Between {
    /// Over the judged squares (their count, mean, largest and where).
    pub judged: Located,
    /// Squares whose lobe has an albedo of at least [`VISIBLE_ALBEDO`] (the population),
    /// and those below it, left out: between corners whose albedos differ by orders of
    /// magnitude (sheen seen head-on at small α) the interpolated norm dwarfs such a lobe.
    pub visible: usize,
    pub left_out: usize,
    /// Whether `judged` holds every visible square (its means are then exact).
    pub all: bool,
    /// Visible squares judged whatever the sample (those touching the
    /// [`BETWEEN_WORST_CELLS`] worst cells and those whose corners' entries jump most;
    /// every one when `all`), and the rest, of which a random sample was judged.
    pub census: usize,
    pub rest: usize,
    /// The mean relative L2 and L1 over every visible square: the census squares' sum plus
    /// the rest's from a random sample of them by `Figure::difference_mean`, with the mean
    /// of each square's four corner cells' held-out figures as the control (± the sample's
    /// standard error scaled by the rest's share; exact, ± 0, when all are judged). A
    /// judged square without a figure (a singular interpolated matrix; none in the
    /// published tables) adds nothing to the census sum and is left out of the sample.
    pub mean_l2: Figure<StdErr>,
    pub mean_l1: Figure<StdErr>,
}

/// The visible squares (indices into the row-major squares) a between-cell measure judges:
/// the census, every one of them judged, and the rest, of which `drawn` were.
struct Picked {
    census: Vec<usize>,
    rest: Vec<usize>,
    drawn: Vec<usize>,
}

/// Per square (row-major), how far its four corners' entries (a, b, c, d, norm) spread:
/// Σ over the entries of (max − min)/(max |v| + the entry's mean |v| over the table).
fn corner_jumps(t: &Table) -> Vec<f64> {
    let n = t.grid.n;
    let entry = |c: &Cell, e: usize| if e < 4 { c.inv[e] } else { c.norm };
    let scale: Vec<f64> = (0..5)
        .map(|e| flat(t).iter().map(|c| entry(c, e).abs()).sum::<f64>() / (n * n) as f64)
        .collect();
    (0..(n - 1) * (n - 1))
        .map(|k| {
            let (i, j) = (k % (n - 1), k / (n - 1));
            let corners =
                [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)].map(|(a, b)| &t.cells[b][a]);
            (0..5)
                .map(|e| {
                    let v = corners.map(|c| entry(c, e));
                    let (lo, hi) = v
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                            (l.min(x), h.max(x))
                        });
                    let big = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                    (hi - lo) / (big + scale[e]).max(f64::MIN_POSITIVE)
                })
                .sum()
        })
        .collect()
}

/// The census — the squares touching the [`BETWEEN_WORST_CELLS`] worst cells, and the
/// quarter of `sample` whose corners' entries jump most ([`corner_jumps`]) — and the other
/// three quarters drawn at random (fixed seed) from the rest; all of them (all census)
/// when those reach the rest's count.
fn pick_squares(t: &Table, visible: &[usize], sample: usize) -> Picked {
    use rand::SeedableRng;
    if sample >= visible.len() {
        return Picked {
            census: visible.to_vec(),
            rest: Vec::new(),
            drawn: Vec::new(),
        };
    }
    let n = t.grid.n;
    let l2 = |(i, j): (usize, usize)| {
        let c: &Cell = &t.cells[j][i];
        c.l2().map_or(f64::NEG_INFINITY, |b| b.value)
    };
    let mut cells: Vec<(usize, usize)> = (0..n).flat_map(|j| (0..n).map(move |i| (i, j))).collect();
    cells.sort_by(|&a, &b| l2(b).total_cmp(&l2(a)));
    cells.truncate(BETWEEN_WORST_CELLS);
    // square k = i + (n − 1)·j has corners (i, j) … (i + 1, j + 1)
    let touches = |k: usize| {
        let (i, j) = (k % (n - 1), k / (n - 1));
        cells
            .iter()
            .any(|&(a, b)| (a == i || a == i + 1) && (b == j || b == j + 1))
    };
    let (mut census, rest): (Vec<usize>, Vec<usize>) = visible.iter().partition(|&&k| touches(k));
    // and the quarter of the sample where the corners' entries jump most (where the
    // interpolated lobe strays furthest from its corners' fits)
    let jump = corner_jumps(t);
    let mut rest = rest;
    rest.sort_by(|&a, &b| jump[b].total_cmp(&jump[a]).then(a.cmp(&b)));
    census.extend(rest.drain(..(sample / 4).min(rest.len())));
    census.sort_unstable();
    rest.sort_unstable();
    let sample = sample - sample / 4;
    if sample >= rest.len() {
        return Picked {
            census: visible.to_vec(),
            rest: Vec::new(),
            drawn: Vec::new(),
        };
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(BETWEEN_SEED);
    let mut drawn: Vec<usize> = rand::seq::index::sample(&mut rng, rest.len(), sample)
        .into_iter()
        .map(|k| rest[k])
        .collect();
    drawn.sort_unstable();
    Picked {
        census,
        rest,
        drawn,
    }
}

/// The mean over every visible square of the relative L2 (or L1) from the judged ones:
/// the census's sum plus the rest's from its random sample by `Figure::difference_mean`,
/// the control x being the mean of a square's corner cells' held-out figures.
fn stratified_mean(
    t: &Table,
    p: &Picked,
    y: &dyn Fn(usize) -> Option<f64>,
    l1: bool,
) -> Figure<StdErr> {
    let n = t.grid.n;
    let x = |k: usize| {
        let (i, j) = (k % (n - 1), k / (n - 1));
        let v: Vec<f64> = [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
            .iter()
            .filter_map(|&(a, b)| t.cells[b][a].held.and_then(|h| h.f64))
            .map(|e| if l1 { e.l1.value } else { e.l2.value })
            .collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    let total = (p.census.len() + p.rest.len()) as f64;
    let census: f64 = p.census.iter().filter_map(|&k| y(k)).sum();
    if p.rest.is_empty() {
        return Figure::with_se(census / total, 0.0);
    }
    let x_mean = p.rest.iter().map(|&k| x(k)).sum::<f64>() / p.rest.len() as f64;
    let d: Vec<f64> = p.drawn.iter().filter_map(|&k| Some(y(k)? - x(k))).collect();
    let rest = Figure::difference_mean(x_mean, &d, p.rest.len());
    let share = p.rest.len() as f64 / total;
    Figure::with_se(census / total + share * rest.value, share * rest.error)
}

/// [`Between`] of a fitted table: every square's lobe and albedo, then the judge at the
/// squares [`pick_squares`] chooses.
fn measure_between(f: &Fitted, pl: &Plan, sample: usize) -> Result<Between> {
    let t = &f.table;
    let n = t.grid.n;
    let sh = as_shipped(t);
    let target = |a: f64, th: f64| f.lobe.target(a, th);
    let squares: Vec<(usize, usize)> = (0..n - 1)
        .flat_map(|j| (0..n - 1).map(move |i| (i, j)))
        .collect();
    let albedos: Vec<f64> = crate::memo::map_items("lobe table square albedos", &squares, |&q| {
        Ok(square_lobe(n, q, t.grid.alpha_min, &target)?.1)
    })?;
    let visible: Vec<usize> = (0..squares.len())
        .filter(|&k| albedos[k] >= VISIBLE_ALBEDO)
        .collect();
    let p = pick_squares(t, &visible, sample);
    let judged: Vec<usize> = p.census.iter().chain(&p.drawn).copied().collect();
    let errs: Vec<Option<LobeError>> =
        crate::memo::map_items("lobe table between cells", &judged, |&k| {
            // the lobe again (cheap), not its albedo: the first pass has it
            let (alpha, theta) = square_centre(n, squares[k], t.grid.alpha_min);
            let lobe = target(alpha, theta)?;
            Ok(square_error_of(
                &sh,
                squares[k],
                &lobe,
                albedos[k],
                pl.tolerance(),
            ))
        })?;
    let at = |q: (usize, usize)| {
        let (alpha, theta) = square_centre(n, q, t.grid.alpha_min);
        (alpha, theta.to_degrees())
    };
    let mids: Vec<(Option<LobeError>, (f64, f64))> = judged
        .iter()
        .zip(&errs)
        .map(|(&k, e)| (*e, at(squares[k])))
        .collect();
    let by_square: std::collections::HashMap<usize, LobeError> = judged
        .iter()
        .zip(&errs)
        .filter_map(|(&k, e)| Some((k, (*e)?)))
        .collect();
    let by_square = &by_square;
    let y = |l1: bool| {
        move |k: usize| {
            by_square
                .get(&k)
                .map(|e| if l1 { e.l1.value } else { e.l2.value })
        }
    };
    Ok(Between {
        judged: Located::of(&mids),
        visible: visible.len(),
        left_out: squares.len() - visible.len(),
        all: p.rest.is_empty(),
        census: p.census.len(),
        rest: p.rest.len(),
        mean_l2: stratified_mean(t, &p, &y(false), false),
        mean_l1: stratified_mean(t, &p, &y(true), true),
    })
}

/// All measures of both tables of a family.
pub(super) fn compute(main: &Fitted, variant: &Fitted, pl: &Plan, sample: usize) -> Result<Report> {
    Ok(Report {
        main: table_report(main, pl, sample)?,
        variant: table_report(variant, pl, sample)?,
    })
}

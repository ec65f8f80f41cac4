//! The error between the cells of an LTC table, where a shader's bilinear lookup lands:
//! the table interpolated at the centres of its squares, judged against the lobe there by
//! the held-out integrals (`ltc::lobe_error`). The GGX table judges every square (its
//! errors between cells have a tail no affordable sample covers, and its lobe is cheap to
//! judge). For the sheen and diffuse tables, judging every square cost as much as the
//! cells' own judge, so their figures come from a calibrated sample: the squares where the
//! error is likeliest to be largest are judged always, a fixed-seed random sample of the
//! rest, and the mean over every square is estimated without bias with its standard error
//! (`Figure::difference_mean`).

use crate::error::Result;
use crate::integrate::{Figure, StdErr};
use crate::ltc::compare::{square_centre, square_error_of, square_lobe, Shipped};
use crate::ltc::fit::{Cell, Table};
use crate::ltc::lobe_error::{LobeError, Tolerance};
use crate::ltc::target::LtcTarget;
pub use crate::results::between::Between;
use crate::results::ltc::Located;

pub mod report;

/// The random squares judged where a sheen or diffuse spec gives no `between_sample`
/// (quick and default presets). Measured against judging every square of the published
/// tables (results of one full run, the sample redrawn 2000 times): ±2 s.e. covered the
/// exact mean in 94–96 % of the draws at 1024 (and at 512; at 2048 the sheen tables'
/// coverage fell to 92–93 %), for about a quarter of the judge's work between cells. The
/// GGX table judges every square: its check, in fits/ltc-ggx.toml, found no sample size
/// whose bars hold.
pub const BETWEEN_SAMPLE: usize = 1024;

/// The random squares judged at `preset` given the spec's `between_sample` (`usize::MAX`:
/// all): the spec's number, else every square at the precise preset and
/// [`BETWEEN_SAMPLE`] at the others.
pub fn sample_at(given: Option<usize>, preset: crate::integrate::Preset) -> usize {
    match (given, preset) {
        (Some(m), _) => m,
        (None, crate::integrate::Preset::Precise) => usize::MAX,
        (None, _) => BETWEEN_SAMPLE,
    }
}

/// The spec check of `between_sample`: 0 would judge no square.
pub fn check_sample(given: Option<usize>) -> std::result::Result<(), String> {
    match given {
        Some(0) => Err("between_sample = 0 judges no square: give at least 1".into()),
        _ => Ok(()),
    }
}

/// The table in the shipped layout, the norm as the second texture's first channel.
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

/// The albedo below which a lobe's relative error is left out of the between-cell means
/// (a ten-thousandth of a white light's energy).
pub const VISIBLE_ALBEDO: f64 = 1e-4;

/// The seed of the random sample of squares the between-cell figures judge.
const BETWEEN_SEED: u64 = 0x005e_edb7;

/// The cells (by held-out relative L2, worst first) whose squares the between-cell figures
/// always judge, so that the largest error between cells is not left to chance.
pub const BETWEEN_WORST_CELLS: usize = 16;

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
        .map(|e| {
            t.cells
                .iter()
                .flatten()
                .map(|c| entry(c, e).abs())
                .sum::<f64>()
                / (n * n) as f64
        })
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

/// [`Between`] of a fitted table `t` whose lobe at (α, θ) is `target`: every square's
/// lobe and albedo (which decides the population), then the held-out judge (`tol`) at the
/// squares [`pick_squares`] chooses, `sample` of them at random.
pub fn measure<T: LtcTarget>(
    t: &Table,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    tol: Tolerance,
    sample: usize,
) -> Result<Between> {
    let n = t.grid.n;
    let sh = as_shipped(t);
    let squares: Vec<(usize, usize)> = (0..n - 1)
        .flat_map(|j| (0..n - 1).map(move |i| (i, j)))
        .collect();
    let albedos: Vec<f64> = crate::memo::map_items("lobe table square albedos", &squares, |&q| {
        Ok(square_lobe(n, q, t.grid.alpha_min, target)?.1)
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
            Ok(square_error_of(&sh, squares[k], &lobe, albedos[k], tol))
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

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
use crate::ltc::fit::Table;
use crate::ltc::lobe_error::{LobeError, Tolerance};
use crate::ltc::target::LtcTarget;
pub use crate::results::between::Between;
use crate::results::ltc::Located;

pub mod report;

/// The random squares judged where a sheen or diffuse spec gives no `between_sample`
/// (quick and default presets), chosen from the curve of the `ltc-between-sample` study
/// (results/ltc-between-sample.md: every square of each published table judged, the
/// sample redrawn per size): at 1024 the ±2 s.e. interval covers the exact mean about as
/// often as an honest one should, for about a quarter of the judge's work between cells;
/// at 2048 the sheen tables' coverage falls (the rest's heavy tail is too thin a sample).
/// The GGX table judges every square: on that curve its s.e. at 1024 is 180 times its
/// integrals' bars, and judging all costs it little.
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

/// The tables whose figures between cells judge every square unless their spec names a
/// sample: the GGX table (see [`BETWEEN_SAMPLE`]; measured in fits/ltc-ggx.toml).
pub const JUDGE_ALL: &[&str] = &["ltc-ggx"];

/// The random squares table `table` judges at `preset` given its spec's `between_sample`
/// (`usize::MAX`: all): the spec's number, else every square for the tables of
/// [`JUDGE_ALL`], else [`sample_at`]. The one rule the studies and the calibration study
/// both read.
pub fn sample_for(table: &str, given: Option<usize>, preset: crate::integrate::Preset) -> usize {
    match given {
        None if JUDGE_ALL.contains(&table) => usize::MAX,
        _ => sample_at(given, preset),
    }
}

/// The spec check of `between_sample`: 0 would judge no square.
pub fn check_sample(given: Option<usize>) -> std::result::Result<(), String> {
    match given {
        Some(0) => Err("between_sample = 0 judges no square: give at least 1".into()),
        _ => Ok(()),
    }
}

/// What the sample design and the estimator read of a table, cell k = i + n·j (i the
/// roughness index, j the view's): its entries and its held-out figures.
pub struct Cells {
    pub n: usize,
    pub alpha_min: f64,
    /// (a, b, c, d, norm) of the f64 cell.
    pub entries: Vec<[f64; 5]>,
    /// The f64 cell's held-out (relative L2, relative L1); `None` where it has none.
    pub held: Vec<Option<[f64; 2]>>,
}

impl Cells {
    /// A fitted, judged table's cells.
    pub fn of_table(t: &Table) -> Cells {
        let n = t.grid.n;
        let cell = |k: usize| &t.cells[k / n][k % n];
        Cells {
            n,
            alpha_min: t.grid.alpha_min,
            entries: (0..n * n)
                .map(|k| {
                    let c = cell(k);
                    [c.inv[0], c.inv[1], c.inv[2], c.inv[3], c.norm]
                })
                .collect(),
            held: (0..n * n)
                .map(|k| {
                    let e = cell(k).held.and_then(|h| h.f64)?;
                    Some([e.l2.value, e.l1.value])
                })
                .collect(),
        }
    }

    /// The table in the shipped layout, the norm as the second texture's first channel.
    fn shipped(&self) -> Shipped {
        Shipped {
            n: self.n,
            mat: self
                .entries
                .iter()
                .map(|e| [e[0], e[1], e[2], e[3]])
                .collect(),
            mag: self.entries.iter().map(|e| [e[4], 0.0]).collect(),
        }
    }

    /// Square k = i + (n − 1)·j as (i, j): its corners are (i, j) … (i + 1, j + 1).
    pub fn square(&self, k: usize) -> (usize, usize) {
        (k % (self.n - 1), k / (self.n - 1))
    }

    /// The squares' count, (n − 1)².
    pub fn squares(&self) -> usize {
        (self.n - 1) * (self.n - 1)
    }
}

/// The albedo below which a lobe's relative error is left out of the between-cell means
/// (a ten-thousandth of a white light's energy).
pub const VISIBLE_ALBEDO: f64 = 1e-4;

/// The seed of the random sample of squares the between-cell figures judge.
pub const BETWEEN_SEED: u64 = 0x005e_edb7;

/// The cells (by held-out relative L2, worst first) whose squares the between-cell figures
/// always judge, so that the largest error between cells is not left to chance.
pub const BETWEEN_WORST_CELLS: usize = 16;

/// The visible squares (indices k = i + (n − 1)·j) a between-cell measure judges: the
/// census, every one of them judged, and the rest, of which `drawn` were.
#[derive(Clone)]
pub struct Picked {
    pub census: Vec<usize>,
    pub rest: Vec<usize>,
    pub drawn: Vec<usize>,
}

/// Per square, how far its four corners' entries (a, b, c, d, norm) spread: Σ over the
/// entries of (max − min)/(max |v| + the entry's mean |v| over the table).
fn corner_jumps(c: &Cells) -> Vec<f64> {
    let n = c.n;
    let scale: Vec<f64> = (0..5)
        .map(|e| c.entries.iter().map(|v| v[e].abs()).sum::<f64>() / (n * n) as f64)
        .collect();
    (0..c.squares())
        .map(|k| {
            let (i, j) = c.square(k);
            let corners = [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
                .map(|(a, b)| &c.entries[a + n * b]);
            (0..5)
                .map(|e| {
                    let v = corners.map(|x| x[e]);
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
/// three quarters drawn at random (`seed`) from the rest; all of them (all census) when
/// those reach the rest's count. The studies draw with [`BETWEEN_SEED`].
pub fn pick_squares(c: &Cells, visible: &[usize], sample: usize, seed: u64) -> Picked {
    draw(census(c, visible, sample), sample, seed)
}

/// [`pick_squares`]' census and rest, nothing drawn yet (all census when `sample` reaches
/// the visible squares or, past the census, the rest).
pub fn census(c: &Cells, visible: &[usize], sample: usize) -> Picked {
    let all = || Picked {
        census: visible.to_vec(),
        rest: Vec::new(),
        drawn: Vec::new(),
    };
    if sample >= visible.len() {
        return all();
    }
    let n = c.n;
    let l2 = |(i, j): (usize, usize)| c.held[i + n * j].map_or(f64::NEG_INFINITY, |h| h[0]);
    let mut cells: Vec<(usize, usize)> = (0..n).flat_map(|j| (0..n).map(move |i| (i, j))).collect();
    cells.sort_by(|&a, &b| l2(b).total_cmp(&l2(a)));
    cells.truncate(BETWEEN_WORST_CELLS);
    let touches = |k: usize| {
        let (i, j) = c.square(k);
        cells
            .iter()
            .any(|&(a, b)| (a == i || a == i + 1) && (b == j || b == j + 1))
    };
    let (mut census, rest): (Vec<usize>, Vec<usize>) = visible.iter().partition(|&&k| touches(k));
    // and the quarter of the sample where the corners' entries jump most (where the
    // interpolated lobe strays furthest from its corners' fits)
    let jump = corner_jumps(c);
    let mut rest = rest;
    rest.sort_by(|&a, &b| jump[b].total_cmp(&jump[a]).then(a.cmp(&b)));
    census.extend(rest.drain(..(sample / 4).min(rest.len())));
    census.sort_unstable();
    rest.sort_unstable();
    if sample - sample / 4 >= rest.len() {
        return all();
    }
    Picked {
        census,
        rest,
        drawn: Vec::new(),
    }
}

/// The three quarters of `sample` drawn at random (`seed`) from a [`census`]'s rest (the
/// whole rest where they reach it: a census made for a smaller sample).
pub fn draw(base: Picked, sample: usize, seed: u64) -> Picked {
    use rand::SeedableRng;
    if base.rest.is_empty() {
        return base;
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let rest = base.rest;
    let amount = (sample - sample / 4).min(rest.len());
    let mut drawn: Vec<usize> = rand::seq::index::sample(&mut rng, rest.len(), amount)
        .into_iter()
        .map(|k| rest[k])
        .collect();
    drawn.sort_unstable();
    Picked {
        census: base.census,
        rest,
        drawn,
    }
}

/// Per square, the control of [`stratified_mean`]: the mean of its corner cells' held-out
/// relative L2 (or L1 with `l1`), over the corners that have one.
pub fn control(c: &Cells, l1: bool) -> Vec<f64> {
    let n = c.n;
    (0..c.squares())
        .map(|k| {
            let (i, j) = c.square(k);
            let (sum, count) = [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
                .iter()
                .filter_map(|&(a, b)| c.held[a + n * b])
                .fold((0.0, 0usize), |(s, m), h| (s + h[usize::from(l1)], m + 1));
            sum / count.max(1) as f64
        })
        .collect()
}

/// Per square, the judged (relative L2, relative L1) of the squares `which` (`errs` in
/// the same order); `None` where a square was not judged or has no figure.
pub fn figures(c: &Cells, which: &[usize], errs: &[Option<LobeError>]) -> Vec<Option<[f64; 2]>> {
    let mut fig = vec![None; c.squares()];
    for (&k, e) in which.iter().zip(errs) {
        fig[k] = e.map(|e| [e.l2.value, e.l1.value]);
    }
    fig
}

/// The mean over every visible square of the relative L2 (or L1 with `l1`) from the judged
/// ones (`fig`, by square, [`figures`]): the census's sum plus the rest's from its random
/// sample by `Figure::difference_mean`, the control `x` (by square, [`control`]) being the
/// mean of a square's corner cells' held-out figures.
pub fn stratified_mean(
    p: &Picked,
    fig: &[Option<[f64; 2]>],
    x: &[f64],
    l1: bool,
) -> Figure<StdErr> {
    let y = |k: usize| fig[k].map(|f| f[usize::from(l1)]);
    let total = (p.census.len() + p.rest.len()) as f64;
    let census: f64 = p.census.iter().filter_map(|&k| y(k)).sum();
    if p.rest.is_empty() {
        return Figure::with_se(census / total, 0.0);
    }
    let x_mean = p.rest.iter().map(|&k| x[k]).sum::<f64>() / p.rest.len() as f64;
    let d: Vec<f64> = p.drawn.iter().filter_map(|&k| Some(y(k)? - x[k])).collect();
    let rest = Figure::difference_mean(x_mean, &d, p.rest.len());
    let share = p.rest.len() as f64 / total;
    Figure::with_se(census / total + share * rest.value, share * rest.error)
}

/// Every square's albedo (the lobe at its centre; 1e-8 quadrature), which decides the
/// population ([`VISIBLE_ALBEDO`]) and is the judge's norm.
pub fn square_albedos<T: LtcTarget>(
    c: &Cells,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
) -> Result<Vec<f64>> {
    let squares: Vec<usize> = (0..c.squares()).collect();
    crate::memo::map_items("lobe table square albedos", &squares, |&k| {
        Ok(square_lobe(c.n, c.square(k), c.alpha_min, target)?.1)
    })
}

/// The held-out figures (`tol`) of the squares `which`, the table interpolated at each
/// centre as a shader reads it against the lobe there (of albedo `albedos[k]`).
pub fn judge_squares<T: LtcTarget>(
    c: &Cells,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    albedos: &[f64],
    which: &[usize],
    tol: Tolerance,
) -> Result<Vec<Option<LobeError>>> {
    let sh = c.shipped();
    crate::memo::map_items("lobe table between cells", which, |&k| {
        // the lobe again (cheap), not its albedo: the first pass has it
        let (alpha, theta) = square_centre(c.n, c.square(k), c.alpha_min);
        let lobe = target(alpha, theta)?;
        Ok(square_error_of(&sh, c.square(k), &lobe, albedos[k], tol))
    })
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
    let c = Cells::of_table(t);
    let albedos = square_albedos(&c, target)?;
    let visible: Vec<usize> = (0..c.squares())
        .filter(|&k| albedos[k] >= VISIBLE_ALBEDO)
        .collect();
    let p = pick_squares(&c, &visible, sample, BETWEEN_SEED);
    let judged: Vec<usize> = p.census.iter().chain(&p.drawn).copied().collect();
    let errs = judge_squares(&c, target, &albedos, &judged, tol)?;
    let at = |k: usize| {
        let (alpha, theta) = square_centre(c.n, c.square(k), c.alpha_min);
        (alpha, theta.to_degrees())
    };
    let mids: Vec<(Option<LobeError>, (f64, f64))> = judged
        .iter()
        .zip(&errs)
        .map(|(&k, e)| (*e, at(k)))
        .collect();
    let fig = figures(&c, &judged, &errs);
    Ok(Between {
        judged: Located::of(&mids),
        visible: visible.len(),
        left_out: c.squares() - visible.len(),
        all: p.rest.is_empty(),
        census: p.census.len(),
        rest: p.rest.len(),
        mean_l2: stratified_mean(&p, &fig, &control(&c, false), false),
        mean_l1: stratified_mean(&p, &fig, &control(&c, true), true),
    })
}

#[cfg(test)]
mod tests {
    use crate::studies::ltc_between::{census, draw, Cells};

    /// A table of n² cells whose held-out figure grows with the cell index.
    fn cells(n: usize) -> Cells {
        Cells {
            n,
            alpha_min: 1e-5,
            entries: (0..n * n)
                .map(|k| [1.0 + k as f64, 0.0, 0.0, 1.0, 1.0])
                .collect(),
            held: (0..n * n).map(|k| Some([k as f64, k as f64])).collect(),
        }
    }

    /// `draw` is total: a census made for one sample and drawn at a larger one takes the
    /// whole rest (no panic), at the same size the three quarters, each square once.
    #[test]
    fn a_draw_never_asks_for_more_than_the_rest() {
        let c = cells(24);
        let visible: Vec<usize> = (0..c.squares()).collect();
        let base = census(&c, &visible, 64);
        assert!(!base.rest.is_empty());
        let p = draw(base.clone(), 64, 7);
        assert_eq!(p.drawn.len(), 64 - 16);
        let big = draw(base.clone(), 100_000, 7);
        assert_eq!(big.drawn, base.rest);
        let mut d = p.drawn.clone();
        d.dedup();
        assert_eq!(d.len(), p.drawn.len());
    }
}

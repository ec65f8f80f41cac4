//! Fitting a table for what a shader sees: a shader never reads one cell, it reads the
//! bilinear interpolation of four (the matrix entries a, b, c, d and the norm, each
//! interpolated linearly). This pass refits every cell's production inverse against its
//! own lobe and against the lobes at the centres of the (up to four) squares it is a
//! corner of, each interpolated as a GPU does, so that the table is good between cells
//! too — not only at them.
//!
//! Objective of cell k: Σ_P w_P (e_P/e_P⁰)² over P = the cell (w = 1) and its squares
//! (w = the square weight), e_P the relative L2 ‖f − norm·γ‖/‖f‖ on the training set (n×n
//! per technique, offset 0.5) and e_P⁰ the same before the pass: each place counts by its
//! relative change, so a cell whose lobe fits well is not spent on a square that cannot. Nelder–Mead
//! (argmin) on (ln a, ln d, b, c) from the current entries; the move is kept only if the
//! same objective on the validation set ((n + 7)², offset 0.37) drops too. The norm is
//! not touched (it stays the albedo: energy-exact). Cells are visited in four colours by
//! (i mod 2, j mod 2): no square has two corners of one colour, so the cells of a colour
//! are refitted in parallel against a fixed snapshot of the others — deterministic at any
//! thread count.

use crate::error::{Error, Result};
use crate::ltc::fit::{inverse_from_production, metrics_on, FixedNodes, TargetSamples};
use crate::ltc::target::LtcTarget;
use crate::ltc::LtcDist;
use crate::parmap::ParMap;
use rayon::prelude::*;

/// The relative L2 of one production-form lobe against a target (∞ where singular).
fn rel_l2<T: LtcTarget + ?Sized>(t: &T, inv: &[f64; 4], norm: f64, n: usize, off: f64) -> f64 {
    rel_l2_on(t, &TargetSamples::new(t, n, off), inv, norm)
}

/// [`rel_l2`] on the target's samples `s` drawn beforehand.
fn rel_l2_on<T: LtcTarget + ?Sized>(t: &T, s: &TargetSamples, inv: &[f64; 4], norm: f64) -> f64 {
    rel_l2_at(t, s, None, inv, norm)
}

/// The LTC of production-form entries, `None` where singular.
fn ltc_of(inv: &[f64; 4]) -> Option<LtcDist> {
    inverse_from_production(inv)
        .try_inverse()
        .and_then(|m| LtcDist::new(m).ok())
}

/// [`rel_l2_on`], on `fixed` nodes where given (drawn from `s`, `FixedNodes`).
fn rel_l2_at<T: LtcTarget + ?Sized>(
    t: &T,
    s: &TargetSamples,
    fixed: Option<&FixedNodes>,
    inv: &[f64; 4],
    norm: f64,
) -> f64 {
    ltc_of(inv)
        .map(|l| match fixed {
            Some(f) => f.metrics(&l, norm).1,
            None => metrics_on(t, s, &l, norm).1,
        })
        .filter(|x| x.is_finite())
        .unwrap_or(f64::INFINITY)
}

/// The places a cell's entries reach: its own centre, and each square it is a corner of
/// (its square index and the cell's corner weight, always ¼ at the centre).
fn places(i: usize, j: usize, n: usize) -> Vec<(usize, usize)> {
    let mut v = Vec::new();
    for (di, dj) in [(0usize, 0usize), (1, 0), (0, 1), (1, 1)] {
        if i >= di && j >= dj && i - di < n - 1 && j - dj < n - 1 {
            v.push((i - di, j - dj));
        }
    }
    v
}

/// The cells (a, b, c, d, norm) at i + n·j, the targets at the cells and at the square
/// centres ((i + ½, j + ½) at i + (n − 1)·j).
pub struct Lattice<'a, T> {
    pub n: usize,
    /// The weight of each square's term against the cell's own (1).
    pub square_weight: f64,
    /// The training-set errors of the table before the pass at every cell and square
    /// centre: each place's term is (e/e₀)², so a place counts by how much it changes
    /// relative to where it was, and a cell with a small error is not spent on a square
    /// with a large one. `None`: plain e².
    pub before: Option<(&'a [f64], &'a [f64])>,
    pub cells: &'a [[f64; 5]],
    pub at_cells: &'a [T],
    pub at_squares: &'a [T],
    /// Whether a refit's trials are measured on fixed nodes (each place's LTC half drawn
    /// once from the entries there before the refit, `FixedNodes`) instead of on samples of
    /// each trial: the table's route (`ltc::fit::Method::FixedNodesAll`).
    pub fixed: bool,
}

/// The target's samples of one set (n×n, offset `off`) at cell k's places: its own lobe,
/// then its squares in [`places`] order. Drawn once per refit of the cell; with the fixed
/// nodes of each place ([`Lattice::fixed`]) where asked for.
struct PlaceSets {
    cell: TargetSamples,
    squares: Vec<TargetSamples>,
    fixed: Option<(Option<FixedNodes>, Vec<Option<FixedNodes>>)>,
}

impl<T: LtcTarget> Lattice<'_, T> {
    fn place_sets(&self, k: usize, n: usize, off: f64) -> PlaceSets {
        let nn = self.n;
        let (i, j) = (k % nn, k / nn);
        PlaceSets {
            cell: TargetSamples::new(&self.at_cells[k], n, off),
            squares: places(i, j, nn)
                .into_iter()
                .map(|(si, sj)| TargetSamples::new(&self.at_squares[si + (nn - 1) * sj], n, off))
                .collect(),
            fixed: None,
        }
    }

    /// [`Self::place_sets`] with each place's fixed nodes, their LTC half drawn from the
    /// entries there now (a place whose entries are singular keeps moving samples).
    fn fixed_sets(&self, k: usize, n: usize, off: f64) -> PlaceSets {
        let mut sets = self.place_sets(k, n, off);
        let nn = self.n;
        let (i, j) = (k % nn, k / nn);
        let at = |t: &T, s: &TargetSamples, e: [f64; 5]| {
            ltc_of(&[e[0], e[1], e[2], e[3]]).map(|l| FixedNodes::new(t, s, &l))
        };
        let cell = at(&self.at_cells[k], &sets.cell, self.cells[k]);
        let squares = places(i, j, nn)
            .into_iter()
            .zip(&sets.squares)
            .map(|((si, sj), s)| {
                at(
                    &self.at_squares[si + (nn - 1) * sj],
                    s,
                    self.mid(si, sj, &|q| self.cells[q]),
                )
            })
            .collect();
        sets.fixed = Some((cell, squares));
        sets
    }

    /// The entries a shader reads at the centre of square (si, sj), with `entry(q)` the
    /// entries of cell q.
    fn mid(&self, si: usize, sj: usize, entry: &dyn Fn(usize) -> [f64; 5]) -> [f64; 5] {
        let nn = self.n;
        let corners = [
            entry(si + nn * sj),
            entry(si + 1 + nn * sj),
            entry(si + nn * (sj + 1)),
            entry(si + 1 + nn * (sj + 1)),
        ];
        std::array::from_fn(|c| corners.iter().map(|x| x[c]).sum::<f64>() / 4.0)
    }

    /// Σ e² over the cell's places with cell k's entries replaced by `inv`, on the
    /// places' sample sets `sets` (`place_sets`).
    fn objective(&self, k: usize, inv: &[f64; 4], sets: &PlaceSets) -> f64 {
        let nn = self.n;
        let (i, j) = (k % nn, k / nn);
        let entry = |q: usize| -> [f64; 5] {
            if q == k {
                [inv[0], inv[1], inv[2], inv[3], self.cells[k][4]]
            } else {
                self.cells[q]
            }
        };
        let scale = |e0: Option<f64>| {
            e0.filter(|x| *x > 0.0 && x.is_finite())
                .map(|x| 1.0 / (x * x))
                .unwrap_or(1.0)
        };
        let cell = entry(k);
        let fixed = |q: Option<usize>| {
            sets.fixed.as_ref().and_then(|(c, sq)| match q {
                None => c.as_ref(),
                Some(q) => sq[q].as_ref(),
            })
        };
        let e = rel_l2_at(
            &self.at_cells[k],
            &sets.cell,
            fixed(None),
            &[cell[0], cell[1], cell[2], cell[3]],
            cell[4],
        );
        let mut sum = e * e * scale(self.before.map(|b| b.0[k]));
        for (q, ((si, sj), set)) in places(i, j, nn).into_iter().zip(&sets.squares).enumerate() {
            let mid = self.mid(si, sj, &entry);
            let e = rel_l2_at(
                &self.at_squares[si + (nn - 1) * sj],
                set,
                fixed(Some(q)),
                &[mid[0], mid[1], mid[2], mid[3]],
                mid[4],
            );
            sum += self.square_weight * e * e * scale(self.before.map(|b| b.1[si + (nn - 1) * sj]));
        }
        sum
    }
}

struct Cost<'a, 'b, T> {
    grid: &'a Lattice<'b, T>,
    k: usize,
    train: &'a PlaceSets,
}

fn inv_of(q: &[f64]) -> [f64; 4] {
    [
        q[0].clamp(-60.0, 10.0).exp(),
        q[2],
        q[3],
        q[1].clamp(-60.0, 10.0).exp(),
    ]
}

impl<T: LtcTarget> argmin::core::CostFunction for Cost<'_, '_, T> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, q: &Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
        if q.iter().any(|x| !x.is_finite()) {
            return Ok(1e30);
        }
        let v = self.grid.objective(self.k, &inv_of(q), self.train);
        Ok(if v.is_finite() { v } else { 1e30 })
    }
}

/// The refitted entries of cell k (or its current ones where nothing better is found).
fn refit_cell<T: LtcTarget>(
    grid: &Lattice<'_, T>,
    k: usize,
    n: usize,
    max_iters: u64,
) -> Result<[f64; 4]> {
    use argmin::core::{Executor, State};
    use argmin::solver::neldermead::NelderMead;
    let c = grid.cells[k];
    let now = [c[0], c[1], c[2], c[3]];
    if !(c[0] > 0.0 && c[3] > 0.0) {
        return Ok(now);
    }
    // the trials' sets; the verdict below is on their moving samples either way
    let train = if grid.fixed {
        grid.fixed_sets(k, n, 0.5)
    } else {
        grid.place_sets(k, n, 0.5)
    };
    let q0 = vec![c[0].ln(), c[3].ln(), c[1], c[2]];
    let scale = 1e-3 * c[0].max(c[3]);
    let steps = [
        0.01,
        0.01,
        0.01 * (c[1].abs() + scale),
        0.01 * (c[2].abs() + scale),
    ];
    let mut simplex = vec![q0.clone()];
    for (d, st) in steps.iter().enumerate() {
        let mut q = q0.clone();
        q[d] += st;
        simplex.push(q);
    }
    let err = |e: argmin::core::Error| Error::InvalidArgument(format!("bilinear refit: {e}"));
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(1e-10)
        .map_err(err)?;
    let res = Executor::new(
        Cost {
            grid,
            k,
            train: &train,
        },
        solver,
    )
    .configure(|s| s.max_iters(max_iters))
    .run()
    .map_err(err)?;
    let best = res.state().get_best_param().cloned().unwrap_or(q0);
    let cand = inv_of(&best);
    let val = grid.place_sets(k, n + 7, 0.37);
    let (vn, vc) = (
        grid.objective(k, &now, &val),
        grid.objective(k, &cand, &val),
    );
    // the same training sets on their moving samples: without the fixed nodes
    let train = PlaceSets {
        fixed: None,
        ..train
    };
    let (tn, tc) = (
        grid.objective(k, &now, &train),
        grid.objective(k, &cand, &train),
    );
    Ok(if tc < tn && vc < vn { cand } else { now })
}

/// The training-set errors (n×n, offset 0.5) at every cell and square centre of `cells`:
/// the `before` of a [`Lattice`].
pub fn errors<T: LtcTarget>(
    nn: usize,
    cells: &[[f64; 5]],
    at_cells: &[T],
    at_squares: &[T],
    n: usize,
) -> (Vec<f64>, Vec<f64>) {
    let c: Vec<f64> = (0..nn * nn)
        .into_par_iter()
        .map(|k| {
            let e = cells[k];
            rel_l2(&at_cells[k], &[e[0], e[1], e[2], e[3]], e[4], n, 0.5)
        })
        .collect();
    let s: Vec<f64> = (0..(nn - 1) * (nn - 1))
        .into_par_iter()
        .map(|q| {
            let (si, sj) = (q % (nn - 1), q / (nn - 1));
            let ks = [
                si + nn * sj,
                si + 1 + nn * sj,
                si + nn * (sj + 1),
                si + 1 + nn * (sj + 1),
            ];
            let mid: [f64; 5] =
                std::array::from_fn(|c| ks.iter().map(|&k| cells[k][c]).sum::<f64>() / 4.0);
            rel_l2(
                &at_squares[q],
                &[mid[0], mid[1], mid[2], mid[3]],
                mid[4],
                n,
                0.5,
            )
        })
        .collect();
    (c, s)
}

/// One sweep over the table in four colours; returns the new cells and how many moved.
pub fn sweep<T: LtcTarget>(
    pm: &impl ParMap,
    grid: &Lattice<'_, T>,
    n: usize,
    max_iters: u64,
    progress: &(dyn Fn() + Sync),
) -> Result<(Vec<[f64; 5]>, usize)> {
    let nn = grid.n;
    let mut cells = grid.cells.to_vec();
    let mut moved = 0;
    for colour in 0..4 {
        let ks: Vec<usize> = (0..nn * nn)
            .filter(|k| (k % nn) % 2 + 2 * ((k / nn) % 2) == colour)
            .collect();
        let snapshot = Lattice {
            n: nn,
            square_weight: grid.square_weight,
            before: grid.before,
            cells: &cells,
            at_cells: grid.at_cells,
            at_squares: grid.at_squares,
            fixed: grid.fixed,
        };
        // one item per cell of this colour: a pure function of the snapshot
        let label = format!("bilinear sweep {nn}², colour {colour}");
        let new: Vec<[f64; 4]> = pm.map(&label, ks.len(), |x| {
            let r = refit_cell(&snapshot, ks[x], n, max_iters);
            progress();
            r
        })?;
        for (&k, inv) in ks.iter().zip(&new) {
            if inv[..] != cells[k][..4] {
                moved += 1;
            }
            cells[k][..4].copy_from_slice(inv);
        }
    }
    Ok((cells, moved))
}

/// What the bilinear pass did.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct BilinearPass {
    pub square_weight: f64,
    pub max_iters: u64,
    pub cells_moved: usize,
}

/// One sweep of the bilinear-aware refit over a fitted table: each cell against its own
/// lobe and, with weight ¼ each, the lobes (`target(α, θ)`) at the centres of its squares
/// as a GPU interpolates them, every term relative to its error before the pass; then the
/// moved cells' fit parameters are recomputed (and their held-out figures cleared).
pub fn bilinear_pass<T: LtcTarget>(
    pm: &impl ParMap,
    main: &mut crate::ltc::fit::Table,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    n: usize,
) -> Result<BilinearPass> {
    use crate::ltc::fit::{self, Cell};
    let g = main.grid.n;
    let alpha_min = main.grid.alpha_min;
    let flat: Vec<&Cell> = (0..g * g).map(|k| &main.cells[k / g][k % g]).collect();
    let cells: Vec<[f64; 5]> = flat
        .iter()
        .map(|c| [c.inv[0], c.inv[1], c.inv[2], c.inv[3], c.norm])
        .collect();
    let at_cells: Vec<T> = flat
        .iter()
        .map(|c| target(c.alpha, c.theta))
        .collect::<Result<_>>()?;
    let at_squares: Vec<T> = (0..(g - 1) * (g - 1))
        .map(|k| {
            let r = ((k % (g - 1)) as f64 + 0.5) / (g - 1) as f64;
            let t = ((k / (g - 1)) as f64 + 0.5) / (g - 1) as f64;
            target((r * r).max(alpha_min), (1.0 - t * t).clamp(0.0, 1.0).acos())
        })
        .collect::<Result<_>>()?;
    let (square_weight, max_iters) = (0.25, 40);
    let before = errors(g, &cells, &at_cells, &at_squares, n);
    let lattice = Lattice {
        n: g,
        square_weight,
        before: Some((&before.0, &before.1)),
        cells: &cells,
        at_cells: &at_cells,
        at_squares: &at_squares,
        // the table's route: fixed nodes here too where every stage has them
        fixed: main.method == fit::Method::FixedNodesAll,
    };
    let pb = crate::progress::Progress::new("ltc bilinear pass", (g * g) as u64);
    let (new, cells_moved) = sweep(pm, &lattice, n, max_iters, &|| pb.inc(1))?;
    pb.finish();
    // write back, with the held-out errors and the fit parameters of the moved cells
    let before_cols = main.cells.clone();
    main.cells = pm.map(
        &format!("bilinear write-back {g}²"),
        g,
        |j| -> Result<Vec<Cell>> {
            let mut col = before_cols[j].clone();
            for (i, c) in col.iter_mut().enumerate() {
                let e = new[i + g * j];
                let inv = [e[0], e[1], e[2], e[3]];
                if inv == c.inv {
                    continue;
                }
                let t = target(c.alpha, c.theta)?;
                let (_, _, _, zm) = t.moments(32);
                c.inv = inv;
                if let Some((m11, m22, m13, phi)) = fit::params_from_production(&inv, &zm) {
                    let z = fit::turn(&zm, phi);
                    (c.m11, c.m22, c.m13, c.turn, c.z_dir) = (m11, m22, m13, phi, [z.x, z.z]);
                }
                inverse_from_production(&inv)
                    .try_inverse()
                    .ok_or_else(|| Error::InvalidArgument("bilinear pass: singular cell".into()))?;
                // its held-out figures are judged again (`fit::judge_table`)
                c.held = None;
            }
            Ok(col)
        },
    )?;
    Ok(BilinearPass {
        square_weight,
        max_iters,
        cells_moved,
    })
}

//! Canonical polyadic decomposition of a dense 3-way tensor by alternating least squares
//! (seed 002 Eq 5, §4.2): T ≈ Σ_r C_r · X_r ⊗ Y_r ⊗ Z_r with unit-norm factor columns.
//!
//! MTTKRP is computed directly from the tensor (no unfolding is materialised); each ALS
//! step solves the R×R normal equations (the Hadamard product of Gram matrices) by
//! nalgebra's Cholesky, falling back to the SVD pseudo-inverse when they are singular.
//! Convergence: the relative reconstruction error ‖T − T̂‖/‖T‖, computed in f64, changes
//! by less than `tol` between sweeps or falls below it. Initialisation: seeded uniform random factors; `restarts` runs with
//! different seeds, the best kept (deterministic for a given seed).

use super::mttkrp::{mode0, mode1, mode2, partial};
use crate::error::{Error, Result};
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use serde::Serialize;

/// A dense tensor of shape (n0, n1, n2), index (i, j, k) at i + n0·(j + n1·k).
#[derive(Clone, Debug)]
pub struct Tensor3 {
    pub shape: [usize; 3],
    pub data: Vec<f64>,
}

impl Tensor3 {
    pub fn new(shape: [usize; 3], data: Vec<f64>) -> Result<Tensor3> {
        if shape.iter().any(|&n| n == 0) || data.len() != shape[0] * shape[1] * shape[2] {
            return Err(Error::InvalidArgument(format!(
                "tensor of shape {shape:?} needs {} values, got {}",
                shape[0] * shape[1] * shape[2],
                data.len()
            )));
        }
        if let Some(v) = data.iter().find(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                what: "tensor entry",
                value: *v,
            });
        }
        Ok(Tensor3 { shape, data })
    }
    #[inline]
    pub fn at(&self, i: usize, j: usize, k: usize) -> f64 {
        self.data[i + self.shape[0] * (j + self.shape[1] * k)]
    }
    pub fn norm(&self) -> f64 {
        self.data.iter().map(|v| v * v).sum::<f64>().sqrt()
    }
}

/// A CP model: weights C_r and unit-norm factor matrices (columns r).
#[derive(Clone, Debug, Serialize)]
pub struct Cp {
    pub rank: usize,
    pub shape: [usize; 3],
    pub weights: Vec<f64>,
    /// factors[m][r * shape[m] + i]
    pub factors: [Vec<f64>; 3],
    /// Relative reconstruction error ‖T − T̂‖/‖T‖ (f64) and ALS iterations.
    pub rel_error: f64,
    pub iterations: usize,
}

impl Cp {
    pub fn factor(&self, m: usize, r: usize) -> &[f64] {
        let n = self.shape[m];
        &self.factors[m][r * n..(r + 1) * n]
    }
    /// T̂(i, j, k) = Σ_r C_r X_r(i) Y_r(j) Z_r(k) (seed 002 Eq 6).
    pub fn at(&self, i: usize, j: usize, k: usize) -> f64 {
        (0..self.rank)
            .map(|r| {
                self.weights[r] * self.factor(0, r)[i] * self.factor(1, r)[j] * self.factor(2, r)[k]
            })
            .sum()
    }
    /// Storage in numbers: R·(n0 + n1 + n2 + 1).
    pub fn storage(&self) -> usize {
        self.rank * (self.shape.iter().sum::<usize>() + 1)
    }
}

/// ‖T − T̂‖/‖T‖ in f64, summed entry by entry (‖T̂‖² and ⟨T, T̂⟩ by factor algebra would
/// cancel when the error is small; this is direct).
pub fn rel_error(t: &Tensor3, cp: &Cp) -> f64 {
    let [n0, n1, n2] = t.shape;
    let r = cp.rank;
    // mode-0 factor row-major, so the inner sum over the rank is contiguous
    let mut a = vec![0.0; n0 * r];
    for q in 0..r {
        for (i, v) in cp.factor(0, q).iter().enumerate() {
            a[i * r + q] = *v;
        }
    }
    let mut wv = vec![0.0; r];
    let mut e = 0.0;
    for k in 0..n2 {
        for j in 0..n1 {
            for (q, x) in wv.iter_mut().enumerate() {
                *x = cp.weights[q] * cp.factor(1, q)[j] * cp.factor(2, q)[k];
            }
            let base = n0 * (j + n1 * k);
            for i in 0..n0 {
                let rec: f64 = a[i * r..(i + 1) * r]
                    .iter()
                    .zip(&wv)
                    .map(|(x, y)| x * y)
                    .sum();
                let d = t.data[base + i] - rec;
                e += d * d;
            }
        }
    }
    let n = t.norm();
    if n > 0.0 {
        e.sqrt() / n
    } else {
        e.sqrt()
    }
}

/// The seeded uniform start of one ALS run (values in [0.1, 1.1)), row-major n_m × R per
/// mode. Public so that another implementation can be started from the same factors.
pub fn initial_factors(shape: [usize; 3], rank: usize, seed: u64) -> [Vec<f64>; 3] {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    // drawn column by column (the layout of `Cp::factors`), stored row-major
    let init: [Vec<f64>; 3] = std::array::from_fn(|m| {
        (0..shape[m] * rank)
            .map(|_| rng.random::<f64>() + 0.1)
            .collect()
    });
    std::array::from_fn(|m| {
        let n = shape[m];
        let mut v = vec![0.0; n * rank];
        for q in 0..rank {
            for i in 0..n {
                v[i * rank + q] = init[m][q * n + i];
            }
        }
        v
    })
}

/// The seed of restart `s` of a run seeded with `seed`.
pub fn restart_seed(seed: u64, s: usize) -> u64 {
    seed.wrapping_add(s as u64 * 0x9E37_79B9)
}

/// Options of [`cp_als`].
#[derive(Clone, Copy, Debug, Serialize)]
pub struct AlsOptions {
    pub rank: usize,
    pub tol: f64,
    pub max_iters: usize,
    pub restarts: usize,
    pub seed: u64,
    /// Non-negative factors (HALS column updates instead of the least-squares solve):
    /// the reconstruction is then ≥ 0 everywhere, which exact hierarchical sampling
    /// (seed 002 §5.2) needs; unconstrained CP can dip below zero.
    pub nonnegative: bool,
}

/// CP-ALS (seed 002 §4.2: tolerance 1e-4, 500 iterations).
pub fn cp_als(t: &Tensor3, o: &AlsOptions) -> Result<Cp> {
    if o.rank == 0 {
        return Err(Error::InvalidArgument("CP rank must be ≥ 1".into()));
    }
    let cap = t.shape[0] * t.shape[1] * t.shape[2];
    if o.rank > cap {
        return Err(Error::InvalidArgument(format!(
            "rank {} exceeds the {} entries of a {:?} block",
            o.rank, cap, t.shape
        )));
    }
    let mut best: Option<Cp> = None;
    for s in 0..o.restarts.max(1) {
        let seed = restart_seed(o.seed, s);
        let start = (initial_factors(t.shape, o.rank, seed), vec![1.0; o.rank]);
        let cp = if o.nonnegative {
            // HALS from a random positive start stalls on spiky P-NDF tensors (60 % error
            // where the unconstrained fit reaches 26 %, flakes, R = 16). It starts instead
            // from the unconstrained solution: each component's signs moved so that its
            // mode-0 and mode-1 factors sum positive (the product is unchanged), then
            // negative entries clamped to 0 (better than dropping the signs: 14 % against
            // 34 % at R = 32 on the same tensor).
            let free = als_once(
                t,
                &AlsOptions {
                    nonnegative: false,
                    ..*o
                },
                &start,
            )?;
            let r = o.rank;
            let mut f: [Vec<f64>; 3] = std::array::from_fn(|m| vec![0.0; t.shape[m] * r]);
            for q in 0..r {
                let sg = |m: usize| {
                    if free.factor(m, q).iter().sum::<f64>() < 0.0 {
                        -1.0
                    } else {
                        1.0
                    }
                };
                let signs = [sg(0), sg(1), sg(0) * sg(1) * free.weights[q].signum()];
                for (m, fm) in f.iter_mut().enumerate() {
                    for (i, v) in free.factor(m, q).iter().enumerate() {
                        fm[i * r + q] = (signs[m] * v).max(0.0) + 1e-12;
                    }
                }
            }
            let w = free.weights.iter().map(|x| x.abs()).collect();
            let mut nn = als_once(t, o, &(f, w))?;
            nn.iterations += free.iterations;
            nn
        } else {
            als_once(t, o, &start)?
        };
        if best.as_ref().is_none_or(|b| cp.rel_error < b.rel_error) {
            best = Some(cp);
        }
    }
    Ok(best.expect("at least one run"))
}

/// F = M V⁻¹ for the SPD R×R normal matrix V (Cholesky; the pseudo-inverse when V is
/// singular or the solve is not finite), written row-major into `out` (n × R).
#[inline(always)]
fn solve_normal(m: &[f64], n: usize, r: usize, v: DMatrix<f64>, out: &mut [f64]) -> Result<()> {
    let inv = match v.clone().cholesky().map(|c| c.inverse()) {
        Some(x) if x.iter().all(|z| z.is_finite()) => x,
        _ => v
            .pseudo_inverse(1e-12)
            .map_err(|e| Error::InvalidArgument(format!("CP-ALS normal equations: {e}")))?,
    };
    // row-major copy of the (symmetric) inverse, so each output row is a sum of its rows
    let inv: Vec<f64> = (0..r * r).map(|x| inv[(x / r, x % r)]).collect();
    for i in 0..n {
        let row = &mut out[i * r..(i + 1) * r];
        row.iter_mut().for_each(|x| *x = 0.0);
        for (p, mp) in m[i * r..(i + 1) * r].iter().enumerate() {
            for (x, y) in row.iter_mut().zip(&inv[p * r..(p + 1) * r]) {
                *x += mp * y;
            }
        }
    }
    Ok(())
}

/// One HALS pass (hierarchical alternating least squares; Cichocki & Phan 2009) for a
/// non-negative factor: column by column, F[:, q] ← max(0, F[:, q] + (M[:, q] − F V[:, q])
/// / V[q, q]), each column using the ones already updated. `f` holds the normalised
/// factor and `w` its column scales on entry; on exit `f` is the unnormalised update.
#[inline(always)]
fn hals_update(m: &[f64], n: usize, r: usize, v: &DMatrix<f64>, f: &mut [f64], w: &[f64]) {
    for i in 0..n {
        for q in 0..r {
            f[i * r + q] *= w[q];
        }
    }
    for q in 0..r {
        let vqq = v[(q, q)];
        if !(vqq > 0.0) {
            continue;
        }
        for i in 0..n {
            let row = &f[i * r..(i + 1) * r];
            let fv: f64 = (0..r).map(|p| row[p] * v[(p, q)]).sum();
            let x = f[i * r + q] + (m[i * r + q] - fv) / vqq;
            // a tiny floor keeps a column from dying out entirely (it could not recover)
            f[i * r + q] = x.max(1e-300);
        }
    }
}

/// Gram matrix FᵀF of a row-major n × R factor (row-major R × R, accumulated row by row
/// so the inner loop runs over the rank contiguously).
#[inline(always)]
fn gram(f: &[f64], n: usize, r: usize) -> Vec<f64> {
    let mut g = vec![0.0; r * r];
    for i in 0..n {
        let row = &f[i * r..(i + 1) * r];
        for (p, a) in row.iter().enumerate() {
            for (x, b) in g[p * r..(p + 1) * r].iter_mut().zip(row) {
                *x += a * b;
            }
        }
    }
    g
}

/// The normal matrix V = G_a ∘ G_b of an ALS step.
#[inline(always)]
fn hadamard(a: &[f64], b: &[f64], r: usize) -> DMatrix<f64> {
    DMatrix::from_fn(r, r, |p, q| a[p * r + q] * b[p * r + q])
}

/// Normalise the columns of a row-major n × R factor; their norms go to `w`.
#[inline(always)]
fn normalise(f: &mut [f64], n: usize, r: usize, w: &mut [f64]) {
    for q in 0..r {
        let nrm = (0..n)
            .map(|i| f[i * r + q] * f[i * r + q])
            .sum::<f64>()
            .sqrt();
        w[q] = nrm;
        for i in 0..n {
            f[i * r + q] = if nrm > 0.0 { f[i * r + q] / nrm } else { 0.0 };
        }
    }
}

/// One ALS run. Factors are held row-major (n × R) so every inner loop runs over the rank
/// contiguously; the partial product P[j, k, ·] = Σ_i T[i, j, k] A[i, ·] (A = mode-0
/// factor) serves both the mode-1 and the mode-2 MTTKRP, so a sweep costs ≈ 2·nnz·R.
/// The error between sweeps uses ‖T − T̂‖² = ‖T‖² − 2⟨T, T̂⟩ + ‖T̂‖² from quantities the
/// sweep already has; where that cancels (relative error below 1e-4) and for the returned
/// error, it is computed directly by [`rel_error`].
/// A start for one run: row-major factors and column weights.
type Start = ([Vec<f64>; 3], Vec<f64>);

fn als_once(t: &Tensor3, o: &AlsOptions, start: &Start) -> Result<Cp> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU supports AVX2 and FMA (checked just above).
        return unsafe { als_once_avx2(t, o, start) };
    }
    als_once_body(t, o, start)
}

/// The same code compiled with AVX2 enabled: the contiguous loops over the rank vectorise
/// 4-wide. Rust never fuses a multiply and an add on its own and reductions stay in
/// order, so the result is bit-identical to the baseline build (unit test below).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn als_once_avx2(t: &Tensor3, o: &AlsOptions, start: &Start) -> Result<Cp> {
    als_once_body(t, o, start)
}

#[inline(always)]
fn als_once_body(t: &Tensor3, o: &AlsOptions, start: &Start) -> Result<Cp> {
    let r = o.rank;
    let sh = t.shape;
    let [n0, n1, n2] = sh;
    let mut f = start.0.clone();
    let to_cp = |f: &[Vec<f64>; 3], w: &[f64], iterations: usize| {
        let factors = std::array::from_fn(|m| {
            let n = sh[m];
            let mut v = vec![0.0; n * r];
            for q in 0..r {
                for i in 0..n {
                    v[q * n + i] = f[m][i * r + q];
                }
            }
            v
        });
        Cp {
            rank: r,
            shape: sh,
            weights: w.to_vec(),
            factors,
            rel_error: 0.0,
            iterations,
        }
    };
    let mut w = start.1.clone();
    let tn2: f64 = t.data.iter().map(|v| v * v).sum();
    if tn2 == 0.0 {
        let mut cp = to_cp(&f, &vec![0.0; r], 0);
        cp.rel_error = 0.0;
        return Ok(cp);
    }
    // the non-zero entries of each fibre T[·, j, k] (P-NDF blocks are mostly empty):
    // (start, end) into (index, value) lists
    let mut nz: Vec<(usize, f64)> = Vec::new();
    let mut fib = Vec::with_capacity(n1 * n2 + 1);
    fib.push(0);
    for jk in 0..n1 * n2 {
        for i in 0..n0 {
            let v = t.data[n0 * jk + i];
            if v != 0.0 {
                nz.push((i, v));
            }
        }
        fib.push(nz.len());
    }
    let mut prev = f64::INFINITY;
    let mut iters = 0;
    let mut g: [Vec<f64>; 3] = std::array::from_fn(|m| gram(&f[m], sh[m], r));
    let mut m0 = vec![0.0; n0 * r];
    let mut m1 = vec![0.0; n1 * r];
    let mut m2 = vec![0.0; n2 * r];
    let mut p = vec![0.0; n1 * n2 * r];
    let mut wv = vec![0.0; r];
    for it in 0..o.max_iters {
        iters = it + 1;
        // mode 0: M0[i, q] = Σ_{j,k} T[i, j, k] B[j, q] C[k, q]
        mode0(&nz, &fib, &f[1], &f[2], [n1, n2], r, &mut wv, &mut m0);
        let v = hadamard(&g[1], &g[2], r);
        if o.nonnegative {
            hals_update(&m0, n0, r, &v, &mut f[0], &w);
        } else {
            solve_normal(&m0, n0, r, v, &mut f[0])?;
        }
        normalise(&mut f[0], n0, r, &mut w);
        g[0] = gram(&f[0], n0, r);
        // P[j, k, q] = Σ_i T[i, j, k] A[i, q]
        partial(&nz, &fib, &f[0], n1 * n2, r, &mut p);
        // mode 1: M1[j, q] = Σ_k P[j, k, q] C[k, q]
        mode1(&p, &f[2], [n1, n2], r, &mut m1);
        let v = hadamard(&g[0], &g[2], r);
        if o.nonnegative {
            hals_update(&m1, n1, r, &v, &mut f[1], &w);
        } else {
            solve_normal(&m1, n1, r, v, &mut f[1])?;
        }
        normalise(&mut f[1], n1, r, &mut w);
        g[1] = gram(&f[1], n1, r);
        // mode 2: M2[k, q] = Σ_j P[j, k, q] B[j, q]
        mode2(&p, &f[1], [n1, n2], r, &mut m2);
        let v = hadamard(&g[0], &g[1], r);
        if o.nonnegative {
            hals_update(&m2, n2, r, &v, &mut f[2], &w);
        } else {
            solve_normal(&m2, n2, r, v, &mut f[2])?;
        }
        normalise(&mut f[2], n2, r, &mut w);
        g[2] = gram(&f[2], n2, r);
        // ‖T − T̂‖² = ‖T‖² − 2 Σ_q w_q Σ_k C[k, q] M2[k, q] + wᵀ (G0 ∘ G1 ∘ G2) w
        let inner: f64 = (0..n2)
            .map(|k| {
                (0..r)
                    .map(|q| w[q] * f[2][k * r + q] * m2[k * r + q])
                    .sum::<f64>()
            })
            .sum();
        let mut norm2 = 0.0;
        for a in 0..r {
            for b in 0..r {
                norm2 += w[a] * w[b] * g[0][a * r + b] * g[1][a * r + b] * g[2][a * r + b];
            }
        }
        let e2 = (tn2 - 2.0 * inner + norm2) / tn2;
        let err = if e2 > 1e-8 {
            e2.sqrt()
        } else {
            rel_error(t, &to_cp(&f, &w, iters))
        };
        if !err.is_finite() {
            return Err(Error::InvalidArgument(format!(
                "CP-ALS diverged (non-finite error) at iteration {iters}, rank {r}"
            )));
        }
        // Stop when the relative error changes by less than tol between sweeps: the
        // convention of the MATLAB Tensor Toolbox `cp_als` (fit change < tol) and of
        // TensorLy's `parafac` (cvg_criterion = "abs_rec_error"), so a tolerance means the
        // same thing in the paper (seed 002 §4.2: 1e-4), there and here.
        if err < o.tol || (prev - err).abs() < o.tol {
            break;
        }
        prev = err;
    }
    let mut cp = to_cp(&f, &w, iters);
    cp.rel_error = rel_error(t, &cp);
    Ok(cp)
}

/// A random CP model with non-negative factors (as NDF blocks are).
pub fn random_cp(rank: usize, shape: [usize; 3], seed: u64) -> Cp {
    let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(seed);
    let factors: [Vec<f64>; 3] = std::array::from_fn(|m| {
        (0..shape[m] * rank)
            .map(|_| rand::Rng::random::<f64>(&mut rng))
            .collect()
    });
    Cp {
        rank,
        shape,
        weights: (0..rank)
            .map(|_| rand::Rng::random::<f64>(&mut rng) * 10.0)
            .collect(),
        factors,
        rel_error: 0.0,
        iterations: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX2 build of the ALS sweep gives bit-identical factors and errors to the
    /// baseline build (no fused multiply-adds, no reordered sums), so results do not
    /// depend on the CPU they ran on.
    #[test]
    fn avx2_build_is_bit_identical_to_the_baseline() {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
            let data: Vec<f64> = (0..12 * 10 * 9)
                .map(|_| {
                    let u: f64 = rng.random();
                    if u < 0.4 {
                        0.0
                    } else {
                        u * u
                    }
                })
                .collect();
            let t = Tensor3::new([12, 10, 9], data).unwrap();
            for rank in [1, 3, 8, 13] {
                let o = AlsOptions {
                    rank,
                    tol: 1e-9,
                    max_iters: 60,
                    restarts: 1,
                    seed: 4,
                    nonnegative: false,
                };
                let start = (initial_factors(t.shape, rank, 4), vec![1.0; rank]);
                let a = als_once_body(&t, &o, &start).unwrap();
                let b = unsafe { als_once_avx2(&t, &o, &start) }.unwrap();
                assert_eq!(a.iterations, b.iterations);
                assert_eq!(a.rel_error.to_bits(), b.rel_error.to_bits(), "rank {rank}");
                for m in 0..3 {
                    assert!(a.factors[m]
                        .iter()
                        .zip(&b.factors[m])
                        .all(|(x, y)| x.to_bits() == y.to_bits()));
                }
            }
        } else {
            eprintln!("no AVX2+FMA on this CPU: only the baseline build runs");
        }
    }
}

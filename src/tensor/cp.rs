//! Canonical polyadic decomposition of a dense 3-way tensor by alternating least squares
//! (seed 002 Eq 5, §4.2): T ≈ Σ_r C_r · X_r ⊗ Y_r ⊗ Z_r with unit-norm factor columns.
//!
//! MTTKRP is computed directly from the tensor (no unfolding is materialised); each ALS
//! step solves the R×R normal equations (the Hadamard product of Gram matrices) with
//! nalgebra's SVD (pseudo-inverse: robust to rank deficiency). Convergence: the relative
//! reconstruction error ‖T − T̂‖/‖T‖, computed in f64, changes by less than `tol` or falls
//! below it. Initialisation: seeded uniform random factors; `restarts` runs with
//! different seeds, the best kept (deterministic for a given seed).

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

/// ‖T − T̂‖/‖T‖ in f64 (‖T̂‖² and ⟨T, T̂⟩ by factor algebra would cancel; this is direct).
pub fn rel_error(t: &Tensor3, cp: &Cp) -> f64 {
    let [n0, n1, n2] = t.shape;
    let mut e = 0.0;
    for k in 0..n2 {
        for j in 0..n1 {
            for i in 0..n0 {
                let d = t.at(i, j, k) - cp.at(i, j, k);
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

/// Options of [`cp_als`].
#[derive(Clone, Copy, Debug, Serialize)]
pub struct AlsOptions {
    pub rank: usize,
    pub tol: f64,
    pub max_iters: usize,
    pub restarts: usize,
    pub seed: u64,
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
        let cp = als_once(t, o, o.seed.wrapping_add(s as u64 * 0x9E37_79B9))?;
        if best.as_ref().is_none_or(|b| cp.rel_error < b.rel_error) {
            best = Some(cp);
        }
    }
    Ok(best.expect("at least one run"))
}

fn als_once(t: &Tensor3, o: &AlsOptions, seed: u64) -> Result<Cp> {
    let r = o.rank;
    let sh = t.shape;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut f: [Vec<f64>; 3] =
        std::array::from_fn(|m| (0..sh[m] * r).map(|_| rng.random::<f64>() + 0.1).collect());
    let mut w = vec![1.0; r];
    let tn = t.norm();
    if tn == 0.0 {
        return Ok(Cp {
            rank: r,
            shape: sh,
            weights: vec![0.0; r],
            factors: f,
            rel_error: 0.0,
            iterations: 0,
        });
    }
    let mut prev = f64::INFINITY;
    let mut iters = 0;
    let mut err = f64::INFINITY;
    for it in 0..o.max_iters {
        iters = it + 1;
        for m in 0..3 {
            let (a, b) = ((m + 1) % 3, (m + 2) % 3);
            // MTTKRP: M[i, q] = Σ_{other indices} T · F_a[·, q] · F_b[·, q]
            let mut mk = vec![0.0; sh[m] * r];
            for k in 0..sh[2] {
                for j in 0..sh[1] {
                    for i in 0..sh[0] {
                        let v = t.at(i, j, k);
                        if v == 0.0 {
                            continue;
                        }
                        let idx = [i, j, k];
                        for q in 0..r {
                            mk[q * sh[m] + idx[m]] +=
                                v * f[a][q * sh[a] + idx[a]] * f[b][q * sh[b] + idx[b]];
                        }
                    }
                }
            }
            // Gram Hadamard product V = (F_aᵀF_a) ∘ (F_bᵀF_b)
            let gram = |fm: &Vec<f64>, n: usize| {
                DMatrix::from_fn(r, r, |p, q| {
                    (0..n).map(|i| fm[p * n + i] * fm[q * n + i]).sum::<f64>()
                })
            };
            let v = gram(&f[a], sh[a]).component_mul(&gram(&f[b], sh[b]));
            let pinv = v
                .pseudo_inverse(1e-12)
                .map_err(|e| Error::InvalidArgument(format!("CP-ALS normal equations: {e}")))?;
            let mmat = DMatrix::from_fn(sh[m], r, |i, q| mk[q * sh[m] + i]);
            let sol = mmat * pinv;
            // normalise columns into the weights
            for q in 0..r {
                let nrm = (0..sh[m])
                    .map(|i| sol[(i, q)] * sol[(i, q)])
                    .sum::<f64>()
                    .sqrt();
                w[q] = nrm;
                for i in 0..sh[m] {
                    f[m][q * sh[m] + i] = if nrm > 0.0 { sol[(i, q)] / nrm } else { 0.0 };
                }
            }
        }
        let cp = Cp {
            rank: r,
            shape: sh,
            weights: w.clone(),
            factors: f.clone(),
            rel_error: 0.0,
            iterations: iters,
        };
        err = rel_error(t, &cp);
        if err < o.tol || (prev - err).abs() < o.tol * 1e-2 {
            break;
        }
        prev = err;
    }
    Ok(Cp {
        rank: r,
        shape: sh,
        weights: w,
        factors: f,
        rel_error: err,
        iterations: iters,
    })
}

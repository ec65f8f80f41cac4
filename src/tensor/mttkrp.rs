//! The MTTKRP passes of one CP-ALS sweep (seed 002 §4.2) over the non-zero fibres of a
//! 3-way tensor: const-generic kernels for R = 4, 8, 16, 32 and runtime-rank loops for
//! the other ranks, each dispatcher always inlined into the sweep (and so compiled with
//! the sweep's target features).

// Why each pass exists twice (a const-generic kernel for R = 4, 8, 16, 32 and the
// runtime-rank loop inside `als_once_body` for other ranks): a single runtime-rank
// kernel, always inlined and called with literal ranks, was tried and measured 1.8×
// slower at R = 8 (191 vs 106 µs per sweep on a 16×16×236 P-NDF tensor) with
// bit-identical results — LLVM keeps the accumulators in registers only for array types.

/// The mode-0 MTTKRP for a rank known at compile time (the row and the Khatri–Rao row
/// stay in registers); the same operations in the same order as the generic loop.
#[inline(always)]
pub(super) fn m0_pass<const R: usize>(
    nz: &[(usize, f64)],
    fib: &[usize],
    b: &[f64],
    c: &[f64],
    n1: usize,
    m0: &mut [f64],
) {
    m0.iter_mut().for_each(|x| *x = 0.0);
    for (jk, w) in fib.windows(2).enumerate() {
        let (j, k) = (jk % n1, jk / n1);
        let mut wv = [0.0f64; R];
        for q in 0..R {
            wv[q] = b[j * R + q] * c[k * R + q];
        }
        for &(i, v) in &nz[w[0]..w[1]] {
            let row: &mut [f64; R] = (&mut m0[i * R..(i + 1) * R]).try_into().expect("R");
            for q in 0..R {
                row[q] += v * wv[q];
            }
        }
    }
}

/// P[jk, ·] = Σ_i T[i, jk] A[i, ·] for a rank known at compile time (the accumulator
/// stays in registers); the same operations in the same order as the generic loop.
#[inline(always)]
fn p_pass<const R: usize>(nz: &[(usize, f64)], fib: &[usize], a: &[f64], p: &mut [f64]) {
    for (jk, w) in fib.windows(2).enumerate() {
        let mut acc = [0.0f64; R];
        for &(i, v) in &nz[w[0]..w[1]] {
            let row: &[f64; R] = (&a[i * R..(i + 1) * R]).try_into().expect("R");
            for q in 0..R {
                acc[q] += v * row[q];
            }
        }
        p[jk * R..(jk + 1) * R].copy_from_slice(&acc);
    }
}

/// M1[j, ·] = Σ_k P[j, k, ·] ∘ C[k, ·] for a compile-time rank (same order as the
/// generic loop).
#[inline(always)]
fn contract_k<const R: usize>(p: &[f64], c: &[f64], n1: usize, m1: &mut [f64]) {
    m1.iter_mut().for_each(|x| *x = 0.0);
    for (k, cr) in c.chunks_exact(R).enumerate() {
        let cr: &[f64; R] = cr.try_into().expect("R");
        for j in 0..n1 {
            let pp: &[f64; R] = (&p[(j + n1 * k) * R..(j + n1 * k + 1) * R])
                .try_into()
                .expect("R");
            let row: &mut [f64; R] = (&mut m1[j * R..(j + 1) * R]).try_into().expect("R");
            for q in 0..R {
                row[q] += pp[q] * cr[q];
            }
        }
    }
}

/// M2[k, ·] = Σ_j P[j, k, ·] ∘ B[j, ·] for a compile-time rank (the row stays in
/// registers; same order as the generic loop).
#[inline(always)]
fn contract_j<const R: usize>(p: &[f64], b: &[f64], n1: usize, m2: &mut [f64]) {
    for (k, out) in m2.chunks_exact_mut(R).enumerate() {
        let mut acc = [0.0f64; R];
        for j in 0..n1 {
            let pp: &[f64; R] = (&p[(j + n1 * k) * R..(j + n1 * k + 1) * R])
                .try_into()
                .expect("R");
            let br: &[f64; R] = (&b[j * R..(j + 1) * R]).try_into().expect("R");
            for q in 0..R {
                acc[q] += pp[q] * br[q];
            }
        }
        out.copy_from_slice(&acc);
    }
}

/// Mode 0: M0[i, q] = Σ_{j,k} T[i, j, k] B[j, q] C[k, q] (`wv`: scratch of length R).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn mode0(
    nz: &[(usize, f64)],
    fib: &[usize],
    b_f: &[f64],
    c_f: &[f64],
    [n1, n2]: [usize; 2],
    r: usize,
    wv: &mut [f64],
    m0: &mut [f64],
) {
    match r {
        4 => m0_pass::<4>(nz, fib, b_f, c_f, n1, m0),
        8 => m0_pass::<8>(nz, fib, b_f, c_f, n1, m0),
        16 => m0_pass::<16>(nz, fib, b_f, c_f, n1, m0),
        32 => m0_pass::<32>(nz, fib, b_f, c_f, n1, m0),
        _ => {
            m0.iter_mut().for_each(|x| *x = 0.0);
            for k in 0..n2 {
                for j in 0..n1 {
                    let (b, c) = (&b_f[j * r..(j + 1) * r], &c_f[k * r..(k + 1) * r]);
                    for q in 0..r {
                        wv[q] = b[q] * c[q];
                    }
                    for &(i, v) in &nz[fib[j + n1 * k]..fib[j + n1 * k + 1]] {
                        for (x, y) in m0[i * r..(i + 1) * r].iter_mut().zip(wv.iter()) {
                            *x += v * y;
                        }
                    }
                }
            }
        }
    }
}

/// P[j, k, q] = Σ_i T[i, j, k] A[i, q] over the `fibres` = n1·n2 fibres.
#[inline(always)]
pub(super) fn partial(
    nz: &[(usize, f64)],
    fib: &[usize],
    a_f: &[f64],
    fibres: usize,
    r: usize,
    p: &mut [f64],
) {
    match r {
        4 => p_pass::<4>(nz, fib, a_f, p),
        8 => p_pass::<8>(nz, fib, a_f, p),
        16 => p_pass::<16>(nz, fib, a_f, p),
        32 => p_pass::<32>(nz, fib, a_f, p),
        _ => {
            p.iter_mut().for_each(|x| *x = 0.0);
            for jk in 0..fibres {
                let acc = &mut p[jk * r..(jk + 1) * r];
                for &(i, v) in &nz[fib[jk]..fib[jk + 1]] {
                    for (x, y) in acc.iter_mut().zip(&a_f[i * r..(i + 1) * r]) {
                        *x += v * y;
                    }
                }
            }
        }
    }
}

/// Mode 1: M1[j, q] = Σ_k P[j, k, q] C[k, q].
#[inline(always)]
pub(super) fn mode1(p: &[f64], c_f: &[f64], [n1, n2]: [usize; 2], r: usize, m1: &mut [f64]) {
    match r {
        4 => contract_k::<4>(p, c_f, n1, m1),
        8 => contract_k::<8>(p, c_f, n1, m1),
        16 => contract_k::<16>(p, c_f, n1, m1),
        32 => contract_k::<32>(p, c_f, n1, m1),
        _ => {
            m1.iter_mut().for_each(|x| *x = 0.0);
            for k in 0..n2 {
                let c = &c_f[k * r..(k + 1) * r];
                for j in 0..n1 {
                    let pp = &p[(j + n1 * k) * r..(j + n1 * k + 1) * r];
                    for ((x, y), z) in m1[j * r..(j + 1) * r].iter_mut().zip(pp).zip(c) {
                        *x += y * z;
                    }
                }
            }
        }
    }
}

/// Mode 2: M2[k, q] = Σ_j P[j, k, q] B[j, q].
#[inline(always)]
pub(super) fn mode2(p: &[f64], b_f: &[f64], [n1, n2]: [usize; 2], r: usize, m2: &mut [f64]) {
    match r {
        4 => contract_j::<4>(p, b_f, n1, m2),
        8 => contract_j::<8>(p, b_f, n1, m2),
        16 => contract_j::<16>(p, b_f, n1, m2),
        32 => contract_j::<32>(p, b_f, n1, m2),
        _ => {
            m2.iter_mut().for_each(|x| *x = 0.0);
            for k in 0..n2 {
                for j in 0..n1 {
                    let b = &b_f[j * r..(j + 1) * r];
                    let pp = &p[(j + n1 * k) * r..(j + n1 * k + 1) * r];
                    for ((x, y), z) in m2[k * r..(k + 1) * r].iter_mut().zip(pp).zip(b) {
                        *x += y * z;
                    }
                }
            }
        }
    }
}

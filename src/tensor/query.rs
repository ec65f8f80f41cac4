//! Point and angular range queries on a CP model (seed 002 Eq 6–7).
//!
//! Range query: the box average of Σ_r C_r X_r ⊗ Y_r at depth z is
//! Σ_r C_r · X̄_r([x1, x2]) · Ȳ_r([y1, y2]) · Z_r(z) (Appendix Eq 10–12: for a rank-1
//! tensor the box average factorises, proofs/tensor-rank1-box.md), and each 1D average
//! comes from a summed-area table in O(1), so a query costs O(R) whatever the box.
//!
//! f32 SATs: prefix sums built with Kahan compensation (each stored prefix is the exact
//! sum rounded once), so a range sum S[b] − S[a] carries at most ε·(|S[a]| + |S[b]|) + ε·|S[b] − S[a]|
//! absolute error — the cancellation bound tests/tensor.rs checks at the largest ranges.

use super::cp::Cp;

/// 1D summed-area tables of every factor column: sat[m][r][i] = Σ_{i' < i} F_m,r(i').
#[derive(Clone, Debug)]
pub struct Sat {
    pub f64: [Vec<Vec<f64>>; 3],
    pub f32: [Vec<Vec<f32>>; 3],
}

impl Sat {
    pub fn build(cp: &Cp) -> Sat {
        let mk64 = |m: usize| -> Vec<Vec<f64>> {
            (0..cp.rank)
                .map(|r| {
                    let mut s = vec![0.0; cp.shape[m] + 1];
                    for (i, v) in cp.factor(m, r).iter().enumerate() {
                        s[i + 1] = s[i] + v;
                    }
                    s
                })
                .collect()
        };
        let mk32 = |m: usize| -> Vec<Vec<f32>> {
            (0..cp.rank)
                .map(|r| {
                    // Kahan-compensated running sum in f32, each prefix rounded once
                    let mut s = vec![0.0f32; cp.shape[m] + 1];
                    let (mut sum, mut c) = (0.0f32, 0.0f32);
                    for (i, v) in cp.factor(m, r).iter().enumerate() {
                        let y = *v as f32 - c;
                        let t = sum + y;
                        c = (t - sum) - y;
                        sum = t;
                        s[i + 1] = sum;
                    }
                    s
                })
                .collect()
        };
        Sat {
            f64: [mk64(0), mk64(1), mk64(2)],
            f32: [mk32(0), mk32(1), mk32(2)],
        }
    }
}

/// Point query T̂(x, y, z) (Eq 6).
pub fn point(cp: &Cp, x: usize, y: usize, z: usize) -> f64 {
    cp.at(x, y, z)
}

/// Box average over [x1, x2] × [y1, y2] (inclusive) at depth z, in O(R) (Eq 7), f64.
pub fn range(cp: &Cp, sat: &Sat, x: (usize, usize), y: (usize, usize), z: usize) -> f64 {
    let (nx, ny) = ((x.1 - x.0 + 1) as f64, (y.1 - y.0 + 1) as f64);
    (0..cp.rank)
        .map(|r| {
            let sx = (sat.f64[0][r][x.1 + 1] - sat.f64[0][r][x.0]) / nx;
            let sy = (sat.f64[1][r][y.1 + 1] - sat.f64[1][r][y.0]) / ny;
            cp.weights[r] * sx * sy * cp.factor(2, r)[z]
        })
        .sum()
}

/// The same query from the f32 tables (shading precision).
pub fn range_f32(cp: &Cp, sat: &Sat, x: (usize, usize), y: (usize, usize), z: usize) -> f32 {
    let (nx, ny) = ((x.1 - x.0 + 1) as f32, (y.1 - y.0 + 1) as f32);
    (0..cp.rank)
        .map(|r| {
            let sx = (sat.f32[0][r][x.1 + 1] - sat.f32[0][r][x.0]) / nx;
            let sy = (sat.f32[1][r][y.1 + 1] - sat.f32[1][r][y.0]) / ny;
            cp.weights[r] as f32 * sx * sy * cp.factor(2, r)[z] as f32
        })
        .sum()
}

/// The naive box average of the reconstruction (the O(box) reference), summed with
/// Neumaier compensation so that its own rounding stays at a few ε whatever the box.
pub fn range_naive(cp: &Cp, x: (usize, usize), y: (usize, usize), z: usize) -> f64 {
    let (mut s, mut c) = (0.0f64, 0.0f64);
    for j in y.0..=y.1 {
        for i in x.0..=x.1 {
            let v = cp.at(i, j, z);
            let t = s + v;
            c += if s.abs() >= v.abs() {
                (s - t) + v
            } else {
                (v - t) + s
            };
            s = t;
        }
    }
    (s + c) / (((x.1 - x.0 + 1) * (y.1 - y.0 + 1)) as f64)
}

/// A-priori rounding bound on |range − exact| for a query (absolute), from the data only:
/// per factor, the subtraction S(b) − S(a) of prefix sums carries the prefixes' own error
/// (≤ `prefix`·ε·Σ|F| each: `prefix` = t for plain f64 sums, 2 for Kahan-built f32) plus ε
/// of the difference, divided by the box length; the product and the R-term sum add
/// (R + 4)ε relative. `eps` = f64::EPSILON or f32::EPSILON.
pub fn range_error_bound(
    cp: &Cp,
    x: (usize, usize),
    y: (usize, usize),
    z: usize,
    eps: f64,
    prefix: f64,
) -> f64 {
    let mut b = 0.0;
    for r in 0..cp.rank {
        let avg_err = |m: usize, lo: usize, hi: usize| -> (f64, f64) {
            let f = cp.factor(m, r);
            let tot: f64 = f.iter().map(|v| v.abs()).sum();
            let part: f64 = f[lo..=hi].iter().sum::<f64>();
            let len = (hi - lo + 1) as f64;
            let err = (2.0 * prefix * eps * tot + eps * part.abs()) / len;
            (part / len, err)
        };
        let (ax, ex) = avg_err(0, x.0, x.1);
        let (ay, ey) = avg_err(1, y.0, y.1);
        let cz = (cp.weights[r] * cp.factor(2, r)[z]).abs();
        b += cz * (ex * ay.abs() + ey * ax.abs() + ex * ey)
            + (cp.rank as f64 + 4.0) * eps * cz * (ax * ay).abs();
    }
    b
}

/// A P-NDF image stored as a grid of CP-compressed t×t blocks (one depth each):
/// `blocks[by * nb + bx] = (cp, depth, sat)`, None for dropped (all-zero) blocks.
pub struct BlockedImage<'a> {
    pub t: usize,
    pub nb: usize,
    pub blocks: Vec<Option<(&'a Cp, usize, &'a Sat)>>,
}

impl BlockedImage<'_> {
    /// Box average over pixel ranges [x0, x1] × [y0, y1] of the whole image that may span
    /// several blocks: the area-weighted sum of each overlapped block's O(R) range query.
    pub fn range(&self, x: (usize, usize), y: (usize, usize)) -> f64 {
        let t = self.t;
        let mut s = 0.0;
        for by in y.0 / t..=y.1 / t {
            for bx in x.0 / t..=x.1 / t {
                let lx = (x.0.max(bx * t) - bx * t, x.1.min(bx * t + t - 1) - bx * t);
                let ly = (y.0.max(by * t) - by * t, y.1.min(by * t + t - 1) - by * t);
                if let Some((cp, z, sat)) = self.blocks[by * self.nb + bx] {
                    let area = ((lx.1 - lx.0 + 1) * (ly.1 - ly.0 + 1)) as f64;
                    s += area * range(cp, sat, lx, ly, z);
                }
            }
        }
        s / (((x.1 - x.0 + 1) * (y.1 - y.0 + 1)) as f64)
    }
}

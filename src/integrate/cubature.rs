//! Adaptive cubature of a vector integrand over a rectangle: tensor-product G7/K15
//! panels, globally adaptive.
//!
//! Each panel is integrated twice on the same 15 × 15 Kronrod nodes: by the K15 ⊗ K15
//! rule (the value) and by the G7 ⊗ G7 rule on the odd nodes (a coarser resolution of
//! the same panel). A multiple of their difference (the caller's `safety`, per
//! component), summed over the panels, is the error estimate: conservative for smooth
//! panels (the K15 value is far more accurate than the G7 one it is compared with). At a
//! kink (|f − g| where f = g) both rules err alike and the plain difference can fall far
//! short of the true error; [`SAFETY_SMOOTH`] and [`SAFETY_KINKED`] are the multiples the
//! LTC lobe errors use, calibrated on LTC cells against references 10³ times tighter and
//! checked against an independent product rule (tests/lobe_error.rs). The panel whose weighted error is
//! largest is split in two along the axis where the one-axis rules (G7 in x ⊗ K15 in y,
//! K15 in x ⊗ G7 in y) disagree most, until the caller's `done` accepts the totals or
//! the budget is spent. Deterministic: the same inputs give the same bits.
//!
//! The integrand writes `n` components at a point; `weights` turns the components'
//! errors into one panel priority (set them to the sensitivity of whatever the caller
//! derives from the integrals, so the split goes where the derived figure is least sure).

use super::quad::{kronrod_nodes, WG, WGK};
use crate::lanes::{Lanes, LANES};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The multiple of |K15 ⊗ K15 − G7 ⊗ G7| taken as a panel's error estimate for a smooth
/// integrand (the plain difference was seen up to 2.2× short of the true error).
pub const SAFETY_SMOOTH: f64 = 3.0;
/// The same for an integrand with kinks inside panels (|f − g|: seen up to 9× short).
pub const SAFETY_KINKED: f64 = 20.0;

/// The totals of an adaptive cubature: per component, the value (K15 ⊗ K15) and its
/// error (Σ over panels of safety·|K15 ⊗ K15 − G7 ⊗ G7|), the evaluations spent and whether
/// `done` accepted them before the budget ran out.
#[derive(Clone, Debug, PartialEq)]
pub struct Cubature {
    pub value: Vec<f64>,
    pub error: Vec<f64>,
    pub evals: u64,
    pub converged: bool,
}

struct Panel {
    lo: [f64; 2],
    hi: [f64; 2],
    val: Vec<f64>,
    err: Vec<f64>,
    /// Which axis to split (the one whose coarse rule disagrees most).
    axis: usize,
    priority: f64,
}

impl PartialEq for Panel {
    fn eq(&self, o: &Self) -> bool {
        self.priority == o.priority
    }
}
impl Eq for Panel {}
impl PartialOrd for Panel {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Panel {
    fn cmp(&self, o: &Self) -> Ordering {
        self.priority.total_cmp(&o.priority)
    }
}

/// The Kronrod weight of node k (0..15) and its Gauss weight (0 off the Gauss nodes).
fn weights_1d() -> ([f64; 15], [f64; 15]) {
    let mut k = [0.0; 15];
    let mut g = [0.0; 15];
    for j in 0..7 {
        k[j] = WGK[j];
        k[14 - j] = WGK[j];
        if j % 2 == 1 {
            g[j] = WG[j / 2];
            g[14 - j] = WG[j / 2];
        }
    }
    k[7] = WGK[7];
    g[7] = WG[3];
    (k, g)
}

/// sin and cos of the last 16 distinct arguments. A panel evaluates its integrand on a
/// 15 × 15 tensor grid, so an integrand that needs the sine and cosine of a coordinate
/// computes each of its 15 values once per panel instead of 15 times; the values are
/// `f64::sin_cos`'s own, so results do not change by a bit.
#[derive(Clone, Debug, Default)]
pub struct SinCosMemo {
    keys: [u64; 16],
    vals: [(f64, f64); 16],
    len: usize,
    next: usize,
    /// The entry returned last: a panel asks for the same angle again (x fixed along a
    /// row) or for the one after it (y along the row), so these two are tried first.
    last: usize,
}

impl SinCosMemo {
    /// `a.sin_cos()`, from the memo where `a` was asked for among the last 16.
    #[inline]
    pub fn get(&mut self, a: f64) -> (f64, f64) {
        let b = a.to_bits();
        let after = (self.last + 1) % 16;
        let k = if self.last < self.len && self.keys[self.last] == b {
            Some(self.last)
        } else if after < self.len && self.keys[after] == b {
            Some(after)
        } else {
            self.keys[..self.len].iter().position(|&x| x == b)
        };
        if let Some(k) = k {
            self.last = k;
            return self.vals[k];
        }
        let v = a.sin_cos();
        self.keys[self.next] = b;
        self.vals[self.next] = v;
        self.last = self.next;
        self.next = (self.next + 1) % 16;
        self.len = (self.len + 1).min(16);
        v
    }
}

/// The integrand of [`cubature_lanes`]: the first `live` of four nodes (x, y), writing
/// component c of lane i to `out[c][i]` (all zero on entry).
pub trait LaneIntegrand: FnMut(&Lanes, &Lanes, usize, &mut [Lanes]) {}
impl<F: FnMut(&Lanes, &Lanes, usize, &mut [Lanes])> LaneIntegrand for F {}

fn panel<F: LaneIntegrand>(f: &mut F, safety: &[f64], lo: [f64; 2], hi: [f64; 2]) -> Panel {
    let n = safety.len();
    let (wk, wg) = weights_1d();
    let xs = kronrod_nodes(lo[0], hi[0]);
    let ys = kronrod_nodes(lo[1], hi[1]);
    let area = 0.25 * (hi[0] - lo[0]) * (hi[1] - lo[1]);
    let mut kk = vec![0.0; n];
    let mut gg = vec![0.0; n];
    let mut gk = vec![0.0; n]; // G7 in x, K15 in y
    let mut kg = vec![0.0; n]; // K15 in x, G7 in y
    let mut round = vec![0.0; n];
    let mut out = vec![[0.0; LANES]; n];
    // the 225 nodes in row order (x outer), four at a time; each node's terms are added in
    // that order, as one node at a time would add them
    for q0 in (0..225).step_by(LANES) {
        let live = LANES.min(225 - q0);
        let px: Lanes = std::array::from_fn(|i| xs[(q0 + i).min(224) / 15]);
        let py: Lanes = std::array::from_fn(|i| ys[(q0 + i).min(224) % 15]);
        out.iter_mut().for_each(|o| *o = [0.0; LANES]);
        f(&px, &py, live, &mut out);
        for lane in 0..live {
            let (i, j) = ((q0 + lane) / 15, (q0 + lane) % 15);
            let (kij, gij, gkij, kgij) =
                (wk[i] * wk[j], wg[i] * wg[j], wg[i] * wk[j], wk[i] * wg[j]);
            for c in 0..n {
                let v = out[c][lane];
                let v = if v.is_finite() { v } else { 0.0 };
                kk[c] += kij * v;
                gg[c] += gij * v;
                gk[c] += gkij * v;
                kg[c] += kgij * v;
                round[c] += kij * v.abs();
            }
        }
    }
    let mut val = vec![0.0; n];
    let mut err = vec![0.0; n];
    let (mut ex, mut ey) = (0.0f64, 0.0f64);
    for c in 0..n {
        val[c] = kk[c] * area;
        // the rounding floor of a 225-term sum (as QUADPACK's 50 ε Σ|w f|)
        let floor = 50.0 * f64::EPSILON * round[c] * area.abs();
        // the G7 ⊗ G7 rule is the coarse resolution; at a kink both rules err alike and
        // |K − G| alone can fall short of K's own error, so the estimate is a multiple
        let raw = (kk[c] - gg[c]).abs() * safety[c];
        err[c] = (raw * area.abs()).max(floor);
        let scale = kk[c].abs().max(1e-300);
        ex = ex.max((kk[c] - gk[c]).abs() / scale);
        ey = ey.max((kk[c] - kg[c]).abs() / scale);
    }
    Panel {
        lo,
        hi,
        val,
        err,
        axis: if ey > ex { 1 } else { 0 },
        priority: 0.0,
    }
}

/// ∫∫ f (`safety.len()` components) over the union of the rectangles of the grid `xb` ×
/// `yb` (break points, sorted): adaptive until `done(value, error)` holds or `max_evals`
/// are spent. A panel's error estimate of component c is safety[c]·|K15 ⊗ K15 − G7 ⊗ G7|;
/// `weights(value)` gives each component's weight in a panel's priority (Σ weight·error).
pub fn cubature<F, W, D>(
    mut f: F,
    safety: &[f64],
    xb: &[f64],
    yb: &[f64],
    weights: W,
    done: D,
    max_evals: u64,
) -> Cubature
where
    F: FnMut(f64, f64, &mut [f64]),
    W: Fn(&[f64]) -> Vec<f64>,
    D: Fn(&[f64], &[f64]) -> bool,
{
    let mut one = vec![0.0; safety.len()];
    let lanes = |x: &Lanes, y: &Lanes, live: usize, out: &mut [Lanes]| {
        for i in 0..live {
            one.iter_mut().for_each(|o| *o = 0.0);
            f(x[i], y[i], &mut one);
            for (c, o) in out.iter_mut().enumerate() {
                o[i] = one[c];
            }
        }
    };
    cubature_lanes(lanes, safety, xb, yb, weights, done, max_evals)
}

/// [`cubature`] with an integrand that takes four nodes at a time (`crate::lanes`), so that
/// an integrand whose value is a chain of divisions and roots can compute four chains
/// side by side. The nodes, their order and every sum are [`cubature`]'s: an integrand
/// that gives each lane the bits of the scalar one gives the same result, bit for bit.
pub fn cubature_lanes<F, W, D>(
    mut f: F,
    safety: &[f64],
    xb: &[f64],
    yb: &[f64],
    weights: W,
    done: D,
    max_evals: u64,
) -> Cubature
where
    F: LaneIntegrand,
    W: Fn(&[f64]) -> Vec<f64>,
    D: Fn(&[f64], &[f64]) -> bool,
{
    let n = safety.len();
    let mut heap: BinaryHeap<Panel> = BinaryHeap::new();
    let mut evals = 0u64;
    for wx in xb.windows(2) {
        for wy in yb.windows(2) {
            heap.push(panel(&mut f, safety, [wx[0], wy[0]], [wx[1], wy[1]]));
            evals += 225;
        }
    }
    let mut frozen_val = vec![0.0; n];
    let mut frozen_err = vec![0.0; n];
    let totals = |heap: &BinaryHeap<Panel>, fv: &[f64], fe: &[f64]| {
        let (mut v, mut e) = (fv.to_vec(), fe.to_vec());
        for p in heap.iter() {
            for c in 0..n {
                v[c] += p.val[c];
                e[c] += p.err[c];
            }
        }
        (v, e)
    };
    let reprioritise = |heap: BinaryHeap<Panel>, w: &[f64]| -> BinaryHeap<Panel> {
        heap.into_iter()
            .map(|mut p| {
                p.priority = (0..n).map(|c| w[c] * p.err[c]).sum();
                p
            })
            .collect()
    };
    let (mut value, mut error) = totals(&heap, &frozen_val, &frozen_err);
    let mut w = weights(&value);
    heap = reprioritise(heap, &w);
    let mut splits = 0usize;
    loop {
        if done(&value, &error) || evals >= max_evals || heap.is_empty() {
            let converged = done(&value, &error);
            return Cubature {
                value,
                error,
                evals,
                converged,
            };
        }
        let p = heap.pop().expect("non-empty heap");
        let a = p.axis;
        let mid = 0.5 * (p.lo[a] + p.hi[a]);
        if !(mid > p.lo[a] && mid < p.hi[a])
            || (p.hi[a] - p.lo[a]) <= 64.0 * f64::EPSILON * mid.abs().max(1e-300)
        {
            // cannot be split further in f64: kept as it is
            for c in 0..n {
                frozen_val[c] += p.val[c];
                frozen_err[c] += p.err[c];
            }
        } else {
            let (mut hi1, mut lo2) = (p.hi, p.lo);
            hi1[a] = mid;
            lo2[a] = mid;
            for (lo, hi) in [(p.lo, hi1), (lo2, p.hi)] {
                let mut q = panel(&mut f, safety, lo, hi);
                q.priority = (0..n).map(|c| w[c] * q.err[c]).sum();
                heap.push(q);
                evals += 225;
            }
        }
        splits += 1;
        // exact re-summation (no drift) and fresh weights every 16 splits
        (value, error) = totals(&heap, &frozen_val, &frozen_err);
        if splits % 16 == 0 {
            w = weights(&value);
            heap = reprioritise(heap, &w);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_polynomial_and_gaussian() {
        // x²y³ on [0,1]² = 1/12; a narrow Gaussian at (0.3, 0.7) of width 1e-3
        let s = 1e-3;
        let r = cubature(
            |x, y, o: &mut [f64]| {
                o[0] = x * x * y * y * y;
                let d2 = (x - 0.3).powi(2) + (y - 0.7).powi(2);
                o[1] = (-d2 / (2.0 * s * s)).exp() / (2.0 * std::f64::consts::PI * s * s);
            },
            &[SAFETY_SMOOTH; 2],
            &[0.0, 1.0],
            &[0.0, 1.0],
            |v| v.iter().map(|x| 1.0 / x.abs().max(1e-300)).collect(),
            |v, e| (0..2).all(|c| e[c] <= 1e-10 * v[c].abs()),
            10_000_000,
        );
        assert!(r.converged);
        assert!((r.value[0] - 1.0 / 12.0).abs() < 1e-13);
        assert!((r.value[1] - 1.0).abs() < 1e-9, "{}", r.value[1]);
    }
}

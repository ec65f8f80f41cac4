//! Deterministic quadrature: Gauss–Legendre of any order (1D and 2D tensor products),
//! adaptive Gauss–Kronrod (G7–K15, global subdivision) with an error estimate, nested
//! adaptive 2D integration, and variable substitutions for endpoint singularities and
//! semi-infinite ranges.

use super::estimate::{ErrorKind, Estimate};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Tolerance and budget for adaptive rules. Stop when error ≤ max(abs, rel·|value|).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tol {
    pub abs: f64,
    pub rel: f64,
    pub max_evals: u64,
}

impl Tol {
    pub fn new(abs: f64, rel: f64, max_evals: u64) -> Self {
        Tol {
            abs,
            rel,
            max_evals,
        }
    }
    fn target(&self, value: f64) -> f64 {
        self.abs.max(self.rel * value.abs())
    }
}

/// Gauss–Legendre nodes and weights on [-1, 1] for order `n` ≥ 1 (Newton iteration on
/// the three-term recurrence; accurate to a few ulp for n up to several thousand).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    assert!(n >= 1, "Gauss–Legendre order must be >= 1");
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    let m = n.div_ceil(2);
    for i in 0..m {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            if n == 1 {
                p1 = z;
                p0 = 1.0;
            } else {
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
            }
            // p1 = P_n(z), p0 = P_{n-1}(z)
            dp = n as f64 * (z * p1 - p0) / (z * z - 1.0);
            let dz = p1 / dp;
            z -= dz;
            // quadratic convergence from the asymptotic start: 3–6 steps
            if dz.abs() <= 1e-15 {
                break;
            }
        }
        if n == 1 {
            z = 0.0;
            dp = 1.0;
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        let wi = 2.0 / ((1.0 - z * z) * dp * dp);
        w[i] = wi;
        w[n - 1 - i] = wi;
    }
    if n == 1 {
        w[0] = 2.0;
    }
    (x, w)
}

fn gl_sum<F: Fn(f64) -> f64>(f: &F, a: f64, b: f64, n: usize) -> f64 {
    let (x, w) = gauss_legendre(n);
    let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
    x.iter()
        .zip(&w)
        .map(|(xi, wi)| wi * f(c + h * xi))
        .sum::<f64>()
        * h
}

/// n-point Gauss–Legendre on [a, b]. The error estimate is |Q_n − Q_⌈n/2⌉|, the error of
/// the half-order rule, which over-states the error of Q_n for smooth integrands.
pub fn gl_1d<F: Fn(f64) -> f64>(f: &F, a: f64, b: f64, n: usize) -> Estimate {
    let q = gl_sum(f, a, b, n);
    let h = n.div_ceil(2).max(1);
    let q2 = if n > 1 { gl_sum(f, a, b, h) } else { q };
    Estimate {
        value: q,
        error: (q - q2).abs(),
        evals: (n + if n > 1 { h } else { 0 }) as u64,
        kind: ErrorKind::Quadrature,
        converged: true,
    }
}

fn gl2_sum<F: Fn(f64, f64) -> f64>(f: &F, x: [f64; 2], y: [f64; 2], nx: usize, ny: usize) -> f64 {
    let (gx, wx) = gauss_legendre(nx);
    let (gy, wy) = gauss_legendre(ny);
    let (cx, hx) = (0.5 * (x[0] + x[1]), 0.5 * (x[1] - x[0]));
    let (cy, hy) = (0.5 * (y[0] + y[1]), 0.5 * (y[1] - y[0]));
    let mut s = 0.0;
    for (xi, wi) in gx.iter().zip(&wx) {
        let mut row = 0.0;
        for (yj, wj) in gy.iter().zip(&wy) {
            row += wj * f(cx + hx * xi, cy + hy * yj);
        }
        s += wi * row;
    }
    s * hx * hy
}

/// Tensor-product Gauss–Legendre on a rectangle; error as in [`gl_1d`] (half orders).
pub fn gl_2d<F: Fn(f64, f64) -> f64>(
    f: &F,
    x: [f64; 2],
    y: [f64; 2],
    nx: usize,
    ny: usize,
) -> Estimate {
    let q = gl2_sum(f, x, y, nx, ny);
    let (hx, hy) = (nx.div_ceil(2).max(1), ny.div_ceil(2).max(1));
    let q2 = gl2_sum(f, x, y, hx, hy);
    Estimate {
        value: q,
        error: (q - q2).abs(),
        evals: (nx * ny + hx * hy) as u64,
        kind: ErrorKind::Quadrature,
        converged: true,
    }
}

const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
pub(crate) const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
pub(crate) const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// The 15 Kronrod abscissae on [a, b] (index 7 is the midpoint).
pub fn kronrod_nodes(a: f64, b: f64) -> [f64; 15] {
    let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
    let mut xs = [0.0; 15];
    for j in 0..7 {
        xs[j] = c - h * XGK[j];
        xs[14 - j] = c + h * XGK[j];
    }
    xs[7] = c;
    xs
}

/// Values at the 15 nodes, the error of each value (for nested rules; 0 for plain
/// functions) and the evaluations spent.
pub type NodeValues = ([f64; 15], [f64; 15], u64);

#[derive(Clone, Copy)]
struct Seg {
    a: f64,
    b: f64,
    val: f64,
    err: f64,
}
impl PartialEq for Seg {
    fn eq(&self, o: &Self) -> bool {
        self.err == o.err
    }
}
impl Eq for Seg {}
impl PartialOrd for Seg {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Seg {
    fn cmp(&self, o: &Self) -> Ordering {
        self.err.total_cmp(&o.err)
    }
}

fn gk_segment<E: Fn(&[f64; 15]) -> NodeValues>(eval: &E, a: f64, b: f64) -> (Seg, u64) {
    let xs = kronrod_nodes(a, b);
    let (fv, fe, n) = eval(&xs);
    let h = 0.5 * (b - a);
    let mut k = WGK[7] * fv[7];
    let mut g = WG[3] * fv[7];
    let mut inner = WGK[7] * fe[7];
    let mut resabs = WGK[7] * fv[7].abs();
    for j in 0..7 {
        let pair = fv[j] + fv[14 - j];
        resabs += WGK[j] * (fv[j].abs() + fv[14 - j].abs());
        k += WGK[j] * pair;
        inner += WGK[j] * (fe[j] + fe[14 - j]);
        if j % 2 == 1 {
            g += WG[j / 2] * pair;
        }
    }
    let val = k * h;
    // rounding floor (as QUADPACK): the K15 sum cannot be trusted below ~50 ε Σ|w f|
    let round = 50.0 * f64::EPSILON * resabs * h.abs();
    let err = ((k - g) * h).abs().max(round) + inner * h.abs();
    let err = if err.is_finite() { err } else { f64::INFINITY };
    (Seg { a, b, val, err }, n)
}

/// Globally adaptive G7–K15 over the initial intervals given by `breaks` (sorted, at
/// least two points), driven by a batch evaluator of the 15 nodes of a segment.
pub fn adaptive_batched<E: Fn(&[f64; 15]) -> NodeValues>(
    eval: &E,
    breaks: &[f64],
    tol: Tol,
) -> Estimate {
    assert!(breaks.len() >= 2, "need at least one interval");
    let mut heap = BinaryHeap::new();
    let mut evals = 0u64;
    let mut frozen_val = 0.0;
    let mut frozen_err = 0.0;
    for w in breaks.windows(2) {
        let (s, n) = gk_segment(eval, w[0], w[1]);
        evals += n;
        heap.push(s);
    }
    let totals = |heap: &BinaryHeap<Seg>, fv: f64, fe: f64| {
        let v: f64 = heap.iter().map(|s| s.val).sum::<f64>() + fv;
        let e: f64 = heap.iter().map(|s| s.err).sum::<f64>() + fe;
        (v, e)
    };
    let mut iter = 0usize;
    let (mut value, mut error) = totals(&heap, 0.0, 0.0);
    loop {
        if error <= tol.target(value) {
            return Estimate {
                value,
                error,
                evals,
                kind: ErrorKind::Quadrature,
                converged: true,
            };
        }
        if evals >= tol.max_evals || heap.is_empty() {
            return Estimate {
                value,
                error,
                evals,
                kind: ErrorKind::Quadrature,
                converged: false,
            };
        }
        let s = heap.pop().expect("non-empty heap");
        let mut children: [Option<Seg>; 2] = [None, None];
        let m = 0.5 * (s.a + s.b);
        if !(m > s.a && m < s.b) || (s.b - s.a).abs() <= 64.0 * f64::EPSILON * m.abs().max(1e-300) {
            // cannot be split further in f64: keep it, frozen
            frozen_val += s.val;
            frozen_err += s.err;
        } else {
            let (l, n1) = gk_segment(eval, s.a, m);
            let (r, n2) = gk_segment(eval, m, s.b);
            evals += n1 + n2;
            heap.push(l);
            heap.push(r);
            children = [Some(l), Some(r)];
        }
        iter += 1;
        // exact re-summation (no drift) every 32 splits and whenever we might stop
        if iter % 32 == 0 || heap.len() < 64 {
            let t = totals(&heap, frozen_val, frozen_err);
            value = t.0;
            error = t.1;
        } else {
            let t = children
                .iter()
                .flatten()
                .fold((-s.val, -s.err), |acc, c| (acc.0 + c.val, acc.1 + c.err));
            let t = if children[0].is_none() { (0.0, 0.0) } else { t };
            value += t.0;
            error += t.1;
            if error <= tol.target(value) {
                let t = totals(&heap, frozen_val, frozen_err);
                value = t.0;
                error = t.1;
            }
        }
    }
}

/// Adaptive G7–K15 of a scalar function on [a, b].
pub fn gk15<F: Fn(f64) -> f64>(f: &F, a: f64, b: f64, tol: Tol) -> Estimate {
    gk15_breaks(f, &[a, b], tol)
}

/// Adaptive G7–K15 with initial break points (kinks, discontinuities, periodic splits).
pub fn gk15_breaks<F: Fn(f64) -> f64>(f: &F, breaks: &[f64], tol: Tol) -> Estimate {
    let eval = |xs: &[f64; 15]| {
        let mut v = [0.0; 15];
        for (o, x) in v.iter_mut().zip(xs) {
            *o = f(*x);
        }
        (v, [0.0; 15], 15u64)
    };
    adaptive_batched(&eval, breaks, tol)
}

/// Change of variables for 1D integrals, x = φ(t), integrated over t with the Jacobian.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Subst {
    /// No substitution.
    None,
    /// x = a + (b − a)(3t² − 2t³): dx/dt vanishes at both ends, which removes integrable
    /// endpoint singularities of type (x − a)^(−1/2) and softens log singularities.
    Smoothstep,
    /// ∫_a^∞ with x = a + s·t/(1 − t), t ∈ [0, 1); `b` is ignored. Choose s near the
    /// integrand's length scale (e.g. the roughness).
    SemiInfinite { scale: f64 },
}

/// Adaptive integral of f over [a, b] (or [a, ∞) for `SemiInfinite`) after substitution.
pub fn integrate_1d<F: Fn(f64) -> f64>(f: &F, a: f64, b: f64, subst: Subst, tol: Tol) -> Estimate {
    match subst {
        Subst::None => gk15(f, a, b, tol),
        Subst::Smoothstep => {
            let g = |t: f64| {
                let x = a + (b - a) * t * t * (3.0 - 2.0 * t);
                let dx = 6.0 * (b - a) * t * (1.0 - t);
                if dx == 0.0 {
                    0.0
                } else {
                    f(x) * dx
                }
            };
            gk15(&g, 0.0, 1.0, tol)
        }
        Subst::SemiInfinite { scale } => {
            let g = |t: f64| {
                if t >= 1.0 {
                    return 0.0;
                }
                let om = 1.0 - t;
                let x = a + scale * t / om;
                let v = f(x) * scale / (om * om);
                if v.is_finite() {
                    v
                } else {
                    0.0
                }
            };
            gk15(&g, 0.0, 1.0, tol)
        }
    }
}

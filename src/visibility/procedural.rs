//! Procedural maps (seed 004 §6): filtered without a texture, from the map's formula.
//!
//! - Colour (§6.1) on Fig. 6's pulse train f(x) = ⌊2x⌋ mod 2: global fading toward the
//!   mean ([`faded`]), analytic integration with F(x) = ½⌊x⌋ + max(x − ⌊x⌋ − ½, 0)
//!   ([`box_average`]: F(b) − F(a) is the box integral exactly,
//!   proofs/box-filter-analytic-integration.md), and its 2D grid f(x)f(y) under a sheared
//!   footprint, where the separable product of 1D integrals over the bounding box is an
//!   approximation ([`grid_average_separable`] against the exact clipped areas,
//!   [`grid_average_exact`]); frequency clamping of a spectral sum ([`Spectral`]).
//! - Normals (§6.2): a sum of height waves whose terms above the footprint's cut-off are
//!   clamped; the clamped terms' slope covariance widens the lobe (Bruneton et al.'s ocean
//!   filtering), [`Waves`].

use nalgebra::{Matrix2, Vector2, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

type V2 = Vector2<f64>;

/// f(x) = ⌊2x⌋ mod 2.
pub fn pulse(x: f64) -> f64 {
    (2.0 * x).floor().rem_euclid(2.0)
}

/// F(x) = ½⌊x⌋ + max(x − ⌊x⌋ − ½, 0), an antiderivative of [`pulse`].
pub fn pulse_integral(x: f64) -> f64 {
    let f = x.floor();
    0.5 * f + (x - f - 0.5).max(0.0)
}

/// The pulse train's integral over [a, b] by summing its unit pulses (independent of F).
pub fn pulse_integral_by_cells(a: f64, b: f64) -> f64 {
    let mut s = 0.0;
    let mut k = a.floor();
    while k <= b.floor() {
        let (lo, hi) = ((k + 0.5).max(a), (k + 1.0).min(b));
        if hi > lo {
            s += hi - lo;
        }
        k += 1.0;
    }
    s
}

/// The box average of f over [a, b] by analytic integration (the point value when the box
/// is empty).
pub fn box_average(a: f64, b: f64) -> f64 {
    if !(b > a) {
        return pulse(a);
    }
    (pulse_integral(b) - pulse_integral(a)) / (b - a)
}

/// Global fading: the point sample blended toward the mean ½ as the footprint width w grows
/// from half the smallest feature (¼) to one period (1).
pub fn faded(x: f64, w: f64) -> f64 {
    let t = ((w - 0.25) / 0.75).clamp(0.0, 1.0);
    (1.0 - t) * pulse(x) + t * 0.5
}

/// Area of a convex polygon clipped to the axis-aligned box [x0, x1] × [y0, y1]
/// (Sutherland–Hodgman, then the shoelace formula).
fn clipped_area(poly: &[V2], x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    let mut p: Vec<V2> = poly.to_vec();
    let planes: [(usize, f64, f64); 4] = [(0, x0, 1.0), (0, x1, -1.0), (1, y0, 1.0), (1, y1, -1.0)];
    for (axis, v, sign) in planes {
        let inside = |q: &V2| sign * (q[axis] - v) >= 0.0;
        let mut out = Vec::with_capacity(p.len() + 2);
        for k in 0..p.len() {
            let (a, b) = (p[k], p[(k + 1) % p.len()]);
            let (ia, ib) = (inside(&a), inside(&b));
            if ia {
                out.push(a);
            }
            if ia != ib {
                let t = (v - a[axis]) / (b[axis] - a[axis]);
                out.push(a + (b - a) * t);
            }
        }
        p = out;
        if p.is_empty() {
            return 0.0;
        }
    }
    0.5 * (0..p.len())
        .map(|k| {
            let (a, b) = (p[k], p[(k + 1) % p.len()]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        .abs()
}

/// The parallelogram c ± e1/2 ± e2/2.
fn parallelogram(c: V2, e1: V2, e2: V2) -> [V2; 4] {
    let h = (e1 + e2) * 0.5;
    let k = (e1 - e2) * 0.5;
    [c - h, c + k, c + h, c - k]
}

/// The exact average of f(x)f(y) over the parallelogram: the clipped area of every cell
/// [i + ½, i + 1] × [j + ½, j + 1] where the product is 1.
pub fn grid_average_exact(c: V2, e1: V2, e2: V2) -> f64 {
    let p = parallelogram(c, e1, e2);
    let area = (e1.x * e2.y - e1.y * e2.x).abs();
    let (xs, ys): (Vec<f64>, Vec<f64>) = p.iter().map(|q| (q.x, q.y)).unzip();
    let lo = |v: &[f64]| v.iter().cloned().fold(f64::INFINITY, f64::min).floor() as i64;
    let hi = |v: &[f64]| v.iter().cloned().fold(f64::NEG_INFINITY, f64::max).ceil() as i64;
    let mut s = 0.0;
    for j in lo(&ys)..=hi(&ys) {
        for i in lo(&xs)..=hi(&xs) {
            let (x0, y0) = (i as f64 + 0.5, j as f64 + 0.5);
            s += clipped_area(&p, x0, x0 + 0.5, y0, y0 + 0.5);
        }
    }
    s / area
}

/// The separable approximation: the product of the 1D analytic box averages over the
/// parallelogram's bounding box.
pub fn grid_average_separable(c: V2, e1: V2, e2: V2) -> f64 {
    let hx = 0.5 * (e1.x.abs() + e2.x.abs());
    let hy = 0.5 * (e1.y.abs() + e2.y.abs());
    box_average(c.x - hx, c.x + hx) * box_average(c.y - hy, c.y + hy)
}

/// A spectral sum f(x) = Σ_i a_i sin(2π f_i x + φ_i) (octaves f_i = 2^i, a_i = 2^{−i}).
#[derive(Clone, Debug)]
pub struct Spectral {
    pub terms: Vec<(f64, f64, f64)>,
}

impl Spectral {
    pub fn octaves(n: usize, seed: u64) -> Spectral {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        Spectral {
            terms: (0..n)
                .map(|i| {
                    (
                        0.5f64.powi(i as i32),
                        2f64.powi(i as i32),
                        2.0 * PI * rng.random::<f64>(),
                    )
                })
                .collect(),
        }
    }
    /// The exact box average over [x − w/2, x + w/2]: each term times sinc(π f w).
    pub fn box_average(&self, x: f64, w: f64) -> f64 {
        self.terms
            .iter()
            .map(|&(a, f, p)| {
                let z = PI * f * w;
                let sinc = if z.abs() < 1e-8 { 1.0 } else { z.sin() / z };
                a * (2.0 * PI * f * x + p).sin() * sinc
            })
            .sum()
    }
    /// Frequency clamping: terms with f·w ≤ c/2 kept, faded linearly to 0 at f·w = c.
    pub fn clamped(&self, x: f64, w: f64, c: f64) -> f64 {
        self.terms
            .iter()
            .map(|&(a, f, p)| {
                let r = f * w / c;
                let k = if r <= 0.5 {
                    1.0
                } else {
                    (2.0 * (1.0 - r)).max(0.0)
                };
                k * a * (2.0 * PI * f * x + p).sin()
            })
            .sum()
    }
}

/// A procedural height field Σ_i a_i cos(k_i·x + φ_i) (ocean-like: 32 waves, wavelengths
/// 2–64 units, amplitude ∝ wavelength so every octave carries similar slope).
#[derive(Clone, Debug)]
pub struct Waves {
    pub waves: Vec<(f64, V2, f64)>,
}

impl Waves {
    pub fn new(seed: u64, slope_rms: f64) -> Waves {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let raw: Vec<(f64, V2, f64)> = (0..32)
            .map(|_| {
                let lambda = 2.0 * 32f64.powf(rng.random::<f64>());
                let th = 2.0 * PI * rng.random::<f64>();
                let k = V2::new(th.cos(), th.sin()) * (2.0 * PI / lambda);
                (lambda, k, 2.0 * PI * rng.random::<f64>())
            })
            .collect();
        // slope variance Σ a²|k|²/2; a = s λ with one s for all
        let v: f64 = raw
            .iter()
            .map(|(l, k, _)| l * l * k.norm_squared() / 2.0)
            .sum();
        let s = slope_rms / v.sqrt();
        Waves {
            waves: raw.into_iter().map(|(l, k, p)| (s * l, k, p)).collect(),
        }
    }
    /// The unit normal at p from the waves with |k| ≤ `kmax`.
    pub fn normal(&self, p: V2, kmax: f64) -> Vector3<f64> {
        let mut g = V2::zeros();
        for (a, k, ph) in &self.waves {
            if k.norm() <= kmax {
                g -= k * (a * (k.dot(&p) + ph).sin());
            }
        }
        Vector3::new(-g.x, -g.y, 1.0).normalize()
    }
    /// The slope covariance of the waves above `kmax` (each a²kkᵀ/2).
    pub fn clamped_covariance(&self, kmax: f64) -> Matrix2<f64> {
        self.waves
            .iter()
            .filter(|(_, k, _)| k.norm() > kmax)
            .fold(Matrix2::zeros(), |acc, (a, k, _)| {
                acc + k * k.transpose() * (a * a / 2.0)
            })
    }
}

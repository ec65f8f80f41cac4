//! Hierarchical importance sampling of one reconstructed NDF block (seed 002 §5.2):
//! quad-tree descent with range queries (each child chosen with probability ∝ its box
//! average, O(R) per query), then a tent perturbation inside the pixel. The returned pdf
//! is the tent-filtered reconstruction normalised by the block's total — exactly the
//! density the samples follow (toroidal wrap at the block border keeps it normalised).

use super::cp::Cp;
use super::query::{range, Sat};

/// A sample position (continuous pixel coordinates in [0, t)²) and its pdf (per unit
/// pixel area).
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub x: f64,
    pub y: f64,
    pub pdf: f64,
}

fn clamp0(v: f64) -> f64 {
    v.max(0.0)
}

/// What the sampler reads of one compressed block: its side t (a power of two), the
/// reconstruction at a pixel (Eq 6) and the box average (Eq 7). Implemented by a CP with
/// its SATs, and by any layout of the same numbers a renderer prefers.
pub trait Block {
    fn side(&self) -> usize;
    fn at(&self, i: usize, j: usize, z: usize) -> f64;
    fn range(&self, x: (usize, usize), y: (usize, usize), z: usize) -> f64;
}

impl Block for (&Cp, &Sat) {
    fn side(&self) -> usize {
        if self.0.shape[1] == self.0.shape[0] {
            self.0.shape[0]
        } else {
            0
        }
    }
    fn at(&self, i: usize, j: usize, z: usize) -> f64 {
        self.0.at(i, j, z)
    }
    fn range(&self, x: (usize, usize), y: (usize, usize), z: usize) -> f64 {
        range(self.0, self.1, x, y, z)
    }
}

/// Descend to a pixel: at each level split the current square into 4 and pick a child
/// with probability ∝ max(0, its average)·area. `u` is consumed (rescaled) per level.
/// Returns the pixel and the probability of having chosen it (= v_p/total).
pub fn descend(cp: &Cp, sat: &Sat, z: usize, u: f64) -> Option<(usize, usize, f64)> {
    descend_in(&(cp, sat), z, u)
}

/// [`descend`] on any [`Block`].
pub fn descend_in<B: Block>(b: &B, z: usize, mut u: f64) -> Option<(usize, usize, f64)> {
    let t = b.side();
    if !t.is_power_of_two() {
        return None;
    }
    let (mut x0, mut y0, mut size) = (0usize, 0usize, t);
    let mut prob = 1.0;
    while size > 1 {
        let h = size / 2;
        let kids = [(x0, y0), (x0 + h, y0), (x0, y0 + h), (x0 + h, y0 + h)];
        let w = kids.map(|(a, c)| clamp0(b.range((a, a + h - 1), (c, c + h - 1), z)));
        let tot: f64 = w.iter().sum();
        if !(tot > 0.0) {
            return None;
        }
        let mut acc = 0.0;
        let mut pick = 3;
        for (k, wk) in w.iter().enumerate() {
            if u * tot < acc + wk {
                pick = k;
                break;
            }
            acc += wk;
        }
        let wk = w[pick];
        u = ((u * tot - acc) / wk).clamp(0.0, 1.0 - 1e-16);
        prob *= wk / tot;
        (x0, y0) = kids[pick];
        size = h;
    }
    Some((x0, y0, prob))
}

/// The normalised piecewise-constant reconstruction at pixel (i, j) (wrapped).
fn pixel_p<B: Block>(b: &B, z: usize, total: f64, i: i64, j: i64) -> f64 {
    let t = b.side() as i64;
    clamp0(b.at(i.rem_euclid(t) as usize, j.rem_euclid(t) as usize, z)) / total
}

/// The sampling density at continuous (x, y): the tent-filtered (bilinear) normalised
/// reconstruction, wrapped at the border.
pub fn pdf(cp: &Cp, z: usize, total: f64, x: f64, y: f64) -> f64 {
    let sat = Sat {
        f64: Default::default(),
        f32: Default::default(),
    };
    pdf_in(&(cp, &sat), z, total, x, y)
}

/// [`pdf`] on any [`Block`] (only its pixels are read).
pub fn pdf_in<B: Block>(b: &B, z: usize, total: f64, x: f64, y: f64) -> f64 {
    // pixel centres at k + 0.5; tent of half-width 1 pixel
    let (fx, fy) = (x - 0.5, y - 0.5);
    let (i0, j0) = (fx.floor() as i64, fy.floor() as i64);
    let (ax, ay) = (fx - i0 as f64, fy - j0 as f64);
    (1.0 - ax) * (1.0 - ay) * pixel_p(b, z, total, i0, j0)
        + ax * (1.0 - ay) * pixel_p(b, z, total, i0 + 1, j0)
        + (1.0 - ax) * ay * pixel_p(b, z, total, i0, j0 + 1)
        + ax * ay * pixel_p(b, z, total, i0 + 1, j0 + 1)
}

/// Draw one sample from three uniforms: descent (u0), tent offsets (u1, u2).
pub fn sample(cp: &Cp, sat: &Sat, z: usize, total: f64, u: [f64; 3]) -> Option<Sample> {
    sample_in(&(cp, sat), z, total, u)
}

/// [`sample`] on any [`Block`].
pub fn sample_in<B: Block>(b: &B, z: usize, total: f64, u: [f64; 3]) -> Option<Sample> {
    let (i, j, _) = descend_in(b, z, u[0])?;
    let tent = |v: f64| {
        if v < 0.5 {
            (2.0 * v).sqrt() - 1.0
        } else {
            1.0 - (2.0 - 2.0 * v).sqrt()
        }
    };
    let t = b.side() as f64;
    let x = (i as f64 + 0.5 + tent(u[1])).rem_euclid(t);
    let y = (j as f64 + 0.5 + tent(u[2])).rem_euclid(t);
    Some(Sample {
        x,
        y,
        pdf: pdf_in(b, z, total, x, y),
    })
}

/// Σ over pixels of max(0, reconstruction) at depth z (the normaliser).
pub fn total(cp: &Cp, z: usize) -> f64 {
    let t = cp.shape[0];
    let mut s = 0.0;
    for j in 0..t {
        for i in 0..t {
            s += clamp0(cp.at(i, j, z));
        }
    }
    s
}

/// A χ² goodness-of-fit test of [`sample`] against [`pdf`] on one block slice.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ChiSquare {
    /// bins of 2×2 pixels: (t/2)² of them
    pub bins: usize,
    pub samples: usize,
    pub chi2: f64,
    pub dof: usize,
    /// upper-tail p-value (Wilson–Hilferty approximation of the χ² distribution)
    pub p: f64,
    /// max |returned pdf − pdf(x, y)| over the samples (0 when the sampler is exact)
    pub pdf_mismatch: f64,
    /// ∫ pdf over the block by midpoint sums on an 8× finer grid (1 for a density)
    pub integral: f64,
}

/// χ² test of the hierarchical sampler on slice `z`: `n` samples from a seeded ChaCha8
/// stream, expected bin masses from midpoint integration of [`pdf`] (exact: the pdf is
/// bilinear between pixel centres, sampled at 8×8 points per pixel). `None` when the
/// slice is empty or the block is not a power-of-two square.
pub fn chi_square(cp: &Cp, sat: &Sat, z: usize, n: usize, seed: u64) -> Option<ChiSquare> {
    use rand::{Rng, SeedableRng};
    let t = cp.shape[0];
    let tot = total(cp, z);
    if !(tot > 0.0) || t < 2 {
        return None;
    }
    let (nb, sub) = (t / 2, 8usize);
    let mut expected = vec![0.0f64; nb * nb];
    let mut integral = 0.0;
    for j in 0..t * sub {
        for i in 0..t * sub {
            let (x, y) = ((i as f64 + 0.5) / sub as f64, (j as f64 + 0.5) / sub as f64);
            let p = pdf(cp, z, tot, x, y) / (sub * sub) as f64;
            integral += p;
            expected[(y as usize / 2) * nb + x as usize / 2] += p;
        }
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut counts = vec![0usize; nb * nb];
    let mut mismatch = 0.0f64;
    for _ in 0..n {
        let s = sample(cp, sat, z, tot, [rng.random(), rng.random(), rng.random()])?;
        counts[((s.y as usize).min(t - 1) / 2) * nb + (s.x as usize).min(t - 1) / 2] += 1;
        mismatch = mismatch.max((s.pdf - pdf(cp, z, tot, s.x, s.y)).abs());
    }
    // bins with (almost) no expected mass are pooled into one, as usual for χ²
    let (mut chi2, mut dof, mut pooled_e, mut pooled_c) = (0.0, 0usize, 0.0, 0.0);
    for (&c, &e) in counts.iter().zip(&expected) {
        let ne = n as f64 * e;
        if ne < 5.0 {
            pooled_e += ne;
            pooled_c += c as f64;
        } else {
            chi2 += (c as f64 - ne).powi(2) / ne;
            dof += 1;
        }
    }
    if pooled_e > 0.0 {
        chi2 += (pooled_c - pooled_e).powi(2) / pooled_e;
        dof += 1;
    }
    let dof = dof.saturating_sub(1).max(1);
    let k = dof as f64;
    let zz = ((chi2 / k).powf(1.0 / 3.0) - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    Some(ChiSquare {
        bins: nb * nb,
        samples: n,
        chi2,
        dof,
        p: 0.5 * libm::erfc(zz / std::f64::consts::SQRT_2),
        pdf_mismatch: mismatch,
        integral,
    })
}

/// The paper's binning comparison (seed 002 §5.2): a per-pixel histogram of `n`
/// descents, normalised, against the normalised reconstruction: (MSE, its Monte Carlo
/// expectation Σ p(1 − p)/n). `None` for an empty slice.
pub fn binning_mse(cp: &Cp, sat: &Sat, z: usize, n: usize, seed: u64) -> Option<(f64, f64)> {
    use rand::{Rng, SeedableRng};
    let t = cp.shape[0];
    let tot = total(cp, z);
    if !(tot > 0.0) {
        return None;
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut hist = vec![0usize; t * t];
    for _ in 0..n {
        let (i, j, _) = descend(cp, sat, z, rng.random())?;
        hist[j * t + i] += 1;
    }
    let (mut mse, mut expect) = (0.0, 0.0);
    for j in 0..t {
        for i in 0..t {
            let p = clamp0(cp.at(i, j, z)) / tot;
            mse += (hist[j * t + i] as f64 / n as f64 - p).powi(2);
            expect += p * (1.0 - p) / n as f64;
        }
    }
    Some((mse, expect))
}

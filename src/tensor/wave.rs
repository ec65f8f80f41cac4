//! Wave-optics NDF images (seed 002 §3.1, Eq 3–4, after Kuznetsov et al. 2019 and Yan
//! et al. 2018): the generalised NDF of a height field seen through a Gaussian coherence
//! window, aggregated over a pixel footprint, in colour from 8 spectral samples.
//!
//! - **Eq 3:** D*(u, ψ) = 4/(A_c λ²) · |∫ G_c(s; u, σ_c) e^{−i(4π/λ)[h(s) + ψ·s]} ds|², with
//!   G_c the unit-peak Gaussian window exp(−|s − u|²/(2σ_c²)) and A_c = ∫ G_c² ds = π σ_c²
//!   its coherence area. With that A_c, Parseval gives ∫ D* dψ = 1 over the whole ψ plane
//!   (the check of [`energy`]); ψ is the projected half vector, as h_xy is for the
//!   geometric P-NDF. Lengths are in µm.
//! - **Discretisation:** the window is sampled on the height field's grid (spacing dx) in
//!   an m × m patch, and one 2D FFT (`rustfft`) gives D* at ψ_k = λ k/(2 m dx),
//!   k ∈ [−m/2, m/2)²; [`gndf_direct`] is the O(m²)-per-ψ direct sum it is tested against.
//!   The ψ grid reaches |ψ| = λ/(4 dx), so dx ≤ λ/4 is needed to cover [−1, 1]².
//! - **Eq 4:** D*_P(x, ψ) = Σ_u G_P(u; x, σ_P) D*(u, ψ) / Σ_u G_P over window centres u
//!   on a grid of the given step.
//! - **Geometric limit:** by stationary phase, as λ → 0 (or for features much larger than
//!   λ) D*(u, ψ) → ∫ G_c(s)² δ(ψ + ∇h(s)) ds / A_c: the distribution of −∇h under the
//!   squared window ([`slope_image`]), which is what the geometric P-NDF of the same
//!   surface's normals tends to for gentle slopes (n_xy ≈ −∇h).
//! - **Colour:** 8 wavelengths 420, 460, …, 700 nm, weighted by the CIE 1931 2° colour
//!   matching functions (CIE 015:2018, tabulated values at those wavelengths) into XYZ,
//!   then linear sRGB, each channel scaled so that a flat spectrum is neutral: a
//!   λ-independent D* gives R = G = B.

use crate::error::{Error, Result};
use rand::{Rng, SeedableRng};
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;
use std::f64::consts::PI;

/// A periodic height field: n × n samples at spacing `dx` (µm), heights in µm, row-major.
#[derive(Clone, Debug)]
pub struct HeightField {
    pub n: usize,
    pub dx: f64,
    pub h: Vec<f64>,
}

impl HeightField {
    #[inline]
    fn at(&self, i: i64, j: i64) -> f64 {
        let n = self.n as i64;
        self.h[(j.rem_euclid(n) * n + i.rem_euclid(n)) as usize]
    }
}

/// A smooth periodic surface: a sum of cosines with integer wave numbers over the period
/// L, h(s) = Σ a_q cos(2π (k_q · s)/L + φ_q), scaled to a chosen RMS slope. Its gradient
/// is analytic, so the geometric limit has an exact reference.
#[derive(Clone, Debug)]
pub struct Waves {
    pub period: f64,
    comps: Vec<([f64; 2], f64, f64)>,
}

impl Waves {
    /// `count` cosines with wave numbers drawn in [1, kmax]² (either sign), amplitudes
    /// ∝ 1/|k|², phases uniform, then scaled so that the RMS slope is `rms_slope`.
    pub fn new(count: usize, kmax: u32, period: f64, rms_slope: f64, seed: u64) -> Result<Waves> {
        if count == 0 || kmax == 0 || !(period > 0.0 && period.is_finite()) || !(rms_slope > 0.0) {
            return Err(Error::InvalidArgument(format!(
                "a wave surface needs count ≥ 1, kmax ≥ 1, period > 0 and RMS slope > 0 (got {count}, {kmax}, {period:e}, {rms_slope:e})"
            )));
        }
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut comps = Vec::with_capacity(count);
        for _ in 0..count {
            let k = loop {
                let k = [
                    rng.random_range(-(kmax as i64)..=kmax as i64) as f64,
                    rng.random_range(-(kmax as i64)..=kmax as i64) as f64,
                ];
                if k != [0.0, 0.0] {
                    break k;
                }
            };
            let a = 1.0 / (k[0] * k[0] + k[1] * k[1]);
            comps.push((k, a, rng.random::<f64>() * 2.0 * PI));
        }
        // mean square slope of Σ a cos(w·s + φ): Σ a² |w|² / 2 (distinct wave vectors)
        let w = 2.0 * PI / period;
        let ms: f64 = comps
            .iter()
            .map(|(k, a, _)| a * a * w * w * (k[0] * k[0] + k[1] * k[1]) / 2.0)
            .sum();
        let scale = rms_slope / ms.sqrt();
        for c in &mut comps {
            c.1 *= scale;
        }
        Ok(Waves { period, comps })
    }

    pub fn height(&self, x: f64, y: f64) -> f64 {
        let w = 2.0 * PI / self.period;
        self.comps
            .iter()
            .map(|(k, a, p)| a * (w * (k[0] * x + k[1] * y) + p).cos())
            .sum()
    }

    /// ∇h at (x, y).
    pub fn gradient(&self, x: f64, y: f64) -> [f64; 2] {
        let w = 2.0 * PI / self.period;
        let mut g = [0.0; 2];
        for (k, a, p) in &self.comps {
            let s = -a * w * (w * (k[0] * x + k[1] * y) + p).sin();
            g[0] += s * k[0];
            g[1] += s * k[1];
        }
        g
    }

    /// The same surface magnified by `f` in every length (heights and period): the same
    /// slopes with features f times larger, which is optically the wavelength divided by f.
    pub fn magnified(&self, f: f64) -> Waves {
        Waves {
            period: self.period * f,
            comps: self.comps.iter().map(|(k, a, p)| (*k, a * f, *p)).collect(),
        }
    }

    /// Sampled on n × n points over one period.
    pub fn sample(&self, n: usize) -> HeightField {
        let dx = self.period / n as f64;
        let h = (0..n * n)
            .map(|q| self.height((q % n) as f64 * dx, (q / n) as f64 * dx))
            .collect();
        HeightField { n, dx, h }
    }
}

/// The coherence window and its patch: the first grid index of the m × m patch centred
/// on u, and the window's values on it.
fn window(
    hf: &HeightField,
    u: (f64, f64),
    sigma_c: f64,
    m: usize,
) -> Result<((i64, i64), Vec<f64>)> {
    if !(u.0.is_finite() && u.1.is_finite() && hf.dx > 0.0 && hf.dx.is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "a coherence window needs a finite centre and grid spacing (got ({:e}, {:e}), dx {:e})",
            u.0, u.1, hf.dx
        )));
    }
    if !(sigma_c > 0.0 && sigma_c.is_finite()) || m < 8 || !m.is_power_of_two() {
        return Err(Error::InvalidArgument(format!(
            "a coherence window needs σ_c > 0 and a power-of-two patch m ≥ 8 (got {sigma_c:e}, {m})"
        )));
    }
    let span = m as f64 * hf.dx;
    if span < 8.0 * sigma_c || m > hf.n {
        return Err(Error::InvalidArgument(format!(
            "a patch of {m} samples spans {span:.3} µm: it must cover ±4σ_c = {:.3} µm and fit in the {}-sample height field",
            8.0 * sigma_c,
            hf.n
        )));
    }
    let i0 = (
        (u.0 / hf.dx).round() as i64 - m as i64 / 2,
        (u.1 / hf.dx).round() as i64 - m as i64 / 2,
    );
    let g = (0..m * m)
        .map(|q| {
            let (a, b) = ((q % m) as i64, (q / m) as i64);
            let (sx, sy) = (
                (i0.0 + a) as f64 * hf.dx - u.0,
                (i0.1 + b) as f64 * hf.dx - u.1,
            );
            (-(sx * sx + sy * sy) / (2.0 * sigma_c * sigma_c)).exp()
        })
        .collect();
    Ok((i0, g))
}

/// A D* image on the FFT's own ψ grid: `values[(ky + m/2)·m + kx + m/2]` at
/// ψ = (kx, ky)·`dpsi`.
#[derive(Clone, Debug)]
pub struct Gndf {
    pub m: usize,
    pub dpsi: f64,
    pub values: Vec<f64>,
}

fn check_lambda(lambda: f64) -> Result<()> {
    if !(lambda > 0.0 && lambda.is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "wavelength must be > 0 µm (got {lambda:e})"
        )));
    }
    Ok(())
}

/// Eq 3 by one 2D FFT of the windowed phase over an m × m patch centred on u.
pub fn gndf_fft(
    hf: &HeightField,
    u: (f64, f64),
    sigma_c: f64,
    lambda: f64,
    m: usize,
) -> Result<Gndf> {
    check_lambda(lambda)?;
    let (i0, g) = window(hf, u, sigma_c, m)?;
    let k = 4.0 * PI / lambda;
    let mut buf: Vec<Complex64> = (0..m * m)
        .map(|q| {
            let h = hf.at(i0.0 + (q % m) as i64, i0.1 + (q / m) as i64);
            Complex64::from_polar(g[q], -k * h)
        })
        .collect();
    let fft = FftPlanner::<f64>::new().plan_fft_forward(m);
    // rows, then columns through a transpose
    for row in buf.chunks_exact_mut(m) {
        fft.process(row);
    }
    let mut t = vec![Complex64::new(0.0, 0.0); m * m];
    for j in 0..m {
        for i in 0..m {
            t[i * m + j] = buf[j * m + i];
        }
    }
    for row in t.chunks_exact_mut(m) {
        fft.process(row);
    }
    // t[kx·m + ky] now holds the 2D transform at (kx, ky)
    let ac = PI * sigma_c * sigma_c;
    let scale = 4.0 / (ac * lambda * lambda) * hf.dx.powi(4);
    let half = m / 2;
    let mut values = vec![0.0; m * m];
    for qx in 0..m {
        for qy in 0..m {
            let (sx, sy) = ((qx + half) % m, (qy + half) % m);
            values[sy * m + sx] = scale * t[qx * m + qy].norm_sqr();
        }
    }
    Ok(Gndf {
        m,
        dpsi: lambda / (2.0 * m as f64 * hf.dx),
        values,
    })
}

/// Eq 3 by the direct sum over the same patch, at any ψ (the FFT's reference).
pub fn gndf_direct(
    hf: &HeightField,
    u: (f64, f64),
    sigma_c: f64,
    lambda: f64,
    m: usize,
    psi: &[(f64, f64)],
) -> Result<Vec<f64>> {
    check_lambda(lambda)?;
    let (i0, g) = window(hf, u, sigma_c, m)?;
    let k = 4.0 * PI / lambda;
    let ac = PI * sigma_c * sigma_c;
    Ok(psi
        .iter()
        .map(|&(px, py)| {
            let mut s = Complex64::new(0.0, 0.0);
            for q in 0..m * m {
                let (a, b) = (i0.0 + (q % m) as i64, i0.1 + (q / m) as i64);
                let (x, y) = (a as f64 * hf.dx, b as f64 * hf.dx);
                s += Complex64::from_polar(g[q], -k * (hf.at(a, b) + px * x + py * y));
            }
            4.0 / (ac * lambda * lambda) * (hf.dx * hf.dx * s).norm_sqr()
        })
        .collect())
}

/// ∫ D* dψ over the FFT grid (Σ D*·dψ²), and the discrete window's Σ G_c² dx² / A_c
/// that Parseval says it equals; both tend to 1 as the window is resolved.
pub fn energy(g: &Gndf, hf: &HeightField, sigma_c: f64, u: (f64, f64)) -> Result<(f64, f64)> {
    let (_, w) = window(hf, u, sigma_c, g.m)?;
    let lhs = g.values.iter().sum::<f64>() * g.dpsi * g.dpsi;
    let rhs = w.iter().map(|v| v * v).sum::<f64>() * hf.dx * hf.dx / (PI * sigma_c * sigma_c);
    Ok((lhs, rhs))
}

/// Bin a D* grid into a res × res image over ψ ∈ [−1, 1)² (values per unit ψ area, each
/// node's mass D*·dψ² into the pixel holding it). Errors when the grid does not reach
/// the image's edge (dx > λ/4).
pub fn bin(g: &Gndf, res: usize) -> Result<Vec<f64>> {
    let half = (g.m / 2) as f64 * g.dpsi;
    if half < 1.0 || res < 2 {
        return Err(Error::InvalidArgument(format!(
            "the ψ grid reaches ±{half:.3}: the image [−1, 1]² needs dx ≤ λ/4 (and res ≥ 2, got {res})"
        )));
    }
    let cell = 2.0 / res as f64;
    let mut img = vec![0.0; res * res];
    let m = g.m as i64;
    for (q, v) in g.values.iter().enumerate() {
        let (kx, ky) = ((q as i64 % m) - m / 2, (q as i64 / m) - m / 2);
        let (px, py) = (kx as f64 * g.dpsi, ky as f64 * g.dpsi);
        let (i, j) = (((px + 1.0) / cell).floor(), ((py + 1.0) / cell).floor());
        if i >= 0.0 && j >= 0.0 && (i as usize) < res && (j as usize) < res {
            img[j as usize * res + i as usize] += v * g.dpsi * g.dpsi / (cell * cell);
        }
    }
    Ok(img)
}

/// A footprint: centre x, σ_P, and the step of the window centres u (µm).
#[derive(Clone, Copy, Debug)]
pub struct Footprint {
    pub x: (f64, f64),
    pub sigma_p: f64,
    pub step: f64,
}

impl Footprint {
    /// The window centres within 3σ_P and their normalised weights G_P (Eq 4).
    pub fn centres(&self) -> Result<Vec<((f64, f64), f64)>> {
        if !(self.sigma_p > 0.0 && self.step > 0.0)
            || 3.0 * self.sigma_p / self.step > 64.0
            || !(self.x.0.is_finite() && self.x.1.is_finite())
        {
            return Err(Error::InvalidArgument(format!(
                "a footprint needs a finite centre, σ_P > 0 and a step > 0 with at most 64 centres per radius (got ({:e}, {:e}), {:e}, {:e})",
                self.x.0, self.x.1, self.sigma_p, self.step
            )));
        }
        let r = (3.0 * self.sigma_p / self.step).floor() as i64;
        let mut c = Vec::new();
        for b in -r..=r {
            for a in -r..=r {
                let (dx, dy) = (a as f64 * self.step, b as f64 * self.step);
                let w = (-(dx * dx + dy * dy) / (2.0 * self.sigma_p * self.sigma_p)).exp();
                c.push(((self.x.0 + dx, self.x.1 + dy), w));
            }
        }
        let s: f64 = c.iter().map(|(_, w)| w).sum();
        c.iter_mut().for_each(|(_, w)| *w /= s);
        Ok(c)
    }
}

/// The pixel-wise sum of images of `n` values.
fn sum_images(parts: Vec<Vec<f64>>, n: usize) -> Vec<f64> {
    let mut out = vec![0.0; n];
    for p in parts {
        for (o, v) in out.iter_mut().zip(p) {
            *o += v;
        }
    }
    out
}

/// The power-of-two patch (≥ 8) that covers ±4σ_c at spacing dx.
pub fn patch_for(dx: f64, sigma_c: f64) -> usize {
    ((8.0 * sigma_c / dx).ceil() as usize)
        .next_power_of_two()
        .max(8)
}

/// The largest height-field side [`sampled_for`] builds (4096² samples: 128 MB of f64).
pub const MAX_SIDE: usize = 4096;

/// The power-of-two side that samples a `period` finely enough for λ (dx ≤ λ/4); a typed
/// error past [`MAX_SIDE`] or for a non-positive or non-finite input.
pub fn field_side(period: f64, lambda: f64) -> Result<usize> {
    let n = 4.0 * period / lambda;
    if !(n.is_finite() && n > 0.0) || n > MAX_SIDE as f64 {
        return Err(Error::InvalidArgument(format!(
            "a {period:e} µm period at λ = {lambda:e} µm needs {n:.0} samples per side (at most {MAX_SIDE})"
        )));
    }
    Ok((n.ceil() as usize).next_power_of_two())
}

/// `w` sampled over one period finely enough for λ ([`field_side`]), and the patch
/// covering ±4σ_c at that spacing.
pub fn sampled_for(w: &Waves, lambda: f64, sigma_c: f64) -> Result<(HeightField, usize)> {
    let hf = w.sample(field_side(w.period, lambda)?);
    let m = patch_for(hf.dx, sigma_c);
    Ok((hf, m))
}

/// Eq 4: the footprint's wave-optics NDF image at one wavelength (res × res over
/// ψ ∈ [−1, 1)²).
pub fn wave_image(
    hf: &HeightField,
    fp: &Footprint,
    sigma_c: f64,
    lambda: f64,
    m: usize,
    res: usize,
) -> Result<Vec<f64>> {
    use rayon::prelude::*;
    let parts: Vec<Vec<f64>> = fp
        .centres()?
        .par_iter()
        .map(|&(u, w)| {
            let img = bin(&gndf_fft(hf, u, sigma_c, lambda, m)?, res)?;
            Ok(img.into_iter().map(|v| v * w).collect())
        })
        .collect::<Result<_>>()?;
    Ok(sum_images(parts, res * res))
}

/// The geometric limit of [`wave_image`] for a [`Waves`] surface: the distribution of
/// −∇h(s) under Σ_u G_P(u) G_c(s − u)²/A_c, by a midpoint rule of spacing `ds` over the
/// windows' ±4σ_c, binned like [`bin`].
pub fn slope_image(
    w: &Waves,
    fp: &Footprint,
    sigma_c: f64,
    ds: f64,
    res: usize,
) -> Result<Vec<f64>> {
    use rayon::prelude::*;
    let centres = fp.centres()?;
    if !(ds > 0.0) || 8.0 * sigma_c / ds > 4096.0 || res < 2 {
        return Err(Error::InvalidArgument(format!(
            "the slope image needs 0 < ds with at most 4096 nodes per window and res ≥ 2 (got {ds:e}, {res})"
        )));
    }
    let cell = 2.0 / res as f64;
    let ac = PI * sigma_c * sigma_c;
    let n = (8.0 * sigma_c / ds).ceil() as i64;
    let parts: Vec<Vec<f64>> = centres
        .par_iter()
        .map(|&(u, wu)| {
            let mut img = vec![0.0; res * res];
            for b in 0..n {
                for a in 0..n {
                    let (sx, sy) = (
                        -4.0 * sigma_c + (a as f64 + 0.5) * ds,
                        -4.0 * sigma_c + (b as f64 + 0.5) * ds,
                    );
                    let g = (-(sx * sx + sy * sy) / (sigma_c * sigma_c)).exp();
                    let d = w.gradient(u.0 + sx, u.1 + sy);
                    let (i, j) = (((1.0 - d[0]) / cell).floor(), ((1.0 - d[1]) / cell).floor());
                    if i >= 0.0 && j >= 0.0 && (i as usize) < res && (j as usize) < res {
                        img[j as usize * res + i as usize] += wu * g * ds * ds / ac / (cell * cell);
                    }
                }
            }
            img
        })
        .collect();
    Ok(sum_images(parts, res * res))
}

/// Half the L1 distance of two images of densities over [−1, 1)² (the total-variation
/// distance of the two distributions, in [0, 1] when both hold unit mass).
pub fn tv_distance(a: &[f64], b: &[f64], res: usize) -> f64 {
    let cell = 2.0 / res as f64;
    0.5 * a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f64>() * cell * cell
}

/// The 8 wavelengths (µm).
/// Table 2's wave row (isotropic noise, 8K², stride 64, R = 16): NDF generation and
/// compression minutes on 40 cores, storage without / with compression (MB), ratio (%).
pub const TABLE2_WAVE: (f64, f64, f64, f64, f64) = (156.00, 347.94, 4292.25, 352.50, 8.21);

pub const WAVELENGTHS: [f64; 8] = [0.42, 0.46, 0.50, 0.54, 0.58, 0.62, 0.66, 0.70];

/// CIE 1931 2° x̄, ȳ, z̄ at [`WAVELENGTHS`] (CIE 015:2018).
const CMF: [[f64; 3]; 8] = [
    [0.134380, 0.004000, 0.645600],
    [0.290800, 0.060000, 1.669200],
    [0.004900, 0.323000, 0.272000],
    [0.290400, 0.954000, 0.020300],
    [0.916300, 0.870000, 0.001650],
    [0.854450, 0.381000, 0.000190],
    [0.164900, 0.061000, 0.000000],
    [0.011359, 0.004102, 0.000000],
];

/// XYZ → linear sRGB (IEC 61966-2-1).
const XYZ_TO_RGB: [[f64; 3]; 3] = [
    [3.2404542, -1.5371385, -0.4985314],
    [-0.9692660, 1.8760108, 0.0415560],
    [0.0556434, -0.2040259, 1.0572252],
];

/// Per wavelength, the weight of each RGB channel: M·cmf(λ), each channel normalised so
/// that its weights sum to 1 (a flat spectrum is neutral).
pub fn rgb_weights() -> [[f64; 3]; 8] {
    let mut w = [[0.0; 3]; 8];
    for (l, c) in CMF.iter().enumerate() {
        for ch in 0..3 {
            w[l][ch] = (0..3).map(|k| XYZ_TO_RGB[ch][k] * c[k]).sum();
        }
    }
    for ch in 0..3 {
        let s: f64 = w.iter().map(|r| r[ch]).sum();
        for r in &mut w {
            r[ch] /= s;
        }
    }
    w
}

/// The RGB images of one footprint from its 8 spectral images (linear, white-balanced
/// to a flat spectrum).
pub fn to_rgb(spectral: &[Vec<f64>]) -> Result<[Vec<f64>; 3]> {
    if spectral.len() != 8 || spectral.iter().any(|s| s.len() != spectral[0].len()) {
        return Err(Error::InvalidArgument(format!(
            "RGB needs 8 spectral images of one size (got {})",
            spectral.len()
        )));
    }
    let w = rgb_weights();
    let n = spectral[0].len();
    Ok(std::array::from_fn(|ch| {
        (0..n)
            .map(|p| (0..8).map(|l| w[l][ch] * spectral[l][p]).sum())
            .collect()
    }))
}

//! Spherical harmonics and zonal convolution (seed 004 §3.2.2, Han et al.; §7.3.2):
//!
//! - [`sh_basis`]: the real orthonormal spherical harmonics Y_lm up to degree L.
//! - [`Zonal`]: the zonal coefficients k̂_l = 2π ∫ k(t) P_l(t) dt of the base lobe's
//!   density k(n·η) = D(θ) cos θ, by which the Funk–Hecke theorem turns a convolution into
//!   a product: ∫ k(n·η) p(n) dn = Σ_lm k̂_l p_lm Y_lm(η) (the SH convolution theorem,
//!   proofs/sh-convolution.md).
//! - [`HanSh`]: the macroscopic NDF's coefficients p_lm = Σ ŵ Y_lm(n_x) (linear in the
//!   texels, so they MIP-map exactly: a convolution basis method, §7.3.2), times k̂_l.
//! - [`VmfConvolved`]: a vMF mixture of the macroscopic NDF (Eq 22) convolved with the
//!   base lobe by seed 004's zonal form, q̂(η) = Σ_k a_k Σ_l (2l+1)/(4π) k̂_l e^{−l²/(2κ_k)}
//!   P_l(μ_k·η) — a convolution spanning-set method (§7.4.2).
//! - [`coefficients_needed`]: the SH coefficient count a Blinn–Phong lobe needs, against the
//!   survey's rule of thumb 4(α + √α).

use super::em::VmfMixture;
use super::{BaseLobe, NormalPdf, Texels};
use crate::error::{Error, Result};
use crate::integrate::quad::gauss_legendre;
use nalgebra::Vector3;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// Largest SH degree of [`sh_basis`] (factorials stay exact in f64).
pub const MAX_DEGREE: usize = 24;

/// Index of (l, m) in a degree-L coefficient vector: l² + l + m.
pub fn index(l: usize, m: i64) -> usize {
    (l * l + l) as usize + m as usize
}

/// Y_lm(d) for every l ≤ L into `out` (length (L + 1)²), for a unit d. Uses
/// sin^m θ (cos mφ, sin mφ) = (Re, Im)(x + iy)^m, so no angle is formed.
pub fn sh_basis(lmax: usize, d: &V3, out: &mut [f64]) {
    let z = d.z;
    let mut fact = [1.0f64; 2 * MAX_DEGREE + 2];
    for i in 1..fact.len() {
        fact[i] = fact[i - 1] * i as f64;
    }
    let (mut re, mut im) = (1.0, 0.0); // (x + iy)^m
    let mut pmm = 1.0; // P̃_m^m = (−1)^m (2m − 1)!!
    for m in 0..=lmax {
        if m > 0 {
            let (r2, i2) = (re * d.x - im * d.y, re * d.y + im * d.x);
            re = r2;
            im = i2;
            pmm *= -((2 * m - 1) as f64);
        }
        let (mut pl2, mut pl1) = (0.0, 0.0); // P̃_{l−2}^m, P̃_{l−1}^m
        for l in m..=lmax {
            let p = if l == m {
                pmm
            } else if l == m + 1 {
                z * (2 * m + 1) as f64 * pmm
            } else {
                ((2 * l - 1) as f64 * z * pl1 - (l + m - 1) as f64 * pl2) / (l - m) as f64
            };
            pl2 = pl1;
            pl1 = p;
            let k = ((2 * l + 1) as f64 / (4.0 * PI) * fact[l - m] / fact[l + m]).sqrt();
            if m == 0 {
                out[index(l, 0)] = k * p;
            } else {
                let s = std::f64::consts::SQRT_2 * k * p;
                out[index(l, m as i64)] = s * re;
                out[index(l, -(m as i64))] = s * im;
            }
        }
    }
}

/// Legendre polynomials P_0..P_n at t into `out`.
pub fn legendre(n: usize, t: f64, out: &mut [f64]) {
    out[0] = 1.0;
    if n >= 1 {
        out[1] = t;
    }
    for l in 2..=n {
        out[l] = ((2 * l - 1) as f64 * t * out[l - 1] - (l - 1) as f64 * out[l - 2]) / l as f64;
    }
}

/// The zonal coefficients k̂_0..k̂_L of a zonal kernel k(t), t = cos θ about its axis,
/// concentrated within `width` radians of it: Gauss–Legendre on the θ-pieces [0, w],
/// [w, 3w], [3w, 8w], [8w, π], also split at the horizon π/2, with at least 128 nodes and 1.5 per oscillation of P_L.
pub fn zonal_coefficients(k: &dyn Fn(f64) -> f64, width: f64, lmax: usize) -> Vec<f64> {
    let br = super::lobe_breaks(width);
    let mut out = vec![0.0; lmax + 1];
    let mut p = vec![0.0; lmax + 1];
    for seg in br.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        // P_l has l/π oscillations per radian: resolve them on every piece
        let nodes = 128usize.max((1.5 * lmax as f64 * (b - a) / PI).ceil() as usize + 32);
        let (x, wt) = gauss_legendre(nodes);
        for (xi, wi) in x.iter().zip(&wt) {
            let th = 0.5 * (a + b) + 0.5 * (b - a) * xi;
            let t = th.cos();
            let f = k(t) * th.sin() * 0.5 * (b - a) * wi * 2.0 * PI;
            if f == 0.0 {
                continue;
            }
            legendre(lmax, t, &mut p);
            for (o, pl) in out.iter_mut().zip(&p) {
                *o += f * pl;
            }
        }
    }
    out
}

/// The base lobe's zonal coefficients, up to degree `lmax`.
#[derive(Clone, Debug)]
pub struct Zonal {
    pub base: BaseLobe,
    pub khat: Vec<f64>,
}

impl Zonal {
    pub fn new(base: BaseLobe, lmax: usize) -> Zonal {
        let khat = zonal_coefficients(&|t| base.q(t), base.alpha, lmax);
        Zonal { base, khat }
    }
}

/// Han et al.'s SH representation: c_lm = k̂_l p_lm, q̂(η) = Σ c_lm Y_lm(η).
#[derive(Clone, Debug)]
pub struct HanSh {
    pub degree: usize,
    pub coeffs: Vec<f64>,
}

impl HanSh {
    /// From the footprint's texels (p_lm = Σ ŵ Y_lm(n_x)).
    pub fn new(t: &Texels, zonal: &Zonal, degree: usize) -> Result<HanSh> {
        if degree > MAX_DEGREE || degree >= zonal.khat.len() {
            return Err(Error::InvalidArgument(format!(
                "SH degree {degree} above {}",
                MAX_DEGREE.min(zonal.khat.len().saturating_sub(1))
            )));
        }
        let nc = (degree + 1) * (degree + 1);
        let mut p = super::tools::basis_coefficients(
            &|d, out| sh_basis(degree, d, out),
            nc,
            t.normals,
            t.weights,
        );
        for l in 0..=degree {
            for m in -(l as i64)..=(l as i64) {
                p[index(l, m)] *= zonal.khat[l];
            }
        }
        Ok(HanSh { degree, coeffs: p })
    }
}

impl NormalPdf for HanSh {
    fn pdf(&self, h: &V3) -> f64 {
        let mut y = [0.0; (MAX_DEGREE + 1) * (MAX_DEGREE + 1)];
        let n = self.coeffs.len();
        sh_basis(self.degree, h, &mut y[..n]);
        self.coeffs.iter().zip(&y[..n]).map(|(c, b)| c * b).sum()
    }
}

/// A vMF mixture convolved with the base lobe by seed 004's zonal form.
#[derive(Clone, Debug)]
pub struct VmfConvolved {
    /// Per lobe: (a, μ, the series' terms (2l+1)/(4π) k̂_l e^{−l²/(2κ)} up to the last
    /// one above 1e-9 of the first).
    lobes: Vec<(f64, V3, Vec<f64>)>,
}

impl VmfConvolved {
    pub fn new(mix: &VmfMixture, zonal: &Zonal) -> VmfConvolved {
        let lobes = mix
            .comps
            .iter()
            .map(|c| {
                let terms: Vec<f64> = zonal
                    .khat
                    .iter()
                    .enumerate()
                    .map(|(l, k)| {
                        let lf = l as f64;
                        (2.0 * lf + 1.0) / (4.0 * PI)
                            * k
                            * (-lf * lf / (2.0 * c.kappa.max(1e-12))).exp()
                    })
                    .collect();
                let t0 = terms[0].abs();
                let last = terms.iter().rposition(|t| t.abs() > 1e-9 * t0).unwrap_or(0);
                (c.weight, c.mu, terms[..=last].to_vec())
            })
            .collect();
        VmfConvolved { lobes }
    }
    /// The largest series length of any lobe (the evaluation's cost).
    pub fn terms(&self) -> usize {
        self.lobes.iter().map(|l| l.2.len()).max().unwrap_or(0)
    }
}

impl NormalPdf for VmfConvolved {
    fn pdf(&self, h: &V3) -> f64 {
        let mut s = 0.0;
        for (a, mu, terms) in &self.lobes {
            let t = mu.dot(h).clamp(-1.0, 1.0);
            // P_l by the three-term recurrence, summed on the fly
            let (mut p0, mut p1) = (1.0, t);
            let mut acc = terms[0];
            for (l, c) in terms.iter().enumerate().skip(1) {
                let p = if l == 1 {
                    t
                } else {
                    let p = ((2 * l - 1) as f64 * t * p1 - (l - 1) as f64 * p0) / l as f64;
                    p0 = p1;
                    p1 = p;
                    p
                };
                acc += c * p;
            }
            s += a * acc;
        }
        s
    }
}

/// The smallest SH coefficient count (L + 1)² whose truncation of the normalised
/// Blinn–Phong lobe (e + 1)/(2π) t₊^e has relative L2 error ≤ `eps` on the sphere (Parseval
/// on the zonal series: ‖k‖² = Σ (2l+1)/(4π) k̂_l²); `None` beyond degree 600.
pub fn coefficients_needed(exponent: f64, eps: f64) -> Option<usize> {
    let lmax = 600;
    let norm = (exponent + 1.0) / (2.0 * PI);
    let width = (2.0 / (exponent + 2.0)).sqrt();
    let k = zonal_coefficients(
        &|t| {
            if t > 0.0 {
                norm * t.powf(exponent)
            } else {
                0.0
            }
        },
        width,
        lmax,
    );
    let e2: Vec<f64> = k
        .iter()
        .enumerate()
        .map(|(l, c)| (2 * l + 1) as f64 / (4.0 * PI) * c * c)
        .collect();
    let total: f64 = e2.iter().sum();
    let mut acc = 0.0;
    for (l, e) in e2.iter().enumerate() {
        acc += e;
        if ((total - acc).max(0.0) / total).sqrt() <= eps {
            return Some((l + 1) * (l + 1));
        }
    }
    None
}

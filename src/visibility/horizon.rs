//! Horizon maps and their pre-filtering (seed 004 §4).
//!
//! Directions are (elevation e above the mean plane, azimuth φ). A texel sees a direction
//! when e exceeds its horizon elevation Θ_x(φ) (Eq 24): [`horizon`] marches the
//! height field toward φ (0.25-texel steps out to [`REACH`] texels, bilinear heights) and
//! takes the steepest rise, clamped at 0. The footprint's exact visible fraction is
//! V_A(v) = Σ ŵ H(e_v − Θ_x(φ_v)) (Eq 26) and the joint fraction of Eq 23
//! V_A(l, v) = Σ ŵ V_x(l)V_x(v) / Σ ŵ V_x(v), both at the exact azimuth ([`exact`]).
//!
//! Stored per texel, at the four texture-axis azimuths: the HDF's mean and second moment
//! ([`HdfMoments`], 8 parameters, linear: the footprint's are the texels' averages),
//! interpolated linearly in azimuth. From them: Fournier's ramp, Tan et al.'s Gaussian HDF
//! (exact with erf), and the joint forms (the uncorrelated product, Tan et al.'s Eq 28,
//! Ashikhmin et al.'s β form). [`LegendreHorizon`] is Nowrouzezahrai & Snyder's expansion
//! of the step in normalised Legendre polynomials of sin e (Eq 29–30): K coefficients per
//! azimuth, linear in the texels (a basis tool of §7.3.1).

use super::HeightField;
use std::f64::consts::PI;

/// How far the horizon march reaches (texels).
pub const REACH: f64 = 32.0;
const STEP: f64 = 0.25;
/// The stored azimuths: the texture axes.
pub const AZIMUTHS: [f64; 4] = [0.0, 0.5 * PI, PI, 1.5 * PI];

/// A direction above the mean plane.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Dir {
    /// Elevation above the mean plane (radians, 0..π/2).
    pub elev: f64,
    pub azim: f64,
}

impl Dir {
    pub fn cos_between(&self, o: &Dir) -> f64 {
        let (a, b) = (self.elev, o.elev);
        (a.sin() * b.sin() + a.cos() * b.cos() * (self.azim - o.azim).cos()).clamp(-1.0, 1.0)
    }
}

/// Horizon elevation Θ(φ) ≥ 0 at texel (i, j).
pub fn horizon(hf: &HeightField, i: usize, j: usize, phi: f64) -> f64 {
    let (x0, y0) = (i as f64, j as f64);
    let h0 = hf.sample(x0, y0);
    let (dx, dy) = (phi.cos(), phi.sin());
    let mut best = 0.0f64;
    let steps = (REACH / STEP) as usize;
    for s in 1..=steps {
        let t = s as f64 * STEP;
        best = best.max((hf.sample(x0 + t * dx, y0 + t * dy) - h0) / t);
    }
    best.atan()
}

/// The exact V_A(v) and V_A(l, v) (`None` where no texel sees v).
pub fn exact(hf: &HeightField, texels: &[(usize, usize)], v: &Dir, l: &Dir) -> (f64, Option<f64>) {
    let (mut sv, mut slv) = (0.0, 0.0);
    for &(i, j) in texels {
        let vv = (v.elev > horizon(hf, i, j, v.azim)) as u8 as f64;
        let vl = (l.elev > horizon(hf, i, j, l.azim)) as u8 as f64;
        sv += vv;
        slv += vv * vl;
    }
    let n = texels.len() as f64;
    (sv / n, (sv > 0.0).then(|| slv / sv))
}

/// Linear interpolation weights of azimuth φ between the stored azimuths.
fn azimuth_weights(phi: f64) -> (usize, usize, f64) {
    let q = phi.rem_euclid(2.0 * PI) / (0.5 * PI);
    let i = (q.floor() as usize) % 4;
    (i, (i + 1) % 4, q - q.floor())
}

/// The HDF's first and second moments at the four azimuths.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct HdfMoments {
    pub m1: [f64; 4],
    pub m2: [f64; 4],
}

/// Every texel's horizon elevations at the stored azimuths.
pub fn stored_horizons(hf: &HeightField, texels: &[(usize, usize)]) -> Vec<[f64; 4]> {
    texels
        .iter()
        .map(|&(i, j)| AZIMUTHS.map(|phi| horizon(hf, i, j, phi)))
        .collect()
}

impl HdfMoments {
    /// The footprint's moments: the average of its texels' (Θ, Θ²) per azimuth.
    pub fn new(thetas: &[[f64; 4]]) -> HdfMoments {
        let (mut m1, mut m2) = ([0.0; 4], [0.0; 4]);
        for th in thetas {
            for k in 0..4 {
                m1[k] += th[k];
                m2[k] += th[k] * th[k];
            }
        }
        let n = thetas.len() as f64;
        for k in 0..4 {
            m1[k] /= n;
            m2[k] /= n;
        }
        HdfMoments { m1, m2 }
    }
    /// (μ, σ) at azimuth φ from the interpolated moments.
    pub fn at(&self, phi: f64) -> (f64, f64) {
        let (a, b, t) = azimuth_weights(phi);
        let m1 = self.m1[a] * (1.0 - t) + self.m1[b] * t;
        let m2 = self.m2[a] * (1.0 - t) + self.m2[b] * t;
        (m1, (m2 - m1 * m1).max(0.0).sqrt())
    }
}

/// Fournier's linear ramp from μ − σ (0) to μ + σ (1).
pub fn fournier(m: &HdfMoments, d: &Dir) -> f64 {
    let (mu, s) = m.at(d.azim);
    if s <= 1e-12 {
        return (d.elev > mu) as u8 as f64;
    }
    ((d.elev - mu + s) / (2.0 * s)).clamp(0.0, 1.0)
}

/// Tan et al.'s Gaussian HDF: V = Φ((e − μ)/σ) by erf.
pub fn tan_erf(m: &HdfMoments, d: &Dir) -> f64 {
    let (mu, s) = m.at(d.azim);
    if s <= 1e-12 {
        return (d.elev > mu) as u8 as f64;
    }
    0.5 * (1.0 + libm::erf((d.elev - mu) / (s * std::f64::consts::SQRT_2)))
}

/// Fournier's uncorrelated joint fraction, normalised like Eq 23: the lit-and-visible
/// fraction V_A(l)V_A(v) divided by the visible one V_A(v), i.e. V_A(l) (so at l = v it
/// gives V_A(v), not 1).
pub fn joint_product(vl: f64, _vv: f64) -> f64 {
    vl
}

/// Tan et al.'s Eq 28, with α = (1 + l·v)/2: 1 at l = v, V_A(l) when V_A(v) = 1.
pub fn joint_eq28(vl: f64, vv: f64, cos_lv: f64) -> f64 {
    if vv <= 0.0 {
        return 0.0;
    }
    let a = 0.5 * (1.0 + cos_lv);
    ((a * vl.min(vv) + (1.0 - a) * (vl + vv - 1.0).max(0.0)) / vv).clamp(0.0, 1.0)
}

/// Ashikhmin et al.'s form with β = exp(−γ²/(2w²)), γ the angle between l and v.
pub fn joint_ashikhmin(vl: f64, vv: f64, cos_lv: f64, width: f64) -> f64 {
    if vv <= 0.0 {
        return 0.0;
    }
    let g = cos_lv.clamp(-1.0, 1.0).acos();
    let b = (-g * g / (2.0 * width * width)).exp();
    ((b * vl.min(vv) + (1.0 - b) * vl * vv) / vv).clamp(0.0, 1.0)
}

/// Legendre P_0..P_n at u.
fn legendre(n: usize, u: f64) -> Vec<f64> {
    let mut p = vec![0.0; n + 1];
    p[0] = 1.0;
    if n >= 1 {
        p[1] = u;
    }
    for k in 2..=n {
        p[k] = ((2 * k - 1) as f64 * u * p[k - 1] - (k - 1) as f64 * p[k - 2]) / k as f64;
    }
    p
}

/// The coefficients a_k = ∫_s¹ P̂_k(μ) dμ of the step H(μ − s) on [0, 1] in the normalised
/// shifted Legendre basis P̂_k(μ) = √(2k + 1) P_k(2μ − 1), k < K: with u₀ = 2s − 1,
/// a_0 = 1 − s and a_k = −√(2k+1) (P_{k+1}(u₀) − P_{k−1}(u₀))/(2(2k+1)).
pub fn legendre_coeffs(s: f64, order: usize) -> Vec<f64> {
    let u0 = 2.0 * s.clamp(0.0, 1.0) - 1.0;
    let p = legendre(order + 1, u0);
    (0..order)
        .map(|k| {
            if k == 0 {
                1.0 - s.clamp(0.0, 1.0)
            } else {
                let c = (2 * k + 1) as f64;
                -c.sqrt() * (p[k + 1] - p[k - 1]) / (2.0 * c)
            }
        })
        .collect()
}

/// The truncated series Σ_k a_k P̂_k(μ).
pub fn legendre_eval(a: &[f64], mu: f64) -> f64 {
    let p = legendre(a.len(), 2.0 * mu - 1.0);
    a.iter()
        .enumerate()
        .map(|(k, c)| c * ((2 * k + 1) as f64).sqrt() * p[k])
        .sum()
}

/// Nowrouzezahrai & Snyder's horizon visibility: K Legendre coefficients of
/// H(sin e − sin Θ) at each stored azimuth, averaged over the footprint.
#[derive(Clone, Debug, serde::Serialize)]
pub struct LegendreHorizon {
    pub coeffs: [Vec<f64>; 4],
}

impl LegendreHorizon {
    pub fn new(thetas: &[[f64; 4]], order: usize) -> LegendreHorizon {
        let mut coeffs: [Vec<f64>; 4] = std::array::from_fn(|_| vec![0.0; order]);
        let n = thetas.len() as f64;
        for th in thetas {
            for (k, t) in th.iter().enumerate() {
                let a = legendre_coeffs(t.sin(), order);
                for (c, x) in coeffs[k].iter_mut().zip(&a) {
                    *c += x / n;
                }
            }
        }
        LegendreHorizon { coeffs }
    }
    /// V_A(d), clamped to [0, 1] as a shader would.
    pub fn eval(&self, d: &Dir) -> f64 {
        let (a, b, t) = azimuth_weights(d.azim);
        let c: Vec<f64> = self.coeffs[a]
            .iter()
            .zip(&self.coeffs[b])
            .map(|(x, y)| x * (1.0 - t) + y * t)
            .collect();
        legendre_eval(&c, d.elev.sin()).clamp(0.0, 1.0)
    }
}

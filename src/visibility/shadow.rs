//! Shadow maps and their pre-filtering (seed 004 §5).
//!
//! An orthographic light looks down −z on a receiver; the shadow map stores the depth of
//! the nearest surface, Z_s = min(occluders, receiver) ([`Scene::depth_map`]). A receiver
//! point at depth d is lit when Z_s ≥ d (Eq 32; the receiver itself passes, with a
//! 1e-9 bias). The truth is percentage-closer filtering over the footprint (Eq 31) with the
//! receiver's own depth per texel; Eq 33 replaces that depth by its footprint average d̄,
//! whose cost [`pcf`] also measures.
//!
//! Stored per texel, averaged linearly over the footprint ([`Moments`]): z and z²
//! (VSM, Donnelly & Lauritzen: Chebyshev's one-sided bound), sin/cos(c_k z) for k ≤ M
//! (convolution shadow maps, Annen et al.: the Fourier series of the step), e^{cz} (ESM,
//! Annen et al. / Salvi) and the two warps ±e^{±cz} with their squares (EVSM, Lauritzen &
//! McCool). Depths lie in [0, 1].

use half::f16;

/// The occluder scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Occluders {
    /// One plane at depth 0.5 over the left half.
    Plane,
    /// Three overlapping rectangles at depths 0.3, 0.5, 0.7.
    Layers,
    /// Bars two texels wide every six texels at depth 0.5 (a thin-feature fence).
    Fence,
    /// A sphere of radius 0.3 (in depth units; 0.3 of the map across) centred at depth 0.5.
    Sphere,
}

/// The receiver under the occluders.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Receiver {
    /// The plane at depth 0.9, parallel to the occluders.
    Parallel,
    /// A plane tilted along x: depth 0.8 + 0.15 x/N (1.1° per texel at N = 256).
    Tilted,
}

#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Scene {
    pub occluders: Occluders,
    pub receiver: Receiver,
    pub size: usize,
}

impl Scene {
    /// The receiver's depth at texel (i, j).
    pub fn receiver_depth(&self, i: usize, _j: usize) -> f64 {
        match self.receiver {
            Receiver::Parallel => 0.9,
            Receiver::Tilted => 0.8 + 0.15 * (i as f64 + 0.5) / self.size as f64,
        }
    }
    /// The nearest occluder's depth at texel (i, j), if any.
    pub fn occluder_depth(&self, i: usize, j: usize) -> Option<f64> {
        let n = self.size as f64;
        let (x, y) = ((i as f64 + 0.5) / n, (j as f64 + 0.5) / n);
        match self.occluders {
            Occluders::Plane => (x < 0.5).then_some(0.5),
            Occluders::Layers => {
                let mut z: Option<f64> = None;
                for (x0, x1, y0, y1, d) in [
                    (0.1, 0.6, 0.1, 0.6, 0.7),
                    (0.3, 0.8, 0.25, 0.75, 0.5),
                    (0.45, 0.95, 0.4, 0.9, 0.3),
                ] {
                    if x >= x0 && x < x1 && y >= y0 && y < y1 {
                        z = Some(z.map_or(d, |a: f64| a.min(d)));
                    }
                }
                z
            }
            Occluders::Fence => (i % 6 < 2).then_some(0.5),
            Occluders::Sphere => {
                let r2 = (x - 0.5).powi(2) + (y - 0.5).powi(2);
                let r = 0.3;
                (r2 < r * r).then(|| 0.5 - (r * r - r2).sqrt())
            }
        }
    }
    /// Z_s over the map (row-major).
    pub fn depth_map(&self) -> Vec<f64> {
        let n = self.size;
        (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                let r = self.receiver_depth(i, j);
                self.occluder_depth(i, j).map_or(r, |o| o.min(r))
            })
            .collect()
    }
}

const BIAS: f64 = 1e-9;

/// PCF over the footprint: (truth with each texel's own receiver depth, Eq 33's with the
/// average depth d̄), and d̄.
pub fn pcf(scene: &Scene, z: &[f64], texels: &[(usize, usize)]) -> (f64, f64, f64) {
    let n = texels.len() as f64;
    let dbar = texels
        .iter()
        .map(|&(i, j)| scene.receiver_depth(i, j))
        .sum::<f64>()
        / n;
    let (mut own, mut avg) = (0.0, 0.0);
    for &(i, j) in texels {
        let zs = z[j * scene.size + i];
        own += (zs >= scene.receiver_depth(i, j) - BIAS) as u8 as f64;
        avg += (zs >= dbar - BIAS) as u8 as f64;
    }
    (own / n, avg / n, dbar)
}

/// Storage precision of the filtered parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Precision {
    F64,
    F32,
    F16,
}

impl Precision {
    /// A value as stored (overflow gives ±∞, as the GPU's conversion does).
    pub fn store(self, x: f64) -> f64 {
        match self {
            Precision::F64 => x,
            Precision::F32 => x as f32 as f64,
            Precision::F16 => f16::from_f64(x).to_f64(),
        }
    }
    /// The largest finite stored value.
    pub fn max(self) -> f64 {
        match self {
            Precision::F64 => f64::MAX,
            Precision::F32 => f32::MAX as f64,
            Precision::F16 => f16::MAX.to_f64(),
        }
    }
}

/// Chebyshev's one-sided upper bound σ²/(σ² + (d − μ)²) for d > μ, else 1.
pub fn chebyshev(m1: f64, m2: f64, d: f64, min_var: f64) -> f64 {
    let var = (m2 - m1 * m1).max(min_var);
    if d <= m1 {
        return 1.0;
    }
    let t = d - m1;
    (var / (var + t * t)).clamp(0.0, 1.0)
}

/// The footprint averages of one method's stored parameters.
#[derive(Clone, Debug)]
pub struct Moments(pub Vec<f64>);

/// A filtered shadow method.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Method {
    /// (z, z²) + Chebyshev.
    Vsm,
    /// Fourier series of the step with M terms (sin and cos per term: 2M parameters);
    /// `fixed` applies Annen et al.'s offset (d shifted by half the series' transition
    /// width, 1/(2M)) and scale (2× about ½, then clamped).
    Csm { terms: usize, fixed: bool },
    /// e^{cz}: exp(−cd) E[e^{cz}], clamped to 1.
    Esm { c: f64 },
    /// Both warps e^{cz} and −e^{−cz} with their second moments, Chebyshev on each, the
    /// smaller bound.
    Evsm { c: f64 },
}

impl Method {
    pub fn params(&self) -> usize {
        match *self {
            Method::Vsm => 2,
            Method::Csm { terms, .. } => 2 * terms,
            Method::Esm { .. } => 1,
            Method::Evsm { .. } => 4,
        }
    }
    /// The stored parameters of one texel of depth z.
    pub fn encode(&self, z: f64) -> Vec<f64> {
        match *self {
            Method::Vsm => vec![z, z * z],
            Method::Csm { terms, .. } => (1..=terms)
                .flat_map(|k| {
                    let c = harmonic(k);
                    [(c * z).sin(), (c * z).cos()]
                })
                .collect(),
            Method::Esm { c } => vec![(c * z).exp()],
            Method::Evsm { c } => {
                let (p, n) = ((c * z).exp(), -(-c * z).exp());
                vec![p, p * p, n, n * n]
            }
        }
    }
    /// The filtered parameters of a footprint (box average), stored at `prec`.
    pub fn filter(
        &self,
        z: &[f64],
        size: usize,
        texels: &[(usize, usize)],
        prec: Precision,
    ) -> Moments {
        let mut acc = vec![0.0; self.params()];
        for &(i, j) in texels {
            for (a, x) in acc.iter_mut().zip(self.encode(z[j * size + i])) {
                *a += prec.store(x);
            }
        }
        let n = texels.len() as f64;
        Moments(acc.into_iter().map(|a| prec.store(a / n)).collect())
    }
    /// The lit fraction at receiver depth d from filtered parameters.
    pub fn lookup(&self, m: &Moments, d: f64) -> f64 {
        let p = &m.0;
        match *self {
            Method::Vsm => chebyshev(p[0], p[1], d, 1e-10),
            Method::Csm { terms, fixed } => {
                // H(z − d) − ½ = Σ_k 2/c_k · sin(c_k (z − d)), c_k = (2k − 1)π (period 2)
                let d = if fixed { d - 0.5 / terms as f64 } else { d };
                let mut s = 0.5;
                for k in 1..=terms {
                    let c = harmonic(k);
                    let (sd, cd) = (c * d).sin_cos();
                    s += 2.0 / c * (p[2 * (k - 1)] * cd - p[2 * k - 1] * sd);
                }
                if fixed {
                    s = 2.0 * (s - 0.5) + 0.5;
                }
                s.clamp(0.0, 1.0)
            }
            Method::Esm { c } => {
                let v = (-c * d).exp() * p[0];
                if v.is_nan() {
                    0.0
                } else {
                    v.clamp(0.0, 1.0)
                }
            }
            Method::Evsm { c } => {
                let up = chebyshev(p[0], p[1], (c * d).exp(), 1e-10 * (c * d).exp().powi(2));
                let dn = chebyshev(p[2], p[3], -(-c * d).exp(), 1e-10);
                let v = up.min(dn);
                if v.is_nan() {
                    0.0
                } else {
                    v
                }
            }
        }
    }
}

/// c_k = (2k − 1)π, the odd harmonics of the period-2 square wave.
fn harmonic(k: usize) -> f64 {
    (2 * k - 1) as f64 * std::f64::consts::PI
}

/// The largest warp constant c whose stored values stay finite at `prec` for depths ≤ 1:
/// ESM stores e^{c}, EVSM e^{2c} (its second moment).
pub fn max_usable_c(method_evsm: bool, prec: Precision) -> f64 {
    let l = prec.max().ln();
    if method_evsm {
        0.5 * l
    } else {
        l
    }
}

//! The normal-map pre-filtering representations of seed 004 §3.2 that the footprint filters
//! of [`crate::filters`] do not already cover, and the generic tools of §7 they are
//! instances of ([`tools`]).
//!
//! Every representation reconstructs the same thing: the footprint's distribution of
//! microfacet normals q_A(η) = Σ_x ŵ_x D_x(η)(η·n_x)₊ — a probability density over
//! directions, the μNDF f_A of seed 004 Eq 13 (each texel's lobe D_x its own base NDF
//! around its normal n_x). It is stored as a few numbers per texel and evaluated as
//! [`NormalPdf::pdf`]. One shading rule ([`shade`]) turns any such density into the
//! lobe that the footprint study compares with its truth: the separable form of seed 004
//! Eq 12, ρ_A(l, v)(n·l) ≈ r(l, v) q_A(h) with r = G2/(4 v·h), the masking G2 of one
//! isotropic lobe around the footprint's mean normal. The exact q_A under the same rule
//! ([`ExactPdf`]) is the floor that no representation can beat.
//!
//! - [`single`]: one lobe — Schilling's slope covariance in the mean normal's frame,
//!   Olano & North's 3D Gaussian (Eq 17), Neyret's ellipsoid as SGGX (Eq 18), Olano &
//!   Baker's slope-space Gaussian (Eq 19).
//! - [`fournier`]: sums of Blinn–Phong lobes (Eq 20) by non-linear least squares.
//! - [`em`]: Tan et al.'s slope-space Gaussian mixtures (Eq 21) and Han et al.'s vMF
//!   mixtures (Eq 22) by EM, with lobe alignment between neighbouring texels.
//! - [`sh`]: spherical harmonics (Han et al.), zonal convolution, Legendre series.

pub mod em;
pub mod fournier;
pub mod sh;
pub mod single;
pub mod tools;

use crate::error::Result;
use crate::integrate::quad::gauss_legendre;
use crate::microfacet::lobe::Frame;
use crate::microfacet::{Microsurface, NdfKind, Roughness};
use nalgebra::Vector3;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// A reconstructed distribution of microfacet normals (a density over unit directions).
pub trait NormalPdf: Send + Sync {
    /// q̂(η) for a unit η; may be negative for truncated series (the shading clamps).
    fn pdf(&self, h: &V3) -> f64;
}

/// The footprint a representation is built from: base texel normals with weights summing
/// to 1, and the base lobe every texel carries.
#[derive(Clone, Debug)]
pub struct Texels<'a> {
    pub normals: &'a [V3],
    pub weights: &'a [f64],
    pub base: BaseLobe,
}

impl Texels<'_> {
    /// The unnormalised mean normal Σ ŵ n.
    pub fn mean_normal(&self) -> V3 {
        self.normals
            .iter()
            .zip(self.weights)
            .fold(V3::zeros(), |a, (n, w)| a + n * *w)
    }
}

/// The isotropic base lobe of every texel: D of the given kind and α, as a density of
/// microfacet normals around the texel normal, q(θ) = D(θ) cos θ.
#[derive(Clone, Copy, Debug)]
pub struct BaseLobe {
    pub kind: NdfKind,
    pub alpha: f64,
}

impl BaseLobe {
    /// q(t) for t = cos θ ∈ [−1, 1] (zero on the lower hemisphere of the texel).
    pub fn q(&self, t: f64) -> f64 {
        if !(t > 0.0) {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t2 = t * t;
        match self.kind {
            NdfKind::Ggx => {
                let d = t2 * (a2 - 1.0) + 1.0;
                a2 * t / (PI * d * d)
            }
            NdfKind::Beckmann => {
                let tan2 = (1.0 - t2).max(0.0) / t2;
                let e = (-tan2 / a2).exp();
                if e == 0.0 {
                    0.0
                } else {
                    e / (PI * a2 * t2 * t)
                }
            }
        }
    }
    /// cos θ of a microfacet normal drawn from q for a uniform u ∈ [0, 1).
    pub fn sample_cos(&self, u: f64) -> f64 {
        let a2 = self.alpha * self.alpha;
        let tan2 = match self.kind {
            NdfKind::Ggx => a2 * u / (1.0 - u).max(1e-300),
            NdfKind::Beckmann => -a2 * (1.0 - u).max(1e-300).ln(),
        };
        1.0 / (1.0 + tan2).sqrt()
    }
    /// The base lobe's moments (E[cos θ], E[cos² θ], E[sin² θ]/2) by Gauss–Legendre in
    /// u (the sampler's uniform), which maps q to the unit interval exactly.
    pub fn moments(&self) -> [f64; 3] {
        let (x, w) = gauss_legendre(256);
        let mut m = [0.0; 3];
        // u = 1 − s², so that the tail at u → 1 is resolved
        for (xi, wi) in x.iter().zip(&w) {
            let s = 0.5 * (xi + 1.0);
            let u = 1.0 - s * s;
            let c = self.sample_cos(u);
            let jw = 0.5 * wi * 2.0 * s;
            m[0] += jw * c;
            m[1] += jw * c * c;
            m[2] += jw * 0.5 * (1.0 - c * c);
        }
        m
    }
}

/// The exact footprint distribution q_A (the floor of every representation).
pub struct ExactPdf {
    frames: Vec<Frame>,
    weights: Vec<f64>,
    base: BaseLobe,
}

impl ExactPdf {
    pub fn new(t: &Texels) -> ExactPdf {
        ExactPdf {
            frames: t.normals.iter().map(|n| Frame::around(*n)).collect(),
            weights: t.weights.to_vec(),
            base: t.base,
        }
    }
}

impl NormalPdf for ExactPdf {
    fn pdf(&self, h: &V3) -> f64 {
        self.frames
            .iter()
            .zip(&self.weights)
            .map(|(f, w)| w * self.base.q(f.n.dot(h)))
            .sum()
    }
}

/// The shading rule shared by every representation (seed 004 Eq 12): for view v and light
/// l (world, z > 0), ρ(v, l) = max(q̂(h), 0) G2(l, v)/(4 v·h), G2 Smith's height-correlated
/// masking–shadowing of the isotropic lobe (kind, α_eq) around the mean normal n̄.
pub struct Shading {
    frame: Frame,
    surface: Microsurface,
}

impl Shading {
    pub fn new(kind: NdfKind, mean_normal: V3, alpha_eq: f64) -> Result<Shading> {
        let n = if mean_normal.norm() > 0.0 {
            mean_normal.normalize()
        } else {
            V3::z()
        };
        Ok(Shading {
            frame: Frame::around(n),
            surface: Microsurface::new(kind, Roughness::iso(alpha_eq.clamp(1e-4, 4.0))?),
        })
    }
    /// The lobe of the density q̂ for (v, l).
    pub fn value(&self, q: &dyn NormalPdf, v: &V3, l: &V3) -> f64 {
        if v.z <= 0.0 || l.z <= 0.0 {
            return 0.0;
        }
        let h = v + l;
        let hn = h.norm();
        if !(hn > 0.0) {
            return 0.0;
        }
        let h = h / hn;
        let (vl, ll) = (self.frame.local(v), self.frame.local(l));
        if vl.z <= 0.0 || ll.z <= 0.0 {
            return 0.0;
        }
        let g2 = 1.0 / (1.0 + self.surface.lambda(&vl) + self.surface.lambda(&ll));
        q.pdf(&h).max(0.0) * g2 / (4.0 * v.dot(&h))
    }
    /// The frame's normal (the lobe's own mirror direction joins the peak search).
    pub fn normal(&self) -> V3 {
        self.frame.n
    }
}

/// ∫ f over the unit sphere, for a function concentrated around the unit `centre` with
/// angular width `width` (radians): Gauss–Legendre in θ (about the centre) on the pieces
/// [0, w], [w, 3w], [3w, 8w], [8w, π] (those below π, also split at π/2), 24 nodes each, and the periodic
/// trapezoid rule in φ with `n_phi` nodes. Returns (integral, the same with half the
/// nodes) so that a caller can see the rule's error.
pub fn sphere_integral(
    f: &dyn Fn(&V3) -> f64,
    centre: &V3,
    width: f64,
    n_phi: usize,
) -> (f64, f64) {
    let fr = Frame::around(*centre);
    let breaks = lobe_breaks(width);
    let rule = |nt: usize, np: usize| {
        let (x, wt) = gauss_legendre(nt);
        let mut s = 0.0;
        for seg in breaks.windows(2) {
            let (a, b) = (seg[0], seg[1]);
            for (xi, wi) in x.iter().zip(&wt) {
                let th = 0.5 * (a + b) + 0.5 * (b - a) * xi;
                let (st, ct) = th.sin_cos();
                let mut ring = 0.0;
                for k in 0..np {
                    let ph = 2.0 * PI * k as f64 / np as f64;
                    let d = fr.world(&V3::new(st * ph.cos(), st * ph.sin(), ct));
                    ring += f(&d);
                }
                s += 0.5 * (b - a) * wi * st * ring * 2.0 * PI / np as f64;
            }
        }
        s
    };
    (rule(24, n_phi), rule(12, (n_phi / 2).max(4)))
}

/// θ break points about a lobe's axis for quadrature: 0, w, 3w, 8w (those below π), the
/// horizon π/2 (where a lobe clamped there has its kink) and π.
pub fn lobe_breaks(width: f64) -> Vec<f64> {
    let w = width.clamp(1e-6, PI);
    let mut breaks = vec![0.0, PI / 2.0, PI];
    for b in [w, 3.0 * w, 8.0 * w] {
        if b < PI {
            breaks.push(b);
        }
    }
    breaks.sort_by(f64::total_cmp);
    breaks.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    breaks
}

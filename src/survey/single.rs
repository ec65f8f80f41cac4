//! Single-lobe representations (seed 004 §3.2.1), each a moments tool of §7.2
//! ([`super::tools`]): the footprint's distribution is replaced by one lobe with its
//! first and second moments.
//!
//! - [`SlopeGaussian`] in the geometric tangent plane is Olano & Baker's Eq 19 as printed
//!   (a Gaussian of slopes x̃ = −η_xy/η_z, 5 parameters that MIP-map linearly: a direct
//!   moments method); in the mean normal's own frame it is Schilling's representation
//!   (the 2×2 slope covariance about n̄, which does *not* MIP-map linearly: each level's
//!   covariance lives in its own frame).
//! - [`OlanoNorth`]: a 3D Gaussian of the normal vector η (Eq 17), mean and second moments
//!   (9 parameters) averaged linearly, evaluated on the unit sphere and normalised there.
//! - [`SggxLobe`]: Neyret's ellipsoid distribution (Eq 18) in its SGGX form, S linear in
//!   the texels' S_x = α²I + (1 − α²) n_x n_xᵀ (the SGGX matrix of a GGX lobe), 6 entries
//!   less one scale = 5 parameters.

use super::{sphere_integral, NormalPdf, Texels};
use crate::error::{Error, Result};
use crate::microfacet::lobe::Frame;
use crate::microfacet::sggx::Sggx;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};
use std::f64::consts::PI;

type V3 = Vector3<f64>;
type V2 = Vector2<f64>;

/// Slope of a unit direction in a frame (x̃ = −η_x/η_z, −η_y/η_z; seed 001 Eq 1).
fn slope(d: &V3) -> V2 {
    V2::new(-d.x / d.z, -d.y / d.z)
}

/// A Gaussian of slopes N(x̃; m, C) in a frame, as a density of normals:
/// q(η) = N(x̃(η))/η_z³ (the slope ↔ direction Jacobian, seed 001 Eq 1).
#[derive(Clone, Debug)]
pub struct SlopeGaussian {
    pub frame: Frame,
    pub mean: V2,
    pub cov: Matrix2<f64>,
    inv: Matrix2<f64>,
    norm: f64,
}

impl SlopeGaussian {
    /// A typed error when C is not positive definite.
    pub fn new(frame: Frame, mean: V2, cov: Matrix2<f64>) -> Result<SlopeGaussian> {
        let det = cov.determinant();
        if !(det > 0.0) || !(cov[(0, 0)] > 0.0) || cov.iter().any(|x| !x.is_finite()) {
            return Err(Error::NotSpd(format!("slope covariance {cov:?}")));
        }
        let inv = cov
            .try_inverse()
            .ok_or_else(|| Error::NotSpd("slope covariance".into()))?;
        Ok(SlopeGaussian {
            frame,
            mean,
            cov,
            inv,
            norm: 1.0 / (2.0 * PI * det.sqrt()),
        })
    }

    /// Olano & Baker (Eq 19): mean slope E[x̃] and covariance E[x̃x̃ᵀ] − E[x̃]E[x̃]ᵀ of the
    /// texel normals in the geometric frame, plus the base lobe's slope covariance α²/2 I
    /// (a Beckmann lobe of roughness α).
    pub fn olano_baker(t: &Texels) -> Result<SlopeGaussian> {
        let (m, c) = slope_moments(t, &Frame::around(V3::z()), true);
        let base = 0.5 * t.base.alpha * t.base.alpha;
        SlopeGaussian::new(Frame::around(V3::z()), m, c + Matrix2::identity() * base)
    }

    /// Schilling: the slope second moment about the mean normal n̄, in n̄'s frame, plus the
    /// base α²/2 I; centred on n̄ (the representation stores n̄ and the 2×2 matrix).
    pub fn schilling(t: &Texels) -> Result<SlopeGaussian> {
        let frame = Frame::around(mean_dir(t));
        let (_, c) = slope_moments(t, &frame, false);
        let base = 0.5 * t.base.alpha * t.base.alpha;
        SlopeGaussian::new(frame, V2::zeros(), c + Matrix2::identity() * base)
    }

    /// Schilling's representation MIP-mapped linearly anyway: the children's matrices
    /// (each about its own mean normal, in its own frame) averaged as if they shared one
    /// frame, around the average of the children's mean normals. `children` are
    /// (unnormalised mean normal, Schilling lobe) pairs with equal weights.
    pub fn schilling_mipped(children: &[(V3, SlopeGaussian)]) -> Result<SlopeGaussian> {
        let n = children.len().max(1) as f64;
        let mean = children.iter().fold(V3::zeros(), |a, c| a + c.0) / n;
        let cov = children.iter().fold(Matrix2::zeros(), |a, c| a + c.1.cov) / n;
        let dir = if mean.norm() > 0.0 {
            mean.normalize()
        } else {
            V3::z()
        };
        SlopeGaussian::new(Frame::around(dir), V2::zeros(), cov)
    }
}

impl NormalPdf for SlopeGaussian {
    fn pdf(&self, h: &V3) -> f64 {
        let d = self.frame.local(h);
        if !(d.z > 0.0) {
            return 0.0;
        }
        let x = slope(&d) - self.mean;
        let q = x.dot(&(self.inv * x));
        self.norm * (-0.5 * q).exp() / (d.z * d.z * d.z)
    }
}

/// The direction of the mean normal (z when it vanishes).
pub fn mean_dir(t: &Texels) -> V3 {
    let m = t.mean_normal();
    if m.norm() > 1e-300 {
        m.normalize()
    } else {
        V3::z()
    }
}

/// Weighted slope mean and covariance (about the mean when `centred`, about 0 otherwise)
/// of the texel normals seen in `frame`; texels at or below its horizon are skipped.
fn slope_moments(t: &Texels, frame: &Frame, centred: bool) -> (V2, Matrix2<f64>) {
    let (mut m, mut s, mut wsum) = (V2::zeros(), Matrix2::zeros(), 0.0);
    for (n, w) in t.normals.iter().zip(t.weights) {
        let d = frame.local(n);
        if d.z <= 1e-12 {
            continue;
        }
        let x = slope(&d);
        m += x * *w;
        s += x * x.transpose() * *w;
        wsum += w;
    }
    if wsum > 0.0 {
        m /= wsum;
        s /= wsum;
    }
    if centred {
        s -= m * m.transpose();
    }
    (m, s)
}

/// Olano & North's 3D Gaussian of the normal vector (Eq 17) on the unit sphere:
/// q(η) = exp(−½(η − μ)ᵀΣ⁻¹(η − μ))/Z, μ and Σ + μμᵀ the linear averages of the texels'
/// moments (each texel's lobe contributes E[η] = c₁n and E[ηηᵀ] = c⊥I + (c∥ − c⊥)nnᵀ, the
/// base lobe's moments), Z by quadrature over the sphere.
#[derive(Clone, Debug)]
pub struct OlanoNorth {
    pub mu: V3,
    pub sigma: Matrix3<f64>,
    inv: Matrix3<f64>,
    log_z: f64,
    /// The normalisation's quadrature error estimate (relative).
    pub z_rel_err: f64,
}

impl OlanoNorth {
    pub fn new(t: &Texels) -> Result<OlanoNorth> {
        let [c1, cpar, cperp] = t.base.moments();
        let n1 = t.mean_normal();
        let nn = t
            .normals
            .iter()
            .zip(t.weights)
            .fold(Matrix3::zeros(), |a, (n, w)| a + n * n.transpose() * *w);
        let mu = n1 * c1;
        let m2 = Matrix3::identity() * cperp + nn * (cpar - cperp);
        OlanoNorth::from_moments(mu, m2)
    }

    /// From the linear parameters (mean, second moment); Σ = M2 − μμᵀ, with a ridge of
    /// 1e-12 tr(M2) so that a rank-deficient Σ (unit vectors have almost no radial
    /// spread) stays invertible.
    pub fn from_moments(mu: V3, m2: Matrix3<f64>) -> Result<OlanoNorth> {
        let sigma = m2 - mu * mu.transpose() + Matrix3::identity() * (1e-12 * m2.trace());
        let inv = nalgebra::Cholesky::new(sigma)
            .map(|c| c.inverse())
            .ok_or_else(|| Error::NotSpd(format!("Olano–North covariance {sigma:?}")))?;
        let centre = if mu.norm() > 0.0 {
            mu.normalize()
        } else {
            V3::z()
        };
        let width = (sigma.trace() - centre.dot(&(sigma * centre)))
            .max(1e-12)
            .sqrt();
        let mut on = OlanoNorth {
            mu,
            sigma,
            inv,
            log_z: 0.0,
            z_rel_err: 0.0,
        };
        // the exponent's largest value on the sphere bounds the scale: normalise in logs
        let e = |d: &V3| {
            let x = d - mu;
            -0.5 * x.dot(&(inv * x))
        };
        let peak = e(&centre).max(e(&-centre));
        let (z, z_half) = sphere_integral(&|d| (e(d) - peak).exp(), &centre, width, 96);
        if !(z > 0.0) {
            return Err(Error::NotSpd(
                "Olano–North lobe vanishes on the sphere".into(),
            ));
        }
        on.log_z = z.ln() + peak;
        on.z_rel_err = ((z - z_half) / z).abs();
        Ok(on)
    }
}

impl NormalPdf for OlanoNorth {
    fn pdf(&self, h: &V3) -> f64 {
        let x = h - self.mu;
        (-0.5 * x.dot(&(self.inv * x)) - self.log_z).exp()
    }
}

/// Neyret's ellipsoid distribution (Eq 18) as SGGX, on the hemisphere of the mean normal:
/// q(η) = D_S(η)(η·n̄)₊/σ(n̄), σ(n̄) = √(n̄ᵀSn̄) its projected area (so that q integrates
/// to 1; proofs/sggx-projected-area.md).
#[derive(Clone, Debug)]
pub struct SggxLobe {
    pub sggx: Sggx,
    pub n: V3,
    sigma_n: f64,
}

impl SggxLobe {
    /// S = Σ ŵ S_x with S_x = α²I + (1 − α²) n_x n_xᵀ (exactly GGX of roughness α about
    /// n_x), around the mean normal.
    pub fn new(t: &Texels) -> Result<SggxLobe> {
        let a2 = t.base.alpha * t.base.alpha;
        let nn = t
            .normals
            .iter()
            .zip(t.weights)
            .fold(Matrix3::zeros(), |a, (n, w)| a + n * n.transpose() * *w);
        let s = Matrix3::identity() * a2 + nn * (1.0 - a2);
        SggxLobe::from_matrix(s, mean_dir(t))
    }
    pub fn from_matrix(s: Matrix3<f64>, n: V3) -> Result<SggxLobe> {
        let sggx = Sggx::new(s)?;
        let sigma_n = sggx.projected_area(&n);
        Ok(SggxLobe { sggx, n, sigma_n })
    }
}

impl NormalPdf for SggxLobe {
    fn pdf(&self, h: &V3) -> f64 {
        let c = h.dot(&self.n);
        if c <= 0.0 {
            return 0.0;
        }
        self.sggx.d(h) * c / self.sigma_n
    }
}

//! Environment lighting as spherical Gaussians, and seed 002 §5.4's prefiltered NDF query
//! (Eq 8–9).
//!
//! - An SG is G(ω) = A·exp(λ(ω·μ − 1)); its integral over the sphere is
//!   2πA(1 − e^{−2λ})/λ, and ω ~ G/∫G is the von Mises–Fisher distribution, drawn by
//!   w = 1 + ln(u + (1 − u)e^{−2λ})/λ about μ.
//! - Its compact-ε support (Eq 8, after Wang et al. 2009): every direction within
//!   θ = arccos((ln ε − ln A)/λ + 1) of μ has G > ε. ε is an absolute radiance, so θ
//!   depends on the lighting's units: 0 where A ≤ ε, π where the whole sphere exceeds ε.
//! - The prefiltered query (Eq 9): the NDF image is averaged over a square of side
//!   Q = scale · 2·res·θ/π pixels (the paper: res = 256, scale 0.5) about the half
//!   vector's pixel instead of read at that pixel.
//! - [`Env`]: an equirectangular radiance map (z up) and [`fit`], a greedy sum of SGs
//!   with non-negative least-squares amplitudes over a dictionary of axes and bandwidths.

use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector, Vector3};
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// One spherical Gaussian: unit axis μ, bandwidth λ > 0, amplitude A ≥ 0.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sg {
    pub axis: [f64; 3],
    pub lambda: f64,
    pub amp: f64,
}

impl Sg {
    /// A checked SG (axis normalised).
    pub fn new(axis: V3, lambda: f64, amp: f64) -> Result<Sg> {
        let n = axis.norm();
        if !(n.is_finite()
            && n > 0.0
            && lambda > 0.0
            && lambda.is_finite()
            && amp >= 0.0
            && amp.is_finite())
        {
            return Err(Error::InvalidArgument(format!(
                "an SG needs a finite non-zero axis, 0 < λ < ∞ and 0 ≤ A < ∞ (got |μ| {n:e}, λ {lambda:e}, A {amp:e})"
            )));
        }
        let a = axis / n;
        Ok(Sg {
            axis: [a.x, a.y, a.z],
            lambda,
            amp,
        })
    }

    fn mu(&self) -> V3 {
        V3::new(self.axis[0], self.axis[1], self.axis[2])
    }

    /// G(ω) for a unit ω.
    pub fn eval(&self, w: &V3) -> f64 {
        self.amp * (self.lambda * (w.dot(&self.mu()) - 1.0)).exp()
    }

    /// ∫ G dω = 2πA(1 − e^{−2λ})/λ.
    pub fn integral(&self) -> f64 {
        2.0 * PI * self.amp * (-(-2.0 * self.lambda).exp_m1()) / self.lambda
    }

    /// The vMF density G/∫G at a unit ω.
    pub fn pdf(&self, w: &V3) -> f64 {
        let l = self.lambda;
        l * (l * (w.dot(&self.mu()) - 1.0)).exp() / (2.0 * PI * -(-2.0 * l).exp_m1())
    }

    /// A direction drawn from the vMF density from two uniforms in [0, 1).
    pub fn sample(&self, u: [f64; 2]) -> V3 {
        let l = self.lambda;
        // w = 1 + ln(u + (1 − u) e^{−2λ})/λ, written to stay accurate for large λ
        let w = (1.0 + (u[0] + (1.0 - u[0]) * (-2.0 * l).exp()).ln() / l).clamp(-1.0, 1.0);
        let s = (1.0 - w * w).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        let mu = self.mu();
        let t = if mu.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let b1 = t.cross(&mu).normalize();
        let b2 = mu.cross(&b1);
        (b1 * (s * phi.cos()) + b2 * (s * phi.sin()) + mu * w).normalize()
    }

    /// The compact-ε support θ of Eq 8, in [0, π].
    pub fn support(&self, eps: f64) -> f64 {
        if self.amp <= eps {
            return 0.0;
        }
        ((eps.ln() - self.amp.ln()) / self.lambda + 1.0)
            .clamp(-1.0, 1.0)
            .acos()
    }
}

/// The side of Eq 9's query square in pixels of a res² image: scale · 2·res·θ/π,
/// rounded, at least one pixel and at most 2·res (a square that wide covers the image
/// wherever it is centred, so a larger one reads the same pixels).
pub fn query_side(theta: f64, res: usize, scale: f64) -> usize {
    ((scale * 2.0 * res as f64 * theta / PI).round() as usize).clamp(1, 2 * res.max(1))
}

/// The first pixel of Eq 9's q-pixel square along one axis of a res² image over
/// [−1, 1]²: the square whose centre lies nearest h (pixel p spans [p, p + 1) in pixel
/// units), so q = 1 is h's own pixel and an even q is never half a pixel off.
pub fn square_start(h: f64, q: i64, res: usize) -> i64 {
    ((h + 1.0) * 0.5 * res as f64 - 0.5 * q as f64).round() as i64
}

/// A sum of SGs; lobes are picked in proportion to their integrals.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SgEnv {
    pub lobes: Vec<Sg>,
}

impl SgEnv {
    pub fn eval(&self, w: &V3) -> f64 {
        self.lobes.iter().map(|g| g.eval(w)).sum()
    }

    fn total(&self) -> f64 {
        self.lobes.iter().map(|g| g.integral()).sum()
    }

    /// The mixture density of [`SgEnv::sample`].
    pub fn pdf(&self, w: &V3) -> f64 {
        let t = self.total();
        self.lobes.iter().map(|g| g.integral() / t * g.pdf(w)).sum()
    }

    /// A lobe by its share of the integral (u[0]), then a direction from it (u[1], u[2]):
    /// the lobe's index and the direction. A typed error for an empty or dark environment.
    pub fn sample(&self, u: [f64; 3]) -> Result<(usize, V3)> {
        let t = self.total();
        if !(t > 0.0 && t.is_finite()) {
            return Err(Error::InvalidArgument(
                "an SG environment with no light".into(),
            ));
        }
        let (mut acc, mut k) = (0.0, self.lobes.len() - 1);
        for (q, g) in self.lobes.iter().enumerate() {
            acc += g.integral() / t;
            if u[0] < acc {
                k = q;
                break;
            }
        }
        Ok((k, self.lobes[k].sample([u[1], u[2]])))
    }
}

/// An equirectangular radiance map, z up: row y at polar angle π(y + ½)/h, column x at
/// azimuth 2π(x + ½)/w.
#[derive(Clone, Debug)]
pub struct Env {
    pub width: usize,
    pub height: usize,
    pub radiance: Vec<f64>,
}

impl Env {
    /// Pixel (x, y)'s direction and solid angle.
    pub fn texel(&self, x: usize, y: usize) -> (V3, f64) {
        let (th, ph) = (
            PI * (y as f64 + 0.5) / self.height as f64,
            2.0 * PI * (x as f64 + 0.5) / self.width as f64,
        );
        let d = V3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
        (
            d,
            th.sin() * PI / self.height as f64 * 2.0 * PI / self.width as f64,
        )
    }

    /// A procedural sky: a sun of radiance `sun` within 3° of (40° from the zenith, 30°
    /// azimuth), a sky brightening towards the zenith (0.6 + 0.4 z) and a ground of 0.2.
    /// Every pixel is point-sampled at its centre.
    pub fn procedural(width: usize, height: usize, sun: f64) -> Result<Env> {
        let pixels = width.checked_mul(height).unwrap_or(usize::MAX);
        if width < 4 || height < 2 || pixels > 1 << 22 || !(sun >= 0.0 && sun.is_finite()) {
            return Err(Error::InvalidArgument(format!(
                "an environment needs 4..=2^22 pixels, at least 4×2, and a finite sun ≥ 0 (got {width}×{height}, sun {sun:e})"
            )));
        }
        let (st, sp) = (40f64.to_radians(), 30f64.to_radians());
        let s = V3::new(st.sin() * sp.cos(), st.sin() * sp.sin(), st.cos());
        let cap = 3f64.to_radians().cos();
        let mut env = Env {
            width,
            height,
            radiance: vec![0.0; width * height],
        };
        for y in 0..height {
            for x in 0..width {
                let (d, _) = env.texel(x, y);
                let sky = if d.z >= 0.0 { 0.6 + 0.4 * d.z } else { 0.2 };
                env.radiance[y * width + x] = sky + if d.dot(&s) >= cap { sun } else { 0.0 };
            }
        }
        Ok(env)
    }

    /// A user's equirectangular PNG (8- or 16-bit; z up: row 0 at the zenith, column x at
    /// azimuth 2π(x + ½)/w, as [`Env::texel`]): each pixel's sRGB-encoded channels decoded
    /// to linear (IEC 61966-2-1), its luminance 0.2126 R + 0.7152 G + 0.0722 B (Rec. 709)
    /// times `scale` as the radiance. A missing or broken file, a size outside 4×2 ..
    /// 2^22 pixels, or a scale that is not finite and positive is a typed error.
    pub fn from_png(path: &std::path::Path, scale: f64) -> Result<Env> {
        if !(scale > 0.0 && scale.is_finite()) {
            return Err(Error::InvalidArgument(format!(
                "environment {}: the radiance scale must be finite and > 0 (got {scale:e})",
                path.display()
            )));
        }
        let img = crate::filters::footprint::open_image(path, "equirectangular environment map")?
            .to_rgb16();
        let (width, height) = (img.width() as usize, img.height() as usize);
        if width < 4 || height < 2 || width * height > 1 << 22 {
            return Err(Error::InvalidArgument(format!(
                "environment {}: {width}×{height} pixels (an environment needs 4..=2^22 pixels, at least 4×2)",
                path.display()
            )));
        }
        // 8-bit values widen to 16 bits exactly (v·257), so v/65535 is v8/255 in f64
        let linear = |v: u16| {
            let c = f64::from(v) / 65535.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        let radiance = img
            .pixels()
            .map(|p| {
                let [r, g, b] = p.0.map(linear);
                scale * (0.2126 * r + 0.7152 * g + 0.0722 * b)
            })
            .collect();
        Ok(Env {
            width,
            height,
            radiance,
        })
    }

    /// The map averaged over 2×2 pixel blocks (a last odd row or column left out): the
    /// second sampling a fit to a user's map is judged on. At least 8×4 pixels.
    pub fn halved(&self) -> Result<Env> {
        let (w, h) = (self.width / 2, self.height / 2);
        if w < 4 || h < 2 {
            return Err(Error::InvalidArgument(format!(
                "an environment of {}×{} pixels has no 2×2-averaged map of at least 4×2",
                self.width, self.height
            )));
        }
        let at = |x: usize, y: usize| self.radiance[y * self.width + x];
        let radiance = (0..w * h)
            .map(|k| {
                let (x, y) = (2 * (k % w), 2 * (k / w));
                0.25 * (at(x, y) + at(x + 1, y) + at(x, y + 1) + at(x + 1, y + 1))
            })
            .collect();
        Ok(Env {
            width: w,
            height: h,
            radiance,
        })
    }

    /// ‖env − sgs‖ / ‖env‖ over the sphere, by the pixels' solid angles.
    pub fn rel_error(&self, sgs: &SgEnv) -> f64 {
        let (mut d2, mut l2) = (0.0, 0.0);
        for y in 0..self.height {
            for x in 0..self.width {
                let (d, w) = self.texel(x, y);
                let l = self.radiance[y * self.width + x];
                d2 += w * (l - sgs.eval(&d)).powi(2);
                l2 += w * l * l;
            }
        }
        (d2 / l2).sqrt()
    }
}

/// `k` SGs fitted to `env` greedily: each step adds the dictionary lobe (unit amplitude:
/// `axes` Fibonacci-sphere axes plus the centre of the brightest pixels, times `lambdas`) whose
/// least-squares refit of every amplitude, all non-negative, leaves the smallest
/// solid-angle-weighted residual.
pub fn fit(env: &Env, k: usize, axes: usize, lambdas: &[f64]) -> Result<SgEnv> {
    if k == 0 || k > 32 || axes < 4 || axes > 4096 || lambdas.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "an SG fit needs 1..=32 lobes, 4..=4096 axes and a bandwidth (got {k}, {axes}, {})",
            lambdas.len()
        )));
    }
    let (mut dirs, mut weights, mut target) = (Vec::new(), Vec::new(), Vec::new());
    for y in 0..env.height {
        for x in 0..env.width {
            let (d, w) = env.texel(x, y);
            dirs.push(d);
            weights.push(w.sqrt());
            target.push(env.radiance[y * env.width + x]);
        }
    }
    // the radiance-weighted centre of the pixels above half the brightest one's radiance
    let peak = target.iter().cloned().fold(0.0, f64::max);
    let bright: V3 = dirs
        .iter()
        .zip(&target)
        .zip(&weights)
        .filter(|((_, &t), _)| t >= 0.5 * peak)
        .map(|((d, t), w)| d * (t * w * w))
        .sum();
    if !(peak > 0.0 && bright.norm() > 0.0) {
        return Err(Error::InvalidArgument(
            "an environment with no light".into(),
        ));
    }
    let golden = PI * (3.0 - 5f64.sqrt());
    let mut cand = Vec::new();
    for q in 0..=axes {
        let mu = if q == axes {
            bright.normalize()
        } else {
            let z = 1.0 - 2.0 * (q as f64 + 0.5) / axes as f64;
            let r = (1.0 - z * z).sqrt();
            V3::new(
                r * (golden * q as f64).cos(),
                r * (golden * q as f64).sin(),
                z,
            )
        };
        for &l in lambdas {
            cand.push(Sg::new(mu, l, 1.0)?);
        }
    }
    let col = |g: &Sg| {
        DVector::from_iterator(
            dirs.len(),
            dirs.iter().zip(&weights).map(|(d, w)| w * g.eval(d)),
        )
    };
    let b = DVector::from_iterator(
        target.len(),
        target.iter().zip(&weights).map(|(t, w)| t * w),
    );
    let cols: Vec<DVector<f64>> = cand.iter().map(col).collect();
    let mut active: Vec<usize> = Vec::new();
    let mut amps: Vec<f64> = Vec::new();
    for _ in 0..k {
        let mut best: Option<(f64, usize, Vec<f64>)> = None;
        for c in 0..cand.len() {
            if active.contains(&c) {
                continue;
            }
            let set: Vec<usize> = active.iter().copied().chain([c]).collect();
            let a =
                DMatrix::from_columns(&set.iter().map(|&q| cols[q].clone()).collect::<Vec<_>>());
            let Some(x) = a.clone().svd(true, true).solve(&b, 1e-12).ok() else {
                continue;
            };
            if x.iter().any(|v| !(*v >= 0.0)) {
                continue;
            }
            let r = (&a * &x - &b).norm_squared();
            if best.as_ref().is_none_or(|bst| r < bst.0) {
                best = Some((r, c, x.iter().copied().collect()));
            }
        }
        let Some((_, c, x)) = best else { break };
        active.push(c);
        amps = x;
    }
    if active.is_empty() {
        return Err(Error::InvalidArgument(
            "the SG fit found no non-negative lobe".into(),
        ));
    }
    Ok(SgEnv {
        lobes: active
            .iter()
            .zip(&amps)
            .map(|(&c, &a)| Sg { amp: a, ..cand[c] })
            .collect(),
    })
}

/// One footprint's NDF image (a compressed one, read as the renderer reads it) seen from
/// the unit view `o` under an SG environment: the reflected radiance
///
///   I = ∫ L(i) · D(h_xy(i)) · h_z / (4 o·h) di = ∫_{|h_xy| < 1} L(2(o·h)h − o) · D(h_xy) dh_xy,
///
/// D per unit projected area (seed 002 Eq 2's images), h the half vector. The estimators
/// draw i from the environment ([`SgEnv::sample`]); the prefiltered one reads D as the box
/// average of Eq 9's square instead of the pixel.
pub struct Shading<'a> {
    pub ndf: &'a crate::tensor::brdf::CompressedNdf,
    pub image: usize,
    pub o: V3,
}

/// How the estimator reads D.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Read {
    /// The pixel holding h_xy (point query, Eq 6).
    Point,
    /// The mean over Eq 9's square of side scale·2·res·θ/π, θ the sampled lobe's
    /// compact-ε support (Eq 8).
    Prefiltered { eps: f64, scale: f64 },
}

impl Shading<'_> {
    /// I by the midpoint rule, `sub`² points per pixel of the image (D constant on a
    /// pixel, as the point query reads it; points outside the unit disk dropped).
    pub fn reference(&self, env: &SgEnv, sub: usize) -> f64 {
        let res = self.ndf.res();
        let (cell, mut total) = (2.0 / res as f64, 0.0);
        for py in 0..res {
            for px in 0..res {
                let centre = |p: usize| -1.0 + (p as f64 + 0.5) * cell;
                let d = self.ndf.d(self.image, centre(px), centre(py));
                if d == 0.0 {
                    continue;
                }
                let mut acc = 0.0;
                for q in 0..sub * sub {
                    let hx = -1.0 + (px as f64 + ((q % sub) as f64 + 0.5) / sub as f64) * cell;
                    let hy = -1.0 + (py as f64 + ((q / sub) as f64 + 0.5) / sub as f64) * cell;
                    let r2 = hx * hx + hy * hy;
                    if r2 >= 1.0 {
                        continue;
                    }
                    let h = V3::new(hx, hy, (1.0 - r2).sqrt());
                    acc += env.eval(&(h * (2.0 * self.o.dot(&h)) - self.o));
                }
                total += d * acc * cell * cell / (sub * sub) as f64;
            }
        }
        total
    }

    /// One sample of I from three uniforms.
    pub fn sample(&self, env: &SgEnv, read: Read, u: [f64; 3]) -> Result<f64> {
        let (k, i) = env.sample(u)?;
        let s = i + self.o;
        if s.norm() == 0.0 {
            return Ok(0.0);
        }
        let h = s.normalize();
        if h.z <= 0.0 {
            return Ok(0.0);
        }
        let d = match read {
            Read::Point => self.ndf.d(self.image, h.x, h.y),
            Read::Prefiltered { eps, scale } => {
                let q = query_side(env.lobes[k].support(eps), self.ndf.res(), scale) as i64;
                let res = self.ndf.res();
                let (x0, y0) = (square_start(h.x, q, res), square_start(h.y, q, res));
                self.ndf
                    .box_mean(self.image, (x0, x0 + q - 1), (y0, y0 + q - 1))
                    .unwrap_or(0.0)
            }
        };
        // a draw where the mixture density underflows (the far side of a lobe with
        // λ ≳ 350) carries no weight: its radiance underflows with it
        let q = env.pdf(&i);
        if !(q > 0.0) {
            return Ok(0.0);
        }
        Ok(env.eval(&i) * d * h.z / (4.0 * self.o.dot(&h)) / q)
    }
}

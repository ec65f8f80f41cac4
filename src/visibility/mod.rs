//! Visibility and procedural pre-filtering (seed 004 §4–6, §8.1): the maps that seed 004
//! treats after normals, each with its exact footprint average and the published
//! approximations.
//!
//! - [`HeightField`]: periodic height fields (procedural, or a grey PNG), read bilinearly.
//! - [`horizon`]: horizon angles marched on the height field, the exact visible fraction
//!   V_A(v) and joint V_A(l, v) (Eq 23–26), Fournier's ramp, Tan et al.'s Gaussian HDF
//!   (erf), the uncorrelated product, Eq 28, Ashikhmin's β form, Nowrouzezahrai & Snyder's
//!   Legendre series (Eq 29–30).
//! - [`shadow`]: procedural occluder scenes seen by an orthographic light, percentage-closer
//!   filtering (Eq 31–33), VSM, convolution shadow maps, ESM and EVSM, and their storage
//!   precision.
//! - [`procedural`]: global fading, analytic integration (Fig. 6's pulse train), frequency
//!   clamping, and the procedural normal map of §6.2.
//! - [`correlation`]: what Hypothesis 1's separation costs where colour follows slope and
//!   visibility follows the normal (§8.1).

pub mod correlation;
pub mod horizon;
pub mod procedural;
pub mod shadow;

use crate::error::{Error, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;
use std::path::Path;

/// Largest side of a height field read from a file.
pub const MAX_SIDE: usize = 4096;

/// A periodic height field, heights in texel units, row-major.
#[derive(Clone, Debug)]
pub struct HeightField {
    pub name: String,
    pub size: usize,
    pub h: Vec<f64>,
}

/// The procedural height fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Relief {
    /// 48 periodic cosine waves (wavelengths 4–32 texels), slope rms 0.5.
    Noise,
    /// Spherical caps of radius 3–6 texels on a flat plane, one per jittered 12×12 cell:
    /// flat ground, steep rims.
    Bumps,
}

impl HeightField {
    pub fn procedural(kind: Relief, size: usize, seed: u64) -> Result<HeightField> {
        if !(16..=MAX_SIDE).contains(&size) || !size.is_power_of_two() {
            return Err(Error::InvalidArgument(format!(
                "height-field size {size} must be a power of two in 16..={MAX_SIDE}"
            )));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let n = size as f64;
        let h = match kind {
            Relief::Noise => {
                let waves: Vec<(f64, f64, f64)> = (0..48)
                    .map(|_| {
                        let lambda = 4.0 * 8f64.powf(rng.random::<f64>());
                        let dir = rng.random::<f64>() * 2.0 * PI;
                        let k = (n / lambda).round().max(1.0);
                        (
                            (k * dir.cos()).round(),
                            (k * dir.sin()).round(),
                            rng.random::<f64>() * 2.0 * PI,
                        )
                    })
                    .collect();
                let raw: Vec<f64> = (0..size * size)
                    .map(|i| {
                        let (x, y) = ((i % size) as f64, (i / size) as f64);
                        waves
                            .iter()
                            .map(|(kx, ky, p)| {
                                let kk = (kx * kx + ky * ky).sqrt().max(1.0);
                                (2.0 * PI * (kx * x + ky * y) / n + p).cos() / kk
                            })
                            .sum()
                    })
                    .collect();
                let hf = HeightField {
                    name: "noise".into(),
                    size,
                    h: raw,
                };
                let s = hf.slope_rms();
                let k = 0.5 / s.max(1e-12);
                hf.h.iter().map(|v| v * k).collect()
            }
            Relief::Bumps => {
                let cell = 12.0;
                let cells = (n / cell).floor().max(1.0) as usize;
                let cs = n / cells as f64;
                let caps: Vec<(f64, f64, f64)> = (0..cells * cells)
                    .map(|c| {
                        let (cx, cy) = ((c % cells) as f64, (c / cells) as f64);
                        let r = 3.0 + 3.0 * rng.random::<f64>();
                        let m = (cs - 2.0 * r).max(0.0);
                        (
                            cx * cs + r + m * rng.random::<f64>(),
                            cy * cs + r + m * rng.random::<f64>(),
                            r,
                        )
                    })
                    .collect();
                (0..size * size)
                    .map(|i| {
                        let (x, y) = ((i % size) as f64, (i / size) as f64);
                        caps.iter()
                            .map(|&(px, py, r)| {
                                let d2 = (x - px).powi(2) + (y - py).powi(2);
                                (r * r - d2).max(0.0).sqrt()
                            })
                            .fold(0.0, f64::max)
                    })
                    .collect()
            }
        };
        Ok(HeightField {
            name: match kind {
                Relief::Noise => "noise".into(),
                Relief::Bumps => "bumps".into(),
            },
            size,
            h,
        })
    }

    /// A grey (or first-channel) 8/16-bit PNG, heights = value × `scale` texels; square,
    /// power-of-two sides ≤ [`MAX_SIDE`].
    pub fn from_png(path: &Path, scale: f64) -> Result<HeightField> {
        Self::read_png(path, scale).map(|(hf, _)| hf)
    }

    /// [`HeightField::from_png`], with a note when the PNG had colour channels (it is
    /// converted to grey by its luma, Rec. 709 weights, which a caller should say).
    pub fn read_png(path: &Path, scale: f64) -> Result<(HeightField, Option<String>)> {
        if !(scale.is_finite() && scale > 0.0 && scale <= 1e6) {
            return Err(Error::InvalidArgument(format!(
                "height scale {scale} must be finite and in (0, 1e6]"
            )));
        }
        let img = crate::filters::footprint::open_image(path, "height map")?;
        let note = img.color().has_color().then(|| {
            format!(
                "height map {} has colour channels ({:?}); converted to grey by its luma (Rec. 709 weights)",
                crate::error::quoted(&path.display().to_string()),
                img.color()
            )
        });
        let img = img.to_luma32f();
        let (w, h) = (img.width() as usize, img.height() as usize);
        if w != h || w < 16 || !w.is_power_of_two() || w > MAX_SIDE {
            return Err(Error::InvalidArgument(format!(
                "height map {} is {w}×{h}; it must be square with a power-of-two side in 16..={MAX_SIDE}",
                path.display()
            )));
        }
        let hf = HeightField {
            name: path
                .file_stem()
                .map_or("height".into(), |s| s.to_string_lossy().into()),
            size: w,
            h: img.pixels().map(|p| p[0] as f64 * scale).collect(),
        };
        Ok((hf, note))
    }

    fn at(&self, i: i64, j: i64) -> f64 {
        let n = self.size as i64;
        self.h[(j.rem_euclid(n) * n + i.rem_euclid(n)) as usize]
    }

    /// Bilinear height at (x, y) in texel units (texel centres at integers), periodic.
    pub fn sample(&self, x: f64, y: f64) -> f64 {
        let (fx, fy) = (x.floor(), y.floor());
        let (tx, ty) = (x - fx, y - fy);
        let (i, j) = (fx as i64, fy as i64);
        let a = self.at(i, j) * (1.0 - tx) + self.at(i + 1, j) * tx;
        let b = self.at(i, j + 1) * (1.0 - tx) + self.at(i + 1, j + 1) * tx;
        a * (1.0 - ty) + b * ty
    }

    /// Central-difference gradient at texel (i, j).
    pub fn gradient(&self, i: usize, j: usize) -> (f64, f64) {
        let (i, j) = (i as i64, j as i64);
        (
            0.5 * (self.at(i + 1, j) - self.at(i - 1, j)),
            0.5 * (self.at(i, j + 1) - self.at(i, j - 1)),
        )
    }

    /// Root-mean-square slope magnitude.
    pub fn slope_rms(&self) -> f64 {
        let n = self.size;
        let s: f64 = (0..n * n)
            .map(|k| {
                let (gx, gy) = self.gradient(k % n, k / n);
                gx * gx + gy * gy
            })
            .sum();
        (s / (n * n) as f64).sqrt()
    }

    /// The unit normal at texel (i, j) (tangent space, +z up).
    pub fn normal(&self, i: usize, j: usize) -> nalgebra::Vector3<f64> {
        let (gx, gy) = self.gradient(i, j);
        nalgebra::Vector3::new(-gx, -gy, 1.0).normalize()
    }

    /// The texels of the 2^level block (bx, by), as (i, j).
    pub fn block(&self, level: usize, bx: usize, by: usize) -> Vec<(usize, usize)> {
        let b = 1usize << level;
        (by * b..(by + 1) * b)
            .flat_map(|j| (bx * b..(bx + 1) * b).map(move |i| (i % self.size, j % self.size)))
            .collect()
    }
}

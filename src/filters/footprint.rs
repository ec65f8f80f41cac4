//! Footprint statistics of a normal map: procedural maps, PNG input, and a
//! linear mip chain of the unnormalised mean normal and the LEAN/LEADR slope moments
//! (E[x̃], E[ỹ], E[x̃²], E[ỹ²], E[x̃ỹ]) — seed 004 §3.2.1 (Olano–Baker / LEAN, Eq 19),
//! seed 001 §1.
//!
//! Conventions: tangent space with the geometric normal +z; a texel's unit normal n has
//! slope x̃ = (−n_x/n_z, −n_y/n_z) (seed 001 Eq 1). Level L of the chain is the box
//! average of the 2^L × 2^L block of base texels (exact, computed by repeated 2×2
//! averaging; nothing is renormalised). Maps are periodic (procedural ones by
//! construction), so every block is a whole footprint.

use crate::error::{Error, Result};
use nalgebra::{Vector2, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use std::f64::consts::PI;
use std::path::Path;

/// A square-or-rectangular map of unit normals (tangent space), row-major.
#[derive(Clone, Debug)]
pub struct NormalMap {
    pub name: String,
    pub width: usize,
    pub height: usize,
    pub normals: Vec<Vector3<f64>>,
}

/// The procedural generators.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Procedural {
    /// Sum of random cosine waves, isotropic spectrum (slope rms ≈ 0.25).
    IsotropicNoise,
    /// Waves whose wave vectors lie near the y axis: scratches along x (slope rms ≈ 0.25,
    /// almost all of it in ỹ).
    BrushedMetal,
    /// Jittered Voronoi cells, each with one constant normal tilted up to 25°.
    Flakes,
    /// Spherical-cap bumps on a flat plane: slopes jump from 0 to 1 at every rim.
    SharpBumps,
    /// Random straight scratches (V-grooves, slopes ±0.6 across each scratch) on a flat
    /// plane (seed 002's "scratches"; not in [`Procedural::ALL`], used by the tensor study).
    Scratches,
}

impl Procedural {
    pub const ALL: [Procedural; 4] = [
        Procedural::IsotropicNoise,
        Procedural::BrushedMetal,
        Procedural::Flakes,
        Procedural::SharpBumps,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Procedural::IsotropicNoise => "isotropic-noise",
            Procedural::BrushedMetal => "brushed-metal",
            Procedural::Flakes => "flakes",
            Procedural::SharpBumps => "sharp-bumps",
            Procedural::Scratches => "scratches",
        }
    }
}

fn normal_from_slope(sx: f64, sy: f64) -> Vector3<f64> {
    Vector3::new(-sx, -sy, 1.0).normalize()
}

/// Height field as a sum of periodic cosine waves; returns the normal map of its gradient.
fn waves(
    size: usize,
    seed: u64,
    pick: &dyn Fn(&mut ChaCha8Rng) -> (f64, f64),
    rms: f64,
) -> Vec<Vector3<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let waves: Vec<(f64, f64, f64)> = (0..64)
        .map(|_| {
            let (kx, ky) = pick(&mut rng);
            (kx.round(), ky.round(), rng.random::<f64>() * 2.0 * PI)
        })
        .collect();
    // gradient of Σ a cos(2π(k·x)/size + φ) with a = 1/|k|: slope = −a 2π k/size sin(·)
    let grad = |x: f64, y: f64| {
        let (mut gx, mut gy) = (0.0, 0.0);
        for &(kx, ky, ph) in &waves {
            let kk = (kx * kx + ky * ky).sqrt().max(1.0);
            let s = (2.0 * PI * (kx * x + ky * y) / size as f64 + ph).sin();
            gx -= 2.0 * PI * kx / size as f64 / kk * s;
            gy -= 2.0 * PI * ky / size as f64 / kk * s;
        }
        (gx, gy)
    };
    let g: Vec<(f64, f64)> = (0..size * size)
        .map(|i| grad((i % size) as f64 + 0.5, (i / size) as f64 + 0.5))
        .collect();
    let ms = g.iter().map(|(a, b)| a * a + b * b).sum::<f64>() / g.len() as f64;
    let k = rms / ms.sqrt();
    g.iter()
        .map(|&(a, b)| normal_from_slope(k * a, k * b))
        .collect()
}

/// Jittered Voronoi flakes: one site per cell of 8×8 texels, each with a normal tilted
/// up to 25°; a texel takes its nearest site's normal (periodic distance, the first site
/// in index order on a tie). `full_scan` searches every site (O(texels × sites), the
/// reference); otherwise the 5×5 cells around the texel's, which hold the nearest site (a
/// site lies within √2 cells of its own cell's corner, any site three cells away is ≥ 2
/// cells off) and are visited in index order — the same result in O(texels).
pub fn flakes(size: usize, seed: u64, full_scan: bool) -> Vec<Vector3<f64>> {
    let s = size as f64;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let cells = (size / 8).max(1);
    let cs = s / cells as f64;
    let pts: Vec<(f64, f64, Vector3<f64>)> = (0..cells * cells)
        .map(|c| {
            let (cx, cy) = ((c % cells) as f64, (c / cells) as f64);
            let px = (cx + rng.random::<f64>()) * cs;
            let py = (cy + rng.random::<f64>()) * cs;
            let th = (25f64).to_radians() * rng.random::<f64>().sqrt();
            let ph = rng.random::<f64>() * 2.0 * PI;
            let n = Vector3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
            (px, py, n)
        })
        .collect();
    let near = |x: f64, y: f64| -> Vec<usize> {
        if full_scan {
            return (0..pts.len()).collect();
        }
        let (ci, cj) = ((x / cs) as i64, (y / cs) as i64);
        let n = cells as i64;
        let mut v: Vec<usize> = (-2..=2)
            .flat_map(|dj: i64| {
                (-2..=2).map(move |di: i64| {
                    ((cj + dj).rem_euclid(n) * n + (ci + di).rem_euclid(n)) as usize
                })
            })
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    (0..size * size)
        .map(|i| {
            let (x, y) = ((i % size) as f64 + 0.5, (i / size) as f64 + 0.5);
            let mut best = (f64::INFINITY, Vector3::z());
            for &(px, py, n) in near(x, y).iter().map(|&c| &pts[c]) {
                // periodic distance
                let dx = (x - px).abs().min(s - (x - px).abs());
                let dy = (y - py).abs().min(s - (y - py).abs());
                let d = dx * dx + dy * dy;
                if d < best.0 {
                    best = (d, n);
                }
            }
            best.1
        })
        .collect()
}

/// Largest side of a normal-map PNG that is read (8K).
pub const MAX_MAP_SIDE: usize = 8192;
/// A decoded texel is a unit normal when its length is within this of 1: 8-bit storage
/// rounds each component by at most 1/255, i.e. the length by at most √3/255 ≈ 0.007, and
/// tools that store unnormalised mips stay within a few per cent; a grey image decodes to
/// length ≈ 0.
pub const UNIT_TOLERANCE: f64 = 0.05;
/// At most this fraction of texels may be off unit length (isolated bad texels happen in
/// real maps; a map that is not a normal map fails almost everywhere).
pub const MAX_OFF_UNIT_FRACTION: f64 = 0.01;

impl NormalMap {
    /// The flat map of size × size texels: every normal +z.
    pub fn flat(size: usize) -> NormalMap {
        NormalMap {
            name: "flat".into(),
            width: size,
            height: size,
            normals: vec![Vector3::z(); size * size],
        }
    }

    /// A procedural map of size × size texels (size a power of two ≥ 2).
    pub fn procedural(kind: Procedural, size: usize, seed: u64) -> Result<NormalMap> {
        if size < 2 || !size.is_power_of_two() {
            return Err(Error::InvalidArgument(format!(
                "procedural map size must be a power of two ≥ 2, got {size}"
            )));
        }
        let s = size as f64;
        let normals = match kind {
            Procedural::IsotropicNoise => waves(
                size,
                seed,
                &|r| {
                    let k = 2.0 + r.random::<f64>() * (s / 8.0 - 2.0).max(1.0);
                    let t = r.random::<f64>() * 2.0 * PI;
                    (k * t.cos(), k * t.sin())
                },
                0.25,
            ),
            Procedural::BrushedMetal => waves(
                size,
                seed,
                &|r| {
                    let ky = 4.0 + r.random::<f64>() * (s / 4.0 - 4.0).max(1.0);
                    let kx = (r.random::<f64>() - 0.5) * 3.0;
                    (kx, ky)
                },
                0.25,
            ),
            Procedural::Flakes => flakes(size, seed, false),
            Procedural::Scratches => {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                let lines: Vec<(f64, f64, f64)> = (0..(size / 4).max(2))
                    .map(|_| {
                        (
                            rng.random::<f64>() * s,
                            rng.random::<f64>() * s,
                            rng.random::<f64>() * PI,
                        )
                    })
                    .collect();
                (0..size * size)
                    .map(|i| {
                        let (x, y) = ((i % size) as f64 + 0.5, (i / size) as f64 + 0.5);
                        let mut n = Vector3::z();
                        for &(px, py, a) in &lines {
                            // signed periodic distance to the line through (px, py) at angle a
                            let (c, sn) = (a.cos(), a.sin());
                            let mut dx = x - px;
                            let mut dy = y - py;
                            dx -= s * (dx / s).round();
                            dy -= s * (dy / s).round();
                            let d = -sn * dx + c * dy;
                            if d.abs() < 0.75 {
                                let g = 0.6 * d.signum();
                                n = normal_from_slope(-sn * g, c * g);
                            }
                        }
                        n
                    })
                    .collect()
            }
            Procedural::SharpBumps => {
                let cells = (size / 16).max(1);
                let cs = s / cells as f64;
                let r = 0.4 * cs;
                // spherical cap whose rim slope is 1 (45°): sphere radius R = r√2
                let big = r * 2f64.sqrt();
                (0..size * size)
                    .map(|i| {
                        let (x, y) = ((i % size) as f64 + 0.5, (i / size) as f64 + 0.5);
                        let dx = x.rem_euclid(cs) - cs / 2.0;
                        let dy = y.rem_euclid(cs) - cs / 2.0;
                        if dx * dx + dy * dy < r * r {
                            let z = (big * big - dx * dx - dy * dy).sqrt();
                            Vector3::new(dx, dy, z).normalize()
                        } else {
                            Vector3::z()
                        }
                    })
                    .collect()
            }
        };
        Ok(NormalMap {
            name: kind.name().into(),
            width: size,
            height: size,
            normals,
        })
    }

    /// Read an RGB(A) tangent-space normal map (8 or 16 bit PNG; n = 2c − 1, then
    /// normalised). Errors (typed, no panic): unreadable or broken file, a texel whose
    /// decoded normal is zero or points below the surface (n_z ≤ 0), or a size that is
    /// not a power of two (the mip chain needs whole 2×2 blocks).
    pub fn from_png(path: &Path) -> Result<NormalMap> {
        let rgb = open_image(path, "normal map")?.to_rgb32f();
        let (w, h) = (rgb.width() as usize, rgb.height() as usize);
        if w < 2 || h < 2 || !w.is_power_of_two() || !h.is_power_of_two() {
            return Err(Error::InvalidArgument(format!(
                "normal map {} is {w}×{h}; width and height must be powers of two ≥ 2",
                path.display()
            )));
        }
        let mut normals = Vec::with_capacity(w * h);
        let mut off_unit = 0usize;
        for (i, p) in rgb.pixels().enumerate() {
            let v = Vector3::new(
                2.0 * p[0] as f64 - 1.0,
                2.0 * p[1] as f64 - 1.0,
                2.0 * p[2] as f64 - 1.0,
            );
            let n = v.norm();
            if !(n > 1e-6) || v.z <= 0.0 {
                return Err(Error::InvalidArgument(format!(
                    "normal map {}: texel ({}, {}) decodes to ({:.3}, {:.3}, {:.3}), not an upper-hemisphere normal",
                    path.display(),
                    i % w,
                    i / w,
                    v.x,
                    v.y,
                    v.z
                )));
            }
            if (n - 1.0).abs() > UNIT_TOLERANCE {
                off_unit += 1;
            }
            normals.push(v / n);
        }
        let frac = off_unit as f64 / (w * h) as f64;
        if frac > MAX_OFF_UNIT_FRACTION {
            return Err(Error::InvalidArgument(format!(
                "{} is not a normal map: {:.1} % of its texels decode to vectors whose length is off 1 by more than {UNIT_TOLERANCE} (at most {:.0} % may be)",
                path.display(),
                100.0 * frac,
                100.0 * MAX_OFF_UNIT_FRACTION
            )));
        }
        Ok(NormalMap {
            name: path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "map".into()),
            width: w,
            height: h,
            normals,
        })
    }

    /// The map as 8-bit RGB PNG bytes (used by tests and examples).
    pub fn png(&self) -> Result<Vec<u8>> {
        let mut img = image::RgbImage::new(self.width as u32, self.height as u32);
        for (i, n) in self.normals.iter().enumerate() {
            let c = |x: f64| ((x * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8;
            img.put_pixel(
                (i % self.width) as u32,
                (i / self.width) as u32,
                image::Rgb([c(n.x), c(n.y), c(n.z)]),
            );
        }
        let mut bytes = Vec::new();
        img.write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(|e| Error::InvalidArgument(format!("PNG encoding: {e}")))?;
        Ok(bytes)
    }

    /// The base normals of the 2^level × 2^level block at texel (i, j) of `level`.
    pub fn block(&self, level: usize, i: usize, j: usize) -> Vec<Vector3<f64>> {
        let b = 1usize << level;
        let mut out = Vec::with_capacity(b * b);
        for y in j * b..(j + 1) * b {
            for x in i * b..(i + 1) * b {
                out.push(self.normals[y * self.width + x]);
            }
        }
        out
    }
}

/// Linearly filterable statistics of one footprint.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stats {
    /// Unnormalised mean normal μ (|μ| ≤ 1; Toksvig, vMF, seed 000 ‖b̄‖).
    pub mean_normal: [f64; 3],
    /// E[x̃], E[ỹ].
    pub m1: [f64; 2],
    /// E[x̃²], E[ỹ²], E[x̃ỹ].
    pub m2: [f64; 3],
}

impl Stats {
    pub fn of_normal(n: &Vector3<f64>) -> Stats {
        let (sx, sy) = (-n.x / n.z, -n.y / n.z);
        Stats {
            mean_normal: [n.x, n.y, n.z],
            m1: [sx, sy],
            m2: [sx * sx, sy * sy, sx * sy],
        }
    }
    fn average(s: [&Stats; 4]) -> Stats {
        let mut o = Stats {
            mean_normal: [0.0; 3],
            m1: [0.0; 2],
            m2: [0.0; 3],
        };
        for t in s {
            for k in 0..3 {
                o.mean_normal[k] += 0.25 * t.mean_normal[k];
                o.m2[k] += 0.25 * t.m2[k];
            }
            for k in 0..2 {
                o.m1[k] += 0.25 * t.m1[k];
            }
        }
        o
    }
    /// |μ|.
    pub fn mrl(&self) -> f64 {
        Vector3::from(self.mean_normal).norm()
    }
    /// Mean slope (E[x̃], E[ỹ]).
    pub fn mean_slope(&self) -> Vector2<f64> {
        Vector2::from(self.m1)
    }
    /// Slope covariance (xx, yy, xy) = E[x̃x̃ᵀ] − E[x̃]E[x̃]ᵀ, clamped to be PSD.
    pub fn covariance(&self) -> [f64; 3] {
        let xx = (self.m2[0] - self.m1[0] * self.m1[0]).max(0.0);
        let yy = (self.m2[1] - self.m1[1] * self.m1[1]).max(0.0);
        let xy = self.m2[2] - self.m1[0] * self.m1[1];
        let lim = (xx * yy).sqrt();
        [xx, yy, xy.clamp(-lim, lim)]
    }
}

/// One level of the chain.
#[derive(Clone, Debug)]
pub struct Level {
    pub width: usize,
    pub height: usize,
    pub stats: Vec<Stats>,
}

/// The full chain down to 1 texel on the short side.
#[derive(Clone, Debug)]
pub struct MipChain {
    pub levels: Vec<Level>,
}

impl MipChain {
    pub fn build(map: &NormalMap) -> MipChain {
        let mut levels = vec![Level {
            width: map.width,
            height: map.height,
            stats: map.normals.iter().map(Stats::of_normal).collect(),
        }];
        loop {
            let prev = levels.last().expect("level 0 exists");
            if prev.width < 2 || prev.height < 2 {
                break;
            }
            let (w, h) = (prev.width / 2, prev.height / 2);
            let at = |x: usize, y: usize| &prev.stats[y * prev.width + x];
            let stats = (0..w * h)
                .map(|k| {
                    let (i, j) = (k % w, k / w);
                    Stats::average([
                        at(2 * i, 2 * j),
                        at(2 * i + 1, 2 * j),
                        at(2 * i, 2 * j + 1),
                        at(2 * i + 1, 2 * j + 1),
                    ])
                })
                .collect();
            levels.push(Level {
                width: w,
                height: h,
                stats,
            });
        }
        MipChain { levels }
    }
}

/// Decode an image file whose sizes are bounded before anything is decoded (≤
/// MAX_MAP_SIDE per side, ≤ 3 GiB of allocation); a missing, unreadable or broken file is
/// a typed error naming it and `what` it was meant to be.
pub fn open_image(path: &Path, what: &str) -> Result<image::DynamicImage> {
    let bad = |e: String| Error::Io {
        path: path.display().to_string(),
        msg: format!("cannot read the {what}: {e}"),
    };
    let mut reader = image::ImageReader::open(path)
        .map_err(|e| bad(e.to_string()))?
        .with_guessed_format()
        .map_err(|e| bad(e.to_string()))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_MAP_SIDE as u32);
    limits.max_image_height = Some(MAX_MAP_SIDE as u32);
    limits.max_alloc = Some(3 << 30);
    reader.limits(limits);
    reader.decode().map_err(|e| bad(e.to_string()))
}

//! Seed 002's glints as a renderer shades them. A small quad light seen from a pixel
//! covers a small region R of half-vector projections h_xy; with G = F = 1 the pixel's
//! radiance is L_e·Ω/(4 v_z) times the mean of the footprint's P-NDF over R (the
//! Jacobian dω_l = 4(v·h)dω_h, dA_h = h_z dω_h, taken at R's centre). R is the axis-aligned
//! box centred at the light centre's h_xy with the corners' aspect and the exact area
//! Ω·h_z/(4 v·h). Three ways to get the mean over R:
//! - brute force (seed 002 Eq 2): the footprint's texels, Gaussian-weighted with the
//!   pixel's own footprint covariance (J Jᵀ/12, the box pixel's), each contributing the
//!   exact integral of its Gaussian over R (erf);
//! - the CP range query (seed 002 Eq 6–7): P-NDF images precomputed on a footprint grid,
//!   cut into t×t blocks, clustered by quarter-map region, CP-compressed; the nearest
//!   grid footprint's bins whose centres fall in R, summed by O(R) queries in f32;
//! - a plain mip: the renormalised mip normal's single Gaussian.

use super::geometry::{footprint, Camera};
use super::light::Light;
use super::methods::GPixel;
use super::texture::Texture;
use crate::error::{Error, Result};
use crate::tensor::cp::{cp_als, AlsOptions, Cp, Tensor3};
use crate::tensor::pndf::pndf_image_splat;
use crate::tensor::query::{range_f32, Sat};
use nalgebra::{Matrix2, Vector2, Vector3};
use rayon::prelude::*;

type V3 = Vector3<f64>;

/// The half-vector region of the (first) quad light at a pixel: box [lo, hi] in h_xy and
/// the factor L_e·Ω/(4 v_z).
#[derive(Clone, Copy, Debug)]
pub struct Region {
    pub lo: [f64; 2],
    pub hi: [f64; 2],
    pub scale: f64,
}

impl Region {
    fn area(&self) -> f64 {
        (self.hi[0] - self.lo[0]) * (self.hi[1] - self.lo[1])
    }
}

/// R for the pixel's centre.
pub fn region(gp: &GPixel, lights: &[Light]) -> Option<Region> {
    let light = lights.iter().find(|l| matches!(l, Light::Quad { .. }))?;
    let Light::Quad {
        center,
        normal,
        area,
        radiance,
        ..
    } = light
    else {
        return None;
    };
    let fr = &gp.hit.frame;
    let v = fr.local(&gp.view);
    if v.z <= 0.0 {
        return None;
    }
    let hxy = |q: &V3| -> Option<(V3, V3)> {
        let l = fr.local(&(q - gp.hit.p).normalize());
        (l.z > 0.0).then(|| (l, (v + l).normalize()))
    };
    let (_, h0) = hxy(center)?;
    let d = center - gp.hit.p;
    let omega = area * (d.normalize().dot(normal)).abs() / d.norm_squared();
    let (mut bx, mut by) = (
        (f64::INFINITY, f64::NEG_INFINITY),
        (f64::INFINITY, f64::NEG_INFINITY),
    );
    for c in light.corners()? {
        let (_, h) = hxy(&c)?;
        bx = (bx.0.min(h.x), bx.1.max(h.x));
        by = (by.0.min(h.y), by.1.max(h.y));
    }
    let a_h = omega * h0.z / (4.0 * v.dot(&h0));
    let aspect = ((bx.1 - bx.0) / (by.1 - by.0).max(1e-12)).clamp(1e-3, 1e3);
    let wx = (a_h * aspect).sqrt();
    let wy = a_h / wx;
    Some(Region {
        lo: [h0.x - 0.5 * wx, h0.y - 0.5 * wy],
        hi: [h0.x + 0.5 * wx, h0.y + 0.5 * wy],
        scale: radiance * omega / (4.0 * v.z),
    })
}

/// ∫_R of the unit Gaussian of standard deviation σ around n_xy.
fn box_gauss(r: &Region, n: &V3, sigma: f64) -> f64 {
    let k = 1.0 / (sigma * std::f64::consts::SQRT_2);
    let ax = 0.5 * (libm::erf((r.hi[0] - n.x) * k) - libm::erf((r.lo[0] - n.x) * k));
    let ay = 0.5 * (libm::erf((r.hi[1] - n.y) * k) - libm::erf((r.lo[1] - n.y) * k));
    ax * ay
}

/// The plain mip: one Gaussian at the renormalised filtered normal.
pub fn mip(gp: &GPixel, lights: &[Light], sigma_r: f64) -> f32 {
    match region(gp, lights) {
        Some(r) => (r.scale * box_gauss(&r, &gp.n_t, sigma_r) / r.area()) as f32,
        None => 0.0,
    }
}

/// Brute force over the footprint's texels (seed 002 Eq 2 restricted to R).
pub fn brute(
    cam: &Camera,
    gp: &GPixel,
    tex: &Texture,
    lights: &[Light],
    sigma_r: f64,
    x: f64,
    y: f64,
) -> f32 {
    let Some(r) = region(gp, lights) else {
        return 0.0;
    };
    let fp = footprint(cam, &gp.hit, x, y);
    let (w, h) = (tex.map.width as f64, tex.map.height as f64);
    let j = Matrix2::new(fp[0][0] * w, fp[1][0] * w, fp[0][1] * h, fp[1][1] * h);
    let cov = j * j.transpose() / 12.0 + Matrix2::identity() / 12.0;
    let Some(inv) = cov.try_inverse() else {
        return 0.0;
    };
    let reach = (3.0 * cov[(0, 0)].max(cov[(1, 1)]).sqrt())
        .ceil()
        .min(256.0) as i64;
    let c = tex.texel_coords(gp.hit.uv);
    let (ci, cj) = (c[0].floor() as i64, c[1].floor() as i64);
    let (mut sw, mut s) = (0.0, 0.0);
    for dj in -reach..=reach {
        for di in -reach..=reach {
            let d = Vector2::new((ci + di) as f64 + 0.5 - c[0], (cj + dj) as f64 + 0.5 - c[1]);
            let e = 0.5 * (d.transpose() * inv * d)[0];
            if e > 4.5 {
                continue;
            }
            let wgt = (-e).exp();
            sw += wgt;
            s += wgt * box_gauss(&r, &tex.at(ci + di, cj + dj), sigma_r);
        }
    }
    if !(sw > 0.0) {
        return 0.0;
    }
    (r.scale * s / sw / r.area()) as f32
}

/// P-NDF images on a footprint grid, CP-compressed per quarter-map cluster.
pub struct CpGlints {
    pub res: usize,
    pub stride: usize,
    pub t: usize,
    grid: usize,
    clusters: Vec<(Cp, Sat)>,
    /// (footprint, block) → (cluster, slice), None for an all-zero block.
    index: Vec<Option<(u32, u32)>>,
    pub rank: usize,
    pub rel_error: f64,
    /// Numbers stored by the CP factors, and by the dense non-empty blocks.
    pub stored: usize,
    pub dense: usize,
}

/// Every footprint's P-NDF image on the grid (stride s, centres at s/2 + k s), σ_P given.
pub fn pndf_grid(
    tex: &Texture,
    res: usize,
    stride: usize,
    sigma_p: f64,
    sigma_r: f64,
) -> Result<Vec<Vec<f64>>> {
    let g = if stride > 0 {
        tex.map.width / stride
    } else {
        0
    };
    if g == 0 || res == 0 {
        return Err(Error::InvalidArgument(format!(
            "glints: a {}-texel map at footprint stride {stride} gives no footprint grid (or {res}² images)",
            tex.map.width
        )));
    }
    (0..g * g)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % g, k / g);
            let c = |i: usize| (i * stride + stride / 2) as f64;
            pndf_image_splat(&tex.map, c(i), c(j), sigma_p, sigma_r, res)
        })
        .collect()
}

impl CpGlints {
    /// Compress the grid's images at `rank` (plain CP-ALS, the paper's choice).
    pub fn build(
        images: &[Vec<f64>],
        res: usize,
        stride: usize,
        t: usize,
        rank: usize,
        iters: usize,
        seed: u64,
    ) -> Result<CpGlints> {
        let g = (images.len() as f64).sqrt().round() as usize;
        if g == 0 || g * g != images.len() || t == 0 || res % t != 0 || res < t || rank == 0 {
            return Err(Error::InvalidArgument(format!(
                "glints: {} images of {res}² in {t}² blocks at rank {rank} make no square footprint grid of whole blocks",
                images.len()
            )));
        }
        if images.iter().any(|img| img.len() != res * res) {
            return Err(Error::InvalidArgument(format!(
                "glints: every image must hold {res}² values"
            )));
        }
        let nb = res / t;
        let region = g.div_ceil(2);
        let mut index = vec![None; images.len() * nb * nb];
        let mut tensors = Vec::new();
        for reg in 0..4 {
            let mut data = Vec::new();
            let mut l = 0u32;
            for (f, img) in images.iter().enumerate() {
                let (fi, fj) = (f % g, f / g);
                if (fj / region) * 2 + fi / region != reg {
                    continue;
                }
                for b in 0..nb * nb {
                    let (bx, by) = (b % nb, b / nb);
                    let block: Vec<f64> = (0..t * t)
                        .map(|q| img[(by * t + q / t) * res + bx * t + q % t])
                        .collect();
                    if block.iter().any(|v| *v > 0.0) {
                        data.extend(block);
                        index[f * nb * nb + b] = Some((tensors.len() as u32, l));
                        l += 1;
                    }
                }
            }
            if l > 0 {
                tensors.push(Tensor3::new([t, t, l as usize], data)?);
            }
        }
        let fits: Vec<Cp> = tensors
            .par_iter()
            .map(|tt| {
                cp_als(
                    tt,
                    &AlsOptions {
                        rank: rank.min(tt.shape[2] * t),
                        tol: 1e-4,
                        max_iters: iters,
                        restarts: 1,
                        seed,
                        nonnegative: false,
                    },
                )
            })
            .collect::<Result<_>>()?;
        let dense: usize = tensors.iter().map(|t| t.data.len()).sum();
        let num: f64 = tensors
            .iter()
            .zip(&fits)
            .map(|(t, c)| (c.rel_error * t.norm()).powi(2))
            .sum();
        let den: f64 = tensors.iter().map(|t| t.norm().powi(2)).sum();
        Ok(CpGlints {
            res,
            stride,
            t,
            grid: g,
            stored: fits.iter().map(|c| c.storage()).sum(),
            dense,
            rank,
            rel_error: (num / den.max(1e-300)).sqrt(),
            clusters: fits
                .into_iter()
                .map(|c| {
                    let s = Sat::build(&c);
                    (c, s)
                })
                .collect(),
            index,
        })
    }

    /// The grid footprint nearest texel coordinates `c` (the map wraps).
    pub fn footprint_at(&self, c: [f64; 2]) -> usize {
        let g = self.grid as i64;
        let near = |x: f64| ((x - (self.stride / 2) as f64) / self.stride as f64).round() as i64;
        (near(c[1]).rem_euclid(g) * g + near(c[0]).rem_euclid(g)) as usize
    }

    /// The mean of footprint `f`'s reconstructed image over the pixels [x0, x1] × [y0, y1]
    /// clipped to the image (0 where nothing remains), f32 range queries per block
    /// (seed 002 Eq 7).
    pub fn box_mean(&self, f: usize, x: (i64, i64), y: (i64, i64)) -> f32 {
        let n = self.res as i64;
        let (x0, x1, y0, y1) = (x.0.max(0), x.1.min(n - 1), y.0.max(0), y.1.min(n - 1));
        if x0 > x1 || y0 > y1 {
            return 0.0;
        }
        let t = self.t as i64;
        let nb = self.res / self.t;
        let mut sum = 0.0f32;
        for by in y0 / t..=y1 / t {
            for bx in x0 / t..=x1 / t {
                let Some((cl, z)) = self.index[f * nb * nb + (by * nb as i64 + bx) as usize] else {
                    continue;
                };
                let (lx, hx) = (
                    (x0 - bx * t).max(0) as usize,
                    (x1 - bx * t).min(t - 1) as usize,
                );
                let (ly, hy) = (
                    (y0 - by * t).max(0) as usize,
                    (y1 - by * t).min(t - 1) as usize,
                );
                let (cp, sat) = &self.clusters[cl as usize];
                let count = ((hx - lx + 1) * (hy - ly + 1)) as f32;
                sum += count * range_f32(cp, sat, (lx, hx), (ly, hy), z as usize);
            }
        }
        let nbins = ((x1 - x0 + 1) * (y1 - y0 + 1)) as f32;
        (sum / nbins).max(0.0)
    }

    /// The range query at a pixel: nearest grid footprint, bins with centres in R (the bin
    /// of R's centre when none), f32 queries.
    pub fn shade(&self, gp: &GPixel, tex: &Texture, lights: &[Light]) -> f32 {
        let Some(r) = region(gp, lights) else {
            return 0.0;
        };
        let f = self.footprint_at(tex.texel_coords(gp.hit.uv));
        let cell = 2.0 / self.res as f64;
        let n = self.res as i64;
        let bins = |lo: f64, hi: f64| -> (i64, i64) {
            let a = ((lo + 1.0) / cell - 0.5).ceil() as i64;
            let b = ((hi + 1.0) / cell - 0.5).floor() as i64;
            if a <= b {
                (a.max(0), b.min(n - 1))
            } else {
                let m = (((lo + hi) * 0.5 + 1.0) / cell).floor() as i64;
                (m.clamp(0, n - 1), m.clamp(0, n - 1))
            }
        };
        r.scale as f32 * self.box_mean(f, bins(r.lo[0], r.hi[0]), bins(r.lo[1], r.hi[1]))
    }
}

//! The glinty BRDF of seed 002 §5.1–5.2 beside a plain microfacet BRDF (Walter et al.
//! 2007), both in the plain f64 arithmetic a path tracer runs, so that their costs can be
//! set side by side as in the paper's Table 3.
//!
//! Both are f = F(i·h) · D(h) · G2(i, o) / (4 i_z o_z) with Schlick's Fresnel and the
//! height-correlated Smith G2 of GGX roughness α_G; they differ in D only.
//! - **Microfacet:** GGX D of roughness α, sampled by its visible normals (Heitz 2018,
//!   "Sampling the GGX distribution of visible normals"), weight F·G2/G1(i).
//! - **Ours (seed 002):** D(h) is the footprint's P-NDF image (Eq 2, per unit projected
//!   area, so that ∫ D(m) m_z dω = ∫ P dh_xy) read by a point query of its CP model (Eq 6)
//!   at the pixel holding h_xy. Sampling follows Fig 8: a block chosen by the CDF of the
//!   blocks' averages (one range query each, Eq 7), the hierarchical descent inside it
//!   (§5.2), the tent offset; the weight needs the sampled pixel's D, as the paper's
//!   "the PDF is set the same as NDF value" does.
//!
//! Sampling needs a reconstruction that is ≥ 0 everywhere (non-negative CP), else the
//! densities below are not the ones the samples follow.

use super::cluster::BlockStack;
use super::cp::{cp_als, AlsOptions, Cp};
use super::sample::{self, Block};
use crate::error::{Error, Result};
use std::f64::consts::PI;

pub type V3 = [f64; 3];

#[inline]
fn dot(a: &V3, b: &V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn normalize(v: V3) -> V3 {
    let l = dot(&v, &v).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

/// Schlick's Fresnel.
#[inline]
fn fresnel(f0: f64, c: f64) -> f64 {
    let m = (1.0 - c).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (1.0 - f0) * m2 * m2 * m
}

/// GGX Smith Λ of a unit direction with w_z > 0.
#[inline]
fn lambda_ggx(alpha: f64, w: &V3) -> f64 {
    let t2 = (w[0] * w[0] + w[1] * w[1]) / (w[2] * w[2]);
    0.5 * (-1.0 + (1.0 + alpha * alpha * t2).sqrt())
}

/// Height-correlated Smith G2 = 1/(1 + Λ(i) + Λ(o)).
#[inline]
fn g2(alpha: f64, i: &V3, o: &V3) -> f64 {
    1.0 / (1.0 + lambda_ggx(alpha, i) + lambda_ggx(alpha, o))
}

/// A sampled outgoing direction and its weight f·o_z/pdf.
#[derive(Clone, Copy, Debug)]
pub struct Sampled {
    pub o: V3,
    pub weight: f64,
}

/// The plain microfacet BRDF: GGX D, Smith G2, Schlick F (Walter et al. 2007).
#[derive(Clone, Copy, Debug)]
pub struct Microfacet {
    pub alpha: f64,
    pub f0: f64,
}

impl Microfacet {
    /// GGX D(h) for a unit h with h_z > 0.
    #[inline]
    pub fn d(&self, h: &V3) -> f64 {
        let a2 = self.alpha * self.alpha;
        let k = (h[0] * h[0] + h[1] * h[1]) / a2 + h[2] * h[2];
        1.0 / (PI * a2 * k * k)
    }

    /// f(i, o); 0 below the horizon.
    #[inline]
    pub fn eval(&self, i: &V3, o: &V3) -> f64 {
        if i[2] <= 0.0 || o[2] <= 0.0 {
            return 0.0;
        }
        let h = normalize([i[0] + o[0], i[1] + o[1], i[2] + o[2]]);
        fresnel(self.f0, dot(i, &h)) * self.d(&h) * g2(self.alpha, i, o) / (4.0 * i[2] * o[2])
    }

    /// The density of [`Microfacet::sample`] over o (solid angle): D_i(h)/(4 i·h) with
    /// D_i(h) = G1(i) max(0, i·h) D(h)/i_z, i.e. G1(i) D(h)/(4 i_z).
    pub fn pdf(&self, i: &V3, o: &V3) -> f64 {
        if i[2] <= 0.0 || o[2] <= 0.0 {
            return 0.0;
        }
        let h = normalize([i[0] + o[0], i[1] + o[1], i[2] + o[2]]);
        let g1 = 1.0 / (1.0 + lambda_ggx(self.alpha, i));
        g1 * self.d(&h) / (4.0 * i[2])
    }

    /// Visible-normal sampling (Heitz 2018, listing of §3); `None` when the reflected
    /// direction falls below the horizon (weight 0).
    #[inline]
    pub fn sample(&self, i: &V3, u: [f64; 2]) -> Option<Sampled> {
        let a = self.alpha;
        let vh = normalize([a * i[0], a * i[1], i[2]]);
        let lensq = vh[0] * vh[0] + vh[1] * vh[1];
        let t1 = if lensq > 0.0 {
            let l = lensq.sqrt();
            [-vh[1] / l, vh[0] / l, 0.0]
        } else {
            [1.0, 0.0, 0.0]
        };
        let t2 = [
            vh[1] * t1[2] - vh[2] * t1[1],
            vh[2] * t1[0] - vh[0] * t1[2],
            vh[0] * t1[1] - vh[1] * t1[0],
        ];
        let r = u[0].sqrt();
        let phi = 2.0 * PI * u[1];
        let p1 = r * phi.cos();
        let s = 0.5 * (1.0 + vh[2]);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).sqrt() + s * r * phi.sin();
        let pz = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
        let nh = [
            p1 * t1[0] + p2 * t2[0] + pz * vh[0],
            p1 * t1[1] + p2 * t2[1] + pz * vh[1],
            p1 * t1[2] + p2 * t2[2] + pz * vh[2],
        ];
        let h = normalize([a * nh[0], a * nh[1], nh[2].max(0.0)]);
        let c = dot(i, &h);
        let o = [
            2.0 * c * h[0] - i[0],
            2.0 * c * h[1] - i[1],
            2.0 * c * h[2] - i[2],
        ];
        if o[2] <= 0.0 {
            return None;
        }
        let li = lambda_ggx(a, i);
        let g2 = 1.0 / (1.0 + li + lambda_ggx(a, &o));
        Some(Sampled {
            o,
            weight: fresnel(self.f0, c) * g2 * (1.0 + li),
        })
    }
}

/// The P-NDF images of several footprints, cut into blocks and CP-compressed together
/// (seed 002 §4.2), with the SATs of its factors (Eq 7).
#[derive(Clone, Debug)]
pub struct CompressedNdf {
    res: usize,
    t: usize,
    /// log2 t (t is a power of two) and res/t: a pixel's block by shifts, not divisions.
    shift: u32,
    nb: usize,
    cp: Cp,
    rows: Rows,
    slots: Vec<Vec<Option<usize>>>,
}

/// The CP's factors in the layout a renderer reads them: each index's R values
/// contiguous (`x[i·R + r]`, the weights folded into the third mode), and the 1D SATs of
/// the first two modes the same way, so that a point or range query is one pass over R.
#[derive(Clone, Debug)]
struct Rows {
    t: usize,
    rank: usize,
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    sx: Vec<f64>,
    sy: Vec<f64>,
    /// Per component, the sums of its first two factors over the whole block: a block's
    /// total is then Σ_r whole[r]·z[k·R + r].
    whole: Vec<f64>,
}

impl Rows {
    fn new(cp: &Cp) -> Rows {
        let r = cp.rank;
        let rows = |m: usize, w: bool| -> Vec<f64> {
            let n = cp.shape[m];
            let mut v = vec![0.0; n * r];
            for q in 0..r {
                let c = if w { cp.weights[q] } else { 1.0 };
                for (i, f) in cp.factor(m, q).iter().enumerate() {
                    v[i * r + q] = c * f;
                }
            }
            v
        };
        let sums = |m: usize| -> Vec<f64> {
            let n = cp.shape[m];
            let mut v = vec![0.0; (n + 1) * r];
            for q in 0..r {
                for (i, f) in cp.factor(m, q).iter().enumerate() {
                    v[(i + 1) * r + q] = v[i * r + q] + f;
                }
            }
            v
        };
        let (sx, sy) = (sums(0), sums(1));
        let t = cp.shape[0];
        let whole = (0..r)
            .map(|q| (sx[t * r + q] - sx[q]) * (sy[t * r + q] - sy[q]))
            .collect();
        Rows {
            t,
            rank: r,
            whole,
            x: rows(0, false),
            y: rows(1, false),
            z: rows(2, true),
            sx,
            sy,
        }
    }
}

impl Rows {
    /// The sum of the reconstruction over block k (the whole-block range query).
    #[inline]
    fn total(&self, k: usize) -> f64 {
        let r = self.rank;
        let w = &self.z[k * r..(k + 1) * r];
        let mut acc = [0.0f64; 4];
        for (q, (a, b)) in self.whole.iter().zip(w).enumerate() {
            acc[q & 3] += a * b;
        }
        (acc[0] + acc[1]) + (acc[2] + acc[3])
    }
}

impl Block for Rows {
    fn side(&self) -> usize {
        self.t
    }
    #[inline]
    fn at(&self, i: usize, j: usize, z: usize) -> f64 {
        let r = self.rank;
        let (x, y, w) = (
            &self.x[i * r..(i + 1) * r],
            &self.y[j * r..(j + 1) * r],
            &self.z[z * r..(z + 1) * r],
        );
        // four partial sums, as a 4-wide SIMD lane would keep them
        let mut acc = [0.0f64; 4];
        let n4 = r - r % 4;
        for q in (0..n4).step_by(4) {
            for l in 0..4 {
                acc[l] += x[q + l] * y[q + l] * w[q + l];
            }
        }
        for q in n4..r {
            acc[q - n4] += x[q] * y[q] * w[q];
        }
        (acc[0] + acc[1]) + (acc[2] + acc[3])
    }
    #[inline]
    fn range(&self, x: (usize, usize), y: (usize, usize), z: usize) -> f64 {
        let r = self.rank;
        let (x0, x1) = (
            &self.sx[x.0 * r..(x.0 + 1) * r],
            &self.sx[(x.1 + 1) * r..(x.1 + 2) * r],
        );
        let (y0, y1) = (
            &self.sy[y.0 * r..(y.0 + 1) * r],
            &self.sy[(y.1 + 1) * r..(y.1 + 2) * r],
        );
        let w = &self.z[z * r..(z + 1) * r];
        let mut acc = [0.0f64; 4];
        let n4 = r - r % 4;
        for q in (0..n4).step_by(4) {
            for l in 0..4 {
                let p = q + l;
                acc[l] += (x1[p] - x0[p]) * (y1[p] - y0[p]) * w[p];
            }
        }
        for q in n4..r {
            acc[q - n4] += (x1[q] - x0[q]) * (y1[q] - y0[q]) * w[q];
        }
        ((acc[0] + acc[1]) + (acc[2] + acc[3])) / ((x.1 - x.0 + 1) * (y.1 - y.0 + 1)) as f64
    }
}

impl CompressedNdf {
    /// Compress `stack` (images of side `res`) with `opts`. Sampling needs
    /// `opts.nonnegative`; a typed error when the stack does not match `res`.
    pub fn compress(stack: &BlockStack, res: usize, opts: &AlsOptions) -> Result<Self> {
        let t = stack.tensor.shape[0];
        if !t.is_power_of_two()
            || res % t != 0
            || stack.slots.iter().any(|s| s.len() != (res / t).pow(2))
        {
            return Err(Error::InvalidArgument(format!(
                "a block stack of side {t} (a power of two) does not tile {res} × {res} images"
            )));
        }
        let cp = cp_als(&stack.tensor, opts)?;
        Ok(CompressedNdf {
            res,
            t,
            shift: t.trailing_zeros(),
            nb: res / t,
            rows: Rows::new(&cp),
            cp,
            slots: stack.slots.clone(),
        })
    }

    pub fn cp(&self) -> &Cp {
        &self.cp
    }

    /// How many footprint images it holds.
    pub fn images(&self) -> usize {
        self.slots.len()
    }

    /// Image side.
    pub fn res(&self) -> usize {
        self.res
    }

    /// The pixel holding h_xy, or `None` outside [−1, 1)².
    #[inline]
    fn pixel(&self, hx: f64, hy: f64) -> Option<(usize, usize)> {
        let half = 0.5 * self.res as f64;
        let (fx, fy) = ((hx + 1.0) * half, (hy + 1.0) * half);
        let n = self.res as f64;
        // truncation is the floor on [0, n)
        (fx >= 0.0 && fy >= 0.0 && fx < n && fy < n).then_some((fx as usize, fy as usize))
    }

    /// The P-NDF of `image` at h_xy (per unit projected area): the point query (Eq 6) of
    /// the pixel holding it; 0 outside the image, on an all-zero block or for an image
    /// index out of range.
    #[inline]
    pub fn d(&self, image: usize, hx: f64, hy: f64) -> f64 {
        let Some((px, py)) = self.pixel(hx, hy) else {
            return 0.0;
        };
        let (k, m) = (self.shift, self.t - 1);
        match self
            .slots
            .get(image)
            .and_then(|s| s[(py >> k) * self.nb + (px >> k)])
        {
            Some(z) => self.rows.at(px & m, py & m, z).max(0.0),
            None => 0.0,
        }
    }

    /// The mean of `image`'s reconstruction over the pixel box [x0, x1] × [y0, y1]
    /// (inclusive, clipped to the image): one range query (Eq 7) per block it overlaps,
    /// all-zero blocks adding 0 — the box average of seed 002 §5.4's prefiltered query.
    /// `None` for an image out of range or a box that misses the image.
    pub fn box_mean(&self, image: usize, x: (i64, i64), y: (i64, i64)) -> Option<f64> {
        let n = self.res as i64 - 1;
        let (x0, x1, y0, y1) = (x.0.max(0), x.1.min(n), y.0.max(0), y.1.min(n));
        let slots = self.slots.get(image)?;
        if x0 > x1 || y0 > y1 {
            return None;
        }
        let t = self.t as i64;
        let mut sum = 0.0;
        for by in y0 / t..=y1 / t {
            for bx in x0 / t..=x1 / t {
                let Some(z) = slots[(by * self.nb as i64 + bx) as usize] else {
                    continue;
                };
                let (a0, a1) = ((x0 - bx * t).max(0), (x1 - bx * t).min(t - 1));
                let (b0, b1) = ((y0 - by * t).max(0), (y1 - by * t).min(t - 1));
                let count = ((a1 - a0 + 1) * (b1 - b0 + 1)) as f64;
                let r = (a0 as usize, a1 as usize);
                sum += count * self.rows.range(r, (b0 as usize, b1 as usize), z);
            }
        }
        Some((sum / ((x1 - x0 + 1) * (y1 - y0 + 1)) as f64).max(0.0))
    }

    /// Σ of the reconstruction over each block of `image` (0 for an all-zero one), one
    /// whole-block range query each (Eq 7), written into `out` (one per block); `false`
    /// for an image index out of range.
    #[inline]
    fn block_sums(&self, image: usize, out: &mut [f64]) -> bool {
        let Some(s) = self.slots.get(image) else {
            return false;
        };
        for (o, z) in out.iter_mut().zip(s) {
            *o = z.map_or(0.0, |z| self.rows.total(z).max(0.0));
        }
        true
    }

    /// Run `f` on the block sums of `image`, held on the stack for up to 256 blocks.
    #[inline]
    fn with_sums<T>(&self, image: usize, f: impl FnOnce(&[f64]) -> Option<T>) -> Option<T> {
        let n = (self.res / self.t).pow(2);
        let mut stack = [0.0f64; 256];
        let mut heap = Vec::new();
        let sums: &mut [f64] = if n <= stack.len() {
            &mut stack[..n]
        } else {
            heap.resize(n, 0.0);
            &mut heap
        };
        if !self.block_sums(image, sums) {
            return None;
        }
        f(sums)
    }

    /// Draw h_xy from `image` (Fig 8): a block by the CDF of the block sums (u[0]), the
    /// descent inside it (u[1]), the tent offset (u[2], u[3]). Returns (h_x, h_y, the
    /// density per unit projected area); `None` for an empty image.
    pub fn sample(&self, image: usize, u: [f64; 4]) -> Option<(f64, f64, f64)> {
        self.with_sums(image, |sums| {
            let total: f64 = sums.iter().sum();
            if !(total > 0.0) {
                return None;
            }
            let target = u[0] * total;
            let mut acc = 0.0;
            let mut b = sums.len() - 1;
            for (k, s) in sums.iter().enumerate() {
                if *s > 0.0 && target < acc + s {
                    b = k;
                    break;
                }
                acc += s;
            }
            while sums[b] <= 0.0 {
                b -= 1;
            }
            let z = self.slots[image][b]?;
            let s = sample::sample_in(&self.rows, z, sums[b], [u[1], u[2], u[3]])?;
            let (t, nb) = (self.t, self.res / self.t);
            let cell = 2.0 / self.res as f64;
            let hx = -1.0 + ((b % nb * t) as f64 + s.x) * cell;
            let hy = -1.0 + ((b / nb * t) as f64 + s.y) * cell;
            Some((hx, hy, sums[b] / total * s.pdf / (cell * cell)))
        })
    }

    /// The density [`CompressedNdf::sample`] follows at h_xy (per unit projected area).
    pub fn pdf(&self, image: usize, hx: f64, hy: f64) -> f64 {
        let Some((px, py)) = self.pixel(hx, hy) else {
            return 0.0;
        };
        self.with_sums(image, |sums| {
            let total: f64 = sums.iter().sum();
            let (t, nb) = (self.t, self.res / self.t);
            let b = (py / t) * nb + px / t;
            let z = self.slots[image][b]?;
            if !(total > 0.0 && sums[b] > 0.0) {
                return None;
            }
            let cell = 2.0 / self.res as f64;
            let x = (hx + 1.0) / cell - (b % nb * t) as f64;
            let y = (hy + 1.0) / cell - (b / nb * t) as f64;
            Some(sums[b] / total * sample::pdf_in(&self.rows, z, sums[b], x, y) / (cell * cell))
        })
        .unwrap_or(0.0)
    }
}

/// Seed 002's BRDF with D from one footprint's compressed P-NDF.
#[derive(Clone, Copy, Debug)]
pub struct Glinty<'a> {
    pub ndf: &'a CompressedNdf,
    pub image: usize,
    /// GGX roughness of the Smith shadowing term.
    pub alpha_g: f64,
    pub f0: f64,
}

impl Glinty<'_> {
    /// f(i, o); 0 below the horizon.
    #[inline]
    pub fn eval(&self, i: &V3, o: &V3) -> f64 {
        if i[2] <= 0.0 || o[2] <= 0.0 {
            return 0.0;
        }
        let h = normalize([i[0] + o[0], i[1] + o[1], i[2] + o[2]]);
        let d = self.ndf.d(self.image, h[0], h[1]);
        fresnel(self.f0, dot(i, &h)) * d * g2(self.alpha_g, i, o) / (4.0 * i[2] * o[2])
    }

    /// The density of [`Glinty::sample`] over o (solid angle): p(h_xy)·h_z/(4 i·h).
    pub fn pdf(&self, i: &V3, o: &V3) -> f64 {
        if i[2] <= 0.0 || o[2] <= 0.0 {
            return 0.0;
        }
        let h = normalize([i[0] + o[0], i[1] + o[1], i[2] + o[2]]);
        self.ndf.pdf(self.image, h[0], h[1]) * h[2] / (4.0 * dot(i, &h))
    }

    /// One sample (Fig 8 and §5.2); `None` when h leaves the hemisphere or o falls below
    /// the horizon (weight 0).
    #[inline]
    pub fn sample(&self, i: &V3, u: [f64; 4]) -> Option<Sampled> {
        let (hx, hy, p) = self.ndf.sample(self.image, u)?;
        let r2 = hx * hx + hy * hy;
        if r2 >= 1.0 || !(p > 0.0) {
            return None;
        }
        let h = [hx, hy, (1.0 - r2).sqrt()];
        let c = dot(i, &h);
        let o = [
            2.0 * c * h[0] - i[0],
            2.0 * c * h[1] - i[1],
            2.0 * c * h[2] - i[2],
        ];
        if c <= 0.0 || o[2] <= 0.0 {
            return None;
        }
        // f·o_z/pdf with pdf = p·h_z/(4c): F D G2 c/(i_z h_z p)
        let d = self.ndf.d(self.image, hx, hy);
        Some(Sampled {
            o,
            weight: fresnel(self.f0, c) * d * g2(self.alpha_g, i, &o) * c / (i[2] * h[2] * p),
        })
    }
}

/// The images of the Table 3 comparison: the tensor study's default blocks (64² flakes
/// map, 64² P-NDF images, stride 8, σ_r = 0.02), the 16 level-0 footprints of one
/// quarter-map region.
pub fn table3_images() -> Result<Vec<Vec<f64>>> {
    use super::pndf::{pndf_image, sigma_p};
    use crate::filters::footprint::{NormalMap, Procedural};
    let (size, stride) = (64usize, 8usize);
    let map = NormalMap::procedural(Procedural::Flakes, size, 3)?;
    let mut images = Vec::new();
    for cy in (stride / 2..size / 2).step_by(stride) {
        for cx in (stride / 2..size / 2).step_by(stride) {
            images.push(pndf_image(
                &map,
                cx as f64,
                cy as f64,
                sigma_p(stride, 0),
                TABLE3_SIGMA_R,
                TABLE3_RES,
            )?);
        }
    }
    Ok(images)
}

/// Image side, block side and intrinsic roughness of [`table3_images`].
pub const TABLE3_RES: usize = 64;
pub const TABLE3_T: usize = 16;
pub const TABLE3_SIGMA_R: f64 = 0.02;

/// [`table3_images`] in t = 16 blocks, non-negative CP of rank `rank` (200 sweeps,
/// tolerance 1e-4, the tensor study's seed).
pub fn table3_ndf(rank: usize) -> Result<CompressedNdf> {
    let images = table3_images()?;
    let refs: Vec<&[f64]> = images.iter().map(|v| v.as_slice()).collect();
    let stack = super::cluster::stack_blocks(&refs, TABLE3_RES, TABLE3_T)?
        .ok_or_else(|| Error::InvalidArgument("the Table 3 footprints are empty".into()))?;
    CompressedNdf::compress(&stack, TABLE3_RES, &table3_options(rank))
}

/// The CP options of [`table3_ndf`].
pub fn table3_options(rank: usize) -> AlsOptions {
    AlsOptions {
        rank,
        tol: 1e-4,
        max_iters: 200,
        restarts: 1,
        seed: 5,
        nonnegative: true,
    }
}

/// The ranks the Table 3 bench runs.
pub const TABLE3_RANKS: [usize; 3] = [8, 16, 32];

/// The relative reconstruction error of [`table3_ndf`] at each of [`TABLE3_RANKS`].
pub fn table3_cp_errors() -> Result<Vec<(usize, f64)>> {
    TABLE3_RANKS
        .iter()
        .map(|&r| Ok((r, table3_ndf(r)?.cp().rel_error)))
        .collect()
}

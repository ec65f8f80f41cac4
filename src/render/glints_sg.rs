//! Seed 002 §5.4's glints under a distant environment of spherical Gaussians, as a
//! renderer shades them. With G = F = 1 a texel (or a footprint's P-NDF D, per unit
//! projected area of h) reflects f·cos = D(h_xy)/(4 v_z), so a pixel's radiance is
//!
//!   I = ∫ L(l) D(h_xy(l)) / (4 v_z) dl = ∫_{|h_xy| < 1} L(2(v·h)h − v) D(h_xy) (v·h)/(v_z h_z) dh_xy.
//!
//! Three ways to get it:
//! - the CP point query (Eq 6): per sample, one SG picked by its share of the integral and
//!   a direction l drawn from it (vMF), D read at h_xy's bin of the nearest grid
//!   footprint's compressed image; the estimate L(l)·D/(4 v_z)/pdf(l);
//! - the prefiltered query (Eq 8–9): the same draw, D read as the mean over the square of
//!   side scale·2·res·θ/π about h_xy, θ the drawn lobe's compact-ε support;
//! - a plain mip: the renormalised mip normal's single Gaussian of σ_r against the SGs, by
//!   a product Gauss–Hermite rule in h_xy ([`gaussian_lobe_integral`], no noise).
//!
//! Every pixel draws from its own ChaCha8 stream keyed by (seed, x, y); the point and the
//! prefiltered query share their draws, so their difference is the read alone.

use super::glints::CpGlints;
use super::methods::GPixel;
use super::texture::Texture;
use super::truth::pixel_rng;
use crate::leadr::Grid;
use crate::microfacet::lobe::Frame;
use crate::tensor::envsg::{query_side, square_start, Read, SgEnv};
use nalgebra::Vector3;
use rand::Rng;
use rayon::prelude::*;

type V3 = Vector3<f64>;

/// Gauss–Hermite nodes per axis of the plain mip's quadrature.
pub const MIP_NODES: usize = 16;

/// One method's image under the environment.
pub struct SgImage {
    pub key: String,
    pub label: String,
    pub pixels: Vec<f32>,
}

/// How the estimators sample (fits/render.toml's `glints.env_*`).
#[derive(Clone, Copy, Debug)]
pub struct SgPlan {
    /// Draws per pixel of each estimator, and of the largest rank's again (their noise
    /// falls by spp/spp_high: what remains is the estimators' bias).
    pub spp: usize,
    pub spp_high: usize,
    /// Eq 8's threshold ε (absolute radiance) and Eq 9's side scale.
    pub eps: f64,
    pub scale: f64,
}

/// I for a Gaussian lobe of standard deviation σ about the tangent-space normal `n`'s
/// h_xy, seen from tangent-space unit `v` (frame `fr` maps tangent space to world), by a
/// product Gauss–Hermite rule in h_xy; nodes off the unit disk, or whose l falls below
/// the horizon, add nothing.
pub fn gaussian_lobe_integral(
    env: &SgEnv,
    fr: &Frame,
    v: &V3,
    n: &V3,
    sigma: f64,
    grid: &Grid,
) -> f64 {
    if v.z <= 0.0 {
        return 0.0;
    }
    let mut sum = 0.0;
    for (a, wa) in grid.nodes.iter().zip(&grid.weights) {
        for (b, wb) in grid.nodes.iter().zip(&grid.weights) {
            let (hx, hy) = (n.x + sigma * a, n.y + sigma * b);
            let r2 = hx * hx + hy * hy;
            if r2 >= 1.0 {
                continue;
            }
            let h = V3::new(hx, hy, (1.0 - r2).sqrt());
            let vh = v.dot(&h);
            let l = h * (2.0 * vh) - v;
            if vh <= 0.0 || l.z <= 0.0 {
                continue;
            }
            sum += wa * wb * env.eval(&fr.world(&l)) * vh / (v.z * h.z);
        }
    }
    sum
}

/// One pixel of an estimator: the mean of `spp` draws.
#[allow(clippy::too_many_arguments)]
fn estimate(
    cp: &CpGlints,
    gp: &GPixel,
    tex: &Texture,
    env: &SgEnv,
    read: Read,
    spp: usize,
    rng: &mut rand_chacha::ChaCha8Rng,
) -> f64 {
    let fr = &gp.hit.frame;
    let v = fr.local(&gp.view);
    if v.z <= 0.0 {
        return 0.0;
    }
    let f = cp.footprint_at(tex.texel_coords(gp.hit.uv));
    let mut sum = 0.0;
    for _ in 0..spp {
        let u: [f64; 3] = rng.random();
        let Ok((k, lw)) = env.sample(u) else {
            return 0.0;
        };
        let l = fr.local(&lw);
        let pdf = env.pdf(&lw);
        if l.z <= 0.0 || !(pdf > 0.0) {
            continue;
        }
        let h = (v + l).normalize();
        let q = match read {
            Read::Point => 1,
            Read::Prefiltered { eps, scale } => {
                query_side(env.lobes[k].support(eps), cp.res, scale) as i64
            }
        };
        let (x0, y0) = (square_start(h.x, q, cp.res), square_start(h.y, q, cp.res));
        let d = cp.box_mean(f, (x0, x0 + q - 1), (y0, y0 + q - 1)) as f64;
        sum += env.eval(&lw) * d / (4.0 * v.z) / pdf;
    }
    sum / spp as f64
}

/// The glint set's images under `env`: the point and the prefiltered query at every CP
/// rank, both again at the last rank with `spp_high` draws, and the plain mip.
#[allow(clippy::too_many_arguments)]
pub fn images(
    w: usize,
    g: &[Option<GPixel>],
    tex: &Texture,
    env: &SgEnv,
    sigma_r: f64,
    cps: &[CpGlints],
    plan: &SgPlan,
    seed: u64,
) -> Vec<SgImage> {
    let img = |f: &(dyn Fn(usize, &GPixel) -> f32 + Sync)| -> Vec<f32> {
        (0..g.len())
            .into_par_iter()
            .map(|k| g[k].as_ref().map_or(0.0, |gp| f(k, gp)))
            .collect()
    };
    let shade = |cp: &CpGlints, read: Read, spp: usize| {
        img(&|k, gp| {
            let mut rng = pixel_rng(seed ^ 0x5347_5347, k % w, k / w);
            estimate(cp, gp, tex, env, read, spp, &mut rng) as f32
        })
    };
    let mut out = Vec::new();
    let prefiltered = Read::Prefiltered {
        eps: plan.eps,
        scale: plan.scale,
    };
    let mut pair = |cp: &CpGlints, spp: usize, suffix: &str| {
        out.push(SgImage {
            key: format!("sg-point-r{}{suffix}", cp.rank),
            label: format!("CP point query (Eq 6), R = {}, {spp} draws", cp.rank),
            pixels: shade(cp, Read::Point, spp),
        });
        out.push(SgImage {
            key: format!("sg-prefiltered-r{}{suffix}", cp.rank),
            label: format!("CP prefiltered (Eq 9), R = {}, {spp} draws", cp.rank),
            pixels: shade(cp, prefiltered, spp),
        });
    };
    for cp in cps {
        pair(cp, plan.spp, "");
    }
    if let Some(cp) = cps.last() {
        pair(cp, plan.spp_high, "-high");
    }
    let grid = Grid::gauss_hermite(MIP_NODES);
    out.push(SgImage {
        key: "sg-plain-mip".into(),
        label: format!("plain mip, Gauss–Hermite {MIP_NODES}²"),
        pixels: img(&|_, gp| {
            let fr = &gp.hit.frame;
            gaussian_lobe_integral(env, fr, &fr.local(&gp.view), &gp.n_t, sigma_r, &grid) as f32
        }),
    });
    out
}

//! The ground truth: the footprint-averaged BRDF (seed 004 Eq 11) as a pixel sees it
//! (box pixel filter). Every texel the pixel covers is shaded with its own lobe at the
//! base roughness (the f64 reference [`crate::microfacet::Microsurface`], or seed 002's
//! Gaussian, or an LTC) and weighted by its exact coverage; footprints too large for that
//! are supersampled on jittered grids. Point and directional lights are evaluated
//! exactly; a quad light is integrated by one-sample MIS of light-area and visible-normal
//! sampling, an SG environment by one-sample MIS of the SG mixture (vMF) and the lobe
//! (GGX's visible normals, or seed 002's Gaussian of h_xy), both with the balance
//! heuristic. Two independent replicates give each pixel's standard error (see [`pixel`]).

use super::geometry::{Camera, Hit, Surface};
use super::light::Light;
use super::scene::Lobe;
use super::texture::Texture;
use crate::integrate::mc::Strategy;
use crate::ltc::dist::LtcDist;
use crate::microfacet::lobe::{lobe, Frame, ViewedLobe};
use crate::microfacet::sampling::VndfSampler;
use crate::microfacet::{Microsurface, Roughness};
use crate::tensor::envsg::SgEnv;
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

mod lanes;
mod texels;

/// The per-texel lobe and the scene's lights.
pub struct Shader<'a> {
    pub kind: Lobe,
    pub alpha: f64,
    pub sigma_r: f64,
    pub lights: &'a [Light],
    pub tex: &'a Texture,
    surface: Microsurface,
    ltc: Option<LtcDist>,
}

/// What one texel's shading at one hit needs whatever the light direction: the view in
/// the hit's frame, the texel's frame and, for GGX, its lobe with Λ(v) and its
/// visible-normal sampler (with G1(v)), each computed once for every light sample rather
/// than once per sample; the same operations in the same order, so the same bits.
struct Viewed {
    v: V3,
    sf: Frame,
    lobe: Option<ViewedLobe>,
    vndf: Option<(VndfSampler, Frame, V3)>,
}

/// One pixel of the truth: the mean radiance of two independent replicates, which are
/// `value ± diff`.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct PixelTruth {
    pub value: f64,
    /// Half the signed difference of the replicates.
    pub diff: f64,
    /// Every footprint sample hit the surface.
    pub covered: bool,
}

impl PixelTruth {
    /// The standard error of `value` (one degree of freedom): |diff|.
    pub fn se(&self) -> f64 {
        self.diff.abs()
    }
}

impl<'a> Shader<'a> {
    pub fn new(
        kind: Lobe,
        alpha: f64,
        sigma_r: f64,
        lights: &'a [Light],
        tex: &'a Texture,
    ) -> crate::error::Result<Shader<'a>> {
        Ok(Shader {
            kind,
            alpha,
            sigma_r,
            lights,
            tex,
            surface: Microsurface::ggx(Roughness::iso(alpha)?),
            ltc: match kind {
                Lobe::Ltc => Some(LtcDist::isotropic(alpha)?),
                _ => None,
            },
        })
    }

    /// f·cos of the texel with tangent-space normal `nt`, for tangent-space unit v and l.
    pub fn lobe(&self, nt: &V3, v: &V3, l: &V3) -> f64 {
        self.lobe_in(&Frame::around(*nt), nt, v, l)
    }

    /// The same with the texel's frame `sf` = `Frame::around(nt)` already built.
    fn lobe_in(&self, sf: &Frame, nt: &V3, v: &V3, l: &V3) -> f64 {
        match self.kind {
            Lobe::Ggx => lobe(&self.surface, sf, v, l),
            Lobe::Gaussian => gaussian_lobe(self.sigma_r, nt, v, l),
            Lobe::Ltc => {
                if v.z <= 0.0 || l.z <= 0.0 {
                    return 0.0;
                }
                let f = shading_frame(nt, v);
                self.ltc.as_ref().map_or(0.0, |d| d.eval(&f.local(l)))
            }
        }
    }

    /// The texel with normal `nt` at `hit`, seen from the eye, prepared for its lights.
    fn viewed(&self, hit: &Hit, eye: &V3, nt: &V3) -> Viewed {
        let v = hit.frame.local(&(eye - hit.p).normalize());
        let sf = Frame::around(*nt);
        let (lobe, vndf) = match self.kind {
            Lobe::Ggx => {
                let g = ViewedLobe::new(&self.surface, &sf, &v);
                // only the sampled lights draw from it; the lobe's Λ(v) serves it too
                let (vs, lambda) = g.view();
                let vndf = self
                    .has_sampled()
                    .then(|| VndfSampler::seen_with(self.surface, vs, lambda).ok())
                    .flatten()
                    .map(|s| (s, sf, vs));
                (Some(g), vndf)
            }
            _ => (None, None),
        };
        Viewed { v, sf, lobe, vndf }
    }

    /// f·cos of the prepared texel toward tangent-space l.
    fn lobe_at(&self, w: &Viewed, nt: &V3, l: &V3) -> f64 {
        match &w.lobe {
            Some(g) => g.eval(&self.surface, l),
            None => self.lobe_in(&w.sf, nt, &w.v, l),
        }
    }

    /// The point and directional lights' exact radiance at a hit seen from the eye,
    /// texel normal `nt`.
    pub fn exact_part(&self, hit: &Hit, eye: &V3, nt: &V3) -> f64 {
        self.exact_at(&self.viewed(hit, eye, nt), hit, nt)
    }

    /// A point or directional light's factor at `hit` and its direction in the hit's
    /// frame (its exact term is factor × lobe); `None` for the sampled lights.
    fn exact_light(light: &Light, hit: &Hit) -> Option<(f64, V3)> {
        match light {
            Light::Point { pos, intensity } => {
                let d = pos - hit.p;
                let r2 = d.norm_squared();
                Some((intensity / r2, hit.frame.local(&(d / r2.sqrt()))))
            }
            Light::Directional { dir, irradiance } => Some((*irradiance, hit.frame.local(dir))),
            Light::Quad { .. } | Light::Sg(_) => None,
        }
    }

    fn exact_at(&self, w: &Viewed, hit: &Hit, nt: &V3) -> f64 {
        let mut sum = 0.0;
        for light in self.lights {
            sum += match Self::exact_light(light, hit) {
                Some((c, l)) => c * self.lobe_at(w, nt, &l),
                None => 0.0,
            };
        }
        sum
    }

    /// One MC sample of the sampled lights' radiance (quad lights and SG environments; 0
    /// without them) from the three uniforms `u` (strategy, two for the direction).
    pub fn sampled_part(&self, hit: &Hit, eye: &V3, nt: &V3, u: [f64; 3]) -> f64 {
        self.sampled_at(&self.viewed(hit, eye, nt), hit, nt, u)
    }

    fn sampled_at(&self, w: &Viewed, hit: &Hit, nt: &V3, u: [f64; 3]) -> f64 {
        self.lights
            .iter()
            .map(|l| match l {
                Light::Quad { .. } => self.quad_sample(l, hit, w, nt, u),
                Light::Sg(env) => self.sg_sample(env, hit, w, nt, u),
                _ => 0.0,
            })
            .sum()
    }

    pub fn has_sampled(&self) -> bool {
        self.lights
            .iter()
            .any(|l| matches!(l, Light::Quad { .. } | Light::Sg(_)))
    }

    /// One radiance sample: the exact part plus one sample of each sampled light.
    pub fn sample(&self, hit: &Hit, eye: &V3, nt: &V3, u: &mut ChaCha8Rng) -> f64 {
        let w = self.viewed(hit, eye, nt);
        self.exact_at(&w, hit, nt)
            + self.sampled_at(&w, hit, nt, [u.random(), u.random(), u.random()])
    }

    /// One-sample MIS of an SG environment: the mixture's vMF draw or the lobe's own (GGX
    /// visible normals; the Gaussian lobe's h_xy ~ N(n_xy, σ_r²), so that its f·cos/pdf
    /// is (v·h)/(v_z h_z)), balance heuristic; the LTC lobe draws from the SGs alone.
    fn sg_sample(&self, env: &SgEnv, hit: &Hit, w: &Viewed, nt: &V3, u: [f64; 3]) -> f64 {
        let fr = &hit.frame;
        let v = &w.v;
        if v.z <= 0.0 {
            return 0.0;
        }
        let vndf = &w.vndf;
        let has_lobe = vndf.is_some() || self.kind == Lobe::Gaussian;
        // the lobe's density of the tangent-space direction l
        let lobe_pdf = |l: &V3| -> f64 {
            if l.z <= 0.0 {
                return 0.0;
            }
            let h = (v + l).normalize();
            match (vndf, self.kind) {
                (Some((s, sf, vs)), _) => {
                    let ls = sf.local(l);
                    if ls.z <= 0.0 {
                        return 0.0;
                    }
                    let hs = (vs + ls).normalize();
                    s.pdf(&hs) / (4.0 * vs.dot(&hs).abs()).max(1e-300)
                }
                (None, Lobe::Gaussian) => {
                    let s2 = self.sigma_r * self.sigma_r;
                    let r2 = (h.x - nt.x).powi(2) + (h.y - nt.y).powi(2);
                    (-r2 / (2.0 * s2)).exp() / (2.0 * PI * s2) * h.z / (4.0 * v.dot(&h)).max(1e-300)
                }
                _ => 0.0,
            }
        };
        let mix = if has_lobe { 0.5 } else { 0.0 };
        let [pick, s1, s2] = u;
        let l = if pick < mix {
            match (vndf, self.kind) {
                (Some((s, sf, vs)), _) => {
                    let Some(h) = s.sample([s1, s2]) else {
                        return 0.0;
                    };
                    sf.world(&(h * (2.0 * vs.dot(&h)) - vs))
                }
                _ => {
                    let r = self.sigma_r * (-2.0 * (1.0 - s1).ln()).sqrt();
                    let phi = 2.0 * PI * s2;
                    let (hx, hy) = (nt.x + r * phi.cos(), nt.y + r * phi.sin());
                    let r2 = hx * hx + hy * hy;
                    if !(r2 < 1.0) {
                        return 0.0;
                    }
                    let h = V3::new(hx, hy, (1.0 - r2).sqrt());
                    let vh = v.dot(&h);
                    if vh <= 0.0 {
                        return 0.0;
                    }
                    h * (2.0 * vh) - v
                }
            }
        } else {
            let w = (pick - mix) / (1.0 - mix);
            match env.sample([w.min(1.0 - f64::EPSILON / 2.0), s1, s2]) {
                Ok((_, lw)) => fr.local(&lw),
                Err(_) => return 0.0,
            }
        };
        if l.z <= 0.0 {
            return 0.0;
        }
        let lw = fr.world(&l);
        let pdf = mix * lobe_pdf(&l) + (1.0 - mix) * env.pdf(&lw);
        if !(pdf > 0.0) {
            return 0.0;
        }
        env.eval(&lw) * self.lobe_at(w, nt, &l) / pdf
    }

    /// Solid-angle density of area sampling the quad in world direction d from p.
    fn area_pdf(light: &Light, p: &V3, d: &V3) -> f64 {
        light
            .quad_hit(p, d)
            .map_or(0.0, |q| Self::area_pdf_at(light, p, d, &q))
    }

    /// [`Self::area_pdf`] given the point q where d from p hits the quad.
    fn area_pdf_at(light: &Light, p: &V3, d: &V3, q: &V3) -> f64 {
        match light {
            Light::Quad { normal, area, .. } => {
                let r2 = (q - p).norm_squared();
                r2 / (area * d.dot(normal).abs()).max(1e-300)
            }
            _ => 0.0,
        }
    }

    /// One sample's light direction (world) and its density under area sampling of the
    /// quad: with probability `mix` (`u[0] < mix`) a point of the quad, else the lobe's
    /// visible normal reflected (its hit on the quad gives the density); None where the
    /// sample is lost (its value is 0).
    fn quad_direction(
        light: &Light,
        hit: &Hit,
        w: &Viewed,
        u: [f64; 3],
        mix: f64,
    ) -> Option<(V3, f64)> {
        let [pick, s1, s2] = u;
        if pick < mix {
            let q = light.quad_point([s1, s2])?;
            let lw = (q - hit.p).normalize();
            Some((lw, Self::area_pdf(light, &hit.p, &lw)))
        } else {
            let (s, sf, vs) = w.vndf.as_ref()?;
            let h = s.sample([s1, s2])?;
            let ls = h * (2.0 * vs.dot(&h)) - vs;
            let lw = hit.frame.world(&sf.world(&ls));
            // the hit that decides whether the direction sees the light gives its density
            let q = light.quad_hit(&hit.p, &lw)?;
            Some((lw, Self::area_pdf_at(light, &hit.p, &lw, &q)))
        }
    }

    /// The share of light samples the quad draws from its area (the rest from the lobe).
    fn quad_mix(w: &Viewed) -> f64 {
        if w.vndf.is_some() {
            0.5
        } else {
            1.0
        }
    }

    fn quad_sample(&self, light: &Light, hit: &Hit, w: &Viewed, nt: &V3, u: [f64; 3]) -> f64 {
        let Light::Quad { radiance, .. } = light else {
            return 0.0;
        };
        let fr = &hit.frame;
        let vndf = &w.vndf;
        let brdf_pdf = |lw: &V3| -> f64 {
            let Some((s, sf, vs)) = vndf else { return 0.0 };
            let ls = sf.local(&fr.local(lw));
            let h = vs + ls;
            let hn = h.norm();
            if !(hn > 0.0) || ls.z <= 0.0 {
                return 0.0;
            }
            let h = h / hn;
            s.pdf(&h) / (4.0 * vs.dot(&h).abs()).max(1e-300)
        };
        let mix = Self::quad_mix(w);
        let Some((lw, area_pdf)) = Self::quad_direction(light, hit, w, u, mix) else {
            return 0.0;
        };
        let pdf = mix * area_pdf + (1.0 - mix) * brdf_pdf(&lw);
        if !(pdf > 0.0) {
            return 0.0;
        }
        radiance * self.lobe_at(w, nt, &fr.local(&lw)) / pdf
    }
}

/// The frame around n whose x axis points toward the view's projection (an LTC's frame).
pub fn shading_frame(n: &V3, v: &V3) -> Frame {
    let n = n.normalize();
    let t = v - n * n.dot(v);
    let t = if t.norm() > 1e-12 {
        t.normalize()
    } else {
        Frame::around(n).t
    };
    Frame {
        t,
        b: n.cross(&t),
        n,
    }
}

/// Seed 002's intrinsic lobe, f·cos = D(h)/(4 v_z) with D(h) = G_r(h_xy − n_xy), the
/// normalised 2D Gaussian of standard deviation σ_r on the projected disk (G = F = 1).
pub fn gaussian_lobe(sigma_r: f64, nt: &V3, v: &V3, l: &V3) -> f64 {
    if v.z <= 0.0 || l.z <= 0.0 {
        return 0.0;
    }
    let h = (v + l).normalize();
    let (dx, dy) = (h.x - nt.x, h.y - nt.y);
    let s2 = sigma_r * sigma_r;
    (-(dx * dx + dy * dy) / (2.0 * s2)).exp() / (2.0 * PI * s2) / (4.0 * v.z)
}

/// A deterministic stream per (seed, pixel): the same samples in every frame.
pub fn pixel_rng(seed: u64, x: usize, y: usize) -> ChaCha8Rng {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    r.set_stream(((y as u64) << 32) | x as u64);
    r
}

pub use super::coverage::MAX_EXACT_TEXELS;

/// A pixel's truth work: `n` samples (two replicates of n/2), and, where a sampled light
/// (quad, SG) shines on a footprint of more than `draws` texels, `draws` texels drawn per
/// replicate instead of every texel (`None`: every texel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    pub n: usize,
    pub draws: Option<usize>,
}

/// How a pixel's truth shades its sampled lights (quad, SG).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Work {
    /// Every texel of an exact footprint, k light samples per texel and replicate (0: no
    /// sampled light, the point and directional lights alone).
    EveryTexel { texels: usize, k: usize },
    /// `m` texels drawn per replicate, one light sample each.
    Drawn { m: usize },
    /// n footprint samples (no exact footprint).
    Supersampled { n: usize },
}

impl Budget {
    /// The work of a pixel whose exact footprint holds `texels` texels (`None`: none within
    /// [`MAX_EXACT_TEXELS`]), with or without sampled lights.
    pub fn work(&self, texels: Option<usize>, sampled: bool) -> Work {
        match texels {
            None => Work::Supersampled { n: self.n },
            Some(t) if !sampled => Work::EveryTexel { texels: t, k: 0 },
            Some(t) => match self.draws.filter(|&m| t > m) {
                Some(m) => Work::Drawn { m },
                None => Work::EveryTexel {
                    texels: t,
                    k: (self.n / 2).div_ceil(t).max(1),
                },
            },
        }
    }
}

impl Work {
    /// The texel shadings it takes: one per light sample (each takes the texel's point and
    /// directional lights too), or one per texel without sampled lights.
    pub fn shadings(&self) -> usize {
        match *self {
            Work::EveryTexel { texels, k } => texels * (2 * k).max(1),
            Work::Drawn { m } => 2 * m,
            Work::Supersampled { n } => 2 * (n / 2).max(1),
        }
    }
}

/// The texels of pixel (x, y)'s exact footprint, as its truth finds them (`None`: more than
/// [`MAX_EXACT_TEXELS`], or no footprint on the surface; the truth supersamples).
pub fn footprint_texels(
    cam: &Camera,
    surf: &Surface,
    sh: &Shader,
    x: usize,
    y: usize,
) -> Option<usize> {
    footprint(cam, surf, sh, x, y).map(|(shares, _)| shares.len())
}

/// The truth of pixel (x, y). Where the pixel's preimage covers at most
/// [`MAX_EXACT_TEXELS`] texels it is integrated exactly over them
/// ([`super::coverage::shares`]: every texel weighted by its overlap with the pixel,
/// shaded at its overlap's centroid), the sampled lights (quad, SG) by n/2 samples per
/// replicate spread over the texels, or, on a footprint of more than the budget's `draws`
/// texels, by that many texels per replicate drawn in proportion to their overlap
/// (`texels.rs`); otherwise the pixel is supersampled by n footprint samples. Either way
/// two independent replicates give the value (their mean) and the standard error
/// |m₁ − m₂|/2 (0 for point and directional lights on an exact footprint).
pub fn pixel(
    cam: &Camera,
    surf: &Surface,
    sh: &Shader,
    x: usize,
    y: usize,
    budget: Budget,
    seed: u64,
) -> PixelTruth {
    let mut rng = pixel_rng(seed, x, y);
    exact(cam, surf, sh, x, y, budget, &mut rng)
        .unwrap_or_else(|| sh.supersampled(cam, surf, x, y, budget.n, &mut rng))
}

fn exact(
    cam: &Camera,
    surf: &Surface,
    sh: &Shader,
    x: usize,
    y: usize,
    budget: Budget,
    rng: &mut ChaCha8Rng,
) -> Option<PixelTruth> {
    let (shares, size) = footprint(cam, surf, sh, x, y)?;
    let total: f64 = shares.iter().map(|s| s.area).sum();
    // sampled lights: k light samples per texel and replicate, all of a replicate's drawn
    // from one Owen-scrambled Sobol sequence (sobol_burley; its own scramble per pixel
    // and replicate, so the two replicates are independent), or m texels drawn per
    // replicate
    let work = budget.work(Some(shares.len()), sh.has_sampled());
    let prepare = |s: &super::coverage::Share| {
        let hit = surf.point_at([s.centroid[0] / size[0], s.centroid[1] / size[1]]);
        let nt = sh.tex.at(s.i, s.j);
        let w = sh.viewed(&hit, &cam.eye, &nt);
        // the exact part is written in by `Shader::with_exact`
        (hit, nt, w, 0.0)
    };
    let k = match work {
        Work::Drawn { m } => {
            let [m1, m2] = sh.drawn_texels(&shares, m, prepare, rng);
            return Some(PixelTruth {
                value: 0.5 * (m1 + m2),
                diff: 0.5 * (m1 - m2),
                covered: true,
            });
        }
        Work::EveryTexel { k, .. } => k,
        Work::Supersampled { .. } => return None,
    };
    let scrambles: [u32; 2] = [rng.random(), rng.random()];
    let texels = sh.with_exact(shares.iter().map(prepare));
    let reps = if k == 0 {
        // no sampled light: each texel's exact part alone
        let mut reps = [0.0f64; 2];
        for (s, t) in shares.iter().zip(&texels) {
            reps.iter_mut().for_each(|rep| *rep += s.area * (t.3 + 0.0));
        }
        reps
    } else {
        sh.every_texel(&shares, &texels, k, scrambles, rng)
    };
    let (m1, m2) = (reps[0] / total, reps[1] / total);
    Some(PixelTruth {
        value: 0.5 * (m1 + m2),
        diff: 0.5 * (m1 - m2),
        covered: true,
    })
}

/// The texels pixel (x, y) covers with their shares, and the map's size in texels: the
/// pixel square's corners taken to the map through the surface (one period's copy, the
/// closest to the centre's), or `None` (a corner off the surface, more than
/// [`MAX_EXACT_TEXELS`] texels, or no area).
fn footprint(
    cam: &Camera,
    surf: &Surface,
    sh: &Shader,
    x: usize,
    y: usize,
) -> Option<(Vec<super::coverage::Share>, [f64; 2])> {
    let centre = surf.intersect(&cam.eye, &cam.dir(x as f64 + 0.5, y as f64 + 0.5))?;
    let per = surf.periods();
    let size = [sh.tex.map.width as f64, sh.tex.map.height as f64];
    let mut q = [[0.0; 2]; 4];
    for (c, (dx, dy)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        .iter()
        .enumerate()
    {
        let h = surf.intersect(&cam.eye, &cam.dir(x as f64 + dx, y as f64 + dy))?;
        for a in 0..2 {
            let mut d = h.uv[a] - centre.uv[a];
            if per[a].is_finite() {
                d -= per[a] * (d / per[a]).round();
            }
            q[c][a] = (centre.uv[a] + d) * size[a];
        }
    }
    let shares = super::coverage::shares(&q, MAX_EXACT_TEXELS)?;
    let total: f64 = shares.iter().map(|s| s.area).sum();
    (total > 0.0).then_some((shares, size))
}

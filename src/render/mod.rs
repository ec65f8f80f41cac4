//! A small deterministic CPU renderer for rendered evidence: a scene (TOML, `scene`) →
//! camera and surface hits (`geometry`) → the normal map and its mip chain as a shader
//! reads them (`texture`) → the ground truth, the footprint-averaged BRDF with per-pixel
//! standard errors (`truth`, lights in `light`) → the approximations through the shipped
//! f32 code (`methods`; seed 002's glints in `glints`, under SG environments in
//! `glints_sg`) → error, perceptual error and
//! flicker (`measure`) → tone-mapped pictures (`picture`).
//!
//! Determinism: every pixel draws from its own ChaCha8 stream keyed by (seed, x, y), the
//! same in every frame; rayon maps pixels and collects by index, so the bits do not
//! depend on the thread count.

pub mod check;
pub mod coverage;
pub mod geometry;
pub mod glints;
pub mod glints_sg;
pub mod light;
pub mod measure;
pub mod methods;
pub mod picture;
pub mod scene;
pub mod texture;
pub mod truth;

use crate::error::{Error, Result};
use crate::filters::footprint::{NormalMap, Procedural};
use geometry::{Camera, Surface};
use methods::{Constants, Method};
use nalgebra::Vector3;
use rayon::prelude::*;
use scene::{MethodSet, Scene};
use std::path::Path;
use texture::Texture;
use truth::{PixelTruth, Shader};

/// One rendered image of a method.
#[derive(Clone, Debug)]
pub struct MethodImage {
    pub key: String,
    pub label: String,
    pub pixels: Vec<f32>,
}

/// Everything of one view (a scale of the map and a frame of the camera path).
#[derive(Clone, Debug)]
pub struct View {
    pub scale: f64,
    pub frame: usize,
    pub truth: Vec<PixelTruth>,
    pub methods: Vec<MethodImage>,
}

/// A whole render.
#[derive(Clone, Debug)]
pub struct Render {
    pub scene: Scene,
    pub width: usize,
    pub height: usize,
    pub views: Vec<View>,
    /// Extra per-method numbers (the CP models' error and storage).
    pub notes: Vec<String>,
}

/// The scene's normal map: a generator name, "flat", or a PNG relative to `base`, its
/// slopes scaled by `normal_scale`.
pub fn normal_map(scene: &Scene, base: &Path) -> Result<NormalMap> {
    let mut map = unscaled_map(scene, base)?;
    let k = scene.material.normal_scale;
    if k != 1.0 {
        for n in &mut map.normals {
            *n = Vector3::new(n.x * k / n.z, n.y * k / n.z, 1.0).normalize();
        }
    }
    Ok(map)
}

fn unscaled_map(scene: &Scene, base: &Path) -> Result<NormalMap> {
    let m = &scene.material;
    let kinds = Procedural::ALL.into_iter().chain([Procedural::Scratches]);
    if let Some(k) = kinds.clone().find(|k| k.name() == m.normal_map) {
        return NormalMap::procedural(k, m.map_size, m.map_seed);
    }
    if m.normal_map == "flat" {
        return Ok(NormalMap::flat(m.map_size));
    }
    let p = base.join(&m.normal_map);
    if !p.is_file() {
        return Err(Error::InvalidArgument(format!(
            "scene {}: normal_map '{}' is neither a generator ({}, flat) nor a file",
            scene.name,
            m.normal_map,
            kinds.map(|k| k.name()).collect::<Vec<_>>().join(", ")
        )));
    }
    NormalMap::from_png(&p)
}

/// How the glint set's CP models are built (the preset's scale).
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlintPlan {
    /// P-NDF image side.
    pub res: usize,
    /// Footprint stride in texels.
    pub stride: usize,
    /// Block side of the tensors.
    pub t: usize,
    /// CP ranks of the three models.
    pub ranks: [usize; 3],
    /// CP-ALS iteration cap.
    pub iters: usize,
    /// Under an SG environment: draws per pixel of the point and the prefiltered query
    /// (and of the largest rank's again, where the noise has fallen and the bias
    /// remains), Eq 8's ε (absolute radiance) and Eq 9's side scale (the paper: 0.3 and
    /// 0.5).
    pub env_spp: usize,
    pub env_spp_high: usize,
    pub env_eps: f64,
    pub env_scale: f64,
}

impl GlintPlan {
    /// The sizes this plan derives from a normal map `map_width` texels wide, checked
    /// before any work: the footprint grid (map width ÷ stride) must hold at least one
    /// footprint, and the images (res²) a whole number of t² blocks.
    pub fn check(&self, map_width: usize) -> Result<()> {
        if self.stride == 0
            || self.t == 0
            || self.res == 0
            || self.ranks.contains(&0)
            || self.env_spp == 0
            || self.env_spp_high == 0
        {
            return Err(Error::InvalidArgument(format!(
                "glints: the preset's plan has a zero size (stride {}, image {}², block {}², ranks {:?}, {} SG draws per pixel)",
                self.stride, self.res, self.t, self.ranks, self.env_spp
            )));
        }
        let positive = |x: f64| x > 0.0 && x.is_finite();
        if !(positive(self.env_eps) && positive(self.env_scale)) {
            return Err(Error::InvalidArgument(format!(
                "glints: the preset's ε {} and square scale {} must be positive and finite",
                self.env_eps, self.env_scale
            )));
        }
        if map_width / self.stride == 0 {
            return Err(Error::InvalidArgument(format!(
                "glints: material.map_size {map_width} is below the preset's footprint stride {}, so the footprint grid (map_size ÷ stride) would be empty; use map_size ≥ {} or a finer preset",
                self.stride, self.stride
            )));
        }
        if self.res % self.t != 0 || self.res < self.t {
            return Err(Error::InvalidArgument(format!(
                "glints: the preset's {}² images do not split into {}² blocks",
                self.res, self.t
            )));
        }
        Ok(())
    }
}

/// Render every scale × frame of a scene: the truth and each method of its set.
pub fn render(scene: &Scene, base: &Path, c: &Constants, plan: &GlintPlan) -> Result<Render> {
    let tex = Texture::new(normal_map(scene, base)?);
    if scene.render.methods == MethodSet::Glints {
        plan.check(tex.map.width)?;
    }
    let lights = light::resolve(&scene.lights);
    let m = &scene.material;
    let sh = Shader::new(m.lobe, m.alpha, m.sigma_r, &lights, &tex)?;
    let c = &c.clone().with_alpha(m.alpha);
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut views = Vec::new();
    let mut notes = Vec::new();
    let mut cps: Vec<glints::CpGlints> = Vec::new();
    // the truth of every view (scale × frame), memoised per view
    let frames = scene.frames();
    let mut truths = crate::memo::map(
        &format!("render truth {}", scene.name),
        scene.render.scales.len() * frames,
        |v| -> Result<Vec<PixelTruth>> {
            let surf = Surface::new(&scene.surface, scene.render.scales[v / frames]);
            let cam = Camera::at_frame(&scene.camera, v % frames);
            Ok((0..w * h)
                .into_par_iter()
                .map(|k| {
                    truth::pixel(
                        &cam,
                        &surf,
                        &sh,
                        k % w,
                        k / w,
                        truth::Budget {
                            n: scene.render.truth_samples,
                            draws: scene.render.truth_draws,
                        },
                        scene.render.seed,
                    )
                })
                .collect::<Vec<_>>())
        },
    )?
    .into_iter();
    for &scale in &scene.render.scales {
        let surf = Surface::new(&scene.surface, scale);
        for frame in 0..frames {
            let cam = Camera::at_frame(&scene.camera, frame);
            let truth = truths
                .next()
                .ok_or_else(|| Error::InvalidArgument("render: a view without truth".into()))?;
            let g = methods::gbuffer(&cam, &surf, &tex);
            let alpha = m.alpha as f32;
            let mut out = Vec::new();
            let list: &[&str] = match scene.render.methods {
                MethodSet::Multiscale => &methods::MULTISCALE,
                MethodSet::SpecularAa => &methods::SPECULAR_AA,
                _ => &[],
            };
            for key in list {
                let meth = Method::new(key, c)?;
                let pixels = methods::shade_image(meth, &g, w, alpha, &lights, c)?;
                out.push(MethodImage {
                    key: meth.key().into(),
                    label: meth.label(),
                    pixels,
                });
            }
            if scene.render.methods == MethodSet::Glints {
                if cps.is_empty() {
                    cps = build_cps(
                        &tex,
                        &cam,
                        &surf,
                        m.sigma_r,
                        plan,
                        scene.render.seed,
                        &mut notes,
                    )?;
                }
                if lights
                    .iter()
                    .any(|l| matches!(l, light::Light::Quad { .. }))
                {
                    out.extend(glint_images(&cam, &g, &tex, &lights, m.sigma_r, &cps));
                }
                if let Some(light::Light::Sg(env)) =
                    lights.iter().find(|l| matches!(l, light::Light::Sg(_)))
                {
                    let sp = glints_sg::SgPlan {
                        spp: plan.env_spp,
                        spp_high: plan.env_spp_high,
                        eps: plan.env_eps,
                        scale: plan.env_scale,
                    };
                    let imgs = glints_sg::images(
                        w,
                        &g,
                        &tex,
                        env,
                        m.sigma_r,
                        &cps,
                        &sp,
                        scene.render.seed,
                    );
                    out.extend(imgs.into_iter().map(|i| MethodImage {
                        key: i.key,
                        label: i.label,
                        pixels: i.pixels,
                    }));
                }
            }
            views.push(View {
                scale,
                frame,
                truth,
                methods: out,
            });
        }
    }
    Ok(Render {
        scene: scene.clone(),
        width: w,
        height: h,
        views,
        notes,
    })
}

/// The CP models at the plan's ranks, σ_P from the centre pixel's footprint.
fn build_cps(
    tex: &Texture,
    cam: &Camera,
    surf: &Surface,
    sigma_r: f64,
    plan: &GlintPlan,
    seed: u64,
    notes: &mut Vec<String>,
) -> Result<Vec<glints::CpGlints>> {
    let (cx, cy) = (cam.width as f64 * 0.5, cam.height as f64 * 0.5);
    let hit = surf.intersect(&cam.eye, &cam.dir(cx, cy)).ok_or_else(|| {
        Error::InvalidArgument("glints: the centre ray misses the surface".into())
    })?;
    let fp = geometry::footprint(cam, &hit, cx, cy);
    let s = tex.map.width as f64;
    let var =
        (fp[0][0].powi(2) + fp[0][1].powi(2) + fp[1][0].powi(2) + fp[1][1].powi(2)) * s * s / 24.0;
    let sigma_p = (var + 1.0 / 12.0).sqrt();
    let images = glints::pndf_grid(tex, plan.res, plan.stride, sigma_p, sigma_r)?;
    notes.push(format!(
        "P-NDF grid: {}² footprints (stride {}, σ_P = {sigma_p:.2} texels from the centre pixel's footprint), {}² images",
        tex.map.width / plan.stride,
        plan.stride,
        plan.res,
    ));
    let mut out = Vec::new();
    for &rank in &plan.ranks {
        let cp = glints::CpGlints::build(
            &images,
            plan.res,
            plan.stride,
            plan.t,
            rank,
            plan.iters,
            seed,
        )?;
        notes.push(format!(
            "CP rank {rank}: relative reconstruction error {:.2} %, {} of {} numbers ({:.2} %)",
            100.0 * cp.rel_error,
            cp.stored,
            cp.dense,
            100.0 * cp.stored as f64 / cp.dense.max(1) as f64,
        ));
        out.push(cp);
    }
    Ok(out)
}

fn glint_images(
    cam: &Camera,
    g: &[Option<methods::GPixel>],
    tex: &Texture,
    lights: &[light::Light],
    sigma_r: f64,
    cps: &[glints::CpGlints],
) -> Vec<MethodImage> {
    let w = cam.width;
    let img = |f: &(dyn Fn(usize, &methods::GPixel) -> f32 + Sync)| -> Vec<f32> {
        (0..g.len())
            .into_par_iter()
            .map(|k| g[k].as_ref().map_or(0.0, |gp| f(k, gp)))
            .collect()
    };
    let mut out = Vec::new();
    let p = img(&|k, gp| {
        glints::brute(
            cam,
            gp,
            tex,
            lights,
            sigma_r,
            (k % w) as f64 + 0.5,
            (k / w) as f64 + 0.5,
        )
    });
    out.push(MethodImage {
        key: "pndf-brute".into(),
        label: "brute-force P-NDF footprint query (Eq 2)".into(),
        pixels: p,
    });
    for cp in cps {
        let p = img(&|_, gp| cp.shade(gp, tex, lights));
        out.push(MethodImage {
            key: format!("cp-r{}", cp.rank),
            label: format!("CP range query, R = {}", cp.rank),
            pixels: p,
        });
    }
    let p = img(&|_, gp| glints::mip(gp, lights, sigma_r));
    out.push(MethodImage {
        key: "plain-mip".into(),
        label: "plain mip (renormalised normal)".into(),
        pixels: p,
    });
    out
}

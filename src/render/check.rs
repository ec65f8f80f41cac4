//! Checks of the renderer's truth against independent closed forms:
//! - a flat normal map under directional and point lights: the pixel's truth against the
//!   lobe integrated over the pixel square by a 16 × 16 Gauss–Legendre rule;
//! - a flat map with the isotropic LTC lobe under a quad light: the MC truth against the
//!   exact polygon integral of the LTC (seed 000 Eq 1; Heitz et al. 2016 Eq 9), averaged
//!   over the pixel by a 6 × 6 Gauss–Legendre rule;
//! - a flat map with seed 002's Gaussian lobe under an SG environment: the MC truth (MIS
//!   in l) against the same integral written in h_xy and taken by a 32² Gauss–Hermite rule
//!   ([`super::glints_sg::gaussian_lobe_integral`]), averaged over the pixel by 6 × 6
//!   Gauss–Legendre.
//!
//! Each returns the z-scores (truth − exact)/s.e. and the relative differences.

use super::geometry::{Camera, Surface};
use super::glints_sg::gaussian_lobe_integral;
use super::light::{self, Light};
use super::scene::{Lobe, Scene};
use super::texture::Texture;
use super::truth::{self, shading_frame, Shader};
use crate::error::Result;
use crate::integrate::quad::gauss_legendre;
use crate::leadr::Grid;
use crate::ltc::polygon::{ltc_integral, EdgeForm};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

type V3 = Vector3<f64>;

/// The comparison of one check.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct CheckResult {
    pub name: String,
    pub pixels: usize,
    /// Largest |truth − exact| / exact over pixels with exact > 1 % of the mean.
    #[serde(deserialize_with = "crate::integrate::estimate::f64_or_nan")]
    pub max_rel: f64,
    /// Σ(truth − exact)² / Σ s.e.² (≈ 1 when the standard errors are honest: each pixel's
    /// s.e. has one degree of freedom, so only the pooled ratio is meaningful).
    #[serde(deserialize_with = "crate::integrate::estimate::f64_or_nan")]
    pub mse_over_se2: f64,
    /// Fraction of pixels with |truth − exact| > 4 × the pooled s.e. √mean(s.e.²).
    #[serde(deserialize_with = "crate::integrate::estimate::f64_or_nan")]
    pub frac_z4: f64,
    /// Largest |truth − exact| relative to the image's mean.
    #[serde(deserialize_with = "crate::integrate::estimate::f64_or_nan")]
    pub max_abs_over_mean: f64,
}

/// Integrate f over the unit pixel square at (x, y) by an n × n Gauss–Legendre rule.
fn pixel_quad(n: usize, x: usize, y: usize, f: &dyn Fn(f64, f64) -> f64) -> f64 {
    let (nodes, weights) = gauss_legendre(n);
    let mut s = 0.0;
    for (a, wa) in nodes.iter().zip(&weights) {
        for (b, wb) in nodes.iter().zip(&weights) {
            s += 0.25 * wa * wb * f(x as f64 + 0.5 + 0.5 * a, y as f64 + 0.5 + 0.5 * b);
        }
    }
    s
}

/// The exact value at image point (px, py): point/directional lights by the lobe, quad
/// lights by the LTC polygon integral (LTC lobe only).
fn exact_at(cam: &Camera, surf: &Surface, sh: &Shader, alpha: f64, px: f64, py: f64) -> f64 {
    let Some(hit) = surf.intersect(&cam.eye, &cam.dir(px, py)) else {
        return 0.0;
    };
    let fr = &hit.frame;
    let v = fr.local(&(cam.eye - hit.p).normalize());
    let nt = V3::z();
    sh.lights
        .iter()
        .map(|l| match l {
            Light::Point { pos, intensity } => {
                let d = pos - hit.p;
                intensity / d.norm_squared() * sh.lobe(&nt, &v, &fr.local(&d.normalize()))
            }
            Light::Directional { dir, irradiance } => irradiance * sh.lobe(&nt, &v, &fr.local(dir)),
            Light::Quad { radiance, .. } => {
                let f = shading_frame(&nt, &v);
                let poly: Vec<V3> = l
                    .corners()
                    .map(|cs| {
                        cs.iter()
                            .map(|c| f.local(&fr.local(&(c - hit.p))))
                            .collect()
                    })
                    .unwrap_or_default();
                let m_inv = Matrix3::from_diagonal(&V3::new(1.0 / alpha, 1.0 / alpha, 1.0));
                radiance * ltc_integral(&m_inv, &poly, EdgeForm::Exact)
            }
            // the Gaussian lobe's integral in h_xy ([`run`] refuses other lobes under SGs)
            Light::Sg(env) => {
                gaussian_lobe_integral(env, fr, &v, &nt, sh.sigma_r, &Grid::gauss_hermite(32))
            }
        })
        .sum()
}

/// Render the truth of a flat-map scene and compare it with the closed form.
pub fn run(scene: &Scene, name: &str, quad_nodes: usize) -> Result<CheckResult> {
    let tex = Texture::new(super::normal_map(scene, std::path::Path::new("."))?);
    let lights = light::resolve(&scene.lights);
    let m = &scene.material;
    if m.lobe != Lobe::Gaussian && lights.iter().any(|l| matches!(l, Light::Sg(_))) {
        return Err(crate::error::Error::InvalidArgument(format!(
            "render check {name}: an SG environment has a closed form here for seed 002's Gaussian lobe only"
        )));
    }
    let sh = Shader::new(m.lobe, m.alpha, m.sigma_r, &lights, &tex)?;
    let cam = Camera::at_frame(&scene.camera, 0);
    let surf = Surface::new(&scene.surface, 1.0);
    let (w, h) = (cam.width, cam.height);
    let rows: Vec<(f64, f64, f64)> = (0..w * h)
        .into_par_iter()
        .filter_map(|k| {
            let (x, y) = (k % w, k / w);
            let t = truth::pixel(
                &cam,
                &surf,
                &sh,
                x,
                y,
                truth::Budget {
                    n: scene.render.truth_samples,
                    draws: scene.render.truth_draws,
                },
                scene.render.seed,
            );
            if !t.covered {
                return None;
            }
            let e = pixel_quad(quad_nodes, x, y, &|px, py| {
                exact_at(&cam, &surf, &sh, m.alpha, px, py)
            });
            Some((t.value, t.se(), e))
        })
        .collect();
    let n = rows.len().max(1) as f64;
    let mean = rows.iter().map(|r| r.2).sum::<f64>() / n;
    let mut out = CheckResult {
        name: name.into(),
        pixels: rows.len(),
        max_rel: 0.0,
        mse_over_se2: 0.0,
        frac_z4: 0.0,
        max_abs_over_mean: 0.0,
    };
    let se2 = rows.iter().map(|r| r.1 * r.1).sum::<f64>() / n;
    let d2 = rows.iter().map(|r| (r.0 - r.2).powi(2)).sum::<f64>() / n;
    out.mse_over_se2 = if se2 > 0.0 {
        d2 / se2
    } else if d2 == 0.0 {
        0.0
    } else {
        f64::INFINITY
    };
    for &(t, _, e) in &rows {
        if e > 0.01 * mean {
            out.max_rel = out.max_rel.max((t - e).abs() / e);
        }
        out.max_abs_over_mean = out.max_abs_over_mean.max((t - e).abs() / mean.max(1e-300));
        if se2 > 0.0 && (t - e).abs() > 4.0 * se2.sqrt() {
            out.frac_z4 += 1.0 / n;
        }
    }
    Ok(out)
}

/// The check scenes: (name, scene text, Gauss–Legendre nodes per axis).
pub fn scenes() -> Vec<(&'static str, String, usize)> {
    let base = |lobe: &str, lights: &str, samples: usize| {
        format!(
            "name = \"check\"\n[camera]\nposition = [0.0, -1.5, 1.2]\nlook_at = [0.0, 0.0, 0.0]\nfov_deg = 10.0\nwidth = 32\nheight = 32\n[surface]\nkind = \"plane\"\nrepeats = [1.0, 1.0]\n[material]\nlobe = \"{lobe}\"\nalpha = 0.3\nsigma_r = 0.05\nnormal_map = \"flat\"\nmap_size = 8\n{lights}\n[render]\nmethods = \"truth-only\"\ntruth_samples = {samples}\nseed = 5\n"
        )
    };
    vec![
        (
            "flat map, GGX α 0.3, directional + point light (closed form)",
            base(
                "ggx",
                "[[lights]]\nkind = \"directional\"\ndirection = [0.0, 1.0, 1.0]\nirradiance = 1.0\n[[lights]]\nkind = \"point\"\nposition = [0.3, 1.0, 1.0]\nintensity = 2.0",
                64,
            ),
            16,
        ),
        (
            "flat map, isotropic LTC α 0.3, quad light (polygon integral)",
            base(
                "ltc",
                "[[lights]]\nkind = \"quad\"\ncenter = [0.0, 1.2, 1.0]\nu_axis = [1.0, 0.0, 0.0]\nv_axis = [0.0, -1.0, 1.2]\nhalf_size = [0.5, 0.3]\nradiance = 1.0",
                512,
            ),
            6,
        ),
        (
            "flat map, seed 002's Gaussian σ_r 0.05, SG environment (Gauss–Hermite in h_xy)",
            base(
                "gaussian",
                // a broad sky, and a sharp lobe near the mirror direction (the reflection of
                // the view about z points along (0, 0.78, 0.62))
                "[[lights]]\nkind = \"sg\"\nlobes = [{ axis = [0.0, 0.0, 1.0], lambda = 2.0, amplitude = 0.8 }, { axis = [0.05, 0.8, 0.6], lambda = 60.0, amplitude = 5.0 }]",
                512,
            ),
            6,
        ),
    ]
}

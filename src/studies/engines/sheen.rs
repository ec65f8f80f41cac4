//! The sheen check: three.js r187 renders a scene file (the sheen check's own,
//! engines/three/scenes_sheen.json, or the GGX check's) with a
//! MeshPhysicalMaterial that is sheen alone (a black dielectric base with specular
//! intensity 0 under a white sheen of sheenRoughness = the scene's roughness), once as
//! three is and once with our recipe (results/textures/three/RectAreaLightSheen.js:
//! the texture-free Neubelt sheen LTC added to RE_Direct_RectArea_Physical), and every
//! pixel is judged against the truth: L·∫_P f(l) dω with f the Charlie sheen BRDF with
//! Neubelt's visibility (three's BRDF_Sheen without its half-precision clamps) times
//! the cosine, by the same adaptive cubature as the GGX scenes (`engines::truth`).
//!
//! Per scene, against the truth: three as shipped (no sheen under RectAreaLight: 0), the
//! recipe's image, the recipe's series with the exact edge integral (its own share), and
//! our sampled Neubelt table (binary16, bilinear, as a texture would hold it) with the
//! exact edge integral (what a second texture would buy); and the recipe's image against
//! three's formula in f64 with the series' entries (the GPU's share: f32, `exp`).

use super::compute::{check_path, errors, image, EngineScene, Errors, TRUTH_REL};
use crate::engines::truth::{lookup, table_value, three_value, truth_value};
use crate::engines::{EngineScenes, Rect};
use crate::error::{Error, Result};
use crate::integrate::{Figure, Quad};
use crate::ltc::lobes::Lobe;
use crate::ltc::target::LtcTarget;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The table the recipe's series comes from (results/fits/ltc-compact.json's family).
pub const TABLE: &str = "ltc-sheen-neubelt";

/// three.js clamps sheenRoughness to [0.07, 1] (lights_physical_fragment).
pub const THREE_MIN_SHEEN_ROUGHNESS: f64 = 0.07;

/// The harness's sheen run: per path ("shipped", "recipe") every scene's pixels.
#[derive(Clone, Debug, Deserialize)]
pub struct SheenRun {
    pub table: String,
    pub engine: String,
    /// The scene file it rendered, relative to the repository root.
    pub scenes: String,
    #[serde(default)]
    pub adapter: String,
    pub paths: std::collections::BTreeMap<String, Vec<EngineScene>>,
}

/// The paths a sheen run holds: WebGLRenderer as three is and with the recipe.
pub const PATHS: [&str; 2] = ["shipped", "recipe"];

/// The WebGPURenderer paths, as three is and with RectAreaLightSheenNode: both or neither
/// (where Chromium offers no WebGPU adapter).
pub const WEBGPU_PATHS: [&str; 2] = ["webgpu-shipped", "webgpu-recipe"];

impl SheenRun {
    /// Read a run without checking it against a scene file (the scene file it names is
    /// read next; then [`SheenRun::check`]).
    pub fn from_json(text: &str) -> Result<SheenRun> {
        serde_json::from_str(text).map_err(|e| {
            Error::InvalidArgument(format!("engines-sheen: the three.js sheen run: {e}"))
        })
    }

    /// Check against the scenes: the sheen table's run, the WebGL paths and both WebGPU
    /// paths or neither, every scene, every size, every pixel finite.
    pub fn check(&self, scenes: &EngineScenes) -> Result<()> {
        let bad = |m: String| {
            Error::InvalidArgument(format!("engines-sheen: the three.js sheen run: {m}"))
        };
        if self.table != "sheen" {
            return Err(bad(format!(
                "a run of the {} table, not the sheen run (render.mjs --table sheen)",
                crate::error::quoted(&self.table)
            )));
        }
        if let Some(p) = self
            .paths
            .keys()
            .find(|p| !PATHS.contains(&p.as_str()) && !WEBGPU_PATHS.contains(&p.as_str()))
        {
            return Err(bad(format!("unknown path {}", crate::error::quoted(p))));
        }
        let webgpu = WEBGPU_PATHS
            .iter()
            .filter(|p| self.paths.contains_key(**p))
            .count();
        if webgpu == 1 {
            return Err(bad("one WebGPU path without the other".into()));
        }
        let optional: &[&str] = if webgpu == 2 { &WEBGPU_PATHS } else { &[] };
        for p in PATHS.iter().chain(optional) {
            check_path(&self.paths, p, scenes).map_err(bad)?;
        }
        Ok(())
    }

    /// [`SheenRun::from_json`], then [`SheenRun::check`].
    pub fn parse(text: &str, scenes: &EngineScenes) -> Result<SheenRun> {
        let r = Self::from_json(text)?;
        r.check(scenes)?;
        Ok(r)
    }
}

/// A render's error against the truth in two scales: relative to the truth itself
/// (relative RMSE, as the GGX scenes report it; meaningless where the sheen barely
/// reflects the light and the truth is ~0), and relative to the lobe's albedo (the RMS
/// error per pixel over the radiance a unit-radiance sky would give: the error's share of
/// what the sheen can reflect at all); each ± what the truth's bars allow.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SheenErrors {
    pub rel_rmse: Figure<Quad>,
    pub rms_over_albedo: Figure<Quad>,
}

/// `albedo` is (value, its quadrature error bound): both bars widen the figure's.
fn sheen_errors(x: &[f64], truth: &[Figure<Quad>], albedo: (f64, f64)) -> SheenErrors {
    let (albedo, albedo_err) = albedo;
    let (mut a, mut da) = (0.0, 0.0);
    for (x, t) in x.iter().zip(truth) {
        let d = x - t.value;
        a += d * d;
        da += 2.0 * d.abs() * t.error + t.error * t.error;
    }
    let n = truth.len().max(1) as f64;
    let at = |s: f64, alb: f64| (s.max(0.0) / n).sqrt() / alb;
    let v = at(a, albedo);
    let hi = at(a + da, (albedo - albedo_err).max(1e-300));
    let lo = at(a - da, albedo + albedo_err);
    SheenErrors {
        rel_rmse: errors(x, truth).rel_rmse,
        rms_over_albedo: Figure::<Quad>::new(v, (hi - v).max(v - lo)),
    }
}

/// One scene judged.
#[derive(Clone, Debug, Serialize)]
pub struct SheenScene {
    pub name: String,
    pub roughness: f64,
    pub view_deg: f64,
    pub pixels: usize,
    /// The truth's largest relative error bar over the pixels lit by at least 1 % of the
    /// scene's peak.
    pub truth_rel_error: f64,
    /// The truth's largest value (the scene's scale).
    pub truth_peak: f64,
    /// The lobe's directional albedo at the scene's view (quadrature to 1e-8) and its
    /// error bound.
    pub albedo: f64,
    pub albedo_error: f64,
    /// three.js as shipped against the truth.
    pub shipped: SheenErrors,
    /// The largest |pixel| three as shipped renders (0: no sheen at all).
    pub shipped_max: f64,
    /// three.js with the recipe against the truth.
    pub recipe: SheenErrors,
    /// The recipe's series (f32 entries) with the exact edge integral against the truth.
    pub series_share: SheenErrors,
    /// Our sampled Neubelt table (binary16, bilinear) with the exact edge integral against
    /// the truth.
    pub table_share: SheenErrors,
    /// The recipe's image against three's formula in f64 with the series' entries.
    pub gpu_share: Errors,
    /// WebGPURenderer, where the run has it: as shipped (its largest pixel) and with
    /// RectAreaLightSheenNode (against the truth and against the formula).
    pub webgpu: Option<WebGpuSheen>,
    /// Images for a figure: truth, recipe.
    #[serde(skip)]
    pub images: Vec<(String, Vec<f64>)>,
}

/// One scene on WebGPURenderer.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct WebGpuSheen {
    pub shipped_max: f64,
    pub recipe: SheenErrors,
    pub gpu_share: Errors,
}

/// The whole check.
#[derive(Clone, Debug, Serialize)]
pub struct SheenResult {
    /// The scene file (relative to the repository root).
    pub scenes_file: String,
    pub version: String,
    pub adapter: String,
    pub width: usize,
    pub height: usize,
    /// The recipe's series as the compact study describes it.
    pub series: String,
    pub scenes: Vec<SheenScene>,
}

/// Judge a sheen run with the series and table of `results`.
pub fn judge(sc: &EngineScenes, run: &SheenRun, results: &std::path::Path) -> Result<SheenResult> {
    let (series, desc) = crate::results::ltc_compact::texture_free_series(results, TABLE)?
        .ok_or_else(|| {
            Error::InvalidArgument(format!(
                "engines-sheen: {} holds no texture-free {TABLE} form (regen --only ltc-compact)",
                results.join("fits/ltc-compact.json").display()
            ))
        })?;
    let coeffs = series.coeffs_f32();
    let table = super::compute::Held::of(&crate::ltc::compare::stored_half(
        &crate::results::ltc::table(results, TABLE)?,
    ));
    let mut out = Vec::new();
    for (k, s) in sc.scenes.iter().enumerate() {
        crate::report::stage(&format!(
            "engines-sheen: scene {} of {}: {}",
            k + 1,
            sc.scenes.len(),
            s.name
        ));
        let light = Rect::of(&s.light).ok_or_else(|| {
            Error::InvalidArgument(format!("engines-sheen: scene {}: degenerate light", s.name))
        })?;
        let r = s.roughness.clamp(THREE_MIN_SHEEN_ROUGHNESS, 1.0);
        let lobe = Lobe::SheenNeubelt.target(r * r, s.view_deg.to_radians())?;
        let pos = &run.paths["recipe"][k].positions;
        let pts: Vec<(usize, Vector3<f64>)> = (0..sc.width * sc.height)
            .filter(|&p| pos[4 * p + 3] > 0.5)
            .map(|p| (p, Vector3::new(pos[4 * p], pos[4 * p + 1], pos[4 * p + 2])))
            .collect();
        for path in run.paths.keys() {
            let other = &run.paths[path][k].positions;
            if pts
                .iter()
                .any(|(p, x)| (0..3).any(|c| (other[4 * p + c] - x[c]).abs() > 1e-4))
            {
                return Err(Error::InvalidArgument(format!(
                    "engines-sheen: scene {}: the {path} path covers other points",
                    s.name
                )));
            }
        }
        let truth: Vec<Figure<Quad>> =
            crate::memo::map_items(&format!("engine sheen truth {}", s.name), &pts, |(_, x)| {
                Ok(truth_value(&lobe, &light, x, TRUTH_REL))
            })?;
        let ndotv = s.view_deg.to_radians().cos();
        let t = (1.0 - ndotv).max(0.0).sqrt();
        let e = series.eval_f32(&coeffs, r as f32, t as f32).map(f64::from);
        let series_entries = [e[0], e[1], e[2], e[3], e[4]];
        let table_entries = lookup(&table.cells, table.n, r, ndotv);
        let px = |path: &str| -> Vec<f64> {
            let rad = &run.paths[path][k].radiance;
            pts.iter().map(|(p, _)| rad[4 * p]).collect()
        };
        let (shipped, recipe) = (px("shipped"), px("recipe"));
        let at = |f: &dyn Fn(&Vector3<f64>) -> f64| -> Vec<f64> {
            pts.iter().map(|(_, x)| f(x)).collect()
        };
        let series_v = at(&|x| table_value(&series_entries, &light, x));
        let table_v = at(&|x| table_value(&table_entries, &light, x));
        let formula = at(&|x| three_value(&series_entries, &light, x));
        let exact = |v: &[f64]| -> Vec<Figure<Quad>> {
            v.iter().map(|v| Figure::<Quad>::new(*v, 0.0)).collect()
        };
        let peak = truth.iter().map(|b| b.value).fold(0.0, f64::max);
        let (albedo, albedo_err, _) = lobe.albedo(1e-8);
        if !(albedo > albedo_err) {
            return Err(Error::InvalidArgument(format!(
                "engines-sheen: scene {}: the lobe's albedo is {albedo} ± {albedo_err}",
                s.name
            )));
        }
        out.push(SheenScene {
            name: s.name.clone(),
            roughness: s.roughness,
            view_deg: s.view_deg,
            pixels: pts.len(),
            truth_rel_error: truth
                .iter()
                .filter(|b| b.value > 1e-2 * peak && b.value > 0.0)
                .map(|b| b.error / b.value)
                .fold(0.0, f64::max),
            truth_peak: peak,
            albedo,
            albedo_error: albedo_err,
            shipped: sheen_errors(&shipped, &truth, (albedo, albedo_err)),
            shipped_max: shipped.iter().map(|v| v.abs()).fold(0.0, f64::max),
            recipe: sheen_errors(&recipe, &truth, (albedo, albedo_err)),
            series_share: sheen_errors(&series_v, &truth, (albedo, albedo_err)),
            table_share: sheen_errors(&table_v, &truth, (albedo, albedo_err)),
            gpu_share: errors(&recipe, &exact(&formula)),
            webgpu: run.paths.contains_key(WEBGPU_PATHS[1]).then(|| {
                let (ws, wr) = (px(WEBGPU_PATHS[0]), px(WEBGPU_PATHS[1]));
                WebGpuSheen {
                    shipped_max: ws.iter().map(|v| v.abs()).fold(0.0, f64::max),
                    recipe: sheen_errors(&wr, &truth, (albedo, albedo_err)),
                    gpu_share: errors(&wr, &exact(&formula)),
                }
            }),
            images: vec![
                (
                    "truth".into(),
                    image(sc, &pts, &truth.iter().map(|b| b.value).collect::<Vec<_>>()),
                ),
                ("recipe".into(), image(sc, &pts, &recipe)),
            ],
        });
    }
    Ok(SheenResult {
        scenes_file: run.scenes.clone(),
        version: run.engine.clone(),
        adapter: run.adapter.clone(),
        width: sc.width,
        height: sc.height,
        series: desc,
        scenes: out,
    })
}

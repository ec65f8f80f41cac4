//! `regen --only render`: the rendered evidence (fits/render.toml). Three figure sets from
//! the example scenes of fits/render/: seed 000's multi-scale LTC over view distances,
//! seed 003's specular antialiasing over a dolly, seed 002's glints (flakes, and the same
//! scene with the scratches map; and the flakes under a sky of spherical Gaussians, where
//! §5.4's prefiltered query meets the point query) — each against the footprint-averaged
//! truth — and the
//! renderer's own checks against closed forms → results/render.md, results/render/*.png,
//! results/fits/render.json. Also `render SCENE.toml --out DIR` for one scene.
//!
//! Nothing is fitted: each method shades one centre sample per pixel through the shipped
//! f32 code, the map read trilinearly from its linear mip chain, with the refitted
//! constants of results/fits/filters.json; the truth is the supersampled footprint
//! average. Measures: MSE and relative MSE of linear radiance, ꟻLIP of the tone-mapped
//! images, flicker (the change between frames) against the truth's. The spec's tolerance
//! bounds the renderer's checks against closed forms.

pub mod fig11;
pub mod report;

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::io::Outputs;
use crate::render::scene::Scene;
use crate::render::{check, measure, GlintPlan, Render};
use crate::study::{Ctx, FitOutcome};
use std::path::Path;

/// The example scenes, as shipped in fits/render/.
pub const SCENES: [(&str, &str); 4] = [
    (
        "multiscale-ltc-plane",
        include_str!("../../../fits/render/multiscale-ltc-plane.toml"),
    ),
    (
        "specular-aa-torus",
        include_str!("../../../fits/render/specular-aa-torus.toml"),
    ),
    (
        "glints-plane",
        include_str!("../../../fits/render/glints-plane.toml"),
    ),
    (
        "glints-plane-sky",
        include_str!("../../../fits/render/glints-plane-sky.toml"),
    ),
];

/// What fits/render.toml sets: the renders' sizes and the glint models' scale.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Image width in pixels (the height keeps the scene's aspect, even, ≥ 8); absent: as
    /// each scene is written.
    #[serde(default)]
    pub side: Option<usize>,
    /// Each scene's truth samples are multiplied by this (at least 2 remain).
    pub truth_sample_scale: f64,
    /// At most this many frames of a camera path, and view scales (absent: all).
    #[serde(default)]
    pub max_frames: Option<usize>,
    #[serde(default)]
    pub max_scales: Option<usize>,
    /// The glint set's CP models.
    pub glints: GlintPlan,
}

impl crate::fit::spec::Params for Params {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::within;
        if let Some(s) = self.side {
            within("side", s, 8, 4096)?;
        }
        within("truth_sample_scale", self.truth_sample_scale, 1e-3, 64.0)?;
        if let Some(f) = self.max_frames {
            within("max_frames", f, 1, 10_000)?;
        }
        if let Some(f) = self.max_scales {
            within("max_scales", f, 1, 64)?;
        }
        let g = &self.glints;
        within("glints.res", g.res, 4, 1024)?;
        within("glints.stride", g.stride, 1, 1024)?;
        within("glints.t", g.t, 2, 64)?;
        crate::fit::spec::splits("glints.res", g.res, "glints.t", g.t)?;
        for (i, &r) in g.ranks.iter().enumerate() {
            within(&format!("glints.ranks[{i}]"), r, 1, g.t * g.t)?;
        }
        within("glints.iters", g.iters, 1, 100_000)?;
        within("glints.env_spp", g.env_spp, 1, 65_536)?;
        within("glints.env_spp_high", g.env_spp_high, 1, 65_536)?;
        within("glints.env_eps", g.env_eps, 1e-9, 1e9)?;
        within("glints.env_scale", g.env_scale, 1e-3, 1e3)
    }
}

/// fits/render.toml as this build compiled it in: the glint plan of `render SCENE.toml`.
const SPEC: &str = include_str!("../../../fits/render.toml");

/// The study's parameters at `preset`, from the compiled-in spec.
pub fn builtin_params(preset: Preset) -> Result<Params> {
    FitSpec::compiled_params(SPEC, "fits/render.toml", preset)
}

/// The scene at the study's size: the width, truth samples, frames and scales `p` sets.
pub fn sized(mut s: Scene, p: &Params) -> Scene {
    if let Some(side) = p.side {
        let k = side as f64 / s.camera.width as f64;
        s.camera.width = side;
        s.camera.height = ((s.camera.height as f64 * k).round() as usize).max(8) & !1;
    }
    s.render.truth_samples =
        ((s.render.truth_samples as f64 * p.truth_sample_scale).round() as usize).max(2);
    if let Some(f) = p.max_frames {
        if let Some(path) = &mut s.camera.path {
            path.frames = path.frames.min(f);
        }
    }
    if let Some(n) = p.max_scales {
        s.render.scales.truncate(n);
    }
    s
}

/// Render and measure one scene; write its pictures into `pictures`.
pub fn render_one(
    set: &mut crate::io::Outputs,
    scene: &Scene,
    base: &Path,
    results: &Path,
    preset: Preset,
    pictures: &Path,
) -> Result<(Render, measure::Measured, Vec<std::path::PathBuf>)> {
    let c = crate::results::render::constants(results)?;
    let r = crate::render::render(scene, base, &c, &builtin_params(preset)?.glints)?;
    let m = measure::measure_render(&r);
    let files = report::put_pictures(set, pictures, &r, &m, report::TILE.min(r.width))?;
    Ok((r, m, files))
}

/// `render SCENE.toml --out DIR`: DIR/<name>.md, DIR/<name>.json and the pictures.
pub fn render_file(
    set: &mut crate::io::Outputs,
    file: &Path,
    out: &Path,
    results: &Path,
    preset: Preset,
) -> Result<Vec<String>> {
    let scene = Scene::load(file)?;
    let base = file.parent().unwrap_or(Path::new("."));
    let (r, m, files) = render_one(set, &scene, base, results, preset, out)?;
    let md = format!(
        "# Render of {}\n\nWritten by `cargo run --release -- render {}` (preset {}).\n\n{}",
        scene.name,
        file.display(),
        preset.name(),
        report::markdown(&r, &m, ".")
    );
    let mdp = out.join(format!("{}.md", scene.name));
    let jp = out.join(format!("{}.json", scene.name));
    set.put(&mdp, md.as_bytes());
    set.put(
        &jp,
        crate::results::json_text(&scene.name, &report::json(&r, &m))?.as_bytes(),
    );
    let mut names: Vec<String> = files.iter().map(|p| p.display().to_string()).collect();
    names.push(mdp.display().to_string());
    names.push(jp.display().to_string());
    Ok(names)
}

fn checks_section(rows: &[check::CheckResult]) -> String {
    let mut md = String::from("## The truth, checked\n\nThe renderer's truth on flat maps, where a closed form exists (render/check.rs; the same checks run in tests/render.rs). 32² pixels of 10° field of view; the exact value is the lobe (or the LTC's exact polygon integral, or seed 002's Gaussian lobe against the SGs by a 32² Gauss–Hermite rule in h_xy, written independently of the truth's MIS in l) averaged over each pixel square by Gauss–Legendre (16² or 6² nodes). The ratio Σ(truth − exact)²/Σs.e.² is ≈ 1 when the standard errors are honest. Point and directional lights on exact footprints involve no MC: what remains is the midpoint rule within each texel's share of the pixel.\n\n");
    let mut t = crate::report::table::Table::new([
        "check",
        "pixels",
        "max relative difference",
        "Σ(t − e)²/Σ s.e.²",
        "pixels beyond 4 pooled s.e.",
    ]);
    for r in rows {
        let ratio = if r.mse_over_se2.is_finite() {
            format!("{:.2}", r.mse_over_se2)
        } else {
            "— (s.e. 0: no MC)".into()
        };
        t.row([
            r.name.to_string(),
            r.pixels.to_string(),
            format!("{:.2e}", r.max_rel),
            ratio,
            format!("{:.1} %", 100.0 * r.frac_z4),
        ]);
    }
    md.push_str(&t.to_string());
    md
}

/// One rendered scene and its measurements.
pub struct Rendered {
    pub render: Render,
    pub measured: measure::Measured,
}

/// What the render study computed: the truth checks and, per figure set, its scenes.
pub struct Computed {
    pub preset: Preset,
    pub spec: FitSpec,
    pub checks: Vec<check::CheckResult>,
    /// (section title, the scenes rendered for it).
    pub sections: Vec<(&'static str, Vec<Rendered>)>,
    /// Seed 002 Fig 11's claim on the scene under SGs.
    pub fig11: Option<crate::results::render::Fig11>,
}

impl Computed {
    /// The smallest excess of the baseline's mean squared frame-to-frame change over the
    /// truth's, over the paths.
    fn worst_flicker_gap(&self) -> f64 {
        self.sections
            .iter()
            .flat_map(|(_, v)| v)
            .filter_map(
                |r| match (r.measured.flicker.first(), r.measured.truth_change) {
                    (Some(none), Some(_)) => Some(none.2.excess.value),
                    _ => None,
                },
            )
            .fold(f64::INFINITY, f64::min)
    }

    fn worst_check(&self) -> f64 {
        self.checks.iter().map(|c| c.max_rel).fold(0.0, f64::max)
    }
}

pub fn compute(c: &Ctx) -> Result<Computed> {
    let (results, preset) = (c.results, c.preset);
    let pa: Params = c.params()?;
    let checks: Vec<check::CheckResult> = check::scenes()
        .iter()
        .map(|(name, text, nodes)| {
            Scene::parse(text, name).and_then(|s| check::run(&s, name, *nodes))
        })
        .collect::<Result<_>>()?;
    let titles = [
        "## (a) Seed 000: multi-scale LTC under a quad light, over view distances",
        "## (b) Seed 003: specular antialiasing along a dolly",
        "## (c) Seed 002: glints under a small quad light",
        "## (d) Seed 002 §5.4: glints under an environment of spherical Gaussians (Fig 11)",
    ];
    let constants = crate::results::render::constants(results)?;
    let mut sections = Vec::new();
    for (k, (name, text)) in SCENES.iter().enumerate() {
        let base = sized(Scene::parse(text, name)?, &pa);
        let mut variants = vec![base.clone()];
        // the quad-light glints again with the scratches map
        if base.name == "glints-plane" {
            let mut s = base.clone();
            s.name = format!("{}-scratches", base.name);
            s.material.normal_map = "scratches".into();
            s.description = base.description.replace(
                "flakes normal map (1024², flakes tilted up to 25°)",
                "scratches normal map (1024², V-grooves with slopes ±0.6)",
            );
            variants.push(s);
        }
        let mut rendered = Vec::new();
        for s in variants {
            crate::report::stage(&format!(
                "render {}: {}×{}, {} views",
                s.name,
                s.camera.width,
                s.camera.height,
                s.render.scales.len() * s.frames()
            ));
            let render =
                crate::render::render(&s, Path::new("fits/render"), &constants, &pa.glints)?;
            let measured = measure::measure_render(&render);
            rendered.push(Rendered { render, measured });
        }
        sections.push((titles[k], rendered));
    }
    let all: Vec<(&Render, &measure::Measured)> = sections
        .iter()
        .flat_map(|(_, v)| v)
        .map(|r| (&r.render, &r.measured))
        .collect();
    let fig11 = fig11::judge(&all, &pa.glints);
    Ok(Computed {
        preset,
        spec: c.spec.clone(),
        checks,
        sections,
        fig11,
    })
}

fn render(set: &mut Outputs, results: &Path, c: &Computed) -> Result<()> {
    let pictures = results.join("render");
    let mut md = format!(
        "# Rendered evidence\n\nWritten by `cargo run --release -- regen --only render` (preset {}) from `fits/render.toml` and the scenes of `fits/render/`. Every method shades one sample at the pixel centre through the shipped f32 code (the generated twins of the WGSL, the f32 filter forms, the GGX LTC table as stored in binary16, bilinear; quad lights through the SIMD kernel `kernels::ltc_quad`); the truth shades every texel the pixel covers with its own lobe, weighted by its exact overlap (jittered supersampling beyond 4096 texels; where a scene sets `truth_draws`, a larger footprint under a quad light or an SG environment draws that many texels per replicate in proportion to their overlap, the choice results/render-truth-work.md supports), quad lights and SG environments by MIS on scrambled Sobol points (render/truth.rs). Errors are over the pixels the surface covers entirely. Grid tiles are the centre {}² crops (never downsampled); the ꟻLIP maps under each tile use the magma map from 0 (black) to 1 (the bar under the truth column). The cost of each method per pixel is criterion's, in results/performance.md; this report holds no wall clock and no thread count, so it is the same on every machine.\n\n",
        c.preset.name(),
        report::TILE,
    );
    let mut json = Vec::new();
    for (title, rendered) in &c.sections {
        md.push_str(&format!("{title}\n\n"));
        for Rendered {
            render: r,
            measured: m,
        } in rendered
        {
            report::put_pictures(set, &pictures, r, m, report::TILE.min(r.width))?;
            md.push_str(&report::markdown(r, m, "render"));
            md.push('\n');
            json.push(report::json(r, m));
            if let Some(f) = c.fig11.as_ref().filter(|f| f.scene == r.scene.name) {
                md.push_str(&fig11::markdown(f));
            }
        }
    }
    md.push_str(&checks_section(&c.checks));
    set.put(&results.join("render.md"), md.as_bytes());
    crate::results::put_named(
        set,
        results,
        &c.spec.name,
        &crate::results::render::Render {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            checks: c.checks.clone(),
            renders: json,
            fig11: c.fig11.clone(),
            ltc_table_sha256: Some(crate::render::methods::ltc_table_sha256()),
        },
    )
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &Path) -> Result<()> {
        render(set, results, self)
    }

    fn outcome(&self) -> FitOutcome {
        let worst = self.worst_check();
        FitOutcome::judged(
            &self.spec,
            worst,
            format!(
                "{} scenes rendered; truth checks: largest relative difference {:.2e}; the baseline's mean squared change between frames exceeds the truth's by {:.2e}; seed 002 Fig 11: {}",
                self.sections.iter().map(|(_, v)| v.len()).sum::<usize>(),
                worst,
                self.worst_flicker_gap(),
                self.fig11.as_ref().map_or("not rendered", |f| f.verdict.as_str())
            ),
        )
    }
}

crate::study::study! {
    /// The rendered evidence; the renders read the footprint study's refitted constants, as the
    /// registry holds it.
    RenderStudy = "render", after ["filters"], on request false, params Params, computes compute
}

//! The engine check's computation: the engines and their runs, the held-out figures of each
//! table an engine holds, and every scene's pixels against the truth with their error
//! statistics.

use crate::engines::truth::{bevy_value, lobe, lookup, table_value, three_value, truth_value};
use crate::engines::EngineScenes;
use crate::engines::Rect;
use crate::error::{Error, Result};
use crate::integrate::{Figure, Quad};
use crate::ltc::compact::Compact;
use crate::ltc::compare::Shipped;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The engines the check renders in: one list, read by the CLI, the study and the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Engine {
    /// three.js r187's WebGLRenderer (`RectAreaLight`, lights_physical_pars_fragment).
    Three,
    /// Bevy 0.19.1 (`RectLight`, bevy_pbr's pbr_lighting.wgsl).
    Bevy,
}

impl Engine {
    pub const ALL: [Engine; 2] = [Engine::Three, Engine::Bevy];
    /// The name reports use.
    pub fn name(self) -> &'static str {
        match self {
            Engine::Three => "three.js",
            Engine::Bevy => "Bevy",
        }
    }
    /// The paths every harness run holds, each a way the engine stores the table.
    pub fn paths(self) -> &'static [&'static str] {
        match self {
            Engine::Three => &["float", "half"],
            Engine::Bevy => &["half"],
        }
    }
    /// Paths a run holds where the machine allows: three.js's WebGPURenderer (WebGPU on
    /// SwiftShader), on the float or the half textures as the adapter decides.
    pub fn optional_paths(self) -> &'static [&'static str] {
        match self {
            Engine::Three => &["webgpu-float", "webgpu-half"],
            Engine::Bevy => &[],
        }
    }
    /// The engine's own formula in f64 for the entries its lookup returns.
    pub fn formula(self, entries: &[f64; 5], light: &Rect, x: &Vector3<f64>) -> f64 {
        match self {
            Engine::Three => three_value(entries, light, x),
            Engine::Bevy => bevy_value(entries, light, x),
        }
    }
}

/// One engine render: per scene, the radiance (RGBA) and world positions (RGBA, alpha 1
/// where the plane covers the pixel), rows from the bottom, as the harnesses write them.
#[derive(Clone, Debug, Deserialize)]
pub struct EngineScene {
    pub name: String,
    pub radiance: Vec<f64>,
    pub positions: Vec<f64>,
}

/// A harness's output for one table: the engine and version, the adapter it ran on, and
/// the scenes per path.
#[derive(Clone, Debug, Deserialize)]
pub struct EngineRun {
    pub table: String,
    pub engine: String,
    #[serde(default)]
    pub adapter: String,
    /// The adapter of the WebGPU path, where there is one.
    #[serde(default)]
    pub webgpu_adapter: String,
    pub paths: std::collections::BTreeMap<String, Vec<EngineScene>>,
}

impl EngineRun {
    /// Parse and check against the scenes: every path the engine has, every scene, every
    /// size.
    pub fn parse(
        text: &str,
        scenes: &EngineScenes,
        engine: Engine,
        what: &str,
    ) -> Result<EngineRun> {
        let bad = |m: String| Error::InvalidArgument(format!("engines: {what}: {m}"));
        let r: EngineRun = serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
        if let Some(p) = r.paths.keys().find(|p| {
            !engine.paths().contains(&p.as_str()) && !engine.optional_paths().contains(&p.as_str())
        }) {
            return Err(bad(format!("unknown path {}", crate::error::quoted(p))));
        }
        let present = engine
            .optional_paths()
            .iter()
            .filter(|p| r.paths.contains_key(**p));
        for p in engine.paths().iter().chain(present) {
            check_path(&r.paths, p, scenes).map_err(bad)?;
        }
        Ok(r)
    }
}

/// Path `p` of a harness run against the scene file: present, one render per scene in
/// the file's order and names, RGBA images of the file's size, every pixel finite. The
/// defect as a message for the caller's error.
pub(super) fn check_path(
    paths: &std::collections::BTreeMap<String, Vec<EngineScene>>,
    p: &str,
    scenes: &EngineScenes,
) -> std::result::Result<(), String> {
    let px = scenes.width * scenes.height * 4;
    let v = paths.get(p).ok_or_else(|| format!("no {p} path"))?;
    if v.len() != scenes.scenes.len() {
        return Err(format!(
            "{p} path has {} scenes, the scene file {}",
            v.len(),
            scenes.scenes.len()
        ));
    }
    for (s, want) in v.iter().zip(&scenes.scenes) {
        if s.name != want.name || s.radiance.len() != px || s.positions.len() != px {
            return Err(format!(
                "scene {} does not match {} ({}×{} RGBA)",
                crate::error::quoted(&s.name),
                crate::error::quoted(&want.name),
                scenes.width,
                scenes.height
            ));
        }
        if s.radiance
            .iter()
            .chain(&s.positions)
            .any(|x| !x.is_finite())
        {
            return Err(format!(
                "scene {}: a pixel is not a finite number",
                crate::error::quoted(&s.name)
            ));
        }
    }
    Ok(())
}

/// A table as an engine path holds it: n×n cells of [a, b, c, d, norm].
#[derive(Clone, Debug)]
pub struct Held {
    pub n: usize,
    pub cells: Vec<[f64; 5]>,
}

impl Held {
    pub fn of(t: &Shipped) -> Held {
        Held {
            n: t.n,
            cells: t
                .mat
                .iter()
                .zip(&t.mag)
                .map(|(m, g)| [m[0], m[1], m[2], m[3], g[0]])
                .collect(),
        }
    }
}

/// Errors of one image against a reference over the covered pixels: relative RMSE
/// √(Σ(x − ref)²/Σ ref²) and the mean relative error over the pixels whose reference
/// exceeds 1 % of the image's largest; each ± the half-width the reference's error
/// bars allow (zero where the reference is exact).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Errors {
    pub rel_rmse: Figure<Quad>,
    pub mean_rel: Figure<Quad>,
}

pub(super) fn errors(x: &[f64], reference: &[Figure<Quad>]) -> Errors {
    let peak = reference.iter().map(|r| r.value).fold(0.0, f64::max);
    let (mut a, mut b, mut da, mut db) = (0.0, 0.0, 0.0, 0.0);
    let (mut rel, mut drel, mut cnt) = (0.0, 0.0, 0usize);
    for (x, r) in x.iter().zip(reference) {
        let d = x - r.value;
        a += d * d;
        b += r.value * r.value;
        da += 2.0 * d.abs() * r.error + r.error * r.error;
        db += 2.0 * r.value * r.error + r.error * r.error;
        if r.value > 1e-2 * peak && r.value > 0.0 {
            rel += d / r.value;
            // |∂/∂r (x − r)/r| = x/r²
            drel += x.abs() * r.error / (r.value * (r.value - r.error).max(1e-300));
            cnt += 1;
        }
    }
    let ratio = |a: f64, b: f64| {
        if b > 0.0 {
            (a.max(0.0) / b).sqrt()
        } else {
            f64::NAN
        }
    };
    let v = ratio(a, b);
    let hi = ratio(a + da, b - db);
    let lo = ratio(a - da, b + db);
    let m = cnt.max(1) as f64;
    Errors {
        rel_rmse: Figure::<Quad>::new(v, (hi - v).max(v - lo)),
        mean_rel: Figure::<Quad>::new(rel / m, drel / m),
    }
}

/// One (table, path) of one scene.
#[derive(Clone, Debug, Serialize)]
pub struct PathResult {
    pub table: &'static str,
    pub path: &'static str,
    /// The engine's image against the truth.
    pub engine: Errors,
    /// The table's own value (exact edge integral of its lookup) against the truth.
    pub table_share: Errors,
    /// The engine's image against the table's own value (the shader's share).
    pub shader_share: Errors,
    /// Of the shader's share, what the engine's formulas give in f64 ([`Engine::formula`]:
    /// its edge fit, its horizon) against the table's own value…
    pub formula_share: Errors,
    /// …and the engine against those formulas in f64: the GPU's f32 arithmetic and texture
    /// filtering, the rest.
    pub gpu_share: Errors,
}

/// One scene in one engine.
#[derive(Clone, Debug, Serialize)]
pub struct SceneResult {
    pub name: String,
    pub roughness: f64,
    pub view_deg: f64,
    pub pixels: usize,
    /// The truth's largest relative error bar over the pixels.
    pub truth_rel_error: f64,
    pub paths: Vec<PathResult>,
    /// Images for the figure (covered pixels in row order, 0 elsewhere): the truth and,
    /// per path, the engine's image.
    #[serde(skip)]
    pub images: Vec<(String, Vec<f64>)>,
    /// The covered pixels' surface points and the truth there (± its bar), kept for the
    /// judging that reuses them (Godot's formulas) instead of integrating them again.
    #[serde(skip)]
    pub truth: Vec<(Vector3<f64>, Figure<Quad>)>,
}

/// One engine's runs judged.
#[derive(Clone, Debug, Serialize)]
pub struct EngineResult {
    pub engine: Engine,
    /// The paths judged: every required one, and the optional ones every run holds.
    pub paths: Vec<&'static str>,
    /// The tables rendered, the shipped one first, then ours, then any other (three.js:
    /// [`COMPACT`]).
    pub tables: Vec<&'static str>,
    /// The engine and version as its harness reports them.
    pub version: String,
    /// The adapter the harness ran on (WebGL's version string, wgpu's adapter).
    pub adapter: String,
    pub scenes: Vec<SceneResult>,
}

/// Everything the report shows.
#[derive(Clone, Debug, Serialize)]
pub struct EnginesResult {
    pub width: usize,
    pub height: usize,
    pub engines: Vec<EngineResult>,
    /// Godot's formulas in f64 with our Godot files, where they were given.
    pub godot: Vec<GodotScene>,
    /// The files under results/ the runs loaded and the judge read, with their digests
    /// when judged: a table refitted since leaves this report stale.
    pub inputs: Vec<super::inputs::InputDigest>,
}

/// One engine's inputs: its harness runs, one per table, and what each (table, path)
/// holds.
pub struct Inputs<'a> {
    pub engine: Engine,
    /// (table, its run): the shipped table's first, then ours, then any other table the
    /// harness rendered (three.js: [`COMPACT`], the compact drop-in).
    pub runs: Vec<(&'static str, &'a EngineRun)>,
    /// (table, path, the table that path holds), for every path of the engine.
    pub held: Vec<(&'static str, &'static str, Held)>,
}

/// The compact drop-in's table name in the runs and the report.
pub const COMPACT: &str = "compact";

/// What the compact drop-in's textures hold (results/textures/three/
/// RectAreaLightTexturesLib.compact.js): texel (i, j) is the series' f32 evaluation at
/// (i, j)/(n − 1), the same f32 operations as its ES module's `rebuild` (tests/
/// codegen_compact.rs holds them equal bit for bit), for the float path, and its nearest
/// binary16 for the half path. A side below 2 (no texel spacing) is a typed error.
pub fn compact_held(c: &Compact, n: usize) -> Result<(Held, Held)> {
    if n < 2 {
        return Err(Error::InvalidArgument(format!(
            "engines: a compact table of side {n} (at least 2)"
        )));
    }
    let k = c.coeffs_f32();
    let at = |q: usize| {
        let v = c.eval_f32(
            &k,
            (q % n) as f32 / (n - 1) as f32,
            (q / n) as f32 / (n - 1) as f32,
        );
        [v[0], v[1], v[2], v[3], v[4]]
    };
    let f32s: Vec<[f32; 5]> = (0..n * n).map(at).collect();
    let held = |g: &dyn Fn(f32) -> f64| Held {
        n,
        cells: f32s.iter().map(|e| e.map(g)).collect(),
    };
    Ok((
        held(&|x| x as f64),
        held(&|x| half::f16::from_f32(x).to_f64()),
    ))
}

/// What three.js's paths hold: its f32 numbers and its truncated halves for the shipped
/// table; our f32 table and our stored binary16 one; and, given the compact series and its
/// side, what the compact drop-in rebuilds ([`compact_held`]).
pub fn three_held(
    shipped: &Shipped,
    ours: &crate::ltc::table::FittedTable,
    compact: Option<(&Compact, usize)>,
) -> Result<Vec<(&'static str, &'static str, Held)>> {
    use crate::ltc::upload::{f32_table, three_half_table};
    let o = crate::ltc::compare::of_table(ours);
    let (sf, sh) = (
        Held::of(&f32_table(shipped)),
        Held::of(&three_half_table(shipped)),
    );
    let (of, oh) = (
        Held::of(&f32_table(&o)),
        Held::of(&crate::ltc::compare::stored_half(ours)),
    );
    // WebGPURenderer binds the same four textures as WebGL (RectAreaLightNode)
    let mut v = vec![
        ("shipped", "float", sf.clone()),
        ("shipped", "half", sh.clone()),
        ("ours", "float", of.clone()),
        ("ours", "half", oh.clone()),
        ("shipped", "webgpu-float", sf),
        ("shipped", "webgpu-half", sh),
        ("ours", "webgpu-float", of),
        ("ours", "webgpu-half", oh),
    ];
    if let Some((c, n)) = compact {
        let (cf, ch) = compact_held(c, n)?;
        v.extend([
            (COMPACT, "float", cf.clone()),
            (COMPACT, "half", ch.clone()),
            (COMPACT, "webgpu-float", cf),
            (COMPACT, "webgpu-half", ch),
        ]);
    }
    Ok(v)
}

/// What Bevy's path holds: the binary16 texels of the KTX2 it was given (its embedded
/// table, or ours through `AreaLightLuts`).
pub fn bevy_held(shipped: &Shipped, ours: &Shipped) -> Vec<(&'static str, &'static str, Held)> {
    vec![
        ("shipped", "half", Held::of(shipped)),
        ("ours", "half", Held::of(ours)),
    ]
}

/// The truth's relative accuracy per pixel.
pub const TRUTH_REL: f64 = 1e-5;

/// Judge every pixel of every scene of one engine.
pub fn compute(s: &EngineScenes, inp: &Inputs) -> Result<EngineResult> {
    let e = inp.engine;
    let Some(&(_, first_run)) = inp.runs.first() else {
        return Err(Error::InvalidArgument(format!(
            "engines: {}: no run given",
            e.name()
        )));
    };
    // the paths every run holds
    let judged: Vec<&'static str> = e
        .paths()
        .iter()
        .chain(e.optional_paths())
        .copied()
        .filter(|p| inp.runs.iter().all(|(_, r)| r.paths.contains_key(*p)))
        .collect();
    let mut out = Vec::new();
    for (k, sc) in s.scenes.iter().enumerate() {
        crate::report::stage(&format!(
            "engines: {}: scene {} of {}: {}",
            e.name(),
            k + 1,
            s.scenes.len(),
            sc.name
        ));
        let light = Rect::of(&sc.light).ok_or_else(|| {
            Error::InvalidArgument(format!("engines: scene {}: degenerate light", sc.name))
        })?;
        let t = lobe(sc.roughness, sc.view_deg)?;
        let first = e.paths()[0];
        let pos = &first_run.paths[first][k].positions;
        // the covered pixels and their surface points
        let pts: Vec<(usize, Vector3<f64>)> = (0..s.width * s.height)
            .filter(|&p| pos[4 * p + 3] > 0.5)
            .map(|p| (p, Vector3::new(pos[4 * p], pos[4 * p + 1], pos[4 * p + 2])))
            .collect();
        // every run must have rendered the same pixels at the same points
        for (_, run) in &inp.runs {
            for path in &judged {
                let q = &run.paths[*path][k].positions;
                if pts
                    .iter()
                    .any(|(p, x)| (0..3).any(|c| (q[4 * p + c] - x[c]).abs() > 1e-4))
                {
                    return Err(Error::InvalidArgument(format!(
                        "engines: {} scene {}: the {} table's {path} run covers other points",
                        e.name(),
                        sc.name,
                        run.table
                    )));
                }
            }
        }
        let truth: Vec<Figure<Quad>> = crate::memo::map_items(
            &format!("engine truth {} {}", e.name(), sc.name),
            &pts,
            |(_, x)| Ok(truth_value(&t, &light, x, TRUTH_REL)),
        )?;
        let ndotv = sc.view_deg.to_radians().cos();
        let mut paths = Vec::new();
        let mut images = vec![(
            "truth".to_string(),
            image(s, &pts, &truth.iter().map(|b| b.value).collect::<Vec<_>>()),
        )];
        for (table, path, h) in inp.held.iter().filter(|h| judged.contains(&h.1)) {
            let Some(&(_, run)) = inp.runs.iter().find(|r| r.0 == *table) else {
                continue;
            };
            let ent = lookup(&h.cells, h.n, sc.roughness, ndotv);
            let tv: Vec<f64> = pts
                .iter()
                .map(|(_, x)| table_value(&ent, &light, x))
                .collect();
            let fv: Vec<f64> = pts
                .iter()
                .map(|(_, x)| e.formula(&ent, &light, x))
                .collect();
            let rad = &run.paths[*path][k].radiance;
            let ev: Vec<f64> = pts.iter().map(|(p, _)| rad[4 * p]).collect();
            let exact = |v: &[f64]| -> Vec<Figure<Quad>> {
                v.iter().map(|v| Figure::<Quad>::new(*v, 0.0)).collect()
            };
            paths.push(PathResult {
                table,
                path,
                engine: errors(&ev, &truth),
                table_share: errors(&tv, &truth),
                shader_share: errors(&ev, &exact(&tv)),
                formula_share: errors(&fv, &exact(&tv)),
                gpu_share: errors(&ev, &exact(&fv)),
            });
            images.push((format!("{table} ({path})"), image(s, &pts, &ev)));
        }
        out.push(SceneResult {
            name: sc.name.clone(),
            roughness: sc.roughness,
            view_deg: sc.view_deg,
            pixels: pts.len(),
            truth_rel_error: truth
                .iter()
                .filter(|b| b.value > 0.0)
                .map(|b| b.error / b.value)
                .fold(0.0, f64::max),
            paths,
            images,
            truth: pts
                .iter()
                .map(|(_, x)| *x)
                .zip(truth.iter().copied())
                .collect(),
        });
    }
    let adapter = match first_run.webgpu_adapter.as_str() {
        "" => first_run.adapter.clone(),
        w => format!("{}; {w}", first_run.adapter),
    };
    Ok(EngineResult {
        engine: e,
        paths: judged,
        tables: inp.runs.iter().map(|r| r.0).collect(),
        version: first_run.engine.clone(),
        adapter,
        scenes: out,
    })
}

/// Values at the covered pixels laid back into the image (0 elsewhere).
pub(super) fn image(s: &EngineScenes, pts: &[(usize, Vector3<f64>)], v: &[f64]) -> Vec<f64> {
    let mut img = vec![0.0; s.width * s.height];
    for ((p, _), x) in pts.iter().zip(v) {
        img[*p] = *x;
    }
    img
}

/// Godot 4 on one scene, in f64 only (no Godot binary here): its formulas with our
/// files (results/textures/godot/) against the truth, and the same texels with the exact
/// edge integral (the table's share).
#[derive(Clone, Debug, Serialize)]
pub struct GodotScene {
    pub name: String,
    /// Godot's lookup and `ltc_evaluate_specular` (Hill's edge fit) against the truth.
    pub formulas: Errors,
    /// Godot's lookup with the exact edge integral against the truth.
    pub table_share: Errors,
}

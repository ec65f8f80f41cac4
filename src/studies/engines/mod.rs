//! `engines`: three.js r187 renders the engine-check scenes (engines/three, headless
//! Chromium, WebGL2) with its shipped LTC table and with ours, on its float and its
//! half-float path; this study judges every pixel against the truth (`crate::engines`)
//! and splits each error into the table's share and the shader's share. Compute
//! ([`compute`]) → render ([`report`]) → the CLI publishes results/engines.{md,json,svg}.

use crate::engines::truth::{lobe, lookup, table_value, three_value, truth_value, Rect};
use crate::engines::EngineScenes;
use crate::error::{Error, Result};
use crate::ltc::compare::Shipped;
use crate::ltc::lobe_error::Bounded;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

pub mod report;

/// One engine render: per scene, the radiance (RGBA) and world positions (RGBA, alpha 1
/// where the plane covers the pixel), as the harness writes them.
#[derive(Clone, Debug, Deserialize)]
pub struct EngineScene {
    pub name: String,
    pub radiance: Vec<f64>,
    pub positions: Vec<f64>,
}

/// The harness's output for one table: the float and the half-float path.
#[derive(Clone, Debug, Deserialize)]
pub struct EngineRun {
    pub table: String,
    pub three: String,
    #[serde(default)]
    pub webgl: String,
    pub paths: std::collections::BTreeMap<String, Vec<EngineScene>>,
}

impl EngineRun {
    /// Parse and check against the scenes: every path, every scene, every size.
    pub fn parse(text: &str, scenes: &EngineScenes, what: &str) -> Result<EngineRun> {
        let bad = |m: String| Error::InvalidArgument(format!("engines: {what}: {m}"));
        let r: EngineRun = serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
        let px = scenes.width * scenes.height * 4;
        for p in ["float", "half"] {
            let v = r.paths.get(p).ok_or_else(|| bad(format!("no {p} path")))?;
            if v.len() != scenes.scenes.len() {
                return Err(bad(format!(
                    "{p} path has {} scenes, the scene file {}",
                    v.len(),
                    scenes.scenes.len()
                )));
            }
            for (s, want) in v.iter().zip(&scenes.scenes) {
                if s.name != want.name || s.radiance.len() != px || s.positions.len() != px {
                    return Err(bad(format!(
                        "scene {} does not match {} ({}×{} RGBA)",
                        crate::error::quoted(&s.name),
                        crate::error::quoted(&want.name),
                        scenes.width,
                        scenes.height
                    )));
                }
            }
        }
        Ok(r)
    }
}

/// A table as an engine path holds it: n×n cells of [a, b, c, d, norm].
#[derive(Clone, Debug)]
pub struct Held {
    pub n: usize,
    pub cells: Vec<[f64; 5]>,
}

impl Held {
    fn of(t: &Shipped) -> Held {
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
    pub rel_rmse: Bounded,
    pub mean_rel: Bounded,
}

fn errors(x: &[f64], reference: &[Bounded]) -> Errors {
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
        rel_rmse: Bounded {
            value: v,
            error: (hi - v).max(v - lo),
        },
        mean_rel: Bounded {
            value: rel / m,
            error: drel / m,
        },
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
    /// Of the shader's share, what three's formulas give in f64 (`three_value`: its edge
    /// fit and its clipped-sphere horizon) against the table's own value…
    pub formula_share: Errors,
    /// …and the engine against those formulas in f64: the GPU's f32 arithmetic and texture
    /// filtering, the rest.
    pub gpu_share: Errors,
}

/// One scene.
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
}

/// Everything the report shows.
#[derive(Clone, Debug, Serialize)]
pub struct EnginesResult {
    pub three: String,
    pub webgl: String,
    pub width: usize,
    pub height: usize,
    pub scenes: Vec<SceneResult>,
}

/// The inputs: the scenes, both harness runs, the shipped table (three.js's arrays) and
/// ours (results/fits/ltc-ggx.json).
pub struct Inputs<'a> {
    pub scenes: &'a EngineScenes,
    pub shipped_run: &'a EngineRun,
    pub ours_run: &'a EngineRun,
    pub shipped: &'a Shipped,
    pub ours: &'a crate::ltc::table::FittedTable,
}

/// The truth's relative accuracy per pixel.
pub const TRUTH_REL: f64 = 1e-5;

/// Judge every pixel of every scene.
pub fn compute(inp: &Inputs) -> Result<EnginesResult> {
    let s = inp.scenes;
    let ours = crate::ltc::compare::of_table(inp.ours);
    let ours_half = crate::ltc::compare_report::stored_half(inp.ours);
    use crate::ltc::upload::{f32_table, three_half_table};
    // what each (table, path) holds
    let held: [(&'static str, &'static str, Held, &EngineRun); 4] = [
        (
            "shipped",
            "float",
            Held::of(&f32_table(inp.shipped)),
            inp.shipped_run,
        ),
        (
            "shipped",
            "half",
            Held::of(&three_half_table(inp.shipped)),
            inp.shipped_run,
        ),
        ("ours", "float", Held::of(&f32_table(&ours)), inp.ours_run),
        ("ours", "half", Held::of(&ours_half), inp.ours_run),
    ];
    let mut out = Vec::new();
    for (k, sc) in s.scenes.iter().enumerate() {
        crate::report::stage(&format!(
            "engines: scene {} of {}: {}",
            k + 1,
            s.scenes.len(),
            sc.name
        ));
        let light = Rect::of(&sc.light).ok_or_else(|| {
            Error::InvalidArgument(format!("engines: scene {}: degenerate light", sc.name))
        })?;
        let t = lobe(sc.roughness, sc.view_deg)?;
        let pos = &inp.shipped_run.paths["float"][k].positions;
        // the covered pixels and their surface points
        let pts: Vec<(usize, Vector3<f64>)> = (0..s.width * s.height)
            .filter(|&p| pos[4 * p + 3] > 0.5)
            .map(|p| (p, Vector3::new(pos[4 * p], pos[4 * p + 1], pos[4 * p + 2])))
            .collect();
        let truth: Vec<Bounded> =
            crate::memo::map_items(&format!("engine truth {}", sc.name), &pts, |(_, x)| {
                Ok(truth_value(&t, &light, x, TRUTH_REL))
            })?;
        let ndotv = sc.view_deg.to_radians().cos();
        let mut paths = Vec::new();
        let mut images = vec![(
            "truth".to_string(),
            image(s, &pts, &truth.iter().map(|b| b.value).collect::<Vec<_>>()),
        )];
        for (table, path, h, run) in &held {
            let e = lookup(&h.cells, h.n, sc.roughness, ndotv);
            let tv: Vec<f64> = pts
                .iter()
                .map(|(_, x)| table_value(&e, &light, x))
                .collect();
            let fv: Vec<f64> = pts
                .iter()
                .map(|(_, x)| three_value(&e, &light, x))
                .collect();
            let rad = &run.paths[*path][k].radiance;
            let ev: Vec<f64> = pts.iter().map(|(p, _)| rad[4 * p]).collect();
            let exact = |v: &[f64]| -> Vec<Bounded> {
                v.iter()
                    .map(|v| Bounded {
                        value: *v,
                        error: 0.0,
                    })
                    .collect()
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
        });
    }
    Ok(EnginesResult {
        three: inp.shipped_run.three.clone(),
        webgl: inp.shipped_run.webgl.clone(),
        width: s.width,
        height: s.height,
        scenes: out,
    })
}

/// Values at the covered pixels laid back into the image (0 elsewhere).
fn image(s: &EngineScenes, pts: &[(usize, Vector3<f64>)], v: &[f64]) -> Vec<f64> {
    let mut img = vec![0.0; s.width * s.height];
    for ((p, _), x) in pts.iter().zip(v) {
        img[*p] = *x;
    }
    img
}

/// Run the study from files and write `out`/engines.{md,json,svg}; a one-line summary.
pub fn run(
    scenes: &std::path::Path,
    shipped_run: &std::path::Path,
    ours_run: &std::path::Path,
    shipped_table: &std::path::Path,
    results: &std::path::Path,
    out: &std::path::Path,
    command: &str,
) -> Result<String> {
    let sc = EngineScenes::read(scenes)?;
    let read = |p: &std::path::Path| -> Result<String> {
        let len = std::fs::metadata(p)
            .map_err(|e| Error::Io {
                path: p.display().to_string(),
                msg: e.to_string(),
            })?
            .len();
        if len > 256 << 20 {
            return Err(Error::InvalidArgument(format!(
                "engines: {} is {len} bytes, over 256 MiB",
                crate::error::quoted(&p.display().to_string())
            )));
        }
        crate::io::read_to_string(p).map_err(|e| Error::Io {
            path: p.display().to_string(),
            msg: e.to_string(),
        })
    };
    let shipped_run = EngineRun::parse(&read(shipped_run)?, &sc, "the shipped-table run")?;
    let ours_run = EngineRun::parse(&read(ours_run)?, &sc, "our table's run")?;
    let shipped = Shipped::parse(&read(shipped_table)?, "LTC_MAT_1", "LTC_MAT_2")?;
    let ours = crate::ltc::table::read(results, crate::results::names::LTC_GGX)?;
    let r = compute(&Inputs {
        scenes: &sc,
        shipped_run: &shipped_run,
        ours_run: &ours_run,
        shipped: &shipped,
        ours: &ours,
    })?;
    let md = report::markdown(&r, command);
    let picks: Vec<&str> = [
        "r0.1-view30",
        "r0.25-view60",
        "r0.5-view80",
        "r0.25-view60-straddling",
    ]
    .to_vec();
    let svg = report::figure(&r, &picks)?;
    crate::io::write_atomic(&out.join("engines.md"), md.as_bytes())?;
    crate::io::write_atomic(&out.join("engines.svg"), svg.as_bytes())?;
    crate::io::write_atomic(
        &out.join("engines.json"),
        serde_json::to_string_pretty(&r)
            .map_err(|e| Error::InvalidArgument(format!("engines: json: {e}")))?
            .as_bytes(),
    )?;
    let total = |t: &str| -> f64 {
        let v: Vec<f64> = r
            .scenes
            .iter()
            .flat_map(|s| s.paths.iter().filter(|p| p.table == t && p.path == "float"))
            .map(|p| p.engine.rel_rmse.value)
            .collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    Ok(format!(
        "wrote {}: three.js float path, mean relative RMSE over {} scenes: shipped {:.2} %, ours {:.2} %",
        out.join("engines.md").display(),
        r.scenes.len(),
        100.0 * total("shipped"),
        100.0 * total("ours")
    ))
}

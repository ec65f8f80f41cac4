//! "Model only what a scene requires": a scene file names the NDF, the
//! roughness form, the lights, the normal-map filter, the screen-space AA, the precision
//! and an error budget; `scene` writes only the WGSL and Rust that scene needs, and a
//! report of every chosen approximation with its measured error and cost. `auto` takes,
//! among the approximations whose measured error (mean + 1 s.e.) meets the budget, the
//! cheapest and every one whose cost's 95 % interval reaches the cheapest's (not
//! measurably dearer), and of those the most accurate (`filters::choice::pick`); errors from
//! results/fits/filters.json, costs from results/costs.json (ns per evaluation).

use crate::codegen;
use crate::error::{Error, Result};
use crate::filters::choice::{pick, Candidate};
use crate::filters::registry::{Domain, Filter, MapRule, Rule, ScreenRule};
use serde::Deserialize;
use std::path::Path;

/// A scene file. Unknown keys are errors naming the key.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    /// "ggx" | "beckmann"
    pub ndf: String,
    /// "isotropic" | "anisotropic" | "matrix"
    pub roughness: String,
    /// any of "point", "polygon", "environment"
    pub lights: Vec<String>,
    /// a map filter's key with a generated function (results/filters.md), "mip-normal" or "auto"
    pub normal_map_filter: String,
    /// a screen-space kernel's key with a generated function, "none" or "auto"
    pub screen_space_aa: String,
    /// "f32" | "f16"
    pub precision: String,
    /// Largest acceptable mean relative L2 lobe error of each filter (results/filters.md).
    pub error_budget: f64,
}

/// The options of one scene aspect: the footprint filters of `domain` that ship a
/// generated shading function, and the one that filters nothing (read from the registry,
/// [`crate::filters::registry`]).
fn options(domain: Domain) -> Vec<Filter> {
    Filter::all()
        .filter(|f| f.domain() == domain)
        .filter(|f| {
            f.uses().shader.is_some()
                || matches!(
                    f.rule(),
                    Rule::Map(MapRule::Renormalised) | Rule::Screen(ScreenRule::None)
                )
        })
        .collect()
}

/// Longest scene name (it names the output directory and appears in generated headers).
pub const MAX_NAME_LEN: usize = 64;
/// Largest scene file read.
pub const MAX_SCENE_BYTES: u64 = 64 * 1024;
/// Most lights a scene may list.
pub const MAX_LIGHTS: usize = 64;

impl Scene {
    /// Parse and validate; errors name the offending key and the accepted values.
    pub fn parse(text: &str, origin: &str) -> Result<Scene> {
        let s: Scene = toml::from_str(text)
            .map_err(|e| Error::InvalidArgument(format!("scene {origin}: {}", e.message())))?;
        let one_of = |key: &str, v: &str, ok: &[&str]| -> Result<()> {
            if ok.contains(&v) {
                Ok(())
            } else {
                Err(Error::InvalidArgument(format!(
                    "scene {origin}: key '{key}' = {} is not one of {ok:?}",
                    crate::error::quoted(v)
                )))
            }
        };
        let name_ok = !s.name.is_empty()
            && s.name.len() <= MAX_NAME_LEN
            && s.name
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic())
            && s.name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        if !name_ok {
            return Err(Error::InvalidArgument(format!(
                "scene {origin}: key 'name' must be 1–{MAX_NAME_LEN} characters from [A-Za-z0-9_-] starting with a letter, got {:?}",
                s.name.chars().take(80).collect::<String>()
            )));
        }
        one_of("ndf", &s.ndf, &["ggx", "beckmann"])?;
        one_of(
            "roughness",
            &s.roughness,
            &["isotropic", "anisotropic", "matrix"],
        )?;
        for l in &s.lights {
            one_of("lights", l, &["point", "polygon", "environment"])?;
        }
        let keys = |d: Domain| {
            (options(d).into_iter().map(|f| f.key()))
                .chain(["auto"])
                .collect::<Vec<_>>()
        };
        one_of(
            "normal_map_filter",
            &s.normal_map_filter,
            &keys(Domain::Map),
        )?;
        one_of("screen_space_aa", &s.screen_space_aa, &keys(Domain::Screen))?;
        one_of("precision", &s.precision, &["f32", "f16"])?;
        if !(s.error_budget.is_finite() && s.error_budget > 0.0) {
            return Err(Error::InvalidArgument(format!(
                "scene {origin}: key 'error_budget' must be a finite number > 0, got {:e}",
                s.error_budget
            )));
        }
        if s.lights.len() > MAX_LIGHTS {
            return Err(Error::InvalidArgument(format!(
                "scene {origin}: key 'lights' lists {} entries, more than {MAX_LIGHTS}",
                s.lights.len()
            )));
        }
        if s.lights.is_empty() {
            return Err(Error::InvalidArgument(format!(
                "scene {origin}: key 'lights' is empty"
            )));
        }
        // contradictions and what is not generated yet, named by key
        if s.ndf == "beckmann" && s.roughness != "isotropic" {
            return Err(Error::InvalidArgument(format!(
                "scene {origin}: keys 'ndf' = \"beckmann\" and 'roughness' = \"{}\" contradict: only isotropic Beckmann is generated",
                s.roughness
            )));
        }
        let moment = Filter::find(&s.normal_map_filter)
            .is_some_and(|f| f.rule() == Rule::Map(MapRule::Moment));
        if moment && s.ndf != "ggx" {
            return Err(Error::InvalidArgument(format!(
                "scene {origin}: keys 'normal_map_filter' = \"{}\" and 'ndf' = \"{}\" contradict: the multi-scale LTC model is GGX",
                s.normal_map_filter, s.ndf
            )));
        }
        if s.lights.iter().any(|l| l == "polygon") && (s.ndf != "ggx" || s.roughness != "isotropic")
        {
            return Err(Error::InvalidArgument(format!(
                "scene {origin}: keys 'lights' = \"polygon\" and 'ndf' = \"{}\" / 'roughness' = \"{}\" contradict: the LTC table is fitted for isotropic GGX",
                s.ndf, s.roughness
            )));
        }
        if s.lights.iter().any(|l| l == "environment") && s.ndf != "beckmann" {
            return Err(Error::InvalidArgument(format!(
                "scene {origin}: keys 'lights' = \"environment\" and 'ndf' = \"{}\" contradict: the generated LEADR grid integrates Beckmann slopes",
                s.ndf
            )));
        }
        if s.precision == "f16" {
            return Err(Error::InvalidArgument(format!(
                "scene {origin}: key 'precision' = \"f16\": not generated — α² underflows f16's normal range (6.1e-5) for α < 0.008, so the f32 forms cannot be narrowed as they are"
            )));
        }
        Ok(s)
    }

    pub fn load(path: &Path) -> Result<Scene> {
        let io = |e: std::io::Error| Error::Io {
            path: path.display().to_string(),
            msg: e.to_string(),
        };
        let len = std::fs::metadata(path).map_err(io)?.len();
        if len > MAX_SCENE_BYTES {
            return Err(Error::InvalidArgument(format!(
                "scene {}: {len} bytes exceeds the {MAX_SCENE_BYTES}-byte limit",
                path.display()
            )));
        }
        let text = std::fs::read_to_string(path).map_err(io)?;
        Scene::parse(&text, &path.display().to_string())
    }
}

/// A chosen approximation with its measured error and cost.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Choice {
    pub aspect: String,
    pub key: String,
    pub function: Option<String>,
    pub error: Option<crate::integrate::Figure>,
    pub error_note: String,
    pub cost_ns: Option<f64>,
    /// The cost's 95 % confidence interval (criterion's), where measured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cost_ci: Option<(f64, f64)>,
}

/// The measured tables a scene chooses from, read once per build.
struct Measured {
    /// results/fits/filters.json (errors)
    filters: Option<crate::results::filters::Filters>,
    /// results/costs.json (ns per evaluation)
    costs: Option<crate::results::costs::Costs>,
}

impl Measured {
    fn load(results: &Path) -> Result<Measured> {
        Ok(Measured {
            filters: crate::results::read(results)?,
            costs: crate::results::costs::read(results)?,
        })
    }
    fn cost(&self, key: &str) -> Option<f64> {
        self.costs.as_ref().and_then(|c| c.get(key))
    }
    fn cost_interval(&self, key: &str) -> Option<(f64, f64)> {
        self.costs.as_ref().and_then(|c| c.interval(key))
    }
}

type MeasuredCost = Option<(f64, (f64, f64))>;

fn measured(
    m: &Measured,
    f: Filter,
    ndf: &str,
) -> (Option<crate::integrate::Figure>, MeasuredCost) {
    let beck = ndf == "beckmann";
    let err = m
        .filters
        .as_ref()
        .and_then(|t| match (f.family(), f.uses().summary) {
            (Some(family), _) => t
                .fitted(family, if beck { "Beckmann" } else { "GGX" })
                .map(|x| x.held_out.l2),
            (None, Some(k)) => {
                let key = if beck {
                    format!("beckmann:{k}")
                } else {
                    k.to_string()
                };
                t.summary.get(&key).map(|s| s.l2)
            }
            (None, None) => None,
        });
    // a filter that ships no function costs nothing; the others their bench's time
    let cost = match (f.uses().shader, f.uses().bench) {
        (None, _) => Some((0.0, (0.0, 0.0))),
        (Some(_), Some(b)) => {
            let key = format!("filters/{b}");
            m.cost(&key).zip(m.cost_interval(&key))
        }
        (Some(_), None) => None,
    };
    (err, cost)
}

fn choose(
    aspect: &str,
    want: &str,
    opts: &[Filter],
    budget: f64,
    ndf: &str,
    m: &Measured,
) -> Result<Choice> {
    let mk = |o: &Filter| {
        let (error, cost) = measured(m, *o, ndf);
        Choice {
            aspect: aspect.into(),
            key: o.key().into(),
            function: o.uses().shader.map(String::from),
            error,
            error_note: format!("mean relative L2 lobe error ± s.e. against the footprint-averaged {ndf} BRDF (results/filters.md)"),
            cost_ns: cost.map(|c| c.0),
            cost_ci: cost.map(|c| c.1).filter(|ci| ci.0 < ci.1),
        }
    };
    if want != "auto" {
        let o = opts
            .iter()
            .find(|o| o.key() == want)
            .expect("validated key");
        return Ok(mk(o));
    }
    let all: Vec<Choice> = opts.iter().map(mk).collect();
    let cands: Vec<Candidate> = all
        .iter()
        .map(|c| Candidate {
            error: c.error.map(|e| (e.value, e.error)),
            cost: c.cost_ns.map(|m| (m, c.cost_ci.unwrap_or((m, m)))),
        })
        .collect();
    let best = pick(&cands, budget).map(|k| &all[k]);
    match best {
        Some(c) => Ok(c.clone()),
        None => {
            let closest = all.iter().filter(|c| c.error.is_some()).min_by(|a, b| {
                a.error
                    .map(|e| e.value)
                    .unwrap_or(f64::INFINITY)
                    .total_cmp(&b.error.map(|e| e.value).unwrap_or(f64::INFINITY))
            });
            Err(Error::InvalidArgument(format!(
                "scene: no {aspect} approximation meets error_budget = {budget}: the most accurate measured is '{}' at {}",
                closest.map_or("?", |c| c.key.as_str()),
                closest.and_then(|c| c.error).map_or("(no measurement: run regen)".into(), |e| e.fixed(3))
            )))
        }
    }
}

/// A measured cost in ns, or where to get it.
fn fmt_cost(c: Option<f64>) -> String {
    c.map_or("(run bench-report)".to_string(), |v| format!("{v:.2}"))
}

/// The rows and generated functions of the scene's NDF, masking and lights.
fn shading_rows(
    s: &Scene,
    results: &Path,
    measured: &Measured,
    t: &mut crate::report::table::Table,
    fns: &mut Vec<&'static str>,
) -> Result<()> {
    let dg1 = crate::results::read::<crate::results::smith_lambda::SmithLambda>(results)?
        .map(|v| v.held_out.ours.max_dg1);
    let spec_cost = measured.cost("kernel-ggx-specular/per-pixel");
    match (s.ndf.as_str(), s.roughness.as_str()) {
        ("ggx", "isotropic") => {
            fns.push("ggx_specular");
            t.row([
                "point-light specular".to_string(),
                "GGX, fused D·G2/(4v_z)".into(),
                "ggx_specular".into(),
                "≤ 1e-5 relative vs f64 (tests/codegen.rs)".into(),
                format!("{} (scalar, per pixel)", fmt_cost(spec_cost)),
            ]);
        }
        ("ggx", "anisotropic") => {
            fns.extend(["ggx_d_aniso", "ggx_g2"]);
            t.row([
                "NDF",
                "GGX axis-aligned anisotropic",
                "ggx_d_aniso",
                "≤ 2e-6 relative vs f64",
                "—",
            ]);
            t.row([
                "masking",
                "height-correlated G2 (isotropic Λ per axis is the caller's)",
                "ggx_g2",
                "≤ 2e-6",
                "—",
            ]);
        }
        ("ggx", _) => {
            fns.extend(["ggx_d_matrix", "ggx_g2"]);
            t.row([
                "NDF",
                "GGX with SPD roughness matrix",
                "ggx_d_matrix",
                "≤ 2e-6 + 16ε·cond(A) relative",
                "—",
            ]);
        }
        _ => {
            fns.extend(["beckmann_d", "beckmann_g2"]);
            t.row([
                "NDF + masking".to_string(),
                "Beckmann with the refitted Λ".into(),
                "beckmann_d, beckmann_g2".into(),
                format!(
                    "D ≤ 1e-6·(4 + tan²θ/α²); max \\|ΔG1\\| {}",
                    dg1.map_or("(run regen)".into(), |d| format!("{d:.1e}"))
                ),
                "—".into(),
            ]);
        }
    }
    if s.lights.iter().any(|l| l == "polygon") {
        fns.extend(["ltc_lut_u", "ltc_lut_v", "ltc_quad"]);
        let lt: Option<crate::results::ltc::Summary> =
            crate::results::read_named(results, crate::results::names::LTC_GGX)?;
        let mean = lt.as_ref().map(|v| v.held_out.l2.mean.value);
        let sph = lt
            .as_ref()
            .and_then(|v| v.sphere_horizon.map(|s| s.energy_weighted_rel));
        let cost = measured.cost("kernel-ltc-quad/per-pixel");
        t.row([
            "polygonal lights".to_string(),
            "LTC table (results/fits/ltc-ggx.json as two textures) + quad edge integral".into(),
            "ltc_lut_u, ltc_lut_v, ltc_quad".into(),
            format!(
                "table: mean relative L2 {}; clipped-sphere horizon: energy-weighted {} (results/ltc-ggx.md)",
                mean.map_or("(run regen)".into(), |m| format!("{:.1} %", 100.0 * m)),
                sph.map_or("(run regen)".into(), |m| format!("{:.1} %", 100.0 * m)),
            ),
            format!("{} (scalar, per pixel)", fmt_cost(cost)),
        ]);
    }
    if s.lights.iter().any(|l| l == "environment") {
        fns.push("leadr5_env");
        let cost = measured.cost("kernel-leadr/per-pixel");
        t.row([
            "environment".to_string(),
            "LEADR 5×5 slope grid, fitted spacing (shading hook: the generated test environment; replace `leadr_env` with your lookup)".into(),
            "leadr5_env".into(),
            "grid error: results/leadr-grids.md".into(),
            format!("{} (scalar, per pixel)", fmt_cost(cost)),
        ]);
    }
    Ok(())
}

/// Build the scene's outputs: (file name, contents) for scene.wgsl, scene.rs, report.md.
pub fn build(s: &Scene, results: &Path) -> Result<Vec<(String, String)>> {
    let consts = codegen::constants(results)?;
    let mut fns: Vec<&str> = Vec::new();
    let mut report = format!(
        "# Scene '{}'\n\nWritten by `cargo run --release -- scene <file> --out DIR`. Only what this scene needs: NDF {}, {} roughness, lights {:?}, normal-map filter `{}`, screen-space AA `{}`, precision {}, error budget {} (mean relative L2 lobe error per filter).\n\n",
        s.name, s.ndf, s.roughness, s.lights, s.normal_map_filter, s.screen_space_aa, s.precision, s.error_budget
    );
    let mut t = crate::report::table::Table::new([
        "aspect",
        "choice",
        "generated function",
        "measured error",
        "cost (ns/eval, f32)",
    ]);
    let measured_tables = Measured::load(results)?;
    shading_rows(s, results, &measured_tables, &mut t, &mut fns)?;
    let mut choices = Vec::new();
    for (aspect, want, opts) in [
        (
            "normal-map filter",
            s.normal_map_filter.as_str(),
            options(Domain::Map),
        ),
        (
            "screen-space AA",
            s.screen_space_aa.as_str(),
            options(Domain::Screen),
        ),
    ] {
        let c = choose(
            aspect,
            want,
            &opts,
            s.error_budget,
            &s.ndf,
            &measured_tables,
        )?;
        if let Some(f) = &c.function {
            fns.push(
                codegen::desc::FUNCTIONS
                    .iter()
                    .find(|d| d.name == f)
                    .map(|d| d.name)
                    .expect("known function"),
            );
        }
        t.row([
            aspect.to_string(),
            format!(
                "{}{}",
                c.key,
                if want == "auto" {
                    " (auto: the most accurate within budget of those not measurably dearer than the cheapest)"
                } else {
                    ""
                }
            ),
            c.function.as_deref().unwrap_or("—").to_string(),
            c.error.map_or("(no measurement)".into(), |e| e.pct(1)),
            fmt_cost(c.cost_ns),
        ]);
        choices.push(c);
    }
    report.push_str(&t.to_string());
    report.push_str(&format!("\nErrors are the measured means of results/filters.md for {} (normal-map filters over the four procedural maps, screen-space kernels on the Gaussian-pixel study; a fitted constant's error is its held-out error); costs are criterion means of the f32 forms (results/costs.json, results/performance.md). The vMF fitted constant and σ² are fitted for GGX; Beckmann uses the same functions.\n", s.ndf));
    let title = format!("scene '{}'", s.name);
    let cmd = "cargo run --release -- scene";
    let wgsl = codegen::render_wgsl(&title, &fns, &consts, cmd)?;
    // nothing is written unless the shader it would write validates
    crate::codegen::validate::validate_wgsl(&wgsl, &format!("scene '{}'", s.name))?;
    Ok(vec![
        ("scene.wgsl".into(), wgsl),
        ("scene.rs".into(), codegen::render_rust(&fns, &consts, cmd)?),
        ("report.md".into(), report),
    ])
}

/// Write the scene's outputs into `out` (atomically, each file); returns the paths.
pub fn run(
    set: &mut crate::io::Outputs,
    path: &Path,
    out: &Path,
    results: &Path,
) -> Result<Vec<String>> {
    let s = Scene::load(path)?;
    let files = build(&s, results)?;
    let mut written = Vec::new();
    for (name, text) in files {
        let p = out.join(name);
        set.put(&p, text.as_bytes());
        written.push(p.display().to_string());
    }
    Ok(written)
}

/// Rebuild the example scenes (tests/scenes/*.toml → results/scenes/<name>/) so their
/// committed outputs follow the fits and costs; run by `regen` and `bench-report` on the
/// canonical results/ directory. Returns the scene names rebuilt.
pub fn regen_examples(set: &mut crate::io::Outputs, results: &Path) -> Result<Vec<String>> {
    let dir = Path::new("tests/scenes");
    if results != Path::new("results") || !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .map_err(|e| Error::Io {
            path: dir.display().to_string(),
            msg: e.to_string(),
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let mut names = Vec::new();
    for f in files {
        let s = Scene::load(&f)?;
        run(set, &f, &results.join("scenes").join(&s.name), results)?;
        names.push(s.name);
    }
    Ok(names)
}

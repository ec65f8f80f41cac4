//! The engine check from files: the harnesses' outputs, the shipped tables as the engines
//! ship them and ours from results/, judged and published as results/engines.{md,json,svg}.

use super::compute::{
    bevy_held, compute, three_held, Engine, EngineResult, EngineRun, EnginesResult, Inputs, COMPACT,
};
use super::godot::godot;
use super::report;
use crate::engines::EngineScenes;
use crate::error::{Error, Result};
use crate::ltc::compare::Shipped;

/// The files one engine's judging reads: both harness runs, and the shipped table as the
/// engine ships it (three.js's RectAreaLightTexturesLib.js; Bevy's ltc.ktx2); for
/// three.js, optionally the run with the compact drop-in, judged with the series of
/// results/fits/ltc-compact.json.
pub struct EngineFiles<'a> {
    pub engine: Engine,
    pub shipped_run: &'a std::path::Path,
    pub ours_run: &'a std::path::Path,
    pub shipped_table: &'a std::path::Path,
    pub compact_run: Option<&'a std::path::Path>,
}

fn read_capped(p: &std::path::Path) -> Result<Vec<u8>> {
    let io = |e: std::io::Error| Error::Io {
        path: p.display().to_string(),
        msg: e.to_string(),
    };
    let len = std::fs::metadata(p).map_err(io)?.len();
    if len > 256 << 20 {
        return Err(Error::InvalidArgument(format!(
            "engines: {} is {len} bytes, over 256 MiB",
            crate::error::quoted(&p.display().to_string())
        )));
    }
    std::fs::read(p).map_err(io)
}

pub(super) fn read_text(p: &std::path::Path) -> Result<String> {
    String::from_utf8(read_capped(p)?).map_err(|_| {
        Error::InvalidArgument(format!(
            "engines: {} is not UTF-8 text",
            crate::error::quoted(&p.display().to_string())
        ))
    })
}

/// Read and judge one engine from its files; ours is results/fits/ltc-ggx.json as three.js
/// holds it, and results/textures/ltc_ggx_zstd.ktx2 (the file the Bevy harness loads) as
/// Bevy holds it.
pub fn judge_files(
    sc: &EngineScenes,
    f: &EngineFiles,
    results: &std::path::Path,
) -> Result<EngineResult> {
    let what = |t: &str| format!("{} {t}-table run", f.engine.name());
    let shipped_run = EngineRun::parse(&read_text(f.shipped_run)?, sc, f.engine, &what("shipped"))?;
    let ours_run = EngineRun::parse(&read_text(f.ours_run)?, sc, f.engine, &what("our"))?;
    let compact_run = match (f.compact_run, f.engine) {
        (None, _) => None,
        (Some(p), Engine::Three) => {
            let r = EngineRun::parse(&read_text(p)?, sc, f.engine, &what(COMPACT))?;
            if r.table != COMPACT {
                return Err(Error::InvalidArgument(format!(
                    "engines: {}: a run of the {} table given as the compact drop-in's",
                    crate::error::quoted(&p.display().to_string()),
                    crate::error::quoted(&r.table)
                )));
            }
            Some(r)
        }
        (Some(_), e) => {
            return Err(Error::InvalidArgument(format!(
                "engines: {} has no compact drop-in run (three.js only)",
                e.name()
            )))
        }
    };
    let held = match f.engine {
        Engine::Three => {
            let shipped = Shipped::parse(&read_text(f.shipped_table)?, "LTC_MAT_1", "LTC_MAT_2")?;
            shipped.check_comparable("three.js's table")?;
            let ours = crate::results::ltc::table(results, crate::results::names::LTC_GGX)?;
            let compact = match compact_run {
                Some(_) => Some(
                    crate::results::ltc_compact::ggx_series(results)?.ok_or_else(|| {
                        Error::InvalidArgument(format!(
                            "engines: a compact drop-in run, but no {} to judge it with (regen --only ltc-compact)",
                            results.join("fits/ltc-compact.json").display()
                        ))
                    })?,
                ),
                None => None,
            };
            three_held(&shipped, &ours, compact.as_ref().map(|(c, n)| (c, *n)))?
        }
        Engine::Bevy => {
            let shipped = crate::ltc::upload::bevy_ktx2(&read_capped(f.shipped_table)?)?;
            shipped.check_comparable("Bevy's table")?;
            let ours = crate::ltc::upload::bevy_ktx2(&read_capped(&results.join(BEVY_OURS))?)?;
            bevy_held(&shipped, &ours)
        }
    };
    let mut runs = vec![("shipped", &shipped_run), ("ours", &ours_run)];
    if let Some(r) = &compact_run {
        runs.push((COMPACT, r));
    }
    compute(
        sc,
        &Inputs {
            engine: f.engine,
            runs,
            held,
        },
    )
}

/// Our table as the Bevy harness loads it, under results/.
pub const BEVY_OURS: &str = "textures/ltc_ggx_zstd.ktx2";

/// What three.js's run with ours loads (the import map's module) and what judges it.
const THREE_OURS: [&str; 2] = [
    "fits/ltc-ggx.json",
    "textures/three/RectAreaLightTexturesLib.js",
];

/// Those, and what three.js's run with the compact drop-in loads and the series that
/// judges it.
const THREE_WITH_COMPACT: [&str; 5] = [
    THREE_OURS[0],
    THREE_OURS[1],
    "fits/ltc-compact.json",
    "textures/three/RectAreaLightTexturesLib.compact.js",
    "textures/three/ltc_compact.js",
];

/// The files under results/ that one engine's runs loaded and its judging read.
fn inputs_of(f: &EngineFiles) -> &'static [&'static str] {
    match (f.engine, f.compact_run.is_some()) {
        (Engine::Three, false) => &THREE_OURS,
        (Engine::Three, true) => &THREE_WITH_COMPACT,
        (Engine::Bevy, _) => &[BEVY_OURS],
    }
}

/// Run the study from files into `set` (`out`/engines.{md,json,svg}); a one-line summary.
pub fn run(
    set: &mut crate::io::Outputs,
    scenes: &std::path::Path,
    engines: &[EngineFiles],
    results: &std::path::Path,
    out: &std::path::Path,
    command: &str,
) -> Result<String> {
    let sc = EngineScenes::read(scenes)?;
    if engines.is_empty() {
        return Err(Error::InvalidArgument(
            "engines: no engine's runs given".into(),
        ));
    }
    let mut r = EnginesResult {
        width: sc.width,
        height: sc.height,
        engines: Vec::new(),
        godot: Vec::new(),
        inputs: Vec::new(),
    };
    let mut read: Vec<&str> = Vec::new();
    for f in engines {
        r.engines.push(judge_files(&sc, f, results)?);
        read.extend_from_slice(inputs_of(f));
    }
    // Godot's figures below use our table as fits/ltc-ggx.json holds it
    read.push(THREE_OURS[0]);
    read.sort_unstable();
    read.dedup();
    r.inputs = super::inputs::digests(results, &read)?;
    if let Some(first) = r.engines.first() {
        let ours = crate::results::ltc::table(results, crate::results::names::LTC_GGX)?;
        let (l1, l2) = crate::engines::godot::texels(&ours)?;
        // as Godot holds them: f32
        let f32s = |v: Vec<[f64; 4]>| -> Vec<[f64; 4]> {
            v.iter().map(|x| x.map(|c| c as f32 as f64)).collect()
        };
        r.godot = godot(&sc, first, &f32s(l1), &f32s(l2))?;
    }
    let sum = r.summary();
    let md = report::markdown(&r, &sum, command);
    let picks = [
        "r0.1-view30",
        "r0.25-view60",
        "r0.5-view80",
        "r0.25-view60-straddling",
    ];
    let svg = report::figure(&r, &picks)?;
    set.put(&out.join("engines.md"), md.as_bytes());
    set.put(&out.join("engines.svg"), svg.as_bytes());
    set.put(
        &out.join("engines.json"),
        serde_json::to_string_pretty(&File {
            result: &r,
            summary: &sum,
        })
        .map_err(|e| Error::InvalidArgument(format!("engines: json: {e}")))?
        .as_bytes(),
    );
    let summary: Vec<String> = r
        .engines
        .iter()
        .zip(&sum.paths)
        .filter_map(|(e, paths)| {
            let p = paths.first()?;
            Some(format!(
                "{} {} path, mean relative RMSE over {} scenes: shipped {}, ours {}",
                e.engine.name(),
                p.path,
                p.scenes,
                p.shipped_mean.pct(2),
                p.ours_mean.pct(2)
            ))
        })
        .collect();
    Ok(format!(
        "wrote {}: {}",
        out.join("engines.md").display(),
        summary.join("; ")
    ))
}

/// results/engines.json: the result and what the report states of it.
#[derive(serde::Serialize)]
struct File<'a> {
    #[serde(flatten)]
    result: &'a EnginesResult,
    summary: &'a super::summary::Summary,
}

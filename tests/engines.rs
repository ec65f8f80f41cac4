//! The engines render the engine-check scenes with their own LTC table and with ours, and
//! the workbench judges the pixels against the truth:
//!
//! - three.js r187 (engines/three) in headless Chromium, ours through one import-map
//!   entry (the README's recipe), on its float and half-float paths; and the compact
//!   drop-in (results/textures/three/RectAreaLightTexturesLib.compact.js), whose init()
//!   rebuilds the textures from 864 coefficients, the same way. Needs node,
//!   engines/three/node_modules (`npm ci`), Chromium and three's RectAreaLightTexturesLib.js
//!   in target/shipped.
//! - Bevy 0.19.1 (engines/bevy-check, headless wgpu), ours through `AreaLightLuts`. Needs
//!   the harness built in target/bevy-check, Bevy's ltc.ktx2 in target/shipped and an
//!   adapter (lavapipe in CI).
//!
//! .ci/run provides all of it best-effort; each test skips with one line without it.

mod common;

use ndfbench::engines::EngineScenes;
use ndfbench::studies::engines::{Engine, EngineFiles, EngineResult};
use std::path::Path;
use std::process::Command;

const CHROMIUM: &str = "/usr/bin/chromium";
const SHIPPED: &str = "target/shipped/RectAreaLightTexturesLib.js";

fn missing() -> Option<String> {
    if Command::new("node").arg("--version").output().is_err() {
        return Some("node".into());
    }
    for p in [
        "engines/three/node_modules/three",
        "engines/three/node_modules/playwright-core",
        CHROMIUM,
        SHIPPED,
    ] {
        if !Path::new(p).exists() {
            return Some(p.into());
        }
    }
    None
}

fn render(table: &str, out: &Path) -> Result<(), String> {
    let o = Command::new("node")
        .args(["engines/three/render.mjs", "--table", table, "--out"])
        .arg(out)
        .args(["--chromium", CHROMIUM])
        .output()
        .map_err(|e| e.to_string())?;
    if o.status.success() {
        Ok(())
    } else {
        Err(String::from_utf8_lossy(&o.stderr).into_owned())
    }
}

#[test]
fn three_renders_both_tables_as_their_formulas_say_and_ours_is_closer_to_the_truth() {
    if let Some(m) = missing() {
        eprintln!("skipped: {m} absent (see .ci/run: apt chromium, npm ci in engines/three)");
        return;
    }
    let dir = common::scratch("engines", "engines");
    std::fs::create_dir_all(&dir).unwrap();
    let (a, b, c) = (
        dir.join("shipped.json"),
        dir.join("ours.json"),
        dir.join("compact.json"),
    );
    if let Err(e) = render("shipped", &a)
        .and_then(|_| render("ours", &b))
        .and_then(|_| render("compact", &c))
    {
        // a browser that cannot start here (no GPU emulation, a sandbox) is not a failure
        // of the workbench; anything else is
        assert!(
            e.contains("browserType.launch") || e.contains("Failed to launch"),
            "the three.js harness failed: {e}"
        );
        eprintln!(
            "skipped: Chromium could not start: {}",
            e.lines().next().unwrap_or("")
        );
        return;
    }
    let scenes = EngineScenes::read(Path::new("engines/three/scenes.json")).unwrap();
    let r = ndfbench::studies::engines::judge_files(
        &scenes,
        &EngineFiles {
            engine: Engine::Three,
            shipped_run: &a,
            ours_run: &b,
            shipped_table: Path::new(SHIPPED),
            compact_run: Some(&c),
        },
        Path::new("results"),
    )
    .unwrap();
    // 1. each image is what three's formulas give with the table that path should hold
    //    (our f32 table and our stored binary16 one; three's f32 numbers and its truncated
    //    halves; the compact series' f32 rebuild and its nearest binary16, computed here
    //    from results/fits/ltc-compact.json, not by the drop-in): within f32 arithmetic
    //    and texture filtering, 1e-3 relative RMSE. A path
    //    that bound the other table, or a convention off (frame, winding, uv, clamp), is
    //    percent-level here.
    formulas_hold(&r, 1e-3);
    if !r.paths.iter().any(|p| p.starts_with("webgpu")) {
        eprintln!(
            "note: this Chromium offered no WebGPU adapter: the WebGPURenderer path was not judged"
        );
    }
    // 2. against the truth (exact, ± its bars): over the scenes, ours renders closer on
    //    both paths (mean relative RMSE), and the table's own share is smaller for ours
    ours_is_closer(&r);
    compact_is_closer_than_shipped(&r);
    // 3. the committed report is this run's (within 1e-4 relative: another CPU's
    //    SwiftShader may round differently)
    matches_committed(&r);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Bevy harness, built by .ci/run in its own target directory (never by this test).
const BEVY_BIN: &str = "target/bevy-check/debug/bevy-check";
const BEVY_TABLE: &str = "target/shipped/bevy_ltc.ktx2";
const LAVAPIPE: &str = "target/lavapipe/lvp.json";

/// Run the Bevy harness with one table; lavapipe's Vulkan where .ci/run unpacked it, the
/// default adapter otherwise.
fn bevy_render(table: &str, out: &Path) -> Result<(), String> {
    let mut c = Command::new(BEVY_BIN);
    c.args(["--scenes", "engines/three/scenes.json", "--table", table]);
    if table == "ours" {
        c.arg("--ktx2")
            .arg(Path::new("results").join(ndfbench::studies::engines::BEVY_OURS));
    }
    c.arg("--out").arg(out);
    let lavapipe = std::env::var("NDFB_BEVY_ADAPTER").as_deref() != Ok("default");
    if let (true, Ok(icd)) = (lavapipe, std::fs::canonicalize(LAVAPIPE)) {
        c.env("VK_ICD_FILENAMES", icd).env("WGPU_BACKEND", "vulkan");
        // the Vulkan loader unpacked beside it (Debian's multiarch path)
        if let Ok(lib) = std::fs::canonicalize("target/lavapipe/root/usr/lib/x86_64-linux-gnu") {
            let ld = match std::env::var("LD_LIBRARY_PATH") {
                Ok(v) if !v.is_empty() => format!("{}:{v}", lib.display()),
                _ => lib.display().to_string(),
            };
            c.env("LD_LIBRARY_PATH", ld);
        }
    }
    let o = c.output().map_err(|e| e.to_string())?;
    if o.status.success() {
        Ok(())
    } else {
        Err(String::from_utf8_lossy(&o.stderr).into_owned())
    }
}

#[test]
fn bevy_renders_both_tables_as_its_formulas_say_and_ours_is_closer_to_the_truth() {
    for p in [BEVY_BIN, BEVY_TABLE] {
        if !Path::new(p).exists() {
            eprintln!("skipped: {p} absent (see .ci/run: the engines/bevy-check build, cargo fetch of bevy_pbr)");
            return;
        }
    }
    // lavapipe, or the machine's own adapter when asked for (NDFB_BEVY_ADAPTER=default):
    // an arbitrary fallback (a GL driver without what Bevy needs) is not a verdict
    if !Path::new(LAVAPIPE).exists()
        && std::env::var("NDFB_BEVY_ADAPTER").as_deref() != Ok("default")
    {
        eprintln!(
            "skipped: {LAVAPIPE} absent (see .ci/run) and NDFB_BEVY_ADAPTER is not \"default\""
        );
        return;
    }
    let dir = common::scratch("engines", "bevy");
    std::fs::create_dir_all(&dir).unwrap();
    let (a, b) = (dir.join("bevy.json"), dir.join("ours.json"));
    if let Err(e) = bevy_render("bevy", &a).and_then(|_| bevy_render("ours", &b)) {
        // no adapter here (no GPU, no lavapipe) is not a failure of the workbench
        assert!(
            e.contains("Unable to find a GPU")
                || e.contains("No suitable")
                || e.contains("adapter"),
            "the Bevy harness failed: {e}"
        );
        let why = e
            .lines()
            .find(|l| {
                l.contains("Unable to find a GPU")
                    || l.contains("No suitable")
                    || l.contains("adapter")
            })
            .unwrap_or("");
        eprintln!("skipped: Bevy found no adapter: {}", why.trim());
        return;
    }
    let scenes = EngineScenes::read(Path::new("engines/three/scenes.json")).unwrap();
    let r = ndfbench::studies::engines::judge_files(
        &scenes,
        &EngineFiles {
            engine: Engine::Bevy,
            shipped_run: &a,
            ours_run: &b,
            shipped_table: Path::new(BEVY_TABLE),
            compact_run: None,
        },
        Path::new("results"),
    )
    .unwrap();
    eprintln!("Bevy check on {}", r.adapter);
    formulas_hold(&r, 1e-3);
    ours_is_closer(&r);
    matches_committed(&r);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each image is what the engine's formulas give with the table that path should hold:
/// within f32 arithmetic and texture filtering, `bound` relative RMSE. A path that bound
/// the other table, or a convention off (frame, winding, uv, clamp), is percent-level.
fn formulas_hold(r: &EngineResult, bound: f64) {
    for s in &r.scenes {
        for p in &s.paths {
            assert!(
                p.gpu_share.rel_rmse.value < bound,
                "{} {} {} {}: the image is {} from the engine's formulas with that table",
                r.engine.name(),
                s.name,
                p.table,
                p.path,
                p.gpu_share.rel_rmse.pct(3)
            );
        }
    }
}

/// Over the scenes, on every path, ours renders closer to the truth (mean relative RMSE,
/// beyond both means' bars) and the table's own share is smaller for ours.
fn ours_is_closer(r: &EngineResult) {
    for path in &r.paths {
        let (o, s) = (
            r.mean("ours", path, |x| x.engine.rel_rmse),
            r.mean("shipped", path, |x| x.engine.rel_rmse),
        );
        assert!(
            o.value + o.error < s.value - s.error,
            "{} {path} path: ours {} against shipped {}",
            r.engine.name(),
            o.pct(2),
            s.pct(2)
        );
        let (o, s) = (
            r.mean("ours", path, |x| x.table_share.rel_rmse),
            r.mean("shipped", path, |x| x.table_share.rel_rmse),
        );
        assert!(
            o.value + o.error < s.value - s.error,
            "{} {path} path, the tables' share: ours {} against shipped {}",
            r.engine.name(),
            o.pct(2),
            s.pct(2)
        );
    }
}

/// The compact drop-in was rendered on every path, and over the scenes it renders closer to
/// the truth than the shipped table (mean relative RMSE, beyond both means' bars): the
/// 864 coefficients carry results/ltc-compact.md's held-out advantage over the shipped
/// table (8.66 % against 12.03 % mean lobe error at the texel centres) into the engine.
fn compact_is_closer_than_shipped(r: &EngineResult) {
    for path in &r.paths {
        assert!(
            r.scenes.iter().all(|s| s
                .paths
                .iter()
                .any(|p| p.table == "compact" && p.path == *path)),
            "three.js {path} path: a scene without the compact drop-in's image"
        );
        let (c, s) = (
            r.mean("compact", path, |x| x.engine.rel_rmse),
            r.mean("shipped", path, |x| x.engine.rel_rmse),
        );
        assert!(
            c.value + c.error < s.value - s.error,
            "three.js {path} path: compact {} against shipped {}",
            c.pct(2),
            s.pct(2)
        );
    }
}

/// results/engines.json holds this engine's figures (within 1e-4 relative).
fn matches_committed(r: &EngineResult) {
    let committed: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("results/engines.json").expect("results/engines.json"),
    )
    .unwrap();
    let name = serde_json::to_value(r.engine).unwrap();
    let e = committed["engines"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["engine"] == name)
        .unwrap_or_else(|| panic!("results/engines.json has no {} section", r.engine.name()));
    for (s, c) in r.scenes.iter().zip(e["scenes"].as_array().unwrap()) {
        let committed = c["paths"].as_array().unwrap();
        assert_eq!(
            s.paths.len(),
            committed.len(),
            "results/engines.json is stale at {} {}: {} (table, path) pairs committed, {} now",
            r.engine.name(),
            s.name,
            committed.len(),
            s.paths.len()
        );
        for (p, q) in s.paths.iter().zip(committed) {
            assert_eq!(
                q["table"], p.table,
                "results/engines.json's order of tables"
            );
            let v = q["engine"]["rel_rmse"]["value"].as_f64().unwrap();
            assert!(
                (p.engine.rel_rmse.value - v).abs() <= 1e-4 * v + 1e-9,
                "results/engines.json is stale at {} {} {} {}: {v} committed, {} now",
                r.engine.name(),
                s.name,
                p.table,
                p.path,
                p.engine.rel_rmse.value
            );
        }
    }
}

#[test]
fn engine_scene_file_is_validated() {
    let good = std::fs::read_to_string("engines/three/scenes.json").unwrap();
    assert!(EngineScenes::parse(&good).is_ok());
    let v: serde_json::Value = serde_json::from_str(&good).unwrap();
    let nan = serde_json::Value::from(f64::NAN); // serialises as null: a type error
    let cases: Vec<(&str, Box<dyn Fn(&mut serde_json::Value)>)> = vec![
        ("zero width", Box::new(|v| v["width"] = 0.into())),
        ("huge image", Box::new(|v| v["height"] = 100_000.into())),
        (
            "negative plane",
            Box::new(|v| v["plane_half"] = (-1.0).into()),
        ),
        (
            "roughness 1.5",
            Box::new(|v| v["scenes"][0]["roughness"] = 1.5.into()),
        ),
        (
            "view 0°",
            Box::new(|v| v["scenes"][0]["view_deg"] = 0.0.into()),
        ),
        (
            "NaN view",
            Box::new(move |v| v["scenes"][0]["view_deg"] = nan.clone()),
        ),
        (
            "empty light",
            Box::new(|v| v["scenes"][0]["light"]["width"] = 0.0.into()),
        ),
        (
            "1e300 light",
            Box::new(|v| v["scenes"][0]["light"]["center"][0] = 1e300.into()),
        ),
        (
            "light facing itself",
            Box::new(|v| {
                let c = v["scenes"][0]["light"]["center"].clone();
                v["scenes"][0]["light"]["look_at"] = c;
            }),
        ),
        (
            "up along the light",
            Box::new(|v| {
                v["scenes"][0]["light"]["up"] = serde_json::json!([-1.2, 0.0, 1.0]);
            }),
        ),
        (
            "no scenes",
            Box::new(|v| v["scenes"] = serde_json::json!([])),
        ),
        ("unknown field", Box::new(|v| v["extra"] = 1.into())),
    ];
    for (what, f) in cases {
        let mut bad = v.clone();
        f(&mut bad);
        let e = EngineScenes::parse(&bad.to_string()).expect_err(what);
        assert_eq!(e.to_string().lines().count(), 1, "{what}: {e}");
    }
    assert!(EngineScenes::parse("{").is_err());
}

/// A run file of `table` with every pixel 0 (parses; never judged here).
fn blank_run(scenes: &EngineScenes, table: &str, engine: Engine) -> String {
    let px = vec![0.0; scenes.width * scenes.height * 4];
    let scene_list: Vec<serde_json::Value> = scenes
        .scenes
        .iter()
        .map(|s| serde_json::json!({ "name": s.name, "radiance": px, "positions": px }))
        .collect();
    let paths: serde_json::Map<String, serde_json::Value> = engine
        .paths()
        .iter()
        .map(|p| (p.to_string(), serde_json::Value::from(scene_list.clone())))
        .collect();
    serde_json::json!({ "table": table, "engine": "test", "paths": paths }).to_string()
}

#[test]
fn a_compact_run_that_is_not_the_compact_drop_in_is_refused() {
    let scenes = EngineScenes::read(Path::new("engines/three/scenes.json")).unwrap();
    let dir = common::scratch("engines", "compact-refused");
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, table: &str, engine: Engine| {
        let p = dir.join(name);
        std::fs::write(&p, blank_run(&scenes, table, engine)).unwrap();
        p
    };
    let (a, b) = (
        write("shipped.json", "shipped", Engine::Three),
        write("ours.json", "ours", Engine::Three),
    );
    // judge the runs (shipped, ours, compact) of an engine against a results folder: the
    // error's text
    let judge = |engine: Engine, runs: [&Path; 3], table: &str, results: &Path| {
        ndfbench::studies::engines::judge_files(
            &scenes,
            &EngineFiles {
                engine,
                shipped_run: runs[0],
                ours_run: runs[1],
                shipped_table: Path::new(table),
                compact_run: Some(runs[2]),
            },
            results,
        )
        .unwrap_err()
        .to_string()
    };
    // our full table's run handed over as the compact drop-in's
    let e = judge(Engine::Three, [&a, &b, &b], SHIPPED, Path::new("results"));
    assert!(e.contains("compact drop-in") && e.contains("ours"), "{e}");
    // Bevy has no compact drop-in
    let (c, d) = (
        write("bevy.json", "bevy", Engine::Bevy),
        write("bevy-ours.json", "ours", Engine::Bevy),
    );
    let e = judge(Engine::Bevy, [&c, &d, &d], BEVY_TABLE, Path::new("results"));
    assert!(e.contains("three.js only"), "{e}");
    // a compact run, but no compact series in the results folder given (our full table
    // is there)
    let empty = dir.join("results");
    std::fs::create_dir_all(empty.join("fits")).unwrap();
    std::fs::copy("results/fits/ltc-ggx.json", empty.join("fits/ltc-ggx.json")).unwrap();
    let cr = write("compact.json", "compact", Engine::Three);
    if Path::new(SHIPPED).exists() {
        let e = judge(Engine::Three, [&a, &b, &cr], SHIPPED, &empty);
        assert!(e.contains("ltc-compact"), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// three.js r187 renders the sheen alone under each sheen scene's RectAreaLight
/// (engines/three/scenes_sheen.json: lights low on the horizon, where a sheen reflects), as
/// three is and with our recipe (results/textures/three/RectAreaLightSheen.js, the
/// texture-free Neubelt sheen LTC), and the pixels are judged against the exact
/// Charlie–Neubelt lobe (results/engines-sheen.md).
#[test]
fn three_lights_sheen_under_a_rect_area_light_only_with_the_recipe() {
    use ndfbench::studies::engines::sheen::{judge, SheenRun};
    use ndfbench::studies::engines::sheen_report::{mean_of, over_albedo};
    if let Some(m) = missing() {
        eprintln!("skipped: {m} absent (see .ci/run: apt chromium, npm ci in engines/three)");
        return;
    }
    let dir = common::scratch("engines", "sheen");
    let out = dir.join("sheen.json");
    let o = Command::new("node")
        .args([
            "engines/three/render.mjs",
            "--table",
            "sheen",
            "--scenes",
            "scenes_sheen.json",
            "--out",
        ])
        .arg(&out)
        .args(["--chromium", CHROMIUM])
        .output()
        .unwrap();
    if !o.status.success() {
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(
            e.contains("browserType.launch") || e.contains("Failed to launch"),
            "the three.js harness failed: {e}"
        );
        eprintln!(
            "skipped: Chromium could not start: {}",
            e.lines().next().unwrap_or("")
        );
        return;
    }
    let text = std::fs::read_to_string(&out).unwrap();
    let scenes = EngineScenes::read(Path::new("engines/three/scenes_sheen.json")).unwrap();
    let run = SheenRun::parse(&text, &scenes).unwrap();
    assert_eq!(run.scenes, "engines/three/scenes_sheen.json");
    let r = judge(&scenes, &run, Path::new("results")).unwrap();
    let (recipe, shipped) = (
        over_albedo(&r, |s| &s.recipe),
        over_albedo(&r, |s| &s.shipped),
    );
    for (k, s) in r.scenes.iter().enumerate() {
        // 1. three as shipped applies no sheen under RectAreaLight: the image is black
        assert_eq!(
            s.shipped_max, 0.0,
            "{}: three lit the sheen without the recipe",
            s.name
        );
        assert!(
            s.truth_peak > 0.0,
            "{}: a scene the sheen does not reflect",
            s.name
        );
        // 2. with the recipe, the image is three's LTC_Evaluate with the series' entries,
        //    within f32 arithmetic (1e-3 relative RMSE); a frame, winding, channel order or
        //    roughness convention off is percent-level here
        assert!(
            s.gpu_share.rel_rmse.value <= 1e-3,
            "{}: the recipe's image is {} from three's formula with the series",
            s.name,
            s.gpu_share.rel_rmse.value
        );
        // 3. from sheenRoughness 0.25 up, the recipe is closer to the truth than no sheen,
        //    beyond both bars (at 0.1 it is not everywhere: results/engines-sheen.md)
        if s.roughness >= 0.25 {
            assert!(
                recipe[k].value + recipe[k].error < shipped[k].value - shipped[k].error,
                "{}: the recipe {} against no sheen {}",
                s.name,
                recipe[k].value,
                shipped[k].value
            );
        }
    }
    // the same on WebGPURenderer with RectAreaLightSheenNode, where Chromium offers WebGPU
    if r.scenes.iter().all(|s| s.webgpu.is_some()) {
        for (k, s) in r.scenes.iter().enumerate() {
            let w = s.webgpu.as_ref().unwrap();
            assert_eq!(
                w.shipped_max, 0.0,
                "{}: WebGPU lit the sheen without the recipe",
                s.name
            );
            assert!(
                w.gpu_share.rel_rmse.value <= 1e-3,
                "{}: the WebGPU recipe's image is {} from three's formula with the series",
                s.name,
                w.gpu_share.rel_rmse.value
            );
            if s.roughness >= 0.25 {
                let x = w.recipe.rms_over_albedo;
                assert!(
                    x.value + x.error < shipped[k].value - shipped[k].error,
                    "{}: the WebGPU recipe {} against no sheen {}",
                    s.name,
                    x.value,
                    shipped[k].value
                );
            }
        }
    } else {
        eprintln!(
            "note: this Chromium offered no WebGPU adapter: the WebGPU sheen recipe was not judged"
        );
    }
    // … and over all the scenes its mean error is at most half of rendering no sheen
    let (m, z) = (mean_of(&recipe), mean_of(&shipped));
    assert!(
        m.value + m.error <= 0.5 * (z.value - z.error),
        "recipe {} against no sheen {}",
        m.value,
        z.value
    );
    // 4. the committed report is this run's (within 1e-4 relative)
    let committed: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("results/engines-sheen.json").expect("results/engines-sheen.json"),
    )
    .unwrap();
    let c = committed["checks"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["scenes_file"] == "engines/three/scenes_sheen.json")
        .expect("results/engines-sheen.json has no check of the sheen scenes");
    let cs = c["scenes"].as_array().unwrap();
    assert_eq!(
        cs.len(),
        r.scenes.len(),
        "results/engines-sheen.json is stale"
    );
    for (s, c) in r.scenes.iter().zip(cs) {
        let v = c["recipe"]["rms_over_albedo"]["value"].as_f64().unwrap();
        assert!(
            (s.recipe.rms_over_albedo.value - v).abs() <= 1e-4 * v + 1e-12,
            "results/engines-sheen.json is stale at {}: {v} committed, {} now",
            s.name,
            s.recipe.rms_over_albedo.value
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A sheen run is checked against its scene file before anything is judged: another
/// table's run, a path missing or unknown, a scene missing or misnamed, a pixel array of
/// the wrong size or a pixel that is not a number are typed errors naming the defect.
#[test]
fn a_sheen_run_is_checked_before_it_is_judged() {
    use ndfbench::studies::engines::sheen::SheenRun;
    use serde_json::json;
    let scenes = EngineScenes::read(Path::new("engines/three/scenes_sheen.json")).unwrap();
    let px = scenes.width * scenes.height * 4;
    let all: Vec<serde_json::Value> = scenes
        .scenes
        .iter()
        .map(|s| json!({ "name": s.name, "radiance": vec![0.0; px], "positions": vec![0.0; px] }))
        .collect();
    let good = json!({
        "table": "sheen", "engine": "three.js 0.187.0", "scenes": "engines/three/scenes_sheen.json",
        "paths": { "shipped": all.clone(), "recipe": all.clone() }
    });
    assert!(SheenRun::parse(&good.to_string(), &scenes).is_ok());
    let refused = |f: &dyn Fn(&mut serde_json::Value), what: &str| {
        let mut v = good.clone();
        f(&mut v);
        let e = SheenRun::parse(&v.to_string(), &scenes)
            .unwrap_err()
            .to_string();
        assert!(e.contains(what), "{e} (wanted {what:?})");
        assert!(!e.contains('\n'), "one line: {e}");
    };
    refused(&|v| v["table"] = json!("ours"), "not the sheen run");
    refused(
        &|v| {
            v["paths"].as_object_mut().unwrap().remove("recipe");
        },
        "no recipe path",
    );
    refused(&|v| v["paths"]["float"] = json!([]), "unknown path");
    refused(
        &|v| v["paths"]["webgpu-recipe"] = json!(all.clone()),
        "one WebGPU path without the other",
    );
    refused(
        &|v| {
            v["paths"]["shipped"].as_array_mut().unwrap().pop();
        },
        "scenes, the scene file",
    );
    refused(
        &|v| v["paths"]["recipe"][3]["name"] = json!("other"),
        "does not match",
    );
    refused(
        &|v| {
            v["paths"]["recipe"][0]["radiance"]
                .as_array_mut()
                .unwrap()
                .pop();
        },
        "does not match",
    );
    refused(
        &|v| v["paths"]["recipe"][0]["radiance"][5] = serde_json::Value::Null,
        "null",
    );
    refused(
        &|v| {
            v.as_object_mut().unwrap().remove("scenes");
        },
        "scenes",
    );
}

/// The committed engine reports were judged on the tables results/ holds now. The engines
/// run only where Chromium, the Bevy harness and an adapter are; a table refitted on a
/// machine without them would leave results/engines*.json quoting renders of the old
/// table, and only those machines would notice. The reports record the SHA-256 of every
/// file under results/ their runs loaded and their judge read; this checks them here.
#[test]
fn the_committed_engine_reports_were_judged_on_the_current_tables() {
    use ndfbench::studies::engines::inputs::{stale, InputDigest};
    for (report, must) in [
        (
            "results/engines.json",
            &[
                "fits/ltc-ggx.json",
                "textures/three/RectAreaLightTexturesLib.js",
                "textures/three/RectAreaLightTexturesLib.compact.js",
                "fits/ltc-compact.json",
                "textures/ltc_ggx_zstd.ktx2",
            ][..],
        ),
        (
            "results/engines-sheen.json",
            &[
                "fits/ltc-compact.json",
                "fits/ltc-sheen-neubelt.json",
                "textures/three/RectAreaLightSheen.js",
            ][..],
        ),
    ] {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap();
        let inputs: Vec<InputDigest> = serde_json::from_value(v["inputs"].clone())
            .unwrap_or_else(|e| panic!("{report} records no inputs: {e}"));
        for f in must {
            assert!(
                inputs.iter().any(|d| d.file == *f),
                "{report} does not record {f} among its inputs"
            );
        }
        let s = stale(Path::new("results"), &inputs);
        assert!(
            s.is_empty(),
            "{report} is stale (rerun the engines and the command its .md names): {}",
            s.join("; ")
        );
    }
}

/// Of an LTC table file the digest covers what its readers read: a restated report figure
/// (or a reordered file) keeps it, a changed table entry or spec changes it; a file that is
/// no table is digested whole, every byte.
#[test]
fn a_table_files_digest_covers_its_table_not_its_report() {
    use ndfbench::results::published_sha256;
    use ndfbench::studies::engines::inputs::sha256_hex;
    let dir = common::scratch("engines", "table-digest");
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("t.json");
    let write = |text: &str| std::fs::write(&f, text).unwrap();
    write(r#"{"spec": {"n": 2}, "table": [[1.0, 2.0]], "held_out": {"mean": 0.5}}"#);
    let d0 = published_sha256(&f).unwrap();
    // the digest of the table part, spelled here: sorted keys, compact JSON
    assert_eq!(d0, sha256_hex(br#"{"spec":{"n":2},"table":[[1.0,2.0]]}"#));
    write(r#"{"held_out": {"mean": 0.25}, "table": [[1.0, 2.0]], "spec": {"n": 2}}"#);
    assert_eq!(
        published_sha256(&f).unwrap(),
        d0,
        "a report figure moved the digest"
    );
    write(r#"{"spec": {"n": 2}, "table": [[1.0, 2.5]], "held_out": {"mean": 0.5}}"#);
    assert_ne!(
        published_sha256(&f).unwrap(),
        d0,
        "a table entry left the digest"
    );
    write(r#"{"spec": {"n": 3}, "table": [[1.0, 2.0]], "held_out": {"mean": 0.5}}"#);
    assert_ne!(
        published_sha256(&f).unwrap(),
        d0,
        "the spec left the digest"
    );
    let other = r#"{"families": [1, 2], "held_out": 0.5}"#;
    write(other);
    assert_eq!(published_sha256(&f).unwrap(), sha256_hex(other.as_bytes()));
    write("{\"table\": [1.0,");
    let e = published_sha256(&f).unwrap_err().to_string();
    assert!(e.contains("t.json") && e.contains("not JSON"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The staleness check names a changed file and a missing one, and passes an unchanged one;
/// the digest is SHA-256 (FIPS 180-2's example: "abc").
#[test]
fn a_changed_engine_input_is_named() {
    use ndfbench::studies::engines::inputs::{digests, sha256_hex, stale};
    assert_eq!(
        sha256_hex(b"abc"),
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    );
    let dir = common::scratch("engines", "inputs");
    std::fs::create_dir_all(dir.join("fits")).unwrap();
    std::fs::write(dir.join("fits/a.json"), b"{\"m\": [1.0, 2.0]}").unwrap();
    std::fs::write(dir.join("b.js"), b"export const x = 1;").unwrap();
    let d = digests(&dir, &["fits/a.json", "b.js"]).unwrap();
    assert!(stale(&dir, &d).is_empty());
    std::fs::write(dir.join("fits/a.json"), b"{\"m\": [1.0, 2.5]}").unwrap();
    let s = stale(&dir, &d);
    assert_eq!(s.len(), 1, "{s:?}");
    assert!(s[0].starts_with("fits/a.json changed"), "{s:?}");
    std::fs::remove_file(dir.join("b.js")).unwrap();
    let s = stale(&dir, &d);
    assert_eq!(s.len(), 2, "{s:?}");
    assert!(s[1].starts_with("b.js: "), "{s:?}");
    assert!(digests(&dir, &["b.js"]).is_err());
    // a recorded digest read back from a damaged report (not hex, multi-byte characters)
    // is named as changed, not a panic
    let mut bad = d[0].clone();
    bad.sha256 = "é".repeat(20);
    let s = stale(&dir, &[bad]);
    assert_eq!(s.len(), 1, "{s:?}");
    assert!(s[0].contains("éééééééééééé recorded"), "{s:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

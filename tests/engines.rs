//! three.js r187 renders the engine-check scenes (engines/three) in headless Chromium
//! with its own LTC table and — through one import-map entry, the README's recipe — with
//! ours, on its float and half-float paths; the workbench judges the pixels against the
//! truth. Needs node, engines/three/node_modules (`npm ci`), Chromium and three's
//! RectAreaLightTexturesLib.js in target/shipped (see .ci/run); skips with one line
//! without them.

use ndfbench::engines::EngineScenes;
use ndfbench::studies::engines::{compute, EngineRun, Inputs};
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
    let dir = std::env::temp_dir().join(format!("ndfbench-engines-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (a, b) = (dir.join("shipped.json"), dir.join("ours.json"));
    if let Err(e) = render("shipped", &a).and_then(|_| render("ours", &b)) {
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
    let read = |p: &Path, w: &str| {
        EngineRun::parse(&std::fs::read_to_string(p).unwrap(), &scenes, w).unwrap()
    };
    let (sr, or) = (read(&a, "shipped"), read(&b, "ours"));
    let shipped = ndfbench::ltc::compare::Shipped::parse(
        &std::fs::read_to_string(SHIPPED).unwrap(),
        "LTC_MAT_1",
        "LTC_MAT_2",
    )
    .unwrap();
    let ours = ndfbench::ltc::table::read(Path::new("results"), "ltc-ggx").unwrap();
    let r = compute(&Inputs {
        scenes: &scenes,
        shipped_run: &sr,
        ours_run: &or,
        shipped: &shipped,
        ours: &ours,
    })
    .unwrap();
    // 1. each image is what three's formulas give with the table that path should hold
    //    (our f32 table and our stored binary16 one; three's f32 numbers and its truncated
    //    halves): within f32 arithmetic and texture filtering, 1e-3 relative RMSE. A path
    //    that bound the other table, or a convention off (frame, winding, uv, clamp), is
    //    percent-level here.
    for s in &r.scenes {
        for p in &s.paths {
            assert!(
                p.gpu_share.rel_rmse.value < 1e-3,
                "{} {} {}: three's image is {} from its formulas with that table",
                s.name,
                p.table,
                p.path,
                p.gpu_share.rel_rmse.pct(3)
            );
        }
    }
    // 2. against the truth (exact, ± its bars): over the scenes, ours renders closer on
    //    both paths (mean relative RMSE), and the table's own share is smaller for ours
    let mean = |t: &str, p: &str, f: &dyn Fn(&ndfbench::studies::engines::PathResult) -> f64| {
        let v: Vec<f64> = r
            .scenes
            .iter()
            .flat_map(|s| s.paths.iter().filter(|x| x.table == t && x.path == p))
            .map(f)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    for path in ["float", "half"] {
        let (o, s) = (
            mean("ours", path, &|x| x.engine.rel_rmse.value),
            mean("shipped", path, &|x| x.engine.rel_rmse.value),
        );
        assert!(o < s, "{path} path: ours {o} against shipped {s}");
        let (o, s) = (
            mean("ours", path, &|x| x.table_share.rel_rmse.value),
            mean("shipped", path, &|x| x.table_share.rel_rmse.value),
        );
        assert!(
            o < s,
            "{path} path, the tables' share: ours {o} against shipped {s}"
        );
    }
    // 3. the committed report is this run's (within 1e-4 relative: another CPU's
    //    SwiftShader may round differently)
    let committed: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("results/engines.json").expect("results/engines.json"),
    )
    .unwrap();
    for (s, c) in r.scenes.iter().zip(committed["scenes"].as_array().unwrap()) {
        for (p, q) in s.paths.iter().zip(c["paths"].as_array().unwrap()) {
            let v = q["engine"]["rel_rmse"]["value"].as_f64().unwrap();
            assert!(
                (p.engine.rel_rmse.value - v).abs() <= 1e-4 * v + 1e-9,
                "results/engines.json is stale at {} {} {}: {v} committed, {} now",
                s.name,
                p.table,
                p.path,
                p.engine.rel_rmse.value
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
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

//! Scenes: the three examples build minimal, naga-valid WGSL and a report;
//! the committed outputs under results/scenes/ are fresh; bad scene files give errors
//! that name the key.

use ndfbench::scene::{build, Scene};
use std::path::Path;

const EXAMPLES: [&str; 3] = ["forward-ggx", "multiscale-ltc", "beckmann-cheap"];

fn validate(src: &str, what: &str) -> naga::Module {
    let m = naga::front::wgsl::parse_str(src)
        .unwrap_or_else(|e| panic!("{what}: {}", e.emit_to_string(src)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&m)
    .unwrap_or_else(|e| panic!("{what}: {e:?}"));
    m
}

#[test]
fn example_scenes_are_minimal_valid_and_fresh() {
    let all = ndfbench::codegen::desc::FUNCTIONS.len();
    for name in EXAMPLES {
        let s = Scene::load(&Path::new("tests/scenes").join(format!("{name}.toml"))).unwrap();
        let files = build(&s, Path::new("results")).unwrap();
        for (file, text) in &files {
            let committed =
                std::fs::read_to_string(Path::new("results/scenes").join(name).join(file))
                    .unwrap_or_else(|e| panic!("results/scenes/{name}/{file}: {e}"));
            assert!(&committed == text, "results/scenes/{name}/{file} is stale: rerun `cargo run --release -- scene tests/scenes/{name}.toml --out results/scenes/{name}`");
        }
        let wgsl = &files.iter().find(|f| f.0 == "scene.wgsl").unwrap().1;
        let m = validate(wgsl, name);
        let n = m.functions.len();
        assert!(
            n >= 1 && n < all,
            "{name}: {n} functions of {all} — not minimal"
        );
        let report = &files.iter().find(|f| f.0 == "report.md").unwrap().1;
        assert!(
            report.contains("±") && report.contains("ns/eval"),
            "{name}: report lacks error/cost"
        );
    }
    // the multi-scale scene needs α_me but no screen-space kernel
    let s = Scene::load(Path::new("tests/scenes/multiscale-ltc.toml")).unwrap();
    let w = &build(&s, Path::new("results")).unwrap()[0].1;
    assert!(w.contains("fn ndfb_alpha_me") && !w.contains("fn ndfb_filter_deferred"));
    assert!(
        w.contains("fn ndfb_ltc_quad")
            && w.contains("fn ndfb_ltc_lut_u")
            && !w.contains("fn ndfb_leadr5_env")
    );
}

fn parse_err(text: &str) -> String {
    Scene::parse(text, "t.toml").unwrap_err().to_string()
}

const BASE: &str = "name = \"t\"\nndf = \"ggx\"\nroughness = \"isotropic\"\nlights = [\"point\"]\nnormal_map_filter = \"vmf-2\"\nscreen_space_aa = \"none\"\nprecision = \"f32\"\nerror_budget = 0.5\n";

#[test]
fn bad_scenes_name_the_key() {
    assert!(Scene::parse(BASE, "t.toml").is_ok());
    let e = parse_err(&format!("{BASE}colour = 3\n"));
    assert!(e.contains("colour"), "{e}");
    let e = parse_err(&BASE.replace("\"ggx\"", "\"phong\""));
    assert!(e.contains("'ndf'") && e.contains("phong"), "{e}");
    let e = parse_err(
        &BASE
            .replace("\"ggx\"", "\"beckmann\"")
            .replace("isotropic", "matrix"),
    );
    assert!(e.contains("'roughness'") && e.contains("contradict"), "{e}");
    let e = parse_err(&BASE.replace("\"f32\"", "\"f16\""));
    assert!(e.contains("'precision'"), "{e}");
    let e = parse_err(
        &BASE
            .replace("[\"point\"]", "[\"polygon\"]")
            .replace("\"ggx\"", "\"beckmann\""),
    );
    assert!(e.contains("'lights'") && e.contains("contradict"), "{e}");
    let e = parse_err(&BASE.replace("[\"point\"]", "[\"environment\"]"));
    assert!(e.contains("'lights'"), "{e}");
    let e = parse_err(&BASE.replace("0.5", "-1"));
    assert!(e.contains("error_budget"), "{e}");
    let e = parse_err("name = \"t\"\nndf = \"ggx\"\n");
    assert!(e.contains("missing"), "{e}");
}

#[test]
fn auto_respects_the_budget_and_says_when_it_cannot() {
    let tight = BASE.replace("\"vmf-2\"", "\"auto\"").replace("0.5", "0.01");
    let s = Scene::parse(&tight, "t.toml").unwrap();
    let e = build(&s, Path::new("results")).unwrap_err().to_string();
    assert!(
        e.contains("error_budget") && e.contains("most accurate"),
        "{e}"
    );
    // a loose budget picks the cheapest: no filter at all costs nothing
    let loose = BASE.replace("\"vmf-2\"", "\"auto\"").replace("0.5", "10.0");
    let s = Scene::parse(&loose, "t.toml").unwrap();
    let r = &build(&s, Path::new("results")).unwrap()[2].1;
    assert!(r.contains("| normal-map filter | mip-normal (auto"), "{r}");
}

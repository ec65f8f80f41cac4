//! The renderer: scene files (strict and bounded), the exact texel coverage, the truth
//! against closed forms (flat maps: the lobe, and the LTC's exact polygon integral),
//! determinism at any thread count, the splatting P-NDF against the brute-force one, the
//! fast flakes generator against its full scan, the shipped LTC lookup against the f64
//! texture reference, and the `render` command's output and bad input.

mod common;

use ndfbench::filters::footprint::{flakes, NormalMap, Procedural};
use ndfbench::render::coverage::{area_centroid, shares};
use ndfbench::render::scene::Scene;
use ndfbench::render::{check, measure, methods, GlintPlan};
use ndfbench::studies::render::{builtin_params, sized, SCENES};

/// The render study's glint plan at `p`, as fits/render.toml sets it.
fn glint_plan(p: ndfbench::integrate::Preset) -> GlintPlan {
    builtin_params(p).unwrap().glints
}
use ndfbench::Error;
use proptest::prelude::*;
use std::path::Path;

fn scene(text: &str) -> Result<Scene, Error> {
    Scene::parse(text, "test.toml")
}

fn example(k: usize) -> Scene {
    Scene::parse(SCENES[k].1, SCENES[k].0).expect("example scene parses")
}

#[test]
fn the_example_scenes_parse_and_name_their_files() {
    for (name, text) in SCENES {
        let s = Scene::parse(text, name).expect("parses");
        assert_eq!(s.name, name);
        let on_disk = std::fs::read_to_string(format!("fits/render/{name}.toml")).expect("shipped");
        assert_eq!(
            on_disk, text,
            "fits/render/{name}.toml is the scene the study renders"
        );
    }
}

#[test]
fn bad_scenes_are_typed_errors_naming_the_field() {
    let base = SCENES[0].1;
    let cases: Vec<(String, &str)> = vec![
        (base.replace("alpha = 0.1", "alpha = 0.0"), "material.alpha"),
        (base.replace("alpha = 0.1", "alpha = nan"), "material.alpha"),
        (base.replace("width = 256", "width = 255"), "camera.width"),
        (
            base.replace("width = 256", "width = 100000"),
            "camera.width",
        ),
        (
            base.replace("fov_deg = 40.0", "fov_deg = inf"),
            "camera.fov_deg",
        ),
        (
            base.replace("map_size = 256", "map_size = 300"),
            "material.map_size",
        ),
        (
            base.replace("truth_samples = 256", "truth_samples = 1"),
            "render.truth_samples",
        ),
        (
            base.replace("truth_draws = 128", "truth_draws = 0"),
            "render.truth_draws",
        ),
        (
            base.replace("truth_draws = 128", "truth_draws = 4097"),
            "render.truth_draws",
        ),
        (
            // a serde type error names the value and its line
            base.replace("truth_draws = 128", "truth_draws = -3"),
            "integer `-3`",
        ),
        (
            base.replace("width = 256", "width = 2048")
                .replace("height = 256", "height = 2048")
                .replace("truth_samples = 256", "truth_samples = 4096"),
            "truth samples in all",
        ),
        (
            base.replace("v_axis = [0.0, -2.2, 3.0]", "v_axis = [1.0, 0.0, 0.0]"),
            "orthogonal",
        ),
        (
            base.replace("position = [0.0, -2.2, 1.6]", "position = [0.0, 0.0, 0.0]"),
            "look_at",
        ),
        (base.replace("seed = 11", "seed = 11\nbogus = 1"), "bogus"),
        (
            base.replace(
                "scales = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0]",
                "scales = []",
            ),
            "render.scales",
        ),
        (
            base.replace("name = \"multiscale-ltc-plane\"", "name = \"../x\""),
            "name",
        ),
    ];
    for (text, needle) in cases {
        match scene(&text) {
            Err(Error::InvalidArgument(m)) => {
                assert!(m.contains(needle), "{m} should name {needle}");
                assert!(!m.contains('\n'), "one line: {m}");
            }
            other => panic!("expected a typed error naming {needle}, got {other:?}"),
        }
    }
    let torus = SCENES[1]
        .1
        .replace("minor_radius = 0.2", "minor_radius = 2.0");
    assert!(matches!(scene(&torus), Err(Error::InvalidArgument(m)) if m.contains("minor_radius")));
}

/// A point light on the surface (where 1/r² has no value at its own hit and none bounded
/// beside it) is refused, on each kind of surface: on the torus's outer equator, its top
/// and its inner equator, on the sphere and on the plane; a light just off each is
/// accepted, so the check measures distance rather than refusing a region.
#[test]
fn point_lights_on_the_surface_are_typed_errors() {
    let torus = SCENES[1].1;
    let light = "position = [-3.0, -5.0, 6.0]";
    assert!(torus.contains(light), "the torus scene's point light");
    let with = |text: &str, p: [f64; 3]| {
        text.replace(
            light,
            &format!("position = [{:?}, {:?}, {:?}]", p[0], p[1], p[2]),
        )
    };
    // R = 1, r = 0.2: the tube's outer equator at ρ = 1.2, its top at (ρ = 1, z = 0.2), its
    // inner equator at ρ = 0.8
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let on_torus = [
        [1.2, 0.0, 0.0],
        [0.0, -1.2, 0.0],
        [s, s, 0.2],
        [-0.8 * s, 0.8 * s, 0.0],
    ];
    for p in on_torus {
        match scene(&with(torus, p)) {
            Err(Error::InvalidArgument(m)) => {
                assert!(
                    m.contains("lights[0].position") && m.contains("on the surface"),
                    "{m}"
                );
                assert!(!m.contains('\n'), "one line: {m}");
            }
            other => {
                panic!("a point light at {p:?} on the torus: expected a typed error, got {other:?}")
            }
        }
        // 1e-3 up: off the equators by ~2.5e-6 (the tube curves away), off the top by 1e-3
        let off = [p[0], p[1], p[2] + 1e-3];
        assert!(scene(&with(torus, off)).is_ok(), "{off:?} is off the torus");
    }
    let sphere = torus.replace("kind = \"torus\"", "kind = \"sphere\"");
    assert!(
        scene(&with(&sphere, [1.0, 1.0, 1.0])).is_ok(),
        "the sphere scene parses"
    );
    assert!(
        matches!(scene(&with(&sphere, [0.0, 0.0, -1.0])), Err(Error::InvalidArgument(m)) if m.contains("on the surface"))
    );
    assert!(
        matches!(scene(&with(&sphere, [0.6, 0.0, 0.8])), Err(Error::InvalidArgument(m)) if m.contains("on the surface"))
    );
    let plane = torus.replace("kind = \"torus\"", "kind = \"plane\"");
    assert!(
        matches!(scene(&with(&plane, [3.0, -2.0, 0.0])), Err(Error::InvalidArgument(m)) if m.contains("on the surface"))
    );
    assert!(
        matches!(scene(&with(&plane, [1e6, -2.0, -0.0])), Err(Error::InvalidArgument(m)) if m.contains("on the surface"))
    );
    assert!(
        scene(&with(&plane, [3.0, -2.0, 1e-6])).is_ok(),
        "1e-6 above the plane"
    );
}

proptest! {
    #![proptest_config(common::config(10_000))]
    /// The shares of a convex quadrilateral (any size from a tenth of a texel to 30
    /// texels, anywhere, any orientation) sum to its area by the shoelace formula, and
    /// their area-weighted centroids to its centroid.
    #[test]
    fn texel_shares_sum_to_the_footprint(cx in -1e3f64..1e3, cy in -1e3f64..1e3, a in 0.1f64..30.0, b in 0.1f64..30.0, rot in 0.0f64..6.3, shear in -0.9f64..0.9) {
        let (c, s) = (rot.cos(), rot.sin());
        let corner = |u: f64, v: f64| {
            let (x, y) = (a * u + shear * b * v, b * v);
            [cx + c * x - s * y, cy + s * x + c * y]
        };
        let q = [corner(-0.5, -0.5), corner(0.5, -0.5), corner(0.5, 0.5), corner(-0.5, 0.5)];
        let (area, centroid) = area_centroid(&q);
        let sh = shares(&q, 1 << 20).expect("bounded");
        let total: f64 = sh.iter().map(|s| s.area).sum();
        prop_assert!((total - area.abs()).abs() <= 1e-9 * area.abs().max(1.0), "{total} vs {area}");
        let mx = sh.iter().map(|s| s.area * s.centroid[0]).sum::<f64>() / total;
        let my = sh.iter().map(|s| s.area * s.centroid[1]).sum::<f64>() / total;
        prop_assert!((mx - centroid[0]).abs() <= 1e-7 * (1.0 + cx.abs()) && (my - centroid[1]).abs() <= 1e-7 * (1.0 + cy.abs()));
        prop_assert!(sh.iter().all(|s| s.area > 0.0 && s.area <= 1.0 + 1e-12));
    }
}

#[test]
fn a_footprint_too_large_is_left_to_sampling() {
    let q = [[0.0, 0.0], [100.0, 0.0], [100.0, 100.0], [0.0, 100.0]];
    assert!(shares(&q, 4096).is_none());
    assert!(shares(&[[0.0, 0.0], [f64::NAN, 0.0], [1.0, 1.0], [0.0, 1.0]], 4096).is_none());
}

#[test]
fn the_truth_agrees_with_closed_forms_on_flat_maps() {
    for (name, text, nodes) in check::scenes() {
        let s = Scene::parse(&text, name).expect("check scene");
        let r = check::run(&s, name, nodes).expect("renders");
        assert!(r.pixels > 500, "{name}: {} pixels", r.pixels);
        if name.contains("closed form") {
            // point and directional lights on exact footprints: no MC at all, only the
            // midpoint rule within each texel's share (here one texel per pixel)
            assert!(r.max_rel < 5e-4, "{name}: {r:?}");
        } else {
            // the LTC's quad light by MC: the standard errors must be honest
            assert!((0.6..1.6).contains(&r.mse_over_se2), "{name}: {r:?}");
            assert!(r.frac_z4 < 0.03, "{name}: {r:?}");
            assert!(r.max_abs_over_mean < 0.2, "{name}: {r:?}");
        }
    }
}

fn small(mut s: Scene) -> Scene {
    s = sized(
        s,
        &builtin_params(ndfbench::integrate::Preset::Quick).unwrap(),
    );
    s.camera.width = 24;
    s.camera.height = 24;
    s.render.scales.truncate(2);
    if let Some(p) = &mut s.camera.path {
        p.frames = 3;
    }
    s
}

fn plan() -> GlintPlan {
    let mut p = glint_plan(ndfbench::integrate::Preset::Quick);
    p.iters = 4;
    p
}

#[test]
fn renders_are_bit_identical_at_any_thread_count() {
    let c = ndfbench::results::render::constants(Path::new("results"))
        .expect("results/fits/filters.json");
    for k in 0..SCENES.len() {
        let mut s = small(example(k));
        // the glint scenes (quad light, SG sky) on a smaller map
        if k >= 2 {
            s.material.map_size = 128;
        }
        let go = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool")
                .install(|| {
                    ndfbench::render::render(&s, Path::new("fits/render"), &c, &plan())
                        .expect("renders")
                })
        };
        let (a, b) = (go(1), go(3));
        assert_eq!(a.views.len(), b.views.len());
        for (va, vb) in a.views.iter().zip(&b.views) {
            let bits = |v: &ndfbench::render::View| -> Vec<u64> {
                v.truth
                    .iter()
                    .flat_map(|t| [t.value.to_bits(), t.se().to_bits()])
                    .chain(
                        v.methods
                            .iter()
                            .flat_map(|m| m.pixels.iter().map(|p| p.to_bits() as u64)),
                    )
                    .collect()
            };
            assert_eq!(bits(va), bits(vb), "{}", s.name);
            assert!(
                !va.methods.is_empty(),
                "{}: every method of the set renders",
                s.name
            );
        }
        let m = measure::measure_render(&a);
        for v in &m.views {
            for sc in v {
                assert!(
                    sc.m.mse.value.is_finite() && sc.m.flip.value.is_finite(),
                    "{}: {}",
                    s.name,
                    sc.key
                );
            }
        }
    }
}

#[test]
fn the_batched_simd_image_is_the_per_pixel_scalar_image() {
    // quad lights through kernels::ltc_quad (AVX2 ≤ 2 ulp of the scalar twin, tests/kernels.rs)
    let s = small(example(0));
    let c = ndfbench::results::render::constants(Path::new("results"))
        .expect("constants")
        .with_alpha(s.material.alpha);
    let tex = ndfbench::render::texture::Texture::new(
        ndfbench::render::normal_map(&s, Path::new("fits/render")).expect("map"),
    );
    let lights = ndfbench::render::light::resolve(&s.lights);
    let cam = ndfbench::render::geometry::Camera::at_frame(&s.camera, 0);
    for &scale in &s.render.scales {
        let surf = ndfbench::render::geometry::Surface::new(&s.surface, scale);
        let g = methods::gbuffer(&cam, &surf, &tex);
        for key in methods::MULTISCALE {
            let m = methods::Method::new(key, &c).expect("a registry key");
            let img = methods::shade_image(m, &g, cam.width, s.material.alpha as f32, &lights, &c)
                .expect("kernel");
            for (k, v) in img.iter().enumerate() {
                let r = methods::shade(m, &g, cam.width, k, s.material.alpha as f32, &lights, &c);
                assert!(
                    (v - r).abs() <= 4.0 * f32::EPSILON * r.abs().max(1.0),
                    "{m:?} pixel {k}: {v} vs {r}"
                );
            }
        }
    }
}

#[test]
fn the_measures_of_the_truth_itself_are_zero() {
    let c = ndfbench::results::render::constants(Path::new("results")).expect("constants");
    let s = small(example(0));
    let r = ndfbench::render::render(&s, Path::new("fits/render"), &c, &plan()).expect("renders");
    let v = &r.views[0];
    let t: Vec<f32> = v.truth.iter().map(|p| p.value as f32).collect();
    let (rmse, rel, _, n) = measure::errors(&v.truth, &t);
    assert!(n > 0);
    // the truth rounded to f32 against itself in f64: only rounding remains
    assert!(
        rmse.value <= 1e-7 * v.truth.iter().map(|p| p.value).fold(0.0, f64::max)
            && rel.value < 1e-12
    );
    let tv: Vec<f64> = t.iter().map(|&x| x as f64).collect();
    let (_, f) = measure::flip(&tv, &tv, r.width, r.height, 1.0, &measure::mask(&v.truth));
    assert_eq!(f.value, 0.0, "ꟻLIP of an image against itself");
}

#[test]
fn the_splatted_pndf_equals_the_brute_force_one() {
    let map = NormalMap::procedural(Procedural::Flakes, 64, 3).expect("map");
    for &(cx, cy, sp, sr, res) in &[
        (10.3, 20.7, 3.0, 0.02, 32usize),
        (0.0, 63.9, 1.2, 0.05, 16),
        (31.5, 31.5, 6.0, 0.01, 64),
    ] {
        let a = ndfbench::tensor::pndf::pndf_image(&map, cx, cy, sp, sr, res).expect("brute");
        let b = ndfbench::tensor::pndf::pndf_image_splat(&map, cx, cy, sp, sr, res).expect("splat");
        let peak = a.iter().cloned().fold(0.0, f64::max);
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1e-12 * peak, "{x} vs {y}");
        }
    }
}

#[test]
fn the_fast_flakes_are_the_full_scan_flakes() {
    for &(size, seed) in &[(8usize, 1u64), (16, 2), (64, 3), (128, 9), (256, 3)] {
        assert_eq!(
            flakes(size, seed, false),
            flakes(size, seed, true),
            "size {size}"
        );
    }
}

#[test]
fn the_shipped_ltc_lookup_matches_the_texture_reference() {
    let t = ndfbench::results::ltc::table(Path::new("results"), "ltc-ggx")
        .expect("results/fits/ltc-ggx.json");
    let mut worst = 0.0f64;
    for i in 0..=40 {
        for j in 0..=40 {
            let (a, c) = (i as f64 / 40.0, j as f64 / 40.0);
            let r = t.bilinear(a, c, true);
            let (m, norm) = methods::ltc_lookup(a as f32, c as f32);
            for (k, v) in m.iter().enumerate() {
                worst = worst.max((*v as f64 - r[k]).abs() / r[k].abs().max(1e-3));
            }
            worst = worst.max((norm as f64 - r[4]).abs() / r[4].abs().max(1e-3));
        }
    }
    // f32 arithmetic on the same binary16 entries (the f64 reference rounds (α, cos θ)
    // differently by at most an ulp of f32)
    assert!(worst < 1e-4, "{worst}");
}

use common::bin;

#[test]
fn the_render_command_writes_its_report_and_rejects_bad_input() {
    let dir = common::scratch("render", "render");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let sc = dir.join("tiny.toml");
    let text = SCENES[0]
        .1
        .replace("width = 256", "width = 16")
        .replace("height = 256", "height = 16")
        .replace(
            "scales = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0]",
            "scales = [1.0, 4.0]",
        );
    std::fs::write(&sc, text).expect("write");
    let out = dir.join("out");
    let o = bin()
        .args([
            "render",
            sc.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(out.join("multiscale-ltc-plane.md")).expect("report");
    assert!(md.contains("renormalised mip normal") && md.contains("ꟻLIP"));
    assert!(out.join("multiscale-ltc-plane-grid.png").is_file());
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("multiscale-ltc-plane.json")).expect("json"),
    )
    .expect("parses");
    assert_eq!(json["views"].as_array().map(|v| v.len()), Some(2));
    // bad input: exit 2 and one line, nothing written
    let bad = dir.join("bad.toml");
    for body in [
        "not toml [[[",
        &SCENES[0].1.replace("alpha = 0.1", "alpha = -1.0"),
        &SCENES[0]
            .1
            .replace("\"isotropic-noise\"", "\"missing.png\""),
    ] {
        std::fs::write(&bad, body).expect("write");
        let o2 = dir.join("never");
        let o = bin()
            .args([
                "render",
                bad.to_str().unwrap(),
                "--out",
                o2.to_str().unwrap(),
            ])
            .output()
            .expect("runs");
        assert_eq!(
            o.status.code(),
            Some(2),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!o2.join("multiscale-ltc-plane.md").exists());
    }
    let o = bin()
        .args([
            "render",
            dir.join("absent.toml").to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn extreme_scenes_render_finite_images() {
    // α at both ends of the scene range, a camera 0.01° above the plane (89.99° from its
    // normal), and the torus edge-on: every truth value, s.e. and method pixel finite
    // and non-negative
    let c = ndfbench::results::render::constants(Path::new("results")).expect("constants");
    let mut cases = Vec::new();
    for alpha in ["0.0001", "1.0"] {
        for k in 0..2 {
            let mut s = small(example(k));
            s.material.alpha = alpha.parse().unwrap();
            cases.push(s);
        }
    }
    let mut grazing = small(example(0));
    let d = 3.0f64;
    let e = 0.01f64.to_radians();
    grazing.camera.position = [0.0, -d * e.cos(), d * e.sin()];
    grazing.camera.look_at = [0.0, 0.0, 0.0];
    cases.push(grazing);
    let mut edge_on = small(example(1));
    edge_on.camera.position = [0.0, -9.0, 0.0];
    edge_on.camera.path = None;
    cases.push(edge_on);
    for s in cases {
        let r =
            ndfbench::render::render(&s, Path::new("fits/render"), &c, &plan()).expect("renders");
        for v in &r.views {
            for t in &v.truth {
                assert!(
                    t.value.is_finite() && t.value >= 0.0 && t.se().is_finite(),
                    "{} α {}: {t:?}",
                    s.name,
                    s.material.alpha
                );
            }
            for m in &v.methods {
                assert!(
                    m.pixels.iter().all(|p| p.is_finite() && *p >= 0.0),
                    "{} α {}: {}",
                    s.name,
                    s.material.alpha,
                    m.key
                );
            }
        }
    }
}

/// A size derived from two checked inputs is checked where it is derived: the glint
/// footprint grid is map_size ÷ the preset's stride, so a map narrower than the stride
/// (32 at the quick preset's 64, 8 at the default's 16) is a typed one-line error before
/// any work, at every preset; a camera path whose eye reaches look_at on any frame is
/// refused like a position on look_at.
#[test]
fn derived_sizes_and_every_camera_frame_are_checked() {
    use ndfbench::integrate::Preset;
    for (preset, ok, bad) in [
        (Preset::Quick, 64, 32),
        (Preset::Default, 16, 8),
        (Preset::Precise, 8, 4),
    ] {
        let plan = glint_plan(preset);
        assert!(plan.check(ok).is_ok(), "{preset:?} at {ok}");
        match plan.check(bad) {
            Err(Error::InvalidArgument(m)) => {
                assert!(m.contains("map_size") && !m.contains('\n'), "{m}")
            }
            other => panic!("{preset:?} at {bad}: {other:?}"),
        }
    }
    let dir = common::scratch("render", "derived");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let glints = SCENES
        .iter()
        .find(|s| s.0 == "glints-plane")
        .expect("the glints scene")
        .1;
    for (preset, size) in [("quick", 32), ("default", 8)] {
        let sc = dir.join(format!("g{size}.toml"));
        std::fs::write(
            &sc,
            glints.replace("map_size = 1024", &format!("map_size = {size}")),
        )
        .expect("write");
        let out = dir.join(format!("out{size}"));
        let o = bin()
            .args(["render", sc.to_str().unwrap(), "--preset", preset])
            .args(["--out", out.to_str().unwrap()])
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{preset} {size}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains("map_size"), "{err}");
        assert!(!out.join("glints-plane.md").exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
    let torus = SCENES
        .iter()
        .find(|s| s.0 == "specular-aa-torus")
        .expect("the torus scene")
        .1;
    for path in [
        // the last frame on look_at
        "path = { to = [0.0, 0.0, 0.0], frames = 32 }",
        // the middle frame of three on look_at
        "path = { to = [0.0, 9.0, -3.0], frames = 3 }",
    ] {
        let text = torus.replace("path = { to = [0.0, -7.65, 2.55], frames = 32 }", path);
        assert_ne!(text, torus);
        match scene(&text) {
            Err(Error::InvalidArgument(m)) => {
                assert!(m.contains("camera.path") && !m.contains('\n'), "{m}")
            }
            other => panic!("{path}: {other:?}"),
        }
    }
    // a path that passes near but not through look_at still parses
    let near = torus.replace(
        "path = { to = [0.0, -7.65, 2.55], frames = 32 }",
        "path = { to = [0.0, 9.0, -3.0], frames = 4 }",
    );
    assert!(scene(&near).is_ok());
}

#[test]
fn grids_name_their_columns_and_rows_in_the_picture() {
    use ndfbench::render::picture::{grid, label, labelled_grid, Rgb, LINE};
    let tile = |v: u8| Rgb::new(16, 16, [v, v, v]);
    let tiles = vec![vec![tile(10), tile(20)], vec![tile(30), tile(40)]];
    let cols = vec!["A".to_string(), String::new()];
    let rows = vec!["row".to_string(), "α".to_string()];
    let (gap, lines, side) = (2, 2, 24);
    let g = labelled_grid(&tiles, gap, &cols, &rows, lines, side).unwrap();
    let body = grid(&tiles, gap);
    let head = lines * LINE + gap;
    assert_eq!((g.w, g.h), (side + body.w, head + body.h));
    // the body is the plain grid, moved right and down
    for y in 0..body.h {
        for x in 0..body.w {
            assert_eq!(g.px[(head + y) * g.w + side + x], body.px[y * body.w + x]);
        }
    }
    let white = |x0: usize, x1: usize, y0: usize, y1: usize| {
        (y0..y1).any(|y| (x0..x1).any(|x| g.px[y * g.w + x] == [255, 255, 255]))
    };
    // column 0 is named, column 1 is not; both rows are named
    let c0 = side + gap;
    assert!(white(c0, c0 + 16, 0, head));
    assert!(!white(c0 + 16 + gap, c0 + 32 + gap, 0, head));
    assert!(white(0, side, head, head + 16) && white(0, side, head + 18, head + 34));
    // the glyph is font8x8's: 'I' row by row, least significant bit leftmost
    let i = label("I", 8, 1);
    for (gy, bits) in font8x8::legacy::BASIC_LEGACY[b'I' as usize]
        .iter()
        .enumerate()
    {
        for gx in 0..8 {
            let lit = i.px[(1 + gy) * 8 + gx] == [255, 255, 255];
            assert_eq!(lit, bits >> gx & 1 == 1, "pixel ({gx}, {gy}) of 'I'");
        }
    }
    // Greek letters are spelled in ASCII; the wrong number of names is a typed error
    assert_eq!(label("α", 40, 1).px, label("alpha", 40, 1).px);
    // a fourth root after a caret is not given a second caret
    assert_eq!(label("A)^¼", 80, 1).px, label("A)^(1/4)", 80, 1).px);
    assert_eq!(label("A¼", 80, 1).px, label("A^(1/4)", 80, 1).px);
    assert!(labelled_grid(&tiles, gap, &cols[..1], &rows, lines, side).is_err());
}

#[test]
fn the_committed_render_grids_are_labelled() {
    let dir = Path::new("results/render");
    let mut seen = 0;
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.extension().is_none_or(|x| x != "png") {
            continue;
        }
        let img = image::open(&p).unwrap().to_rgb8();
        // the band above the first row of tiles holds the column names: white text pixels
        let band = 2 * ndfbench::render::picture::LINE;
        let text = (0..band as u32)
            .flat_map(|y| (0..img.width()).map(move |x| (x, y)))
            .filter(|&(x, y)| img.get_pixel(x, y).0 == [255, 255, 255])
            .count();
        assert!(
            text > 20,
            "{} has no column names in its top band",
            p.display()
        );
        seen += 1;
    }
    assert!(seen >= 4, "only {seen} render pictures");
}

/// The image MSE is unbiased against the exact image, and its bar is the truth noise's:
/// over independent truth renders of a known image (two replicates per pixel, each with
/// near-Gaussian noise of mean zero, as a mean of many samples is), the estimates scatter about the exact MSE with z-scores of spread ≈ 1,
/// while the plain mean of (m − v)² sits above it by the truth's noise.
#[test]
fn the_image_mse_is_unbiased_and_its_bar_is_the_truth_noise() {
    use ndfbench::render::truth::PixelTruth;
    use rand::{Rng, SeedableRng};
    let n = 4096;
    let exact: Vec<f64> = (0..n)
        .map(|i| 0.2 + 0.8 * ((i * 37) % 101) as f64 / 100.0)
        .collect();
    // a method off by a smooth 5 % and a constant
    let img: Vec<f32> = exact.iter().map(|t| (1.05 * t + 0.01) as f32).collect();
    let mse_exact = exact
        .iter()
        .zip(&img)
        .map(|(t, &m)| (m as f64 - t).powi(2))
        .sum::<f64>()
        / n as f64;
    let t2_exact = exact.iter().map(|t| t * t).sum::<f64>() / n as f64;
    let (mut z, mut zr, mut naive_excess) = (Vec::new(), Vec::new(), 0.0);
    for seed in 0..300u64 {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let truth: Vec<PixelTruth> = exact
            .iter()
            .map(|&t| {
                // each replicate: t plus noise of s.d. 0.1 t (Irwin–Hall: the sum of 12
                // uniforms less 6, near-Gaussian with mean 0 and variance 1)
                let mut g = || (0..12).map(|_| rng.random::<f64>()).sum::<f64>() - 6.0;
                let r1 = t * (1.0 + 0.1 * g());
                let r2 = t * (1.0 + 0.1 * g());
                PixelTruth {
                    value: 0.5 * (r1 + r2),
                    diff: 0.5 * (r1 - r2),
                    covered: true,
                }
            })
            .collect();
        let (mse, rel, _, pixels) = measure::errors(&truth, &img);
        assert_eq!(pixels, n);
        z.push((mse.value - mse_exact) / mse.error);
        zr.push((rel.value - mse_exact / t2_exact) / rel.error);
        let naive = truth
            .iter()
            .zip(&img)
            .map(|(t, &m)| (m as f64 - t.value).powi(2))
            .sum::<f64>()
            / n as f64;
        naive_excess += (naive - mse_exact) / mse.error / 300.0;
    }
    let stats = |v: &[f64]| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        let sd = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt();
        (m, sd)
    };
    let (m, sd) = stats(&z);
    eprintln!("MSE z: mean {m:+.3}, spread {sd:.3}");
    // unbiased: the mean z of 300 runs within 4/√300 of 0; honest bar: spread ≈ 1
    assert!(m.abs() < 4.0 / 300f64.sqrt(), "mean z {m}");
    assert!((0.85..1.15).contains(&sd), "z spread {sd}");
    let (m, sd) = stats(&zr);
    eprintln!("relative MSE z: mean {m:+.3}, spread {sd:.3}");
    assert!(m.abs() < 4.0 / 300f64.sqrt(), "relative: mean z {m}");
    assert!((0.85..1.15).contains(&sd), "relative: z spread {sd}");
    eprintln!("uncorrected MSE: off by {naive_excess:.0} bars on average");
    // the uncorrected mean is off by many bars
    assert!(naive_excess > 10.0, "naive excess {naive_excess} bars");
}

/// Flicker against a noisy truth: the temporal MSE and the excess come from the truth's two
/// replicates, so over a known sequence they match the exact figures (computed from the
/// noiseless truth) within their s.e., while the plain (Δm − Δt̂)² over the replicates'
/// mean sits above by the noise.
#[test]
fn flicker_figures_are_not_biased_by_the_truths_noise() {
    use ndfbench::render::truth::PixelTruth;
    use rand::{Rng, SeedableRng};
    let (n, frames, exposure) = (2048usize, 40usize, 1.0);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let exact: Vec<Vec<f64>> = (0..frames)
        .map(|f| {
            (0..n)
                .map(|i| 0.3 + 0.2 * ((i as f64 * 0.37 + f as f64 * 0.9).sin()))
                .collect()
        })
        .collect();
    // the method lags the truth by a quarter frame and adds a small offset
    let method: Vec<Vec<f32>> = (0..frames)
        .map(|f| {
            (0..n)
                .map(|i| (0.31 + 0.2 * ((i as f64 * 0.37 + (f as f64 - 0.25) * 0.9).sin())) as f32)
                .collect()
        })
        .collect();
    let truth: Vec<Vec<PixelTruth>> = exact
        .iter()
        .map(|fr| {
            fr.iter()
                .map(|&t| {
                    let mut g = || (0..12).map(|_| rng.random::<f64>()).sum::<f64>() - 6.0;
                    let (r1, r2) = (t * (1.0 + 0.03 * g()), t * (1.0 + 0.03 * g()));
                    PixelTruth {
                        value: 0.5 * (r1 + r2),
                        diff: 0.5 * (r1 - r2),
                        covered: true,
                    }
                })
                .collect()
        })
        .collect();
    let tr: Vec<&[PixelTruth]> = truth.iter().map(|v| v.as_slice()).collect();
    let mr: Vec<&[f32]> = method.iter().map(|v| v.as_slice()).collect();
    let f = measure::flicker(&tr, &mr, exposure);
    // exact figures from the noiseless truth
    let tone = |x: f64| measure::tone(x, exposure);
    let (mut mse, mut exc, mut naive) = (0.0, 0.0, 0.0);
    for k in 1..frames {
        let (mut s, mut e, mut q) = (0.0, 0.0, 0.0);
        for p in 0..n {
            let dm = tone(method[k][p] as f64) - tone(method[k - 1][p] as f64);
            let dt = tone(exact[k][p]) - tone(exact[k - 1][p]);
            let dh = tone(truth[k][p].value) - tone(truth[k - 1][p].value);
            s += (dm - dt).powi(2);
            e += dm * dm - dt * dt;
            q += (dm - dh).powi(2);
        }
        mse += s / n as f64 / (frames - 1) as f64;
        exc += e / n as f64 / (frames - 1) as f64;
        naive += q / n as f64 / (frames - 1) as f64;
    }
    eprintln!(
        "temporal MSE {} (exact {mse:.4e}, from the replicates' mean {naive:.4e}); excess {} (exact {exc:.4e})",
        f.temporal_mse.sci(4, 1),
        f.excess.sci(4, 1)
    );
    assert!((f.temporal_mse.value - mse).abs() <= 4.0 * f.temporal_mse.error);
    assert!((f.excess.value - exc).abs() <= 4.0 * f.excess.error);
    assert!(
        naive - mse > 10.0 * f.temporal_mse.error,
        "the noise is visible"
    );
}

/// Texels drawn in proportion to their overlap (`truth_draws`) estimate what shading every
/// texel gives, with honest errors: the multi-scale plane's quad light at scale ×32, the
/// centre 64² pixels (footprints of hundreds of texels), n/2 = 128 draws per replicate
/// against every texel on the footprints larger than that, independent seeds. Both the mean difference and the mean excess
/// (t_d − t_e)² − s.e._d² − s.e._e² must be within 4 of their standard errors of 0.
#[test]
fn drawn_texels_estimate_the_every_texel_truth() {
    use ndfbench::integrate::Figure;
    use ndfbench::render::geometry::{Camera, Surface};
    use ndfbench::render::truth::{footprint_texels, pixel, Budget, Shader};
    use ndfbench::render::{light, normal_map, texture::Texture};
    let s = example(0);
    assert_eq!(s.name, "multiscale-ltc-plane");
    let tex = Texture::new(normal_map(&s, Path::new("fits/render")).expect("map"));
    let lights = light::resolve(&s.lights);
    let m = &s.material;
    let sh = Shader::new(m.lobe, m.alpha, m.sigma_r, &lights, &tex).expect("shader");
    let surf = Surface::new(&s.surface, 32.0);
    let cam = Camera::at_frame(&s.camera, 0);
    let n = s.render.truth_samples;
    let (mut diff, mut excess, mut largest) = (Vec::new(), Vec::new(), 0);
    for y in 96..160 {
        for x in 96..160 {
            let t = footprint_texels(&cam, &surf, &sh, x, y).expect("an exact footprint");
            largest = largest.max(t);
            if t <= 128 {
                continue;
            }
            let e = pixel(&cam, &surf, &sh, x, y, Budget { n, draws: None }, 5);
            let d = pixel(
                &cam,
                &surf,
                &sh,
                x,
                y,
                Budget {
                    n,
                    draws: Some(128),
                },
                6,
            );
            assert!(d.se() > 0.0 && e.se() > 0.0);
            diff.push(d.value - e.value);
            excess.push((d.value - e.value).powi(2) - d.se().powi(2) - e.se().powi(2));
        }
    }
    assert!(largest > 300, "largest footprint {largest} texels");
    assert!(diff.len() > 2000, "{} footprints drew", diff.len());
    for (what, f) in [
        ("difference", Figure::mean_of(&diff)),
        ("excess", Figure::mean_of(&excess)),
    ] {
        assert!(
            f.value.abs() <= 4.0 * f.error,
            "mean {what} {} ± {}",
            f.value,
            f.error
        );
    }
}

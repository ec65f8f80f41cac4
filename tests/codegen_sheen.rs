//! The texture-free sheen LTCs' generated code (`codegen::sheen`) against the series it was
//! generated from (results/fits/ltc-compact.json's texture-free picks):
//!
//! - Rust (src/generated/ltc_sheen.rs) equals `Compact::eval_f32`'s five lobe channels bit
//!   for bit over the whole input range, out-of-range inputs included, for both families;
//! - the WGSL module parses and validates with naga and defines each family's functions;
//! - the GLSL is ASCII, defines the same functions, compiles as a GLSL ES 3.00 fragment
//!   shader with glslangValidator (skips with one line without it), and the three.js
//!   recipe embeds the Neubelt family's GLSL exactly as the file holds it;
//! - the WebGPU recipe's `wgslFn` functions are, each, text of the validated WGSL file.
//!
//! The committed files are stale-checked by tests/codegen.rs with the other generated code;
//! the recipe is rendered in three.js by tests/engines.rs.

mod common;

use ndfbench::codegen::sheen::{self, Lang, FAMILIES};
use ndfbench::generated::ltc_sheen::{ltc_sheen_ek, ltc_sheen_neubelt};
use ndfbench::ltc::compact::Compact;
use proptest::prelude::*;
use std::path::Path;

fn series(table: &str) -> Compact {
    ndfbench::results::ltc_compact::texture_free_series(Path::new("results"), table)
        .unwrap()
        .expect("results/fits/ltc-compact.json holds the texture-free picks")
        .0
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// Both generated evaluations are `Compact::eval_f32`'s first five channels, bit for
    /// bit, at any (r, t) a shader can pass (clamped outside [0, 1]; the ends, tiny values
    /// and three's smallest sheenRoughness 0.07 included).
    #[test]
    fn generated_rust_is_the_f32_form_bit_for_bit(
        r in prop_oneof![Just(0.0f32), Just(1.0f32), Just(0.07f32), Just(1e-30f32), -0.5f32..1.5, 0.0f32..1e-3],
        t in prop_oneof![Just(0.0f32), Just(1.0f32), Just(1e-30f32), -0.5f32..1.5, 0.999f32..1.0],
    ) {
        for (table, got) in [("ltc-sheen", ltc_sheen_ek(r, t)), ("ltc-sheen-neubelt", ltc_sheen_neubelt(r, t))] {
            let c = series(table);
            let want = c.eval_f32(&c.coeffs_f32(), r, t);
            for ch in 0..5 {
                prop_assert_eq!(got[ch].to_bits(), want[ch].to_bits(), "{} channel {} at ({}, {})", table, ch, r, t);
            }
        }
    }
}

/// The forms are lobes a shader can use: a positive norm and an invertible M⁻¹ over the
/// whole (r, t) square (a 257² grid), both families.
#[test]
fn the_generated_forms_give_a_positive_norm_and_an_invertible_matrix() {
    for k in 0..=256 * 257 + 256 {
        let (r, t) = ((k % 257) as f32 / 256.0, (k / 257) as f32 / 256.0);
        for v in [ltc_sheen_ek(r, t), ltc_sheen_neubelt(r, t)] {
            assert!(v.iter().all(|x| x.is_finite()), "({r}, {t}): {v:?}");
            assert!(v[4] > 0.0, "norm {} at ({r}, {t})", v[4]);
            // M⁻¹ = [[a, 0, c], [0, 1, 0], [b, 0, d]]: det = a·d − b·c
            let det = f64::from(v[0]) * f64::from(v[3]) - f64::from(v[1]) * f64::from(v[2]);
            assert!(det.abs() > 1e-6, "det {det} at ({r}, {t})");
        }
    }
}

#[test]
fn the_wgsl_module_validates_with_naga_and_defines_each_family() {
    let src = std::fs::read_to_string("results/wgsl/ltc_sheen.wgsl").unwrap();
    let module = naga::front::wgsl::parse_str(&src)
        .unwrap_or_else(|e| panic!("ltc_sheen.wgsl: {}", e.emit_to_string(&src)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("ltc_sheen.wgsl: {e:?}"));
    for f in &FAMILIES {
        for suffix in ["mat", "norm"] {
            let name = format!("ltc_sheen_{}_{suffix}", f.key);
            assert!(
                module
                    .functions
                    .iter()
                    .any(|(_, g)| g.name.as_deref() == Some(&name)),
                "{name} missing"
            );
        }
    }
}

#[test]
fn the_glsl_is_ascii_compiles_and_is_what_the_recipe_embeds() {
    let glsl = std::fs::read_to_string("results/glsl/ltc_sheen.glsl").unwrap();
    assert!(
        glsl.is_ascii(),
        "results/glsl/ltc_sheen.glsl holds a non-ASCII character"
    );
    let recipe = std::fs::read_to_string("results/textures/three/RectAreaLightSheen.js").unwrap();
    let fams = sheen::read(Path::new("results")).unwrap();
    let (f, c, d) = fams.iter().find(|(f, _, _)| f.key == "neubelt").unwrap();
    let part = sheen::render_family(Lang::Glsl, f, c, d);
    assert!(
        glsl.contains(&part),
        "the GLSL file lacks the Neubelt family's functions"
    );
    assert!(
        recipe.contains(&format!("const GLSL = `{part}`;")),
        "the recipe does not embed the Neubelt GLSL as the file holds it"
    );
    for f in &FAMILIES {
        for (ret, suffix) in [("vec4", "mat"), ("float", "norm")] {
            let sig = format!("{ret} ltc_sheen_{}_{suffix}(float r_in, float t_in)", f.key);
            assert!(glsl.contains(&sig), "{sig} missing");
        }
    }
    if std::process::Command::new("glslangValidator")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("skipped: glslangValidator absent (see .ci/run: apt glslang-tools)");
        return;
    }
    let dir = common::scratch("codegen_sheen", "glsl");
    std::fs::create_dir_all(&dir).unwrap();
    let frag = dir.join("sheen.frag");
    std::fs::write(
        &frag,
        format!(
            "#version 300 es\nprecision highp float;\n{glsl}\nuniform vec2 rt;\nout vec4 color;\nvoid main() {{\n    color = ltc_sheen_ek_mat(rt.x, rt.y) + ltc_sheen_neubelt_mat(rt.x, rt.y) + vec4(ltc_sheen_ek_norm(rt.x, rt.y), ltc_sheen_neubelt_norm(rt.x, rt.y), 0.0, 0.0);\n}}\n"
        ),
    )
    .unwrap();
    let o = std::process::Command::new("glslangValidator")
        .arg(&frag)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "glslangValidator rejects the GLSL: {}",
        String::from_utf8_lossy(&o.stdout)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The WebGPURenderer recipe (RectAreaLightSheenNode.js) hands three exactly the Neubelt
/// functions of the naga-validated WGSL file: every `wgslFn` code string is a piece of it,
/// and there is one per channel plus the matrix and the norm.
#[test]
fn the_webgpu_recipe_embeds_the_validated_wgsl() {
    let wgsl = std::fs::read_to_string("results/wgsl/ltc_sheen.wgsl").unwrap();
    let js = std::fs::read_to_string("results/textures/three/RectAreaLightSheenNode.js").unwrap();
    let pieces: Vec<&str> = js
        .split("wgslFn( `")
        .skip(1)
        .map(|p| p.split('`').next().unwrap())
        .collect();
    assert_eq!(pieces.len(), 7, "5 channels, the matrix and the norm");
    for p in &pieces {
        assert!(
            p.starts_with("fn ltc_sheen_neubelt_"),
            "{}",
            &p[..40.min(p.len())]
        );
        assert!(
            wgsl.contains(p),
            "not in ltc_sheen.wgsl: {}",
            &p[..60.min(p.len())]
        );
    }
}

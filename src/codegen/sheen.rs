//! The texture-free Charlie sheen LTC as generated code: for each sheen family of
//! results/fits/ltc-compact.json (Estevez–Kulla's Λ, glTF's; Neubelt's visibility,
//! three.js's and Filament's), the form the study picked for a shader with no texture
//! (`results::ltc_compact::texture_free_series`), its five lobe channels (M⁻¹'s a, b, c,
//! d and the norm; the sheen has no Fresnel), in three forms of one f32 evaluation,
//! `ltc::compact::Compact::eval_f32`:
//!
//! - Rust, src/generated/ltc_sheen.rs: `ltc_sheen_ek(r, t)`, `ltc_sheen_neubelt(r, t)`;
//! - WGSL, results/wgsl/ltc_sheen.wgsl: `ltc_sheen_<family>_mat(r, t)` (a, b, c, d) and
//!   `ltc_sheen_<family>_norm(r, t)`, straight-line code with the coefficients as
//!   literals;
//! - GLSL ES 3.0, results/glsl/ltc_sheen.glsl: the same functions in GLSL; and
//!   results/textures/three/RectAreaLightSheen.js, the three.js recipe: its `init()` adds
//!   the Neubelt form and a sheen term to three r187's RE_Direct_RectArea_Physical, so a
//!   MeshPhysicalMaterial's sheen is lit by RectAreaLight with no texture and no sampler;
//!   and results/textures/three/RectAreaLightSheenNode.js, the same for WebGPURenderer
//!   (the WGSL functions as `wgslFn` nodes in `PhysicalLightingModel.directRectArea`).
//!
//! r = √α is glTF's sheenRoughness, t = √(1 − cos θ), as the GGX table's lookup.

pub use super::compact::Lang;
use super::compact::{channel_call, code, eval_prelude, lit, series_fn};
use crate::error::Result;
use crate::ltc::compact::Compact;
use std::path::Path;

/// The source the files are generated from.
pub const SOURCE: &str = "results/fits/ltc-compact.json";

/// A sheen family: its key in the generated names, its table and what it is.
pub struct Family {
    pub key: &'static str,
    pub table: &'static str,
    pub title: &'static str,
}

/// The two visibility conventions, in the order the files hold them.
pub const FAMILIES: [Family; 2] = [
    Family {
        key: "ek",
        table: "ltc-sheen",
        title: "Charlie sheen with Estevez & Kulla's Λ (glTF KHR_materials_sheen)",
    },
    Family {
        key: "neubelt",
        table: "ltc-sheen-neubelt",
        title: "Charlie sheen with Neubelt's visibility (three.js, Filament)",
    },
];

/// Each family with its texture-free series and the series' description; empty when the
/// on-request study has not written them (then no sheen code is generated).
pub fn read(results: &Path) -> Result<Vec<(&'static Family, Compact, String)>> {
    let Some((file, path)) = crate::results::ltc_compact::read_file(results)? else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for f in &FAMILIES {
        match crate::results::ltc_compact::texture_free_in(&file, f.table, &path)? {
            Some((c, d)) => out.push((f, c, d)),
            None => return Ok(Vec::new()),
        }
    }
    Ok(out)
}

/// The five lobe channels the sheen uses (a, b, c, d, norm).
const CHANNELS: usize = 5;

fn upper(key: &str) -> String {
    format!("LTC_SHEEN_{}", key.to_uppercase())
}

/// Rust: per family its coefficients and `ltc_sheen_<key>(r, t)`.
pub fn render_rust(fams: &[(&Family, Compact, String)], command: &str) -> String {
    let gmax = fams.iter().map(|(_, c, _)| c.p).max().unwrap_or(1);
    let mut s = format!(
        "{}//! Texture-free Charlie sheen LTCs: `ltc_sheen_<family>(r, t)` = M⁻¹'s (a, b, c, d) and the norm at r = √α (glTF's sheenRoughness), t = √(1 − cos θ), as `ndfbench::ltc::compact::Compact::eval_f32` computes the series' first five channels. Their error against the BRDF and their cost: results/ltc-compact.md, results/performance.md.\n\n/// The largest degree of the series below.\nconst G_MAX: usize = {gmax};\n",
        super::text::header("//", command, SOURCE),
    );
    for (f, c, d) in fams {
        let u = upper(f.key);
        let p = c.p;
        let codes: Vec<String> = c.channels[..CHANNELS]
            .iter()
            .map(|ch| code(ch.transform).to_string())
            .collect();
        s.push_str(&format!(
            "\n// {}: {d}, α_min = {}.\npub const {u}_P: usize = {p};\npub const {u}_ALPHA_MIN: f32 = {};\n/// Per channel: 0 raw, 1 log (exp of the series), 2 over-α (the series times max(r², α_min)).\npub const {u}_TRANSFORM: [u32; {CHANNELS}] = [{}];\n/// Per channel, coefficient k + p·l multiplies T_k(2r − 1)·T_l(2t − 1).\npub const {u}_COEFFS: [[f32; {}]; {CHANNELS}] = [\n",
            f.title,
            lit(c.alpha_min),
            lit(c.alpha_min),
            codes.join(", "),
            p * p
        ));
        for ch in &c.channels[..CHANNELS] {
            s.push_str("    [\n");
            for row in ch.coeffs.chunks(8) {
                let items: Vec<String> = row.iter().map(|&v| lit(v)).collect();
                s.push_str(&format!("        {},\n", items.join(", ")));
            }
            s.push_str("    ],\n");
        }
        s.push_str(&format!(
            "];\n\n/// (a, b, c, d, norm) of the {} at (r, t), both clamped to [0, 1].\npub fn ltc_sheen_{}(r: f32, t: f32) -> [f32; {CHANNELS}] {{\n    let c: [&[f32]; {CHANNELS}] = std::array::from_fn(|k| &{u}_COEFFS[k][..]);\n    series(&c, {u}_P, &{u}_TRANSFORM, {u}_ALPHA_MIN, r, t)\n}}\n",
            f.title, f.key
        ));
    }
    s.push_str(&format!("\n/// Σ c_k T_k(x) by Clenshaw's recurrence in f32.\nfn clenshaw(c: &[f32], x: f32) -> f32 {{\n    let (mut b1, mut b2) = (0.0f32, 0.0f32);\n    for &ck in c.iter().skip(1).rev() {{\n        let b0 = ck + (x + x) * b1 - b2;\n        b2 = b1;\n        b1 = b0;\n    }}\n    c[0] + x * b1 - b2\n}}\n\n/// The channels' series at (r, t) (along r for each t-degree, then along t), each through\n/// its transform.\nfn series(coeffs: &[&[f32]; {CHANNELS}], p: usize, transform: &[u32; {CHANNELS}], alpha_min: f32, r: f32, t: f32) -> [f32; {CHANNELS}] {{\n    let (r, t) = (r.clamp(0.0, 1.0), t.clamp(0.0, 1.0));\n    let (x, y) = (2.0 * r - 1.0, 2.0 * t - 1.0);\n    let alpha = (r * r).max(alpha_min);\n    let mut out = [0.0f32; {CHANNELS}];\n    for (ch, o) in out.iter_mut().enumerate() {{\n        let c = coeffs[ch];\n        let mut g = [0.0f32; G_MAX];\n        for (l, gl) in g[..p].iter_mut().enumerate() {{\n            *gl = clenshaw(&c[p * l..p * (l + 1)], x);\n        }}\n        let v = clenshaw(&g[..p], y);\n        *o = match transform[ch] {{\n            1 => v.exp(),\n            2 => v * alpha,\n            _ => v,\n        }};\n    }}\n    out\n}}\n"));
    s
}

/// GLSL text in ASCII: WebGL compilers need not accept other characters, comments
/// included.
fn ascii(s: &str) -> String {
    s.replace("M⁻¹", "M^-1")
        .replace('α', "alpha")
        .replace('−', "-")
        .replace('√', "sqrt")
        .replace('θ', "theta")
        .replace('²', "^2")
        .replace('Λ', "Lambda")
        .replace('·', "*")
}

/// One family's shading functions in WGSL or GLSL: the channels' series, then
/// `ltc_sheen_<key>_mat` and `ltc_sheen_<key>_norm` (GLSL in ASCII).
pub fn render_family(lang: Lang, f: &Family, c: &Compact, desc: &str) -> String {
    let s = family_text(lang, f, c, desc);
    match lang {
        Lang::Wgsl => s,
        Lang::Glsl => ascii(&s),
    }
}

fn family_text(lang: Lang, f: &Family, c: &Compact, desc: &str) -> String {
    let prefix = format!("ltc_sheen_{}", f.key);
    let mut s = format!("\n// {}: {desc}, α_min = {}.\n", f.title, lit(c.alpha_min));
    for (k, ch) in c.channels[..CHANNELS].iter().enumerate() {
        s.push_str(&series_fn(
            lang,
            &format!("{prefix}_ch{k}"),
            &ch.coeffs,
            c.p,
            &format!("{prefix}: channel {k}'s series at (x, y) = (2r − 1, 2t − 1)."),
        ));
    }
    let (mat, norm) = mat_norm(lang, &prefix, c);
    s.push_str(&format!(
        "\n// M⁻¹'s (a, b, c, d) at (r, t), both clamped to [0, 1]: M⁻¹ = [[a, 0, c], [0, 1, 0], [b, 0, d]].\n{mat}\n\n// The norm (the lobe's directional albedo) at (r, t), both clamped to [0, 1].\n{norm}\n"
    ));
    s
}

/// The two evaluation functions of a family, `{prefix}_mat` (M⁻¹'s a, b, c, d) and
/// `{prefix}_norm`, as code without comments (the WebGPU recipe hands each to `wgslFn`).
fn mat_norm(lang: Lang, prefix: &str, c: &Compact) -> (String, String) {
    let ch = |k: usize| channel_call(prefix, k, c.channels[k].transform);
    let pre = eval_prelude(lang, c.alpha_min);
    let (mat_head, norm_head, vec4) = match lang {
        Lang::Wgsl => (
            format!("fn {prefix}_mat(r_in: f32, t_in: f32) -> vec4<f32> {{"),
            format!("fn {prefix}_norm(r_in: f32, t_in: f32) -> f32 {{"),
            "vec4<f32>",
        ),
        Lang::Glsl => (
            format!("vec4 {prefix}_mat(float r_in, float t_in) {{"),
            format!("float {prefix}_norm(float r_in, float t_in) {{"),
            "vec4",
        ),
    };
    (
        format!(
            "{mat_head}\n{pre}    return {vec4}({}, {}, {}, {});\n}}",
            ch(0),
            ch(1),
            ch(2),
            ch(3)
        ),
        format!("{norm_head}\n{pre}    return {};\n}}", ch(4)),
    )
}

/// The WGSL or GLSL file: header, then every family.
fn render_shader(lang: Lang, fams: &[(&Family, Compact, String)], command: &str) -> String {
    let mut s = format!(
        "{}// Texture-free Charlie sheen LTCs: per family ltc_sheen_<family>_mat(r, t) = M⁻¹'s (a, b, c, d) and ltc_sheen_<family>_norm(r, t) at r = √α (glTF's sheenRoughness), t = √(1 − cos θ). Each channel is Clenshaw's recurrence written out, the coefficients as literals, in the operation order of the Rust form (src/generated/ltc_sheen.rs). Error and cost: results/ltc-compact.md, results/performance.md.\n",
        super::text::header("//", command, SOURCE),
    );
    for (f, c, d) in fams {
        s.push_str(&render_family(lang, f, c, d));
    }
    match lang {
        Lang::Wgsl => s,
        Lang::Glsl => ascii(&s),
    }
}

/// The three.js recipe (an ES module): `RectAreaLightSheen.init()` patches three r187's
/// lights_physical_pars_fragment chunk once, before the first material compiles.
pub fn render_three(f: &Family, c: &Compact, desc: &str, command: &str) -> String {
    let glsl = render_family(Lang::Glsl, f, c, desc);
    format!(
        "{}// The sheen of MeshPhysicalMaterial under RectAreaLight, for three.js r187's WebGLRenderer\n// (three applies no sheen under RectAreaLight: its RE_Direct_RectArea_Physical has no sheen\n// term). RectAreaLightSheen.init(), called once before the first render (beside\n// RectAreaLightUniformsLib.init()), adds to that function\n//\n//     sheenSpecularDirect += lightColor · sheenColor · norm · LTC_Evaluate( …, M⁻¹, rectCoords )\n//\n// with M⁻¹ and the norm of the Charlie sheen lobe with Neubelt's visibility (three's own\n// BRDF_Sheen) evaluated per pixel in the shader from its compact series ({desc}):\n// no texture, no sampler. Fitted for sheenRoughness in [{rmin}, 1] (α ≥ {amin}, the table's\n// α_min): below it the series gives the lobe of α = {amin}. The base layer under the sheen is\n// left as three lights it. Its error against the\n// BRDF and its cost: results/ltc-compact.md, results/performance.md; rendered in three.js and\n// judged against the truth: results/engines-sheen.md.\nimport {{ ShaderChunk }} from 'three';\n\nconst GLSL = `{glsl}`;\n\nconst FUNCTION = 'void RE_Direct_RectArea_Physical(';\nconst DIFFUSE = 'reflectedLight.directDiffuse += lightColor * material.diffuseContribution * LTC_Evaluate( normal, viewDir, position, mat3( 1.0 ), rectCoords );';\nconst TERM = `\n\t\t#ifdef USE_SHEEN\n\n\t\t\tfloat sheenT = sqrt( 1.0 - saturate( dot( normal, viewDir ) ) );\n\t\t\tvec4 sheenMat = ltc_sheen_{key}_mat( material.sheenRoughness, sheenT );\n\t\t\tmat3 mInvSheen = mat3(\n\t\t\t\tvec3( sheenMat.x, 0, sheenMat.y ),\n\t\t\t\tvec3(          0, 1,          0 ),\n\t\t\t\tvec3( sheenMat.z, 0, sheenMat.w )\n\t\t\t);\n\t\t\tsheenSpecularDirect += lightColor * material.sheenColor * ltc_sheen_{key}_norm( material.sheenRoughness, sheenT ) * LTC_Evaluate( normal, viewDir, position, mInvSheen, rectCoords );\n\n\t\t#endif\n`;\n\nexport const RectAreaLightSheen = {{\n\n\tinit() {{\n\n\t\tconst chunk = ShaderChunk.lights_physical_pars_fragment;\n\t\tif ( chunk.includes( 'ltc_sheen_{key}_mat' ) ) return;\n\t\tif ( ! chunk.includes( FUNCTION ) || ! chunk.includes( DIFFUSE ) ) {{\n\n\t\t\tthrow new Error( 'RectAreaLightSheen: this three.js has no RE_Direct_RectArea_Physical as r187 writes it' );\n\n\t\t}}\n\n\t\tShaderChunk.lights_physical_pars_fragment = chunk\n\t\t\t.replace( FUNCTION, '#if defined( USE_SHEEN )\\n' + GLSL + '\\n#endif\\n\\n' + FUNCTION )\n\t\t\t.replace( DIFFUSE, DIFFUSE + TERM );\n\n\t}}\n\n}};\n",
        super::text::header("//", command, SOURCE),
        key = f.key,
        amin = lit(c.alpha_min),
        rmin = lit(c.alpha_min.sqrt()),
    )
}

/// The three.js recipe for WebGPURenderer (an ES module): the same series as `wgslFn`
/// nodes, and `RectAreaLightSheenNode.init()`, which wraps r187's
/// `PhysicalLightingModel.prototype.directRectArea` once so that a sheen adds
/// lightColor · sheen · norm · LTC_Evaluate(…, M⁻¹, …) to `sheenSpecularDirect`.
pub fn render_three_webgpu(f: &Family, c: &Compact, desc: &str, command: &str) -> String {
    let prefix = format!("ltc_sheen_{}", f.key);
    let strip = |code: String| -> String {
        // wgslFn reads the declaration from the code's start: no comment before it
        let at = code.find("fn ").unwrap_or(0);
        code[at..].trim_end().to_string()
    };
    let channels: Vec<String> = c.channels[..CHANNELS]
        .iter()
        .enumerate()
        .map(|(k, ch)| {
            let code = strip(series_fn(
                Lang::Wgsl,
                &format!("{prefix}_ch{k}"),
                &ch.coeffs,
                c.p,
                "",
            ));
            format!("\twgslFn( `{code}` ),\n")
        })
        .collect();
    let (mat, norm) = mat_norm(Lang::Wgsl, &prefix, c);
    format!(
        "{}// The sheen of MeshPhysicalNodeMaterial under RectAreaLight, for three.js r187's\n// WebGPURenderer (its PhysicalLightingModel.directRectArea has no sheen term).\n// RectAreaLightSheenNode.init(), called once before the first render, wraps that method so\n// that a material with sheen also gets\n//\n//     sheenSpecularDirect += lightColor · sheen · norm · LTC_Evaluate( …, M⁻¹, … )\n//\n// with M⁻¹ and the norm of the Charlie sheen lobe with Neubelt's visibility (three's own\n// BRDF_Sheen) evaluated per pixel from its compact series ({desc}) as WGSL functions\n// (wgslFn; the same code as results/wgsl/ltc_sheen.wgsl): no texture, no sampler. Fitted\n// for sheenRoughness in [{rmin}, 1] (α ≥ {amin}): below it the series gives the lobe of\n// α = {amin}. The\n// WebGLRenderer's recipe is RectAreaLightSheen.js. Rendered in three.js and judged against\n// the truth: results/engines-sheen.md.\nimport {{ PhysicalLightingModel }} from 'three/webgpu';\nimport {{ wgslFn, LTC_Evaluate, normalView, positionView, positionViewDirection, sheen, sheenRoughness, mat3, vec3, float }} from 'three/tsl';\n\nconst channels = [\n{}];\nconst sheenMat = wgslFn( `{mat}`, [ channels[ 0 ], channels[ 1 ], channels[ 2 ], channels[ 3 ] ] );\nconst sheenNorm = wgslFn( `{norm}`, [ channels[ 4 ] ] );\n\nlet installed = false;\n\nexport const RectAreaLightSheenNode = {{\n\n\tinit() {{\n\n\t\tif ( installed ) return;\n\t\tinstalled = true;\n\t\tconst base = PhysicalLightingModel.prototype.directRectArea;\n\t\tPhysicalLightingModel.prototype.directRectArea = function ( input, builder ) {{\n\n\t\t\tbase.call( this, input, builder );\n\t\t\tif ( this.sheen !== true ) return;\n\t\t\tconst {{ lightColor, lightPosition, halfWidth, halfHeight }} = input;\n\t\t\tconst p0 = lightPosition.add( halfWidth ).sub( halfHeight );\n\t\t\tconst p1 = lightPosition.sub( halfWidth ).sub( halfHeight );\n\t\t\tconst p2 = lightPosition.sub( halfWidth ).add( halfHeight );\n\t\t\tconst p3 = lightPosition.add( halfWidth ).add( halfHeight );\n\t\t\tconst N = normalView;\n\t\t\tconst V = positionViewDirection;\n\t\t\tconst P = positionView.toVar();\n\t\t\tconst t = float( 1 ).sub( N.dot( V ).saturate() ).sqrt();\n\t\t\tconst m = sheenMat( {{ r_in: sheenRoughness, t_in: t }} ).toVar();\n\t\t\tconst mInv = mat3( vec3( m.x, 0, m.y ), vec3( 0, 1, 0 ), vec3( m.z, 0, m.w ) );\n\t\t\tthis.sheenSpecularDirect.addAssign( lightColor.mul( sheen ).mul( sheenNorm( {{ r_in: sheenRoughness, t_in: t }} ) ).mul( LTC_Evaluate( {{ N, V, P, mInv, p0, p1, p2, p3 }} ) ) );\n\n\t\t}};\n\n\t}}\n\n}};\n",
        super::text::header("//", command, SOURCE),
        channels.concat(),
        amin = lit(c.alpha_min),
        rmin = lit(c.alpha_min.sqrt()),
    )
}

/// Every sheen file: (path: `wgsl/`, `glsl/` and `textures/` relative to results/, `src/`
/// to the repository root, contents); none when the study's picks are absent, the Rust
/// file only with `rust`.
pub fn render_all(results: &Path, rust: bool, command: &str) -> Result<Vec<(String, String)>> {
    let fams = read(results)?;
    if fams.is_empty() {
        return Ok(Vec::new());
    }
    let mut out = vec![
        (
            "wgsl/ltc_sheen.wgsl".to_string(),
            render_shader(Lang::Wgsl, &fams, command),
        ),
        (
            "glsl/ltc_sheen.glsl".to_string(),
            render_shader(Lang::Glsl, &fams, command),
        ),
    ];
    if let Some((f, c, d)) = fams.iter().find(|(f, _, _)| f.key == "neubelt") {
        out.push((
            "textures/three/RectAreaLightSheen.js".to_string(),
            render_three(f, c, d, command),
        ));
        out.push((
            "textures/three/RectAreaLightSheenNode.js".to_string(),
            render_three_webgpu(f, c, d, command),
        ));
    }
    if rust {
        out.push((
            "src/generated/ltc_sheen.rs".to_string(),
            render_rust(&fams, command),
        ));
    }
    Ok(out)
}

//! The compact GGX LTC table as generated code: the GGX family's series of
//! results/fits/ltc-compact.json (the form its goal chose, else its most accurate
//! rebuild; `regen --only ltc-compact`) in three forms of one f32 evaluation,
//! `ltc::compact::Compact::eval_f32` (per channel: Clenshaw's recurrence along r for each
//! t-degree, then along t; the channel's transform last):
//!
//! - Rust, src/generated/ltc_compact.rs: the coefficients and `ltc_compact(r, t)`;
//! - WGSL, results/wgsl/ltc_compact.wgsl: a library module, the same evaluation written
//!   out as straight-line code (`ltc_compact_mat`, `ltc_compact_mag`), and
//!   results/wgsl/ltc_compact_rebuild.wgsl: it with a compute entry, `ltc_compact_rebuild`,
//!   that fills the two rgba16float textures of the shipped layout;
//! - an ES module, results/textures/three/ltc_compact.js: `ltcCompact(r, t)` and
//!   `rebuild(n)`, the f32 and binary16 (nearest) texel arrays; with
//!   results/textures/three/RectAreaLightTexturesLib.compact.js, a drop-in for three.js
//!   r187's RectAreaLightTexturesLib whose `init()` builds its four textures from them.
//!
//! The coefficients are written as f32 bit patterns (JS) or shortest round-trip f32
//! literals (Rust, WGSL), so every form holds the same f32 numbers. The JS form rounds
//! after every operation (`Math.fround`), in the Rust form's order, so for raw and over-α
//! channels (no `exp`) the two give the same bits; tests/codegen_compact.rs checks that and
//! the WGSL module through naga.

use crate::error::Result;
use crate::ltc::compact::{Compact, Transform};
use std::path::Path;

/// The source the files are generated from.
pub const SOURCE: &str = "results/fits/ltc-compact.json";

/// The GGX family's series of results/fits/ltc-compact.json, or `None` when the on-request
/// study has not written that file (then no compact code is generated).
pub fn read(results: &Path) -> Result<Option<(Compact, usize)>> {
    crate::results::ltc_compact::ggx_series(results)
}

pub(super) fn code(t: Transform) -> u32 {
    match t {
        Transform::Raw => 0,
        Transform::Log => 1,
        Transform::OverAlpha => 2,
    }
}

/// The channels' transform codes, each followed by `suffix` ("u" in WGSL), comma-joined.
fn codes(c: &Compact, suffix: &str) -> String {
    c.channels
        .iter()
        .map(|s| format!("{}{suffix}", code(s.transform)))
        .collect::<Vec<_>>()
        .join(", ")
}

pub(super) fn lit(x: f64) -> String {
    format!("{:?}", x as f32)
}

/// The form's name for the headers: transforms and degree.
fn describe(c: &Compact, n: usize) -> String {
    let names: Vec<&str> = c
        .channels
        .iter()
        .map(|s| match s.transform {
            Transform::Raw => "raw",
            Transform::Log => "log",
            Transform::OverAlpha => "over-α",
        })
        .collect();
    format!(
        "p = {} ({} coefficients; channels a, b, c, d, norm, fresnel: {}), α_min = {}, rebuilt at {n}×{n}",
        c.p,
        c.coefficients(),
        names.join(", "),
        lit(c.alpha_min)
    )
}

/// Rust: the coefficients and the f32 evaluation.
pub fn render_rust(c: &Compact, n: usize, command: &str) -> String {
    let p = c.p;
    let mut s = format!(
        "{}//! Compact GGX LTC table: {}. `ltc_compact(r, t)` = (a, b, c, d, norm, fresnel) at r = √α, t = √(1 − cos θ), as `ndfbench::ltc::compact::Compact::eval_f32` computes it; texel (i, j) of the rebuilt table is at (i, j)/(n − 1). Its error against the BRDF: results/ltc-compact.md.\n\npub const LTC_COMPACT_P: usize = {p};\npub const LTC_COMPACT_N: usize = {n};\npub const LTC_COMPACT_ALPHA_MIN: f32 = {};\n/// Per channel: 0 raw, 1 log (exp of the series), 2 over-α (the series times max(r², α_min)).\npub const LTC_COMPACT_TRANSFORM: [u32; 6] = [{}];\n/// Per channel, coefficient k + p·l multiplies T_k(2r − 1)·T_l(2t − 1).\npub const LTC_COMPACT_COEFFS: [[f32; {}]; 6] = [\n",
        super::text::header("//", command, SOURCE),
        describe(c, n),
        lit(c.alpha_min),
        codes(c, ""),
        p * p
    );
    for ch in &c.channels {
        s.push_str("    [\n");
        for row in ch.coeffs.chunks(8) {
            let items: Vec<String> = row.iter().map(|&v| lit(v)).collect();
            s.push_str(&format!("        {},\n", items.join(", ")));
        }
        s.push_str("    ],\n");
    }
    s.push_str("];\n\n/// Σ c_k T_k(x) by Clenshaw's recurrence in f32.\nfn clenshaw(c: &[f32], x: f32) -> f32 {\n    let (mut b1, mut b2) = (0.0f32, 0.0f32);\n    for &ck in c.iter().skip(1).rev() {\n        let b0 = ck + (x + x) * b1 - b2;\n        b2 = b1;\n        b1 = b0;\n    }\n    c[0] + x * b1 - b2\n}\n\n/// The six channels at (r, t), both clamped to [0, 1].\npub fn ltc_compact(r: f32, t: f32) -> [f32; 6] {\n    let (r, t) = (r.clamp(0.0, 1.0), t.clamp(0.0, 1.0));\n    let (x, y) = (2.0 * r - 1.0, 2.0 * t - 1.0);\n    let alpha = (r * r).max(LTC_COMPACT_ALPHA_MIN);\n    let p = LTC_COMPACT_P;\n    let mut out = [0.0f32; 6];\n    for (ch, o) in out.iter_mut().enumerate() {\n        let c = &LTC_COMPACT_COEFFS[ch];\n        let mut g = [0.0f32; LTC_COMPACT_P];\n        for (l, gl) in g.iter_mut().enumerate() {\n            *gl = clenshaw(&c[p * l..p * (l + 1)], x);\n        }\n        let v = clenshaw(&g, y);\n        *o = match LTC_COMPACT_TRANSFORM[ch] {\n            1 => v.exp(),\n            2 => v * alpha,\n            _ => v,\n        };\n    }\n    out\n}\n");
    s
}

/// The shading language a straight-line series is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lang {
    Wgsl,
    Glsl,
}

impl Lang {
    /// How a local is declared.
    fn decl(self) -> &'static str {
        match self {
            Lang::Wgsl => "let",
            Lang::Glsl => "float",
        }
    }
}

/// Clenshaw's recurrence Σ c_k T_k(v) written out as locals named `{name}_{k}` (declared
/// with `decl`), with `v2` = v + v; the operations of [`Compact::eval_f32`]'s recurrence
/// in its order (the first steps, whose b1 and b2 are still 0, keep only what is not a
/// zero term). Returns the lines and the name of the result.
fn clenshaw_lines(c: &[String], v: &str, name: &str, decl: &str) -> (String, String) {
    let p = c.len();
    let b = |k: usize| format!("{name}_{k}");
    let mut s = String::new();
    if p == 1 {
        return (s, c[0].clone());
    }
    // b_k = (c_k + v2·b_{k+1}) − b_{k+2}, k = p − 1 … 1, b_p = b_{p+1} = 0
    for k in (1..p).rev() {
        let e = match (k + 1 < p, k + 2 < p) {
            (false, _) => c[k].clone(),
            (true, false) => format!("{} + {v}2 * {}", c[k], b(k + 1)),
            (true, true) => format!("{} + {v}2 * {} - {}", c[k], b(k + 1), b(k + 2)),
        };
        s.push_str(&format!("    {decl} {} = {e};\n", b(k)));
    }
    let last = if p > 2 {
        format!("{} + {v} * {} - {}", c[0], b(1), b(2))
    } else {
        format!("{} + {v} * {}", c[0], b(1))
    };
    s.push_str(&format!("    {decl} {name} = {last};\n"));
    (s, name.to_string())
}

/// One channel's series at (x, y) = (2r − 1, 2t − 1) as a function `fname` of straight-line
/// code, the coefficients as literals (no array: naga would copy a dynamically indexed
/// `const` array into every invocation's memory), preceded by a `comment` line.
pub(super) fn series_fn(
    lang: Lang,
    fname: &str,
    coeffs: &[f64],
    p: usize,
    comment: &str,
) -> String {
    let lits: Vec<String> = coeffs.iter().map(|&v| lit(v)).collect();
    let d = lang.decl();
    let head = match lang {
        Lang::Wgsl => format!("fn {fname}(x: f32, y: f32) -> f32 {{\n"),
        Lang::Glsl => format!("float {fname}(float x, float y) {{\n"),
    };
    let mut s = format!("\n// {comment}\n{head}    {d} x2 = x + x;\n    {d} y2 = y + y;\n");
    let mut g = Vec::new();
    for l in 0..p {
        let (body, out) = clenshaw_lines(&lits[p * l..p * (l + 1)], "x", &format!("g{l}"), d);
        s.push_str(&body);
        g.push(out);
    }
    let (body, out) = clenshaw_lines(&g, "y", "v", d);
    s.push_str(&body);
    s.push_str(&format!("    return {out};\n}}\n"));
    s
}

/// The lines that open an evaluation at (r_in, t_in): both clamped to [0, 1], x, y and
/// α(r) = max(r², α_min).
pub(super) fn eval_prelude(lang: Lang, alpha_min: f64) -> String {
    let d = lang.decl();
    format!(
        "    {d} r = clamp(r_in, 0.0, 1.0);\n    {d} t = clamp(t_in, 0.0, 1.0);\n    {d} x = 2.0 * r - 1.0;\n    {d} y = 2.0 * t - 1.0;\n    {d} alpha = max(r * r, {});\n",
        lit(alpha_min)
    )
}

/// Channel `k`'s value: its series function `{prefix}_ch{k}` called at (x, y), then the
/// channel's transform.
pub(super) fn channel_call(prefix: &str, k: usize, t: Transform) -> String {
    let call = format!("{prefix}_ch{k}(x, y)");
    match t {
        Transform::Raw => call,
        Transform::Log => format!("exp({call})"),
        Transform::OverAlpha => format!("{call} * alpha"),
    }
}

/// WGSL library (no bindings, no entry point): per channel `ltc_compact_ch<k>(x, y)`, the
/// series at (x, y) = (2r − 1, 2t − 1) as straight-line code with the coefficients as
/// literals (no array: naga would copy a dynamically indexed `const` array into every
/// invocation's memory), and `ltc_compact_mat(r, t)`, `ltc_compact_mag(r, t)`.
pub fn render_wgsl(c: &Compact, n: usize, command: &str) -> String {
    let p = c.p;
    let mut s = format!(
        "{}// Compact GGX LTC table: {}. ltc_compact_mat(r, t) = M⁻¹'s (a, b, c, d), ltc_compact_mag(r, t) = (norm, fresnel) at r = √α, t = √(1 − cos θ). Each channel is Clenshaw's recurrence written out, the coefficients as literals, in the operation order of the Rust form (src/generated/ltc_compact.rs). Error against the BRDF: results/ltc-compact.md; the compute rebuild of the textures: ltc_compact_rebuild.wgsl.\n",
        super::text::header("//", command, SOURCE),
        describe(c, n),
    );
    for (k, ch) in c.channels.iter().enumerate() {
        s.push_str(&series_fn(
            Lang::Wgsl,
            &format!("ltc_compact_ch{k}"),
            &ch.coeffs,
            p,
            &format!("Channel {k}'s series at (x, y) = (2r − 1, 2t − 1): along x for each t-degree l, then along y."),
        ));
    }
    let ch = |k: usize| channel_call("ltc_compact", k, c.channels[k].transform);
    let pre = eval_prelude(Lang::Wgsl, c.alpha_min);
    s.push_str(&format!(
        "\n// M⁻¹'s (a, b, c, d) at (r, t), both clamped to [0, 1].\nfn ltc_compact_mat(r_in: f32, t_in: f32) -> vec4<f32> {{\n{pre}    return vec4<f32>({}, {}, {}, {});\n}}\n\n// (norm, fresnel) at (r, t), both clamped to [0, 1].\nfn ltc_compact_mag(r_in: f32, t_in: f32) -> vec2<f32> {{\n{pre}    return vec2<f32>({}, {});\n}}\n",
        ch(0),
        ch(1),
        ch(2),
        ch(3),
        ch(4),
        ch(5)
    ));
    s
}

/// WGSL compute shader: the library and an entry, `ltc_compact_rebuild`, that writes
/// texel (i, j) at (i, j)/(n − 1) of two rgba16float storage textures.
pub fn render_wgsl_rebuild(c: &Compact, n: usize, command: &str) -> String {
    format!(
        "{}\n// The compute rebuild: texel (i, j) at (i, j)/(n − 1) of two rgba16float storage textures (the shipped layout; LTC_2 = (norm, fresnel, 0, 0)); dispatch ceil(n/8)² workgroups.\n@group(0) @binding(0) var ltc_compact_1: texture_storage_2d<rgba16float, write>;\n@group(0) @binding(1) var ltc_compact_2: texture_storage_2d<rgba16float, write>;\n\n@compute @workgroup_size(8, 8)\nfn ltc_compact_rebuild(@builtin(global_invocation_id) id: vec3<u32>) {{\n    let n = textureDimensions(ltc_compact_1);\n    if (id.x >= n.x || id.y >= n.y) {{\n        return;\n    }}\n    let r = f32(id.x) / f32(n.x - 1u);\n    let t = f32(id.y) / f32(n.y - 1u);\n    textureStore(ltc_compact_1, vec2<i32>(id.xy), ltc_compact_mat(r, t));\n    textureStore(ltc_compact_2, vec2<i32>(id.xy), vec4<f32>(ltc_compact_mag(r, t), 0.0, 0.0));\n}}\n",
        render_wgsl(c, n, command)
    )
}

/// The ES module: coefficients as f32 bit patterns, the evaluation with `Math.fround`
/// after every operation, the rebuild, and nearest binary16.
pub fn render_js(c: &Compact, n: usize, command: &str) -> String {
    let p = c.p;
    let bits: Vec<String> = c
        .channels
        .iter()
        .flat_map(|ch| ch.coeffs.iter().map(|&v| (v as f32).to_bits().to_string()))
        .collect();
    let mut s = format!(
        "{}// Compact GGX LTC table: {}. ltcCompact(r, t) returns (a, b, c, d, norm, fresnel) at r = √α, t = √(1 − cos θ), with the same f32 operations in the same order as the Rust form (src/generated/ltc_compact.rs); rebuild(n) fills texel (i, j) at (i, j)/(n − 1) of the shipped layout (index (i + n·j)·4 + c; LTC_MAT_2 = (norm, fresnel, 0, 0)) in f32 and as the nearest binary16. No dependencies. Error against the BRDF: results/ltc-compact.md.\n\nexport const P = {p};\nexport const N = {n};\nconst f = Math.fround;\nconst ALPHA_MIN = new Float32Array( new Uint32Array( [ {} ] ).buffer )[ 0 ];\nconst TRANSFORM = [ {} ];\nconst COEFFS = new Float32Array( new Uint32Array( [\n",
        super::text::header("//", command, SOURCE),
        describe(c, n),
        (c.alpha_min as f32).to_bits(),
        codes(c, "")
    );
    for row in bits.chunks(12) {
        s.push_str(&format!("\t{},\n", row.join(", ")));
    }
    s.push_str("] ).buffer );\n\n// Σ c[off + k] T_k(x) by Clenshaw's recurrence, rounded to f32 after every operation.\nfunction clenshaw( c, off, x ) {\n\n\tlet b1 = 0, b2 = 0;\n\tfor ( let k = P - 1; k >= 1; k -- ) {\n\n\t\tconst b0 = f( f( c[ off + k ] + f( f( x + x ) * b1 ) ) - b2 );\n\t\tb2 = b1;\n\t\tb1 = b0;\n\n\t}\n\n\treturn f( f( c[ off ] + f( x * b1 ) ) - b2 );\n\n}\n\nconst g = new Float32Array( P );\n\n// The six channels at (r, t), both clamped to [0, 1].\nexport function ltcCompact( r, t ) {\n\n\tr = Math.min( Math.max( f( r ), 0 ), 1 );\n\tt = Math.min( Math.max( f( t ), 0 ), 1 );\n\tconst x = f( f( 2 * r ) - 1 ), y = f( f( 2 * t ) - 1 );\n\tconst alpha = Math.max( f( r * r ), ALPHA_MIN );\n\tconst out = new Float32Array( 6 );\n\tfor ( let ch = 0; ch < 6; ch ++ ) {\n\n\t\tfor ( let l = 0; l < P; l ++ ) g[ l ] = clenshaw( COEFFS, ( ch * P + l ) * P, x );\n\t\tconst v = clenshaw( g, 0, y );\n\t\tout[ ch ] = TRANSFORM[ ch ] === 1 ? f( Math.exp( v ) ) : TRANSFORM[ ch ] === 2 ? f( v * alpha ) : v;\n\n\t}\n\n\treturn out;\n\n}\n\nconst F32 = new Float32Array( 1 ), U32 = new Uint32Array( F32.buffer );\n\n// The nearest binary16 (ties to even) of a number, as its bits.\nexport function toHalf( v ) {\n\n\tF32[ 0 ] = v;\n\tconst x = U32[ 0 ];\n\tconst sign = ( x >>> 16 ) & 0x8000;\n\tconst exp = ( x >>> 23 ) & 0xff;\n\tlet mant = x & 0x7fffff;\n\tif ( exp === 0xff ) return sign | 0x7c00 | ( mant ? 0x200 : 0 );\n\tconst e = exp - 112;\n\tif ( e >= 0x1f ) return sign | 0x7c00;\n\tif ( e <= 0 ) {\n\n\t\tif ( e < - 10 ) return sign;\n\t\tmant |= 0x800000;\n\t\tconst shift = 14 - e;\n\t\tlet h = mant >>> shift;\n\t\tconst rem = mant & ( ( 1 << shift ) - 1 ), half = 1 << ( shift - 1 );\n\t\tif ( rem > half || ( rem === half && ( h & 1 ) ) ) h ++;\n\t\treturn sign | h;\n\n\t}\n\n\tlet h = ( e << 10 ) | ( mant >>> 13 );\n\tconst rem = mant & 0x1fff;\n\tif ( rem > 0x1000 || ( rem === 0x1000 && ( h & 1 ) ) ) h ++;\n\treturn sign | h;\n\n}\n\n// The rebuilt n×n textures: f32 (mat, mag) and binary16 bits (matHalf, magHalf).\nexport function rebuild( n = N ) {\n\n\tif ( ! ( Number.isInteger( n ) && n >= 2 ) ) throw new RangeError( `ltc_compact rebuild: side ${ n } (an integer of at least 2)` );\n\tconst mat = new Float32Array( 4 * n * n ), mag = new Float32Array( 4 * n * n );\n\tfor ( let j = 0; j < n; j ++ ) {\n\n\t\tfor ( let i = 0; i < n; i ++ ) {\n\n\t\t\tconst v = ltcCompact( f( i / ( n - 1 ) ), f( j / ( n - 1 ) ) );\n\t\t\tconst k = 4 * ( i + n * j );\n\t\t\tmat.set( v.subarray( 0, 4 ), k );\n\t\t\tmag[ k ] = v[ 4 ];\n\t\t\tmag[ k + 1 ] = v[ 5 ];\n\n\t\t}\n\n\t}\n\n\treturn { mat, mag, matHalf: Uint16Array.from( mat, toHalf ), magHalf: Uint16Array.from( mag, toHalf ) };\n\n}\n");
    s
}

/// The three.js drop-in: RectAreaLightTexturesLib with `init()` rebuilding its textures.
pub fn render_three(c: &Compact, n: usize, command: &str) -> String {
    super::textures::three_module(&super::textures::ThreeModule {
        comment: &format!(
            "{}// A drop-in for three.js r187's examples/jsm/lights/RectAreaLightTexturesLib.js that\n// rebuilds the LTC textures at init() from the compact GGX table of ./ltc_compact.js\n// ({}): map that module to this file (an import map entry, or a\n// bundler alias) and RectAreaLightUniformsLib.init() (WebGLRenderer) or\n// RectAreaLightNode.setLTC( RectAreaLightTexturesLib.init() ) (WebGPURenderer) use it.\n// The FloatType textures hold the f32 evaluation, the HalfFloatType ones its nearest\n// binary16.\n",
            super::text::header("//", command, SOURCE),
            describe(c, n)
        ),
        imports: "import { N, rebuild } from './ltc_compact.js';\n",
        prelude: "\t\tconst rebuilt = rebuild( N );\n",
        side: "N",
        data: ["rebuilt.mat", "rebuilt.mag", "rebuilt.matHalf", "rebuilt.magHalf"],
    })
}

/// Every compact file: (path: `wgsl/` and `textures/` relative to results/, `src/` to
/// the repository root, contents); none when the study's file is absent, the Rust file
/// only with `rust`.
pub fn render_all(results: &Path, rust: bool, command: &str) -> Result<Vec<(String, String)>> {
    let Some((c, n)) = read(results)? else {
        return Ok(Vec::new());
    };
    let mut out = vec![
        (
            "wgsl/ltc_compact.wgsl".to_string(),
            render_wgsl(&c, n, command),
        ),
        (
            "wgsl/ltc_compact_rebuild.wgsl".to_string(),
            render_wgsl_rebuild(&c, n, command),
        ),
        (
            "textures/three/ltc_compact.js".to_string(),
            render_js(&c, n, command),
        ),
        (
            "textures/three/RectAreaLightTexturesLib.compact.js".to_string(),
            render_three(&c, n, command),
        ),
    ];
    if rust {
        out.push((
            "src/generated/ltc_compact.rs".to_string(),
            render_rust(&c, n, command),
        ));
    }
    Ok(out)
}

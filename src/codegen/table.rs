//! The fitted GGX LTC table as generated data: Rust constants
//! (src/generated/ltc_table.rs: f32 values and IEEE binary16 bit patterns) and WGSL
//! (results/wgsl/ltc_table.wgsl with f32 arrays, results/wgsl/ltc_table_f16.wgsl with
//! binary16 pairs packed in u32, read by the core `unpack2x16float`). Layout as the shipped tables: texel (i, j) = roughness index i
//! (r = √α = i/(n−1)), view index j (t = √(1 − cos θ) = j/(n−1)) at i + n·j; LTC_1 =
//! (a, b, c, d) of M⁻¹ ∝ [[a, 0, c], [0, 1, 0], [b, 0, d]] (column-major as in WGSL's
//! `mat3x3(vec3(a, 0, b), vec3(0, 1, 0), vec3(c, 0, d))`), LTC_2 = (norm, fresnel). The
//! error each precision costs is measured in results/ltc-ggx.md.

use crate::error::Result;
use half::f16;
use std::path::Path;

/// The table read from results/fits/ltc-ggx.json (the one reader, `ltc::table`).
pub type LtcTableData = crate::ltc::table::FittedTable;

/// Read the fitted table.
pub fn read(results: &Path) -> Result<LtcTableData> {
    crate::results::ltc::table(results, crate::results::names::LTC_GGX)
}

/// Shortest round-trip f32 literal (valid in Rust and WGSL).
fn lit32(x: f64) -> String {
    format!("{:?}", x as f32)
}

const LAYOUT: &str = "texel (i, j) at i + n·j: i = roughness index (r = √α = i/(n−1)), j = view index (t = √(1 − cos θ) = j/(n−1)); LTC_1 = (a, b, c, d) with M⁻¹ ∝ mat3x3(vec3(a, 0, b), vec3(0, 1, 0), vec3(c, 0, d)); LTC_2 = (norm, fresnel)";

/// Two f16 (round to nearest even) packed into a u32 as WGSL's `unpack2x16float` reads
/// them: the first in bits 0–15.
pub fn pack2x16(x: f64, y: f64) -> u32 {
    pack_half(f16::from_f64(x), f16::from_f64(y))
}

/// Two binary16 numbers packed into a u32, the first in bits 0–15.
pub fn pack_half(x: f16, y: f16) -> u32 {
    x.to_bits() as u32 | (y.to_bits() as u32) << 16
}

/// WGSL module with the table as `const` arrays: f32 values, or (`half`) binary16 pairs
/// packed into u32 and read with the core built-in `unpack2x16float` (no f16 extension
/// needed; the same bits upload as an rgba16float / rg16float texture).
pub fn render_wgsl(t: &LtcTableData, half: bool, command: &str) -> String {
    let nn = t.n * t.n;
    let mut s = format!(
        "{}// GGX LTC table ({}×{}, {}); {LAYOUT}. The error this precision costs: results/ltc-ggx.md.\n// Most renderers upload the table once as two {} textures and sample it bilinearly at (ndfb_ltc_lut_u, ndfb_ltc_lut_v) of ltc.wgsl; the arrays serve compute passes and tests.\n\nconst LTC_TABLE_N: u32 = {}u;\n\n",
        super::text::header("//", command, "results/fits/ltc-ggx.json"),
        t.n,
        t.n,
        if half { "binary16 pairs packed in u32" } else { "f32" },
        if half { "rgba16float / rg16float" } else { "rgba32float / rg32float" },
        t.n
    );
    let sep = |k: usize| if k + 1 < nn { "," } else { "" };
    if half {
        s.push_str(&format!(
            "const LTC_1: array<vec2<u32>, {nn}> = array<vec2<u32>, {nn}>(\n"
        ));
        for k in 0..nn {
            let c = t.half_cell(k);
            s.push_str(&format!(
                "    vec2<u32>(0x{:08x}u, 0x{:08x}u){}\n",
                pack_half(c[0], c[1]),
                pack_half(c[2], c[3]),
                sep(k)
            ));
        }
        s.push_str(&format!(
            ");\n\nconst LTC_2: array<u32, {nn}> = array<u32, {nn}>(\n"
        ));
        for k in 0..nn {
            let c = t.half_cell(k);
            s.push_str(&format!("    0x{:08x}u{}\n", pack_half(c[4], c[5]), sep(k)));
        }
        s.push_str(");\n\n/// The texel's (a, b, c, d), widened to f32.\nfn ltc_table_texel(i: u32, j: u32) -> vec4<f32> {\n    let k = min(i, LTC_TABLE_N - 1u) + LTC_TABLE_N * min(j, LTC_TABLE_N - 1u);\n    let p = LTC_1[k];\n    return vec4<f32>(unpack2x16float(p.x), unpack2x16float(p.y));\n}\n\n/// The texel's (norm, fresnel), widened to f32.\nfn ltc_table_magnitude(i: u32, j: u32) -> vec2<f32> {\n    let k = min(i, LTC_TABLE_N - 1u) + LTC_TABLE_N * min(j, LTC_TABLE_N - 1u);\n    return unpack2x16float(LTC_2[k]);\n}\n");
    } else {
        s.push_str(&format!(
            "const LTC_1: array<vec4<f32>, {nn}> = array<vec4<f32>, {nn}>(\n"
        ));
        for (k, c) in t.cells.iter().enumerate() {
            s.push_str(&format!(
                "    vec4<f32>({}, {}, {}, {}){}\n",
                lit32(c[0]),
                lit32(c[1]),
                lit32(c[2]),
                lit32(c[3]),
                sep(k)
            ));
        }
        s.push_str(&format!(
            ");\n\nconst LTC_2: array<vec2<f32>, {nn}> = array<vec2<f32>, {nn}>(\n"
        ));
        for (k, c) in t.cells.iter().enumerate() {
            s.push_str(&format!(
                "    vec2<f32>({}, {}){}\n",
                lit32(c[4]),
                lit32(c[5]),
                sep(k)
            ));
        }
        s.push_str(");\n\n/// The texel's (a, b, c, d).\nfn ltc_table_texel(i: u32, j: u32) -> vec4<f32> {\n    return LTC_1[min(i, LTC_TABLE_N - 1u) + LTC_TABLE_N * min(j, LTC_TABLE_N - 1u)];\n}\n\n/// The texel's (norm, fresnel).\nfn ltc_table_magnitude(i: u32, j: u32) -> vec2<f32> {\n    return LTC_2[min(i, LTC_TABLE_N - 1u) + LTC_TABLE_N * min(j, LTC_TABLE_N - 1u)];\n}\n");
    }
    super::namespace::apply(&s, &TABLE_IDENTS)
}

/// The items of the table modules (namespaced in WGSL).
pub const TABLE_IDENTS: [&str; 5] = [
    "LTC_TABLE_N",
    "LTC_1",
    "LTC_2",
    "ltc_table_texel",
    "ltc_table_magnitude",
];

/// Rust constants: f32 values and binary16 bit patterns of the same table.
pub fn render_rust(t: &LtcTableData, command: &str) -> String {
    let nn = t.n * t.n;
    let mut s = format!(
        "{}//! GGX LTC table ({}×{}); {LAYOUT}. `*_F16` hold the table's binary16 storage (the f16 neighbours chosen by the fit, `table_f16`; round to nearest where the file has none), two per u32 with the first in bits 0–15 (WGSL's `unpack2x16float` layout). The error each precision costs: results/ltc-ggx.md.\n\npub const LTC_TABLE_N: usize = {};\n\n",
        super::text::header("//", command, "results/fits/ltc-ggx.json"),
        t.n,
        t.n,
        t.n
    );
    let rows =
        |s: &mut String, name: &str, ty: &str, w: usize, f: &dyn Fn(&[f64; 6]) -> Vec<String>| {
            s.push_str(&format!("pub static {name}: [[{ty}; {w}]; {nn}] = [\n"));
            for c in &t.cells {
                s.push_str(&format!("    [{}],\n", f(c).join(", ")));
            }
            s.push_str("];\n\n");
        };
    rows(&mut s, "LTC_1", "f32", 4, &|c| {
        c[..4].iter().map(|x| lit32(*x)).collect()
    });
    rows(&mut s, "LTC_2", "f32", 2, &|c| {
        c[4..6].iter().map(|x| lit32(*x)).collect()
    });
    let packed = |x: f16, y: f16| format!("0x{:08x}", pack_half(x, y));
    let half_rows = |s: &mut String, name: &str, w: usize, f: &dyn Fn(&[f16; 6]) -> Vec<String>| {
        s.push_str(&format!("pub static {name}: [[u32; {w}]; {nn}] = [\n"));
        for k in 0..nn {
            s.push_str(&format!("    [{}],\n", f(&t.half_cell(k)).join(", ")));
        }
        s.push_str("];\n\n");
    };
    half_rows(&mut s, "LTC_1_F16", 2, &|c| {
        vec![packed(c[0], c[1]), packed(c[2], c[3])]
    });
    half_rows(&mut s, "LTC_2_F16", 1, &|c| vec![packed(c[4], c[5])]);
    s.truncate(s.trim_end().len());
    s.push('\n');
    s
}

/// Round every entry of a cell to f32 or f16 and back.
pub fn rounded(c: &[f64; 6], half: bool) -> [f64; 6] {
    c.map(|x| {
        if half {
            f16::from_f64(x).to_f64()
        } else {
            x as f32 as f64
        }
    })
}

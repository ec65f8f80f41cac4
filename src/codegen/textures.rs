//! Every fitted LTC table (GGX, Charlie sheen, Burley diffuse: [`TABLES`]) as the files
//! engines load, each from its table and in the shipped layout (texel (i, j) at i + n·j, i = roughness index with r = √α =
//! i/(n − 1) across, j = view index with t = √(1 − cos θ) = j/(n − 1) down; the shader
//! samples uv = (r, t)·(n − 1)/n + 0.5/n):
//!
//! - layer/texture 1 = (a, b, c, d) of M⁻¹ ∝ [[a, 0, c], [0, 1, 0], [b, 0, d]], i.e.
//!   `mat3x3(vec3(a, 0, b), vec3(0, 1, 0), vec3(c, 0, d))` (three.js, Bevy, ltc_code);
//! - layer/texture 2 = (norm, fresnel, 0, 0): the specular weight is
//!   F0·norm + (1 − F0)·fresnel (three.js `t2.x`, `t2.y`; Bevy the same). The `.w` of
//!   ltc_code's second texture (a clipped-sphere table that three.js leaves commented
//!   out) is 0 here.
//!
//! Files (under results/textures/, `<stem>` = `ltc_ggx`, `ltc_sheen`, …):
//! - `<stem>.ktx2`: KTX 2.0, VK_FORMAT_R16G16B16A16_SFLOAT, n×n, 2 array layers, one
//!   level, no supercompression, a basic data-format descriptor (Bevy's `AreaLightLuts`
//!   layout: layer 0 the matrix, layer 1 the weights);
//! - `ltc_ggx_zstd.ktx2`: the same, zstd-supercompressed (level 22) as Bevy ships its own
//!   `ltc.ktx2` (the same descriptor, levels aligned to 1 byte);
//! - `<stem>_1.dds`, `<stem>_2.dds`: DDS with a DX10 header, DXGI_FORMAT_R16G16B16A16_FLOAT,
//!   in this layout (for engines that load DDS at run time; not Godot's layout);
//! - `godot/ltc_lut{1,2}.dds` (GGX only): Godot 4's own layout and format
//!   (`crate::engines::godot`: R32G32B32A32_FLOAT, its own matrix form and a θ-linear
//!   view axis), the files that replace servers/rendering/storage/ltc/ltc_lut{1,2}.dds;
//! - `<stem>_{1,2}_{f16,f32}.bin`: raw little-endian RGBA texels, described by
//!   `<stem>.json` (three.js DataTexture, Babylon RawTexture);
//! - `<stem>.js`: an ES module exporting `LTC_MAT_1` and `LTC_MAT_2` as decimal
//!   literals in the shape of three.js's RectAreaLightTexturesLib (shortest f32
//!   round-trip decimals, so `new Float32Array(LTC_MAT_1)` is bit-exact).
//!
//! Every f16 file holds the table's binary16 storage (`FittedTable::half_cell`); every
//! f32 file the f64 table rounded to nearest f32.

use crate::ktx2::u32le;
use crate::ltc::table::FittedTable;
use half::f16;

/// Where the engine files go, relative to the results directory.
pub const DIR: &str = "textures";

/// One shipped table: its fit (results/fits/<fit>.json), the stem of its files and what
/// it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableKind {
    pub fit: &'static str,
    pub stem: &'static str,
    pub title: &'static str,
}

/// Every table shipped as engine files (a table whose fit is absent is skipped).
pub const TABLES: [TableKind; 5] = [
    TableKind {
        fit: "ltc-ggx",
        stem: "ltc_ggx",
        title: "GGX LTC table",
    },
    TableKind {
        fit: "ltc-sheen",
        stem: "ltc_sheen",
        title: "Charlie sheen LTC table (Estevez & Kulla visibility; sheen α = sheenRoughness²)",
    },
    TableKind {
        fit: "ltc-sheen-neubelt",
        stem: "ltc_sheen_neubelt",
        title: "Charlie sheen LTC table (Neubelt visibility, as three.js and Filament shade sheen)",
    },
    TableKind {
        fit: "ltc-diffuse",
        stem: "ltc_diffuse",
        title: "Burley diffuse LTC table (F_D90 with the paper's roughness √α)",
    },
    TableKind {
        fit: "ltc-diffuse-engines",
        stem: "ltc_diffuse_engines",
        title: "Burley diffuse LTC table (F_D90 with α, as Filament and Bevy evaluate it)",
    },
];

/// The GGX table's kind.
pub const GGX: TableKind = TABLES[0];

/// The RGBA texels of texture `layer` (0: matrix, 1: weights) in f32.
pub fn texels_f32(t: &FittedTable, layer: usize) -> Vec<[f32; 4]> {
    t.cells
        .iter()
        .map(|c| {
            let v = if layer == 0 {
                [c[0], c[1], c[2], c[3]]
            } else {
                [c[4], c[5], 0.0, 0.0]
            };
            v.map(|x| x as f32)
        })
        .collect()
}

/// The RGBA texels of texture `layer` in binary16.
pub fn texels_f16(t: &FittedTable, layer: usize) -> Vec<[f16; 4]> {
    (0..t.cells.len())
        .map(|k| {
            let c = t.half_cell(k);
            if layer == 0 {
                [c[0], c[1], c[2], c[3]]
            } else {
                [c[4], c[5], f16::ZERO, f16::ZERO]
            }
        })
        .collect()
}

fn bytes_f16(texels: &[[f16; 4]]) -> Vec<u8> {
    texels
        .iter()
        .flatten()
        .flat_map(|h| h.to_bits().to_le_bytes())
        .collect()
}

fn bytes_f32(texels: &[[f32; 4]]) -> Vec<u8> {
    texels
        .iter()
        .flatten()
        .flat_map(|x| x.to_bits().to_le_bytes())
        .collect()
}

/// VK_FORMAT_R16G16B16A16_SFLOAT.
pub const VK_FORMAT_R16G16B16A16_SFLOAT: u32 = crate::ktx2::R16G16B16A16_SFLOAT;

/// The KTX2 file: both layers in one 2D array texture of R16G16B16A16_SFLOAT (four
/// 16-bit signed-float samples R, G, B, A; `crate::ktx2`).
pub fn ktx2(t: &FittedTable, writer: &str) -> Vec<u8> {
    crate::ktx2::write(&ktx2_texture(t, writer))
}

/// The zstd level of the supercompressed KTX2 (Bevy's `ltc.ktx2` was written with
/// `ktx create --zstd 22`).
pub const ZSTD_LEVEL: i32 = 22;

/// The same texture zstd-supercompressed as Bevy ships its own table
/// (`<stem>_zstd.ktx2`; [`ZSTD_LEVEL`]).
pub fn ktx2_zstd(t: &FittedTable, writer: &str) -> std::io::Result<Vec<u8>> {
    crate::ktx2::write_zstd(&ktx2_texture(t, writer), ZSTD_LEVEL)
}

fn ktx2_texture(t: &FittedTable, writer: &str) -> crate::ktx2::Texture {
    let mut level = bytes_f16(&texels_f16(t, 0));
    level.extend(bytes_f16(&texels_f16(t, 1)));
    crate::ktx2::uncompressed(
        VK_FORMAT_R16G16B16A16_SFLOAT,
        &crate::ktx2::RGBA,
        2,
        true,
        (t.n as u32, t.n as u32, 2),
        vec![level],
        vec![
            ("KTXorientation".into(), "rd".into()),
            ("KTXwriter".into(), writer.into()),
        ],
    )
}

/// DXGI_FORMAT_R16G16B16A16_FLOAT.
pub const DXGI_FORMAT_R16G16B16A16_FLOAT: u32 = 10;

/// DXGI_FORMAT_R32G32B32A32_FLOAT.
pub const DXGI_FORMAT_R32G32B32A32_FLOAT: u32 = 2;

/// A DDS file (DX10 header) of one texture of R16G16B16A16_FLOAT texels.
pub fn dds(n: usize, texels: &[[f16; 4]]) -> Vec<u8> {
    dds_file(n, DXGI_FORMAT_R16G16B16A16_FLOAT, 8, &bytes_f16(texels))
}

/// A DDS file (DX10 header) of one texture of R32G32B32A32_FLOAT texels (Godot's LTC
/// tables).
pub fn dds_f32(n: usize, texels: &[[f32; 4]]) -> Vec<u8> {
    dds_file(n, DXGI_FORMAT_R32G32B32A32_FLOAT, 16, &bytes_f32(texels))
}

/// The 148-byte DX10 DDS header of an n×n 2D texture of `dxgi` texels of
/// `bytes_per_texel`, then `payload`.
fn dds_file(n: usize, dxgi: u32, bytes_per_texel: usize, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(b"DDS ");
    let pitch = (n * bytes_per_texel) as u32;
    // DDS_HEADER: size, flags (CAPS | HEIGHT | WIDTH | PIXELFORMAT | PITCH), height,
    // width, pitch, depth, mip count, 11 reserved
    for v in [
        124u32,
        0x1 | 0x2 | 0x4 | 0x1000 | 0x8,
        n as u32,
        n as u32,
        pitch,
        0,
        1,
    ] {
        u32le(&mut out, v);
    }
    for _ in 0..11 {
        u32le(&mut out, 0);
    }
    // DDS_PIXELFORMAT: size, flags (FOURCC), "DX10", then unused masks
    u32le(&mut out, 32);
    u32le(&mut out, 0x4);
    out.extend_from_slice(b"DX10");
    for _ in 0..5 {
        u32le(&mut out, 0);
    }
    // caps (TEXTURE), caps2–4, reserved
    for v in [0x1000u32, 0, 0, 0, 0] {
        u32le(&mut out, v);
    }
    // DDS_HEADER_DXT10: format, dimension (TEXTURE2D), misc, array size, misc2
    for v in [dxgi, 3, 0, 1, 0] {
        u32le(&mut out, v);
    }
    out.extend_from_slice(payload);
    out
}

/// A layer's texels in f32 as a JavaScript number list (shortest round-trip decimals, so
/// `new Float32Array([...])` is bit-exact).
fn js_f32_list(t: &FittedTable, layer: usize) -> String {
    texels_f32(t, layer)
        .iter()
        .flatten()
        .map(|x| format!("{x}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The ES module in the shape of RectAreaLightTexturesLib's arrays.
pub fn es_module(t: &FittedTable, kind: &TableKind, header: &str) -> String {
    let list = |layer: usize| js_f32_list(t, layer);
    format!(
        "{header}// {title}, {n}×{n} RGBA texels at (i + {n}·j)·4 + c: LTC_MAT_1 = (a, b, c, d) of M⁻¹, LTC_MAT_2 = (norm, fresnel, 0, 0). Drop-in for three.js's RectAreaLightTexturesLib arrays (see README).\nexport const LTC_SIZE = {n};\nexport const LTC_MAT_1 = [ {} ];\nexport const LTC_MAT_2 = [ {} ];\n",
        list(0),
        list(1),
        n = t.n,
        title = kind.title
    )
}

/// The file name of the three.js drop-in (the name of the module it replaces).
pub const THREE_DROP_IN: &str = "RectAreaLightTexturesLib.js";

/// A drop-in for three.js r187's `examples/jsm/lights/RectAreaLightTexturesLib.js`: the
/// same export, a class `RectAreaLightTexturesLib` whose `init()` builds the four
/// DataTextures exactly as three builds them (64×64 RGBA, UVMapping, clamp to edge,
/// linear magnification, nearest minification, no mips) and returns the class, with our
/// table: the FloatType textures hold the table in f32, the HalfFloatType ones our stored
/// binary16 table bit for bit (not three's truncating `toHalfFloat` of the f32 numbers).
/// `RectAreaLightUniformsLib.init()` (WebGL) and `RectAreaLightNode.setLTC(…)` (WebGPU)
/// take it as they take three's.
pub fn three_drop_in(t: &FittedTable, header: &str) -> String {
    let f32s = |layer: usize| js_f32_list(t, layer);
    let bits = |layer: usize| {
        texels_f16(t, layer)
            .iter()
            .flatten()
            .map(|h| h.to_bits().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let n = t.n;
    three_module(&ThreeModule {
        comment: &format!(
            "{header}// A drop-in for three.js r187's examples/jsm/lights/RectAreaLightTexturesLib.js with the
// ndfbench GGX LTC table: map that module to this file (an import map entry, or a bundler
// alias) and RectAreaLightUniformsLib.init() (WebGLRenderer) or
// RectAreaLightNode.setLTC( RectAreaLightTexturesLib.init() ) (WebGPURenderer) use it.
// Texel (i, j) at (i + {n}·j)·4 + c: LTC_MAT_1 = (a, b, c, d) of M⁻¹ ∝ [[a, 0, c], [0, 1, 0],
// [b, 0, d]], LTC_MAT_2 = (norm, fresnel, 0, 0). The FloatType textures hold the table in
// f32; the HalfFloatType ones hold its stored binary16 table bit for bit.
"
        ),
        imports: "",
        prelude: &format!(
            "\t\tconst LTC_MAT_1 = [ {} ];\n\t\tconst LTC_MAT_2 = [ {} ];\n\t\tconst LTC_HALF_BITS_1 = [ {} ];\n\t\tconst LTC_HALF_BITS_2 = [ {} ];\n\n",
            f32s(0),
            f32s(1),
            bits(0),
            bits(1)
        ),
        side: &n.to_string(),
        data: [
            "new Float32Array( LTC_MAT_1 )",
            "new Float32Array( LTC_MAT_2 )",
            "new Uint16Array( LTC_HALF_BITS_1 )",
            "new Uint16Array( LTC_HALF_BITS_2 )",
        ],
    })
}

/// What differs between the three.js drop-ins (the full table's, the compact rebuild's).
pub struct ThreeModule<'a> {
    /// The file's opening comment, header included, each line ending in a newline.
    pub comment: &'a str,
    /// Import lines after three's own.
    pub imports: &'a str,
    /// `init()`'s first lines (tab-indented, ending in a blank line).
    pub prelude: &'a str,
    /// The textures' side as a JS expression.
    pub side: &'a str,
    /// The data of LTC_FLOAT_1, LTC_FLOAT_2, LTC_HALF_1, LTC_HALF_2 as JS expressions.
    pub data: [&'a str; 4],
}

/// An ES module with three.js r187's `RectAreaLightTexturesLib` export, whose `init()`
/// builds the four DataTextures exactly as three builds them (RGBA, UVMapping, clamp to
/// edge, linear magnification, nearest minification, no mips) from `m.data` and returns
/// the class.
pub fn three_module(m: &ThreeModule) -> String {
    let (side, [f1, f2, h1, h2]) = (m.side, m.data);
    format!(
        "{}import {{
	ClampToEdgeWrapping,
	DataTexture,
	FloatType,
	HalfFloatType,
	LinearFilter,
	NearestFilter,
	RGBAFormat,
	UVMapping
}} from 'three';
{}
class RectAreaLightTexturesLib {{

	static init() {{

{}		const texture = ( data, type ) => {{

			const t = new DataTexture( data, {side}, {side}, RGBAFormat, type, UVMapping, ClampToEdgeWrapping, ClampToEdgeWrapping, LinearFilter, NearestFilter, 1 );
			t.needsUpdate = true;
			return t;

		}};

		this.LTC_FLOAT_1 = texture( {f1}, FloatType );
		this.LTC_FLOAT_2 = texture( {f2}, FloatType );
		this.LTC_HALF_1 = texture( {h1}, HalfFloatType );
		this.LTC_HALF_2 = texture( {h2}, HalfFloatType );

		return this;

	}}

}}

RectAreaLightTexturesLib.LTC_HALF_1 = null;
RectAreaLightTexturesLib.LTC_HALF_2 = null;
RectAreaLightTexturesLib.LTC_FLOAT_1 = null;
RectAreaLightTexturesLib.LTC_FLOAT_2 = null;

export {{ RectAreaLightTexturesLib }};
",
        m.comment, m.imports, m.prelude
    )
}

/// The JSON manifest of the raw files.
pub fn manifest(t: &FittedTable, kind: &TableKind, command: &str) -> String {
    let st = kind.stem;
    let v = serde_json::json!({
        "generated": format!("by `{command}` from results/fits/{}.json; do not edit", kind.fit),
        "table": kind.title,
        "width": t.n,
        "height": t.n,
        "channels": 4,
        "byte_order": "little-endian",
        "texel_index": "i + width·j: i = roughness index (r = √α = i/(width − 1)), j = view index (t = √(1 − cos θ) = j/(height − 1)); sample uv = (r, t)·(n − 1)/n + 0.5/n",
        "textures": [
            {"name": "LTC_MAT_1", "channels": "a, b, c, d of M⁻¹ ∝ [[a, 0, c], [0, 1, 0], [b, 0, d]]", "f16": format!("{st}_1_f16.bin"), "f32": format!("{st}_1_f32.bin")},
            {"name": "LTC_MAT_2", "channels": "norm, fresnel, 0, 0 (specular weight F0·norm + (1 − F0)·fresnel)", "f16": format!("{st}_2_f16.bin"), "f32": format!("{st}_2_f32.bin")}
        ],
        "f16": format!("IEEE binary16: the table's binary16 storage (results/fits/{}.json `table_f16`)", kind.fit),
        "f32": "IEEE binary32, the f64 table rounded to nearest",
        "ktx2": format!("{st}.ktx2 (R16G16B16A16_SFLOAT, 2 layers)"),
        "dds": [format!("{st}_1.dds"), format!("{st}_2.dds")],
        "es_module": format!("{st}.js")
    });
    serde_json::to_string_pretty(&v).expect("json") + "\n"
}

/// Every engine file of one table: (path relative to the results directory, bytes).
pub fn render(t: &FittedTable, kind: &TableKind, command: &str) -> Vec<(String, Vec<u8>)> {
    let p = |f: &str| format!("{DIR}/{}{f}", kind.stem);
    let mut out = vec![(p(".ktx2"), ktx2(t, &format!("ndfbench ({command})")))];
    for layer in 0..2 {
        let h = texels_f16(t, layer);
        out.push((p(&format!("_{}.dds", layer + 1)), dds(t.n, &h)));
        out.push((p(&format!("_{}_f16.bin", layer + 1)), bytes_f16(&h)));
        out.push((
            p(&format!("_{}_f32.bin", layer + 1)),
            bytes_f32(&texels_f32(t, layer)),
        ));
    }
    out.push((p(".json"), manifest(t, kind, command).into_bytes()));
    let header = super::text::header("//", command, &format!("results/fits/{}.json", kind.fit));
    out.push((p(".js"), es_module(t, kind, &header).into_bytes()));
    if kind.fit == GGX.fit {
        // Bevy's own file is zstd-supercompressed; an error of the compressor leaves the
        // file out (and the staleness test then says so)
        if let Ok(z) = ktx2_zstd(t, &format!("ndfbench ({command})")) {
            out.push((p("_zstd.ktx2"), z));
        }
        out.push((
            format!("{DIR}/three/{THREE_DROP_IN}"),
            three_drop_in(t, &header).into_bytes(),
        ));
        // Godot's own layout (crate::engines::godot), f32 as Godot embeds it
        // a table Godot's form cannot hold leaves the files out (the staleness test then
        // says so)
        let (l1, l2) = crate::engines::godot::texels(t).unwrap_or_default();
        let f32s =
            |v: Vec<[f64; 4]>| -> Vec<[f32; 4]> { v.iter().map(|x| x.map(|c| c as f32)).collect() };
        for (k, l) in [l1, l2]
            .into_iter()
            .enumerate()
            .filter(|(_, l)| !l.is_empty())
        {
            out.push((
                format!("{DIR}/godot/ltc_lut{}.dds", k + 1),
                dds_f32(crate::engines::godot::N, &f32s(l)),
            ));
        }
    }
    out
}

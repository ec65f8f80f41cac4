//! The anisotropic GGX LTC table (results/fits/ltc-aniso.json) as engine files and its
//! WGSL lookup: `textures/ltc_ggx_aniso.ktx2` (RGBA16F 2D array in the layout of
//! `ltc::aniso_table`), the same texels raw (`ltc_ggx_aniso_f16.bin`) with a JSON
//! manifest, and `ltc_aniso.wgsl` (texture and sampler passed in; the hardware
//! interpolates (r_x, t), the function the four (r_y, φ) neighbours, and undoes the
//! symmetry that folded φ into [0, π/2]). The f64 reference is `AnisoTable::lookup`.

use super::namespace;
use crate::ltc::aniso_table::AnisoTable;
use half::f16;

/// The items of the module (namespaced in WGSL).
pub const IDENTS: [&str; 5] = [
    "LTC_ANISO_PI",
    "ltc_aniso_sample",
    "ltc_aniso_mirror",
    "ltc_aniso_matrix",
    "ltc_aniso_weights",
];

/// The file stem of the engine files.
pub const STEM: &str = "ltc_ggx_aniso";

/// The texels in texture order: layer 3·(k·n_r + i_y) + q, row j (t), column i_x (r_x);
/// q = 0: (a, b, c, d), 1: (norm, fresnel, 0, 0), 2: (e, g, h, 0); binary16.
pub fn texels(t: &AnisoTable) -> Vec<[f16; 4]> {
    let g = t.grid;
    let t = t.to_half();
    let mut out = Vec::with_capacity(g.cells() * 3);
    for k in 0..g.n_phi {
        for iy in 0..g.n_r {
            for q in 0..3 {
                for j in 0..g.n_t {
                    for ix in 0..g.n_r {
                        let c = &t.cells[g.index(ix, iy, k, j)];
                        let v = match q {
                            0 => [c[0], c[1], c[2], c[3]],
                            1 => [c[7], c[8], 0.0, 0.0],
                            _ => [c[4], c[5], c[6], 0.0],
                        };
                        out.push(v.map(f16::from_f64));
                    }
                }
            }
        }
    }
    out
}

fn bytes(texels: &[[f16; 4]]) -> Vec<u8> {
    texels
        .iter()
        .flatten()
        .flat_map(|h| h.to_bits().to_le_bytes())
        .collect()
}

/// Every engine file: (path relative to the results directory, bytes).
pub fn render(t: &AnisoTable, command: &str) -> Vec<(String, Vec<u8>)> {
    let g = t.grid;
    let layers = (3 * g.n_r * g.n_phi) as u32;
    let data = bytes(&texels(t));
    let ktx = crate::ktx2::write(&crate::ktx2::uncompressed(
        crate::ktx2::R16G16B16A16_SFLOAT,
        &crate::ktx2::RGBA,
        2,
        true,
        (g.n_r as u32, g.n_t as u32, layers),
        vec![data.clone()],
        vec![
            ("KTXorientation".into(), "rd".into()),
            ("KTXwriter".into(), format!("ndfbench ({command})")),
        ],
    ));
    let manifest = serde_json::json!({
        "generated": format!("by `{command}` from results/fits/ltc-aniso.json; do not edit"),
        "table": "anisotropic GGX LTC table",
        "width": g.n_r,
        "height": g.n_t,
        "layers": layers,
        "channels": 4,
        "format": "IEEE binary16, little-endian RGBA texels, layer-major",
        "texel": "layer 3·(k·n_r + i_y) + q, row j, column i_x: r_x = √α_x = i_x/(n_r − 1), r_y = i_y/(n_r − 1), φ = (π/2)·k/(n_phi − 1) (the α_x tangent's azimuth from T1), t = √(1 − cos θ) = j/(n_t − 1); q = 0: (a, b, c, d), 1: (norm, fresnel, 0, 0), 2: (e, g, h, 0) of M⁻¹ ∝ [[a, 0, c], [e, 1, g], [b, h, d]] (rows)",
        "n_r": g.n_r,
        "n_phi": g.n_phi,
        "n_t": g.n_t,
        "ktx2": format!("{STEM}.ktx2"),
        "f16": format!("{STEM}_f16.bin"),
        "lookup": "results/wgsl/ltc_aniso.wgsl"
    });
    let p = |f: &str| format!("{}/{STEM}{f}", super::textures::DIR);
    vec![
        (p(".ktx2"), ktx),
        (p("_f16.bin"), data),
        (
            p(".json"),
            (serde_json::to_string_pretty(&manifest).expect("json") + "\n").into_bytes(),
        ),
    ]
}

/// The WGSL module (plain, namespaced).
pub fn render_wgsl(command: &str) -> String {
    let body = "\
const LTC_ANISO_PI: f32 = 3.14159265358979;

/// One layer kind q (0: a, b, c, d; 1: norm, fresnel; 2: e, g, h) of the anisotropic table
/// at (α_x, α_y, φ folded into [0, π/2], cos θ): the sampler interpolates (r_x, t), this
/// function the four (r_y, φ) neighbours (12 fetches for the three kinds).
/// Inputs — lut: `ltc_ggx_aniso.ktx2` (RGBA16F array); s: a linear, clamp-to-edge sampler; alpha_x, alpha_y: GGX α along and across the tangent, each the squared perceptual roughness (Bevy's `roughness` split by the anisotropy); phi: the tangent's azimuth from T1 (radians, any value); cos_theta: clamp(dot(N, V), 0, 1); q: the layer kind.
fn ltc_aniso_sample(lut: texture_2d_array<f32>, s: sampler, alpha_x: f32, alpha_y: f32, phi: f32, cos_theta: f32, q: u32) -> vec4<f32> {
    let dims = textureDimensions(lut);
    let nr = f32(dims.x);
    let nt = f32(dims.y);
    let nphi = f32(textureNumLayers(lut)) / (3.0 * nr);
    var p = phi - LTC_ANISO_PI * floor(phi / LTC_ANISO_PI);
    if (p > 0.5 * LTC_ANISO_PI) {
        p = LTC_ANISO_PI - p;
    }
    let rx = sqrt(clamp(alpha_x, 0.0, 1.0));
    let ry = sqrt(clamp(alpha_y, 0.0, 1.0));
    let t = sqrt(1.0 - clamp(cos_theta, 0.0, 1.0));
    let uv = (vec2<f32>(rx, t) * (vec2<f32>(nr, nt) - 1.0) + 0.5) / vec2<f32>(nr, nt);
    let y = ry * (nr - 1.0);
    let iy = min(floor(y), nr - 2.0);
    let fy = y - iy;
    let kf = p / (0.5 * LTC_ANISO_PI) * (nphi - 1.0);
    let ik = min(floor(kf), nphi - 2.0);
    let fk = kf - ik;
    let l00 = i32(3.0 * (ik * nr + iy)) + i32(q);
    let l01 = l00 + i32(3.0 * nr);
    let v0 = mix(textureSampleLevel(lut, s, uv, l00, 0.0), textureSampleLevel(lut, s, uv, l00 + 3, 0.0), fy);
    let v1 = mix(textureSampleLevel(lut, s, uv, l01, 0.0), textureSampleLevel(lut, s, uv, l01 + 3, 0.0), fy);
    return mix(v0, v1, fk);
}

/// −1 where φ folds into [0, π/2] through the mirror y → −y (then e, g, h change sign), else 1.
/// Inputs — phi: the tangent's azimuth from T1 (radians, any value).
fn ltc_aniso_mirror(phi: f32) -> f32 {
    let p = phi - LTC_ANISO_PI * floor(phi / LTC_ANISO_PI);
    return select(1.0, -1.0, p > 0.5 * LTC_ANISO_PI);
}

/// M⁻¹ of the anisotropic table, rows (a, 0, c), (e, 1, g), (b, h, d) in the frame (T1,
/// T2, N) with T1 the view projected on the tangent plane and T2 = N × T1.
/// Inputs — lut, s, alpha_x, alpha_y (each the squared perceptual roughness), phi, cos_theta: as `ltc_aniso_sample`.
fn ltc_aniso_matrix(lut: texture_2d_array<f32>, s: sampler, alpha_x: f32, alpha_y: f32, phi: f32, cos_theta: f32) -> mat3x3<f32> {
    let m = ltc_aniso_sample(lut, s, alpha_x, alpha_y, phi, cos_theta, 0u);
    let e = ltc_aniso_sample(lut, s, alpha_x, alpha_y, phi, cos_theta, 2u) * ltc_aniso_mirror(phi);
    return mat3x3<f32>(vec3<f32>(m.x, e.x, m.y), vec3<f32>(0.0, 1.0, e.z), vec3<f32>(m.z, e.y, m.w));
}

/// (norm, fresnel) of the anisotropic table: the weight is F0·norm + (1 − F0)·fresnel.
/// Inputs — lut, s, alpha_x, alpha_y (each the squared perceptual roughness), phi, cos_theta: as `ltc_aniso_sample`.
fn ltc_aniso_weights(lut: texture_2d_array<f32>, s: sampler, alpha_x: f32, alpha_y: f32, phi: f32, cos_theta: f32) -> vec2<f32> {
    return ltc_aniso_sample(lut, s, alpha_x, alpha_y, phi, cos_theta, 1u).xy;
}
";
    let text = format!(
        "{}// Anisotropic GGX LTC lookup (results/ltc-aniso.md): the engine binds ltc_ggx_aniso.ktx2 as a 2D array texture and a linear sampler and passes them in.\n\n{body}",
        super::text::header("//", command, "src/codegen/aniso.rs"),
    );
    namespace::apply(&text, &IDENTS)
}

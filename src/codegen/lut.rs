//! `ltc_lut.wgsl`: the lookup of any of the LTC tables of `textures::TABLES` (GGX,
//! sheen, diffuse: all in the one layout) from the 2-layer texture an engine loads
//! (`<stem>.ktx2`, layer 0 = (a, b, c, d), layer 1 = (norm, fresnel)), interpolated by
//! the GPU's bilinear sampler at the texel-centre coordinates of the shipped tables. The
//! texture and the sampler are arguments (the module declares no binding): the engine
//! binds its own. The f64 reference is `ltc::table::FittedTable::bilinear`; tests/gpu.rs
//! reads every table back through these functions against it.

use super::namespace;

/// The items of the module (namespaced in WGSL).
pub const IDENTS: [&str; 3] = ["ltc_lut_uv", "ltc_lut_matrix", "ltc_lut_weights"];

/// The module text (plain WGSL, namespaced).
pub fn render_wgsl(command: &str) -> String {
    let body = "\
/// Texture coordinates of an n×n LTC table (n = the texture's width) for roughness α and
/// view cosine cos θ: the table is uniform in r = √α and t = √(1 − cos θ) over texel
/// centres, uv = ((r, t)(n − 1) + ½)/n, so that bilinear filtering reproduces the
/// table's own interpolation.
/// Inputs — cos_theta: cos θ_v = clamp(dot(N, V), 0, 1); n: the table's side; alpha: the table's α, the squared perceptual roughness (GGX and diffuse: Bevy's `roughness`, glTF's roughnessFactor²; sheen: glTF's sheenRoughnessFactor²).
fn ltc_lut_uv(alpha: f32, cos_theta: f32, n: f32) -> vec2<f32> {
    let r = sqrt(clamp(alpha, 0.0, 1.0));
    let t = sqrt(1.0 - clamp(cos_theta, 0.0, 1.0));
    return (vec2<f32>(r, t) * (n - 1.0) + 0.5) / n;
}

/// M⁻¹ of the table in layer 0 of `lut` at (α, cos θ), bilinearly interpolated:
/// mat3x3(vec3(a, 0, b), vec3(0, 1, 0), vec3(c, 0, d)) in the frame (T1, T2, N) with T1
/// the view projected on the tangent plane (three.js, Bevy and ltc_code's frame).
/// Inputs — lut: the table's 2-layer texture (`<stem>.ktx2`); s: a linear, clamp-to-edge sampler; cos_theta: as `ltc_lut_uv`; alpha: the squared perceptual roughness of the table's lobe, as `ltc_lut_uv`.
fn ltc_lut_matrix(lut: texture_2d_array<f32>, s: sampler, alpha: f32, cos_theta: f32) -> mat3x3<f32> {
    let n = f32(textureDimensions(lut).x);
    let p = textureSampleLevel(lut, s, ltc_lut_uv(alpha, cos_theta, n), 0, 0.0);
    return mat3x3<f32>(vec3<f32>(p.x, 0.0, p.y), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(p.z, 0.0, p.w));
}

/// (norm, fresnel) of the table in layer 1 of `lut` at (α, cos θ), bilinearly
/// interpolated: the lobe's weight is F0·norm + (1 − F0)·fresnel (norm alone for the
/// diffuse and sheen lobes, whose colour multiplies it).
/// Inputs — lut, s, cos_theta: as `ltc_lut_matrix`; alpha: the squared perceptual roughness of the table's lobe, as `ltc_lut_uv`.
fn ltc_lut_weights(lut: texture_2d_array<f32>, s: sampler, alpha: f32, cos_theta: f32) -> vec2<f32> {
    let n = f32(textureDimensions(lut).x);
    return textureSampleLevel(lut, s, ltc_lut_uv(alpha, cos_theta, n), 1, 0.0).xy;
}
";
    let text = format!(
        "{}// LTC table lookup for every table of results/textures/ (GGX, sheen, diffuse): the engine binds the table's 2-layer texture and a linear sampler and passes them in. The error of each table between cells: results/ltc-ggx.md, results/ltc-sheen.md, results/ltc-diffuse.md.\n\n{body}",
        super::text::header("//", command, "src/codegen/lut.rs"),
    );
    namespace::apply(&text, &IDENTS)
}

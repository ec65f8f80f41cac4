//! How engines upload and sample a 64×64 GGX LTC table, so that a table is judged as
//! each engine's shader sees it.
//!
//! - three.js r187 (`RectAreaLightTexturesLib.init()`): the FloatType textures hold the
//!   numbers of `LTC_MAT_1/2` as `Float32Array`; the HalfFloatType ones hold
//!   `DataUtils.toHalfFloat(x)` of each number, which converts to f32 and then *truncates*
//!   the mantissa (its base/shift tables shift the low bits away; no rounding), so about
//!   half of the values sit one binary16 step below round-to-nearest. Its shaders clamp
//!   the material's perceptual roughness to ≥ 0.045 (`lights_physical_fragment`) and
//!   sample at uv = (r, √(1 − saturate(N·V)))·63/64 + 0.5/64 (`LTC_Uv`), bilinearly.
//! - Bevy 0.19 (`bevy_pbr`, `src/ltc/ltc.ktx2`): a 64×64, 2-layer RGBA16F array,
//!   zstd-supercompressed, layer 0 = (a, b, c, d), layer 1 = (norm, fresnel, …); the
//!   shader (`rect_light` in `pbr_lighting.wgsl`) samples the unclamped perceptual
//!   roughness at the same uv.
//!
//! With uv = x·63/64 + 0.5/64 the texel centres are at x = i/63 and a bilinear lookup at
//! a square's centre weighs its four corners ¼ each, so "cells" and "squares" of the
//! tables are exactly what both engines read there.

use super::compare::Shipped;
use crate::error::{Error, Result};

/// three.js's smallest perceptual roughness (`material.roughness = max(…, 0.045)`).
pub const THREE_MIN_ROUGHNESS: f64 = 0.045;

/// `DataUtils.toHalfFloat` of three.js r187, bit for bit: the value clamped to ±65504,
/// rounded to f32, then its mantissa shifted (truncated) into binary16.
pub fn three_half_bits(x: f64) -> u16 {
    let v = x.clamp(-65504.0, 65504.0) as f32;
    let f = v.to_bits();
    let e = ((f >> 23) & 0x1ff) as usize;
    let (base, shift) = three_tables(e);
    (base + ((f & 0x007f_ffff) >> shift)) as u16
}

/// The binary16 value three.js stores for `x`.
pub fn three_half(x: f64) -> f64 {
    half::f16::from_bits(three_half_bits(x)).to_f64()
}

/// Entry `e` (sign bit and exponent, 9 bits) of three.js's base and shift tables.
fn three_tables(e: usize) -> (u32, u32) {
    let sign = if e & 0x100 != 0 { 0x8000 } else { 0 };
    let ex = (e & 0xff) as i32 - 127;
    if ex < -27 {
        (sign, 24)
    } else if ex < -14 {
        ((0x0400 >> (-ex - 14)) | sign, (-ex - 1) as u32)
    } else if ex <= 15 {
        ((((ex + 15) as u32) << 10) | sign, 13)
    } else if ex < 128 {
        (0x7c00 | sign, 24)
    } else {
        (0x7c00 | sign, 13)
    }
}

/// A table as three.js's HalfFloatType textures hold it.
pub fn three_half_table(t: &Shipped) -> Shipped {
    Shipped {
        n: t.n,
        mat: t.mat.iter().map(|c| c.map(three_half)).collect(),
        mag: t.mag.iter().map(|c| c.map(three_half)).collect(),
    }
}

/// A table as three.js's FloatType textures hold it.
pub fn f32_table(t: &Shipped) -> Shipped {
    let q = |x: f64| x as f32 as f64;
    Shipped {
        n: t.n,
        mat: t.mat.iter().map(|c| c.map(q)).collect(),
        mag: t.mag.iter().map(|c| c.map(q)).collect(),
    }
}

/// Largest KTX2 file read as an engine's table (Bevy's is 46 KB).
pub const MAX_KTX2_BYTES: usize = 4 << 20;

/// An LTC table from a KTX2 file in Bevy's layout: one level, 2 layers of n×n
/// R16G16B16A16_SFLOAT texels (layer 0 = (a, b, c, d), layer 1 = (norm, fresnel, …)),
/// uncompressed or zstd-supercompressed. Anything else is a typed error.
pub fn bevy_ktx2(bytes: &[u8]) -> Result<Shipped> {
    let bad = |m: String| Error::InvalidArgument(format!("LTC KTX2: {m}"));
    if bytes.len() > MAX_KTX2_BYTES {
        return Err(bad(format!(
            "{} bytes, over the {MAX_KTX2_BYTES}-byte limit",
            bytes.len()
        )));
    }
    let r = ktx2::Reader::new(bytes).map_err(|e| bad(format!("not a KTX2 file ({e:?})")))?;
    let h = r.header();
    if h.format != Some(ktx2::Format::R16G16B16A16_SFLOAT) {
        return Err(bad(format!(
            "format {:?}, expected R16G16B16A16_SFLOAT",
            h.format
        )));
    }
    let n = h.pixel_width as usize;
    if !(2..=1024).contains(&n) || h.pixel_height as usize != n || h.pixel_depth > 1 {
        return Err(bad(format!(
            "{}×{}×{} texels, expected a square 2D table of 2 to 1024 texels a side",
            h.pixel_width, h.pixel_height, h.pixel_depth
        )));
    }
    if h.layer_count != 2 || h.face_count != 1 {
        return Err(bad(format!(
            "{} layers and {} faces, expected 2 layers and 1 face",
            h.layer_count, h.face_count
        )));
    }
    let level = r
        .levels()
        .next()
        .ok_or_else(|| bad("no mip level".into()))?;
    let want = n * n * 2 * 8;
    let data = match h.supercompression_scheme {
        None => level.data.to_vec(),
        Some(ktx2::SupercompressionScheme::Zstandard) => {
            zstd::bulk::decompress(level.data, want).map_err(|e| bad(format!("zstd: {e}")))?
        }
        Some(s) => return Err(bad(format!("supercompression {s:?} is not read"))),
    };
    if data.len() != want {
        return Err(bad(format!(
            "level 0 holds {} bytes, expected {want} (2 layers of {n}² RGBA16F)",
            data.len()
        )));
    }
    let texel = |layer: usize, k: usize| -> [f64; 4] {
        let at = (layer * n * n + k) * 8;
        std::array::from_fn(|c| {
            half::f16::from_le_bytes([data[at + 2 * c], data[at + 2 * c + 1]]).to_f64()
        })
    };
    let t = Shipped {
        n,
        mat: (0..n * n).map(|k| texel(0, k)).collect(),
        mag: (0..n * n)
            .map(|k| {
                let w = texel(1, k);
                [w[0], w[1]]
            })
            .collect(),
    };
    if t.mat
        .iter()
        .flatten()
        .chain(t.mag.iter().flatten())
        .any(|v| !v.is_finite())
    {
        return Err(bad("a texel is not finite".into()));
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_half_truncates() {
        // 1 + 2⁻¹¹·1.5 lies past the midpoint to the next binary16 (1 + 2⁻¹⁰): nearest
        // rounds up, three.js truncates down
        let x = 1.0 + 1.5 * 2f64.powi(-11);
        assert_eq!(half::f16::from_f64(x).to_f64(), 1.0 + 2f64.powi(-10));
        assert_eq!(three_half(x), 1.0);
        // exact binary16 numbers, signs, subnormals and zero come through unchanged
        for v in [
            0.0,
            -0.0,
            1.0,
            -2.5,
            6.103515625e-5,
            5.960464477539063e-8,
            65504.0,
        ] {
            assert_eq!(three_half(v), v, "{v}");
        }
        // out of range clamps to ±65504
        assert_eq!(three_half(1e9), 65504.0);
        assert_eq!(three_half(-1e9), -65504.0);
    }
}

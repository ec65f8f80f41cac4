//! The prefilter tool's inputs: a tangent-space normal map and a roughness map (or one
//! constant α), decoded once and checked before anything is computed or written.

use crate::error::{Error, Result};
use crate::filters::footprint::{MAX_MAP_SIDE, MAX_OFF_UNIT_FRACTION, UNIT_TOLERANCE};
use std::path::Path;

/// A decoded normal map: unit normals, row-major, and the bit depth it came in.
pub struct Normals {
    pub width: usize,
    pub height: usize,
    pub bits: u8,
    /// Unit normals as f32 (x, y, z).
    pub n: Vec<[f32; 3]>,
}

/// Where each texel's base roughness comes from.
pub enum Roughness {
    /// One α for the whole map.
    Constant(f64),
    /// A perceptual-roughness map (glTF convention: α = value²), `scale` normal-map
    /// texels per roughness texel along each axis (1 = same size).
    Map {
        width: usize,
        height: usize,
        bits: u8,
        scale: usize,
        perceptual: Vec<f32>,
        /// The other two channels of an RGB(A) glTF texture, (R, B) = (occlusion,
        /// metallic) of an ORM map, carried into a glTF-layout output; None for grey maps.
        others: Option<Vec<[f32; 2]>>,
    },
}

impl Roughness {
    /// The perceptual roughness p (α = p²) under normal-map texel (x, y): a smaller map
    /// is read nearest-texel, i.e. each of its texels covers a scale × scale block.
    #[inline]
    pub fn perceptual(&self, x: usize, y: usize) -> f32 {
        match self {
            Roughness::Constant(a) => a.sqrt() as f32,
            Roughness::Map {
                width,
                scale,
                perceptual,
                ..
            } => perceptual[(y / scale) * width + x / scale],
        }
    }
}

fn open(path: &Path, what: &str) -> Result<image::DynamicImage> {
    let img = crate::filters::footprint::open_image(path, what)?;
    let (w, h) = (img.width() as usize, img.height() as usize);
    if !w.is_power_of_two() || !h.is_power_of_two() {
        return Err(Error::InvalidArgument(format!(
            "{what} {} is {w}×{h}; width and height must be powers of two (≤ {MAX_MAP_SIDE})",
            path.display()
        )));
    }
    Ok(img)
}

fn bits(img: &image::DynamicImage) -> u8 {
    match img.color().bytes_per_pixel() / img.color().channel_count().max(1) {
        1 => 8,
        2 => 16,
        _ => 32,
    }
}

/// Read a tangent-space normal map (RGB or RGBA PNG, 8 or 16 bit; n = 2c − 1; OpenGL
/// +Y as glTF). With `reconstruct_z` the blue channel is ignored and n_z = √(1 − x² − y²)
/// (two-channel maps, BC5-style). Typed errors: unreadable, broken, grey or
/// non-power-of-two file; a texel that decodes to zero or below the surface; more than
/// 1 % of texels off unit length by more than 0.05 (not a normal map).
pub fn normals(path: &Path, reconstruct_z: bool) -> Result<Normals> {
    let img = open(path, "normal map")?;
    if img.color().channel_count() < 3 {
        return Err(Error::InvalidArgument(format!(
            "normal map {} is {:?}; it must be RGB or RGBA",
            path.display(),
            img.color()
        )));
    }
    let b = bits(&img);
    let (w, h) = (img.width() as usize, img.height() as usize);
    // the channel values in [0, 1], read in place (no widened copy of the image)
    let fallback;
    let texel: Box<dyn Fn(usize) -> [f64; 3] + '_> = match &img {
        image::DynamicImage::ImageRgb8(b) => {
            let r = b.as_raw();
            Box::new(move |i| std::array::from_fn(|c| r[3 * i + c] as f64 / 255.0))
        }
        image::DynamicImage::ImageRgba8(b) => {
            let r = b.as_raw();
            Box::new(move |i| std::array::from_fn(|c| r[4 * i + c] as f64 / 255.0))
        }
        image::DynamicImage::ImageRgb16(b) => {
            let r = b.as_raw();
            Box::new(move |i| std::array::from_fn(|c| r[3 * i + c] as f64 / 65535.0))
        }
        image::DynamicImage::ImageRgba16(b) => {
            let r = b.as_raw();
            Box::new(move |i| std::array::from_fn(|c| r[4 * i + c] as f64 / 65535.0))
        }
        other => {
            fallback = other.to_rgb32f();
            let r = fallback.as_raw();
            Box::new(move |i| std::array::from_fn(|c| r[3 * i + c] as f64))
        }
    };
    let mut n = Vec::with_capacity(w * h);
    let mut off_unit = 0usize;
    for i in 0..w * h {
        let p = texel(i);
        let x = 2.0 * p[0] - 1.0;
        let y = 2.0 * p[1] - 1.0;
        let z = if reconstruct_z {
            (1.0 - x * x - y * y).max(0.0).sqrt()
        } else {
            2.0 * p[2] - 1.0
        };
        let len = (x * x + y * y + z * z).sqrt();
        if !(len > 1e-6) || z < 0.0 || (z == 0.0 && !reconstruct_z) {
            return Err(Error::InvalidArgument(format!(
                "normal map {}: texel ({}, {}) decodes to ({x:.3}, {y:.3}, {z:.3}), not an upper-hemisphere normal{}",
                path.display(),
                i % w,
                i / w,
                if reconstruct_z { "" } else { " (a two-channel map needs --reconstruct-z)" }
            )));
        }
        if !reconstruct_z && (len - 1.0).abs() > UNIT_TOLERANCE {
            off_unit += 1;
        }
        n.push([(x / len) as f32, (y / len) as f32, (z / len) as f32]);
    }
    let frac = off_unit as f64 / (w * h) as f64;
    if frac > MAX_OFF_UNIT_FRACTION {
        return Err(Error::InvalidArgument(format!(
            "{} is not a normal map: {:.1} % of its texels decode to vectors whose length is off 1 by more than {UNIT_TOLERANCE} (at most {:.0} % may be; a two-channel map needs --reconstruct-z)",
            path.display(),
            100.0 * frac,
            100.0 * MAX_OFF_UNIT_FRACTION
        )));
    }
    Ok(Normals {
        width: w,
        height: h,
        bits: b,
        n,
    })
}

/// The channel of a roughness map that holds the roughness.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
pub enum Channel {
    /// grey maps: the grey value; RGB(A) maps: green (glTF metallicRoughness).
    Auto,
    R,
    G,
    B,
    A,
}

/// Read a perceptual-roughness map (grey or RGB(A) PNG, 8 or 16 bit) for a normal map
/// of `nw` × `nh`. It may be smaller than the normal map by a power of two along both
/// axes (the same factor): each of its texels then covers that block (nearest). Larger,
/// or another aspect ratio, is a typed error.
pub fn roughness(path: &Path, channel: Channel, nw: usize, nh: usize) -> Result<Roughness> {
    let img = open(path, "roughness map")?;
    let b = bits(&img);
    let (w, h) = (img.width() as usize, img.height() as usize);
    if w > nw || h > nh || nw / w != nh / h || nw % w != 0 || nh % h != 0 {
        return Err(Error::InvalidArgument(format!(
            "roughness map {} is {w}×{h} for a {nw}×{nh} normal map: it must be the same size or smaller by one power of two along both axes",
            path.display()
        )));
    }
    let channels = img.color().channel_count() as usize;
    let k = match (channel, channels) {
        (Channel::Auto, 1 | 2) => 0,
        (Channel::Auto, _) => 1,
        (Channel::R, _) => 0,
        (Channel::G, c) if c >= 3 => 1,
        (Channel::B, c) if c >= 3 => 2,
        (Channel::A, 2) => 1,
        (Channel::A, 4) => 3,
        (c, _) => {
            return Err(Error::InvalidArgument(format!(
                "roughness map {} has {channels} channel(s); it has no channel {c:?}",
                path.display()
            )))
        }
    };
    let data = img.into_rgba32f();
    let others = (channels >= 3).then(|| data.pixels().map(|p| [p[0], p[2]]).collect());
    let perceptual: Vec<f32> = data
        .pixels()
        .map(|p| {
            let v = if channels <= 2 && k == 1 { p[3] } else { p[k] };
            v.clamp(0.0, 1.0)
        })
        .collect();
    Ok(Roughness::Map {
        width: w,
        height: h,
        bits: b,
        scale: nw / w,
        perceptual,
        others,
    })
}

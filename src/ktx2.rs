//! KTX 2.0 containers (Khronos KTX 2.0 specification; data-format descriptors after the
//! Khronos Data Format specification 1.3): uncompressed 2D textures and 2D arrays with
//! any number of mip levels, as engines load them (Bevy, three.js's KTX2Loader, Godot 4.x).
//! Writing only; tests read the files back with the `ktx2` crate.

/// VK_FORMAT_R8_UNORM.
pub const R8_UNORM: u32 = 9;
/// VK_FORMAT_R8G8B8A8_UNORM.
pub const R8G8B8A8_UNORM: u32 = 37;
/// VK_FORMAT_R16_UNORM.
pub const R16_UNORM: u32 = 70;
/// VK_FORMAT_R16_SFLOAT.
pub const R16_SFLOAT: u32 = 76;
/// VK_FORMAT_R16G16B16A16_SFLOAT.
pub const R16G16B16A16_SFLOAT: u32 = 97;

/// One sample of a basic data-format descriptor: which bits hold which channel.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub bit_offset: u16,
    pub bit_length: u8,
    /// Channel id (RGBSDA model: 0 R, 1 G, 2 B, 15 A).
    pub channel: u8,
    /// Unsigned normalised (false) or IEEE float, signed (true).
    pub float: bool,
}

impl Sample {
    fn bounds(&self) -> (u32, u32) {
        if self.float {
            ((-1.0f32).to_bits(), 1.0f32.to_bits())
        } else {
            let max = if self.bit_length >= 32 {
                u32::MAX
            } else {
                (1u32 << self.bit_length) - 1
            };
            (0, max)
        }
    }
}

pub fn u32le(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn u64le(out: &mut Vec<u8>, v: u64) {
    out.extend_from_slice(&v.to_le_bytes());
}

/// The basic data-format descriptor of an uncompressed format: RGBSDA colour model,
/// BT.709 primaries, linear transfer (the data are not colours), straight alpha, 1×1
/// texel blocks of `bytes` bytes.
pub fn dfd_basic(bytes: u8, samples: &[Sample]) -> Vec<u8> {
    let mut b = Vec::new();
    let block_size = 24 + 16 * samples.len() as u32;
    u32le(&mut b, 4 + block_size); // dfdTotalSize
    u32le(&mut b, 0); // vendorId 0 (Khronos), descriptorType 0 (basic)
    b.extend_from_slice(&2u16.to_le_bytes()); // versionNumber (1.3)
    b.extend_from_slice(&(block_size as u16).to_le_bytes());
    b.extend_from_slice(&[1, 1, 1, 0]); // RGBSDA, BT709, LINEAR, straight alpha
    b.extend_from_slice(&[0, 0, 0, 0]); // texel block 1×1×1×1
    b.extend_from_slice(&[bytes, 0, 0, 0, 0, 0, 0, 0]); // bytesPlane0
    for s in samples {
        let (lo, hi) = s.bounds();
        b.extend_from_slice(&s.bit_offset.to_le_bytes());
        b.push(s.bit_length - 1);
        b.push(s.channel | if s.float { 0x80 | 0x40 } else { 0 });
        b.extend_from_slice(&[0, 0, 0, 0]); // samplePosition
        u32le(&mut b, lo); // sampleLower
        u32le(&mut b, hi); // sampleUpper
    }
    b
}

/// An uncompressed texture to write.
pub struct Texture {
    pub vk_format: u32,
    /// Bytes per component (typeSize: 1 for 8-bit, 2 for 16-bit formats).
    pub type_size: u32,
    /// Bytes per texel (the alignment of every level is lcm(texel_bytes, 4)).
    pub texel_bytes: u32,
    pub width: u32,
    pub height: u32,
    /// Array layers; 0 for a plain 2D texture.
    pub layers: u32,
    /// Level 0 first; each level holds every layer, layer after layer.
    pub levels: Vec<Vec<u8>>,
    pub dfd: Vec<u8>,
    /// Key/value data in the order written (KTXorientation, KTXwriter, …).
    pub key_values: Vec<(String, String)>,
}

fn kv(out: &mut Vec<u8>, key: &str, value: &str) {
    let len = key.len() + 1 + value.len() + 1;
    u32le(out, len as u32);
    out.extend_from_slice(key.as_bytes());
    out.push(0);
    out.extend_from_slice(value.as_bytes());
    out.push(0);
    while out.len() % 4 != 0 {
        out.push(0);
    }
}

fn lcm4(texel: u64) -> u64 {
    let g = |mut a: u64, mut b: u64| {
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    };
    texel.max(1) * 4 / g(texel.max(1), 4)
}

/// The KTX2 file with every level zstd-supercompressed (supercompressionScheme 2) at
/// `level`, as Khronos's `ktx create --zstd N` writes it (Bevy's embedded `ltc.ktx2`): the
/// descriptor unchanged (bytesPlane0 the texel size, as in Bevy's file), levels aligned
/// to 1 byte, each level index entry
/// holds the compressed and the uncompressed length, and `KTXwriterScParams` says
/// `--zstd N`.
pub fn write_zstd(t: &Texture, level: i32) -> std::io::Result<Vec<u8>> {
    let levels = t
        .levels
        .iter()
        .map(|l| zstd::bulk::compress(l, level))
        .collect::<std::io::Result<Vec<_>>>()?;
    let mut key_values = t.key_values.clone();
    key_values.push(("KTXwriterScParams".into(), format!("--zstd {level}")));
    Ok(layout(
        t,
        &t.dfd,
        &key_values,
        &levels,
        &t.levels.iter().map(Vec::len).collect::<Vec<_>>(),
        2,
    ))
}

/// The KTX2 file. Level data follow the descriptors from the smallest level to level 0
/// (the order the specification prescribes), each aligned to lcm(texel size, 4).
pub fn write(t: &Texture) -> Vec<u8> {
    let raw: Vec<usize> = t.levels.iter().map(Vec::len).collect();
    layout(t, &t.dfd, &t.key_values, &t.levels, &raw, 0)
}

/// Header, level index, descriptor, key/value data and levels; `levels` as stored
/// (`raw`: their uncompressed lengths), `scheme` the supercompression scheme (levels are
/// aligned to lcm(texel size, 4) without one, to 1 byte with one).
fn layout(
    t: &Texture,
    dfd: &[u8],
    key_values: &[(String, String)],
    levels: &[Vec<u8>],
    raw: &[usize],
    scheme: u32,
) -> Vec<u8> {
    let n = levels.len() as u64;
    let mut kvd = Vec::new();
    for (k, v) in key_values {
        kv(&mut kvd, k, v);
    }
    let index_end = 80 + 24 * n;
    let dfd_off = index_end;
    let kvd_off = dfd_off + dfd.len() as u64;
    let align = if scheme == 0 {
        lcm4(t.texel_bytes as u64)
    } else {
        1
    };
    // offsets: smallest level first
    let mut offsets = vec![0u64; levels.len()];
    let mut at = kvd_off + kvd.len() as u64;
    for l in (0..levels.len()).rev() {
        at = at.div_ceil(align) * align;
        offsets[l] = at;
        at += levels[l].len() as u64;
    }
    let mut out = Vec::with_capacity(at as usize);
    out.extend_from_slice(&[
        0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
    ]);
    for v in [
        t.vk_format,
        t.type_size,
        t.width,
        t.height,
        0,
        t.layers,
        1,
        n as u32,
        scheme,
    ] {
        u32le(&mut out, v); // format, typeSize, w, h, depth, layers, faces, levels, scheme
    }
    u32le(&mut out, dfd_off as u32);
    u32le(&mut out, dfd.len() as u32);
    u32le(&mut out, kvd_off as u32);
    u32le(&mut out, kvd.len() as u32);
    u64le(&mut out, 0); // no supercompression global data
    u64le(&mut out, 0);
    for (l, level) in levels.iter().enumerate() {
        u64le(&mut out, offsets[l]);
        u64le(&mut out, level.len() as u64);
        u64le(&mut out, raw[l] as u64);
    }
    out.extend_from_slice(dfd);
    out.extend(kvd);
    for l in (0..levels.len()).rev() {
        out.resize(offsets[l] as usize, 0);
        out.extend_from_slice(&levels[l]);
    }
    out
}

/// An uncompressed texture whose texels are `channels` (RGBSDA ids: 0 R, 1 G, 2 B,
/// 15 A) of `component_bytes` each, unsigned normalised or (`float`) IEEE float, with
/// its data-format descriptor; `levels` level 0 first, each holding every layer.
#[allow(clippy::too_many_arguments)]
pub fn uncompressed(
    vk_format: u32,
    channels: &[u8],
    component_bytes: u32,
    float: bool,
    (width, height, layers): (u32, u32, u32),
    levels: Vec<Vec<u8>>,
    key_values: Vec<(String, String)>,
) -> Texture {
    let samples: Vec<Sample> = channels
        .iter()
        .enumerate()
        .map(|(k, &channel)| Sample {
            bit_offset: (8 * component_bytes as usize * k) as u16,
            bit_length: 8 * component_bytes as u8,
            channel,
            float,
        })
        .collect();
    let texel = component_bytes * channels.len() as u32;
    Texture {
        vk_format,
        type_size: component_bytes,
        texel_bytes: texel,
        width,
        height,
        layers,
        levels,
        dfd: dfd_basic(texel as u8, &samples),
        key_values,
    }
}

/// The RGBA channel ids.
pub const RGBA: [u8; 4] = [0, 1, 2, 15];

//! The prefilter tool's files: the roughness chain as one KTX2 (every level; R8, R16 or
//! R16F) and one grey PNG per level, the normal map's mips as one KTX2 (RGBA8 or RGBA16)
//! and one PNG per level, and a report (markdown + JSON) with the rule's measured error.
//! Rendered to bytes here; the caller publishes them as one set.

use super::{eligible, Choice, Format, Layout, NormalMips, Outcome, Store};
use crate::error::{Error, Result};
use crate::ktx2;

/// VK_FORMAT_R16G16B16A16_UNORM.
const R16G16B16A16_UNORM: u32 = 91;

fn png(img: image::DynamicImage, name: &str) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .map_err(|e| Error::Io {
        path: name.into(),
        msg: e.to_string(),
    })?;
    Ok(bytes)
}

/// The key/value data of every file: orientation, writer and, where given, what the
/// roughness texels mean.
fn key_values(writer: &str, meaning: Option<String>) -> Vec<(String, String)> {
    let mut kv = vec![
        ("KTXorientation".into(), "rd".into()),
        ("KTXwriter".into(), writer.into()),
    ];
    if let Some(m) = meaning {
        kv.push(("ndfbench.roughness".into(), m));
    }
    kv
}

fn q8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn q16(v: f32) -> u16 {
    (v.clamp(0.0, 1.0) * 65535.0).round() as u16
}

/// The glTF-layout chain (R occlusion, G roughness, B metallic, A 1): KTX2 and one
/// RGBA PNG per level.
fn gltf_files(o: &Outcome, writer: &str) -> Result<Vec<(String, Vec<u8>)>> {
    let mut out = Vec::new();
    let mut levels = Vec::new();
    for (l, (lv, vals)) in o.levels.iter().zip(&o.stored).enumerate() {
        let (w, h) = (lv.width as u32, lv.height as u32);
        let texels: Vec<[f32; 4]> = (0..vals.len())
            .map(|k| {
                let [occ, metal] = o.others_at(l, k);
                [occ, vals[k], metal, 1.0]
            })
            .collect();
        let name = format!("metallic_roughness-L{l}.png");
        let (bytes, img) = match o.options.format {
            Format::R8 => {
                let px: Vec<u8> = texels.iter().flat_map(|t| t.map(q8)).collect();
                let img = image::RgbaImage::from_raw(w, h, px.clone()).expect("size");
                (px, image::DynamicImage::ImageRgba8(img))
            }
            f => {
                let px: Vec<u16> = texels.iter().flat_map(|t| t.map(q16)).collect();
                let bytes: Vec<u8> = if f == Format::R16 {
                    px.iter().flat_map(|v| v.to_le_bytes()).collect()
                } else {
                    texels
                        .iter()
                        .flat_map(|t| t.map(|v| half::f16::from_f32(v).to_bits()))
                        .flat_map(|v| v.to_le_bytes())
                        .collect()
                };
                let img =
                    image::ImageBuffer::<image::Rgba<u16>, _>::from_raw(w, h, px).expect("size");
                (bytes, image::DynamicImage::ImageRgba16(img))
            }
        };
        out.push((name.clone(), png(img, &name)?));
        levels.push(bytes);
    }
    let (vk, size, float) = match o.options.format {
        Format::R8 => (ktx2::R8G8B8A8_UNORM, 1u32, false),
        Format::R16 => (R16G16B16A16_UNORM, 2, false),
        Format::R16f => (ktx2::R16G16B16A16_SFLOAT, 2, true),
    };
    let texture = ktx2::uncompressed(
        vk,
        &ktx2::RGBA,
        size,
        float,
        (o.width as u32, o.height as u32, 0),
        levels,
        key_values(
            writer,
            Some(format!(
                "G: {}; R occlusion, B metallic (box mips)",
                stored_meaning(o)
            )),
        ),
    );
    out.insert(0, ("metallic_roughness.ktx2".into(), ktx2::write(&texture)));
    Ok(out)
}

/// The roughness chain: KTX2 bytes and one PNG per level.
fn roughness_files(o: &Outcome, writer: &str) -> Result<Vec<(String, Vec<u8>)>> {
    let mut out = Vec::new();
    let mut levels = Vec::new();
    for (l, (lv, vals)) in o.levels.iter().zip(&o.stored).enumerate() {
        let (w, h) = (lv.width as u32, lv.height as u32);
        let bytes: Vec<u8> = match o.options.format {
            Format::R8 => vals.iter().map(|&v| q8(v)).collect(),
            Format::R16 => vals.iter().flat_map(|&v| q16(v).to_le_bytes()).collect(),
            Format::R16f => vals
                .iter()
                .flat_map(|&v| half::f16::from_f32(v).to_bits().to_le_bytes())
                .collect(),
        };
        let name = format!("roughness-L{l}.png");
        let img = match o.options.format {
            Format::R8 => image::DynamicImage::ImageLuma8(
                image::GrayImage::from_raw(w, h, bytes.clone()).expect("size"),
            ),
            _ => image::DynamicImage::ImageLuma16(
                image::ImageBuffer::from_raw(w, h, vals.iter().map(|&v| q16(v)).collect())
                    .expect("size"),
            ),
        };
        out.push((name.clone(), png(img, &name)?));
        levels.push(bytes);
    }
    let (vk, size, float) = match o.options.format {
        Format::R8 => (ktx2::R8_UNORM, 1, false),
        Format::R16 => (ktx2::R16_UNORM, 2, false),
        Format::R16f => (ktx2::R16_SFLOAT, 2, true),
    };
    let texture = ktx2::uncompressed(
        vk,
        &[0],
        size,
        float,
        (o.width as u32, o.height as u32, 0),
        levels,
        key_values(writer, Some(stored_meaning(o))),
    );
    out.insert(0, ("roughness.ktx2".into(), ktx2::write(&texture)));
    Ok(out)
}

fn stored_meaning(o: &Outcome) -> String {
    format!(
        "{} after the {} rule: {}",
        match o.options.store {
            Store::Perceptual => "perceptual roughness p = sqrt(alpha)",
            Store::Alpha => "alpha",
        },
        o.filter.key(),
        o.label(o.filter)
    )
}

/// The normal mips: KTX2 and one PNG per level, (n + 1)/2 per channel.
fn normal_files(o: &Outcome, writer: &str) -> Result<Vec<(String, Vec<u8>)>> {
    let wide = o.input_bits > 8;
    let mut out = Vec::new();
    let mut levels = Vec::new();
    for (l, lv) in o.levels.iter().enumerate() {
        let enc: Vec<[f32; 3]> = lv
            .mean_n
            .iter()
            .map(|m| {
                let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
                let s = match o.options.normals {
                    NormalMips::Renormalised if len > 0.0 => 1.0 / len,
                    _ => 1.0,
                };
                [
                    0.5 + 0.5 * m[0] * s,
                    0.5 + 0.5 * m[1] * s,
                    0.5 + 0.5 * m[2] * s,
                ]
            })
            .collect();
        let (w, h) = (lv.width as u32, lv.height as u32);
        let name = format!("normal-L{l}.png");
        if wide {
            let px: Vec<u16> = enc.iter().flat_map(|c| c.map(q16)).collect();
            levels.push(
                enc.iter()
                    .flat_map(|c| [q16(c[0]), q16(c[1]), q16(c[2]), u16::MAX])
                    .flat_map(|v| v.to_le_bytes())
                    .collect(),
            );
            let img = image::ImageBuffer::<image::Rgb<u16>, _>::from_raw(w, h, px).expect("size");
            out.push((
                name.clone(),
                png(image::DynamicImage::ImageRgb16(img), &name)?,
            ));
        } else {
            let px: Vec<u8> = enc.iter().flat_map(|c| c.map(q8)).collect();
            levels.push(
                enc.iter()
                    .flat_map(|c| [q8(c[0]), q8(c[1]), q8(c[2]), u8::MAX])
                    .collect(),
            );
            let img = image::RgbImage::from_raw(w, h, px).expect("size");
            out.push((
                name.clone(),
                png(image::DynamicImage::ImageRgb8(img), &name)?,
            ));
        }
    }
    let size = if wide { 2u32 } else { 1 };
    let vk = if wide {
        R16G16B16A16_UNORM
    } else {
        ktx2::R8G8B8A8_UNORM
    };
    let texture = ktx2::uncompressed(
        vk,
        &ktx2::RGBA,
        size,
        false,
        (o.width as u32, o.height as u32, 0),
        levels,
        key_values(writer, None),
    );
    out.insert(0, ("normal.ktx2".into(), ktx2::write(&texture)));
    Ok(out)
}

/// The report (markdown) and its typed twin (JSON).
fn report(o: &Outcome, files: &[String], command: &str) -> (String, String) {
    let chosen = o.evidence.measured.iter().find(|m| m.filter == o.filter);
    let error = chosen.map_or(
        "not measured here: results/fits/filters.json is absent or lacks this rule (run `cargo run --release -- regen --only filters`)".to_string(),
        |m| format!("mean lobe L2 error {} ({})", m.l2.pct(1), m.what),
    );
    let mut md = format!(
        "# Roughness mips of {}\n\nWritten by `{command}`.\n\n- Normal map: {}×{}, {}-bit{}; {} levels (to 1×1).\n- Base roughness: {}.\n- Rule: **{}** — {}.\n- Its measured error: {error}.{}\n- Stored: {}{}; α′ > 1 is clamped to 1 (texels clamped per level: {:?}).\n- Normal mips: {}.\n\n",
        o.options.input.display(),
        o.width,
        o.height,
        o.input_bits,
        if o.options.reconstruct_z { ", z reconstructed from x and y" } else { "" },
        o.levels.len(),
        match (o.roughness_size, o.options.alpha) {
            (Some((w, h, b)), _) => format!(
                "{} ({w}×{h}, {b}-bit, channel {:?}; perceptual roughness, α = value²){}",
                o.options.roughness.as_ref().map_or(String::new(), |p| p.display().to_string()),
                o.options.channel,
                if w < o.width {
                    format!(" — smaller than the normal map: each of its texels covers a {0}×{0} block of normal texels (nearest), and the chain is written at the normal map's size", o.width / w)
                } else {
                    String::new()
                }
            ),
            (None, Some(a)) => format!("constant α = {a}"),
            _ => "—".into(),
        },
        o.filter.key(),
        o.label(o.filter),
        if o.options.filter == Choice::Best {
            " Chosen as the measured rule with the smallest mean error (below)."
        } else {
            ""
        },
        match o.options.store {
            Store::Perceptual => "perceptual roughness p′ = √α′ (glTF, Bevy, three.js, Godot, Filament)",
            Store::Alpha => "α′ itself",
        },
        match (o.options.layout, &o.others) {
            (Layout::R, _) => ", one channel".to_string(),
            (Layout::Gltf, Some(_)) => ", in G of a glTF metallicRoughness texture (R occlusion and B metallic box-filtered from the input's R and B)".to_string(),
            (Layout::Gltf, None) => ", in G of a glTF metallicRoughness texture (R = 1, B = metallic 0: the input had no R/B channels)".to_string(),
        },
        o.clamped,
        match o.options.normals {
            NormalMips::Renormalised => "renormalised mean normals (the variance is in the roughness mips; do not also apply Toksvig at run time)",
            NormalMips::Raw => "the mean normal as it is (‖μ‖ < 1 where the footprint varies), (n + 1)/2 per channel",
        },
    );
    md.push_str("## Every rule's measured error (results/filters.md)\n\n");
    let mut t = crate::report::table::Table::new(["rule", "formula", "mean lobe L2", "cases"]);
    for f in eligible() {
        let m = o.evidence.measured.iter().find(|m| m.filter == f);
        t.row([
            format!("{}{}", f.key(), if f == o.filter { " (used)" } else { "" }),
            o.label(f).to_string(),
            m.map_or("not measured".into(), |m| m.l2.pct(1)),
            m.map_or("—".into(), |m| m.what.clone()),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\nEach level is the equal-weight 2×2 average of the one above (O(N) for the whole chain; Filament's tool re-reads the base level for every mip, O(N log N)). Files: {}.\n",
        files.join(", ")
    ));
    let json = serde_json::json!({
        "command": command,
        "input": o.options.input.display().to_string(),
        "width": o.width,
        "height": o.height,
        "input_bits": o.input_bits,
        "roughness": o.options.roughness.as_ref().map(|p| p.display().to_string()),
        "alpha": o.options.alpha,
        "filter": o.filter.key(),
        "formula": o.label(o.filter),
        "measured": o.evidence.measured,
        "store": o.options.store,
        "format": o.options.format,
        "layout": o.options.layout,
        "normals": o.options.normals,
        "levels": o.levels.iter().map(|l| [l.width, l.height]).collect::<Vec<_>>(),
        "clamped": o.clamped,
        "files": files,
    });
    (md, serde_json::to_string_pretty(&json).expect("json"))
}

/// Every file of the output set: (name, bytes).
pub fn render(o: &Outcome, command: &str) -> Result<Vec<(String, Vec<u8>)>> {
    let writer = format!("ndfbench {} prefilter", env!("CARGO_PKG_VERSION"));
    let mut files = match o.options.layout {
        Layout::R => roughness_files(o, &writer)?,
        Layout::Gltf => gltf_files(o, &writer)?,
    };
    files.extend(normal_files(o, &writer)?);
    let names: Vec<String> = files.iter().map(|f| f.0.clone()).collect();
    let (md, json) = report(o, &names, command);
    files.push(("prefilter.md".into(), md.into_bytes()));
    files.push(("prefilter.json".into(), json.into_bytes()));
    Ok(files)
}

//! `prefilter --input`: the footprint map study on a user's normal map.

use super::cases::map_study;
use super::report::{map_section, map_svg};
use crate::error::Result;
use crate::filters::footprint::{MipChain, NormalMap};
use crate::filters::rules;
use crate::integrate::Preset;
use std::path::Path;

/// `prefilter`: the map study on a user's normal map (PNG), at base roughness `alpha`.
/// Writes DIR/prefilter-<name>.md/.json, the L2-vs-footprint plot, and for every mip
/// level ≥ 1 the vMF (c = 2) filtered α′ as an 8-bit grey PNG (α′ = value/255).
pub fn prefilter(
    set: &mut crate::io::Outputs,
    input: &Path,
    out: &Path,
    alpha: f64,
    preset: Preset,
) -> Result<String> {
    if !(alpha.is_finite() && alpha > 0.0) {
        return Err(crate::error::Error::InvalidRoughness(alpha));
    }
    let map = NormalMap::from_png(input)?;
    let chain = MipChain::build(&map);
    let mut plan = super::plan::builtin(preset)?;
    let top = chain.levels.len() - 1;
    plan.levels.retain(|&l| l >= 1 && l <= top);
    if plan.levels.is_empty() {
        plan.levels = vec![1];
    }
    plan.alphas = vec![alpha];
    let cases = map_study(std::slice::from_ref(&map), &plan, 0x5EED)?;
    let mut md = format!(
        "# Footprint filters on {}\n\nWritten by `cargo run --release -- prefilter --input {} --alpha {alpha}` (preset {}). {}×{} texels, base α {alpha}, levels {:?}, {} footprints per level, views (θ, φ) {:?}°, {} light samples per case. Method and metrics as in results/filters.md; every number is a mean over cases ± its standard error.\n\n",
        map.name,
        input.display(),
        preset.name(),
        map.width,
        map.height,
        plan.levels,
        plan.footprints_per_level,
        plan.views_deg,
        plan.samples
    );
    let section = super::compute::map_section(0, &map, &cases, &plan);
    let rows = map_section(&mut md, &section, &plan);
    set.put(
        &out.join(format!("filters-{}.svg", section.name)),
        map_svg(&section)?.as_bytes(),
    );
    let mut written = Vec::new();
    for (l, lv) in chain.levels.iter().enumerate().skip(1) {
        let mut img = image::GrayImage::new(lv.width as u32, lv.height as u32);
        for (k, s) in lv.stats.iter().enumerate() {
            let a = rules::vmf(alpha, s.mrl().min(1.0), 2.0).min(1.0);
            img.put_pixel(
                (k % lv.width) as u32,
                (k / lv.width) as u32,
                image::Luma([(a * 255.0).round() as u8]),
            );
        }
        let mut bytes = Vec::new();
        img.write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(|e| crate::error::Error::Io {
            path: out.display().to_string(),
            msg: e.to_string(),
        })?;
        let p = out.join(format!("{}-alpha-L{l}.png", map.name));
        set.put(&p, &bytes);
        written.push(p.display().to_string());
    }
    md.push_str(&format!(
        "\nFiltered α′ per level (vMF α′² = α² + 2/κ, the closest shipped variant in results/filters.md), 8-bit: {}.\n",
        written.join(", ")
    ));
    let mdp = out.join(format!("prefilter-{}.md", map.name));
    set.put(&mdp, md.as_bytes());
    let json = serde_json::json!({"input": input.display().to_string(), "alpha": alpha, "plan": plan, "filters": rows});
    set.put(
        &out.join(format!("prefilter-{}.json", map.name)),
        serde_json::to_string_pretty(&json)
            .expect("json")
            .as_bytes(),
    );
    Ok(format!(
        "wrote {} ({} cases) and {} α′ maps",
        mdp.display(),
        cases.len(),
        written.len()
    ))
}

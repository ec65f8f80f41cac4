//! `horizon --input HEIGHT.png`: the horizon-map study of results/visibility.md on
//! a user's height map.

use super::compute::horizon_cases;
use super::report;
use crate::error::Result;
use crate::integrate::Preset;
use crate::visibility::HeightField;

/// `horizon --input HEIGHT.png --scale S --out DIR`: the horizon study of
/// results/visibility.md on a user's height map (heights = grey value × S texels).
/// Writes DIR/horizon.md and DIR/horizon.json; returns their paths, and first the note
/// that an RGB map was converted to grey, where it was.
pub fn horizon_file(
    set: &mut crate::io::Outputs,
    input: &std::path::Path,
    scale: f64,
    out: &std::path::Path,
    preset: Preset,
) -> Result<Vec<String>> {
    let (hf, note) = HeightField::read_png(input, scale)?;
    let mut plan = super::compute::builtin_plan(preset)?;
    let max_level = hf.size.trailing_zeros() as usize;
    plan.levels.retain(|&l| l < max_level);
    let cases = horizon_cases(std::slice::from_ref(&hf), &plan, 19)?;
    let h = super::summary::horizon_summary(&cases);
    let md = format!(
        "# Horizon-map pre-filtering on {}\n\nWritten by `cargo run --release -- horizon --input {} --scale {scale}` (preset {}): \
{} cases, footprints of 2^L texels, L = {:?}, {} per level; the methods and the truth of results/visibility.md.{}\n\n{}",
        input.display(),
        input.display(),
        preset.name(),
        cases.len(),
        plan.levels,
        plan.footprints,
        note.as_ref().map(|n| format!(" The {n}.")).unwrap_or_default(),
        report::horizon_markdown(&h)
    );
    let (mp, jp) = (out.join("horizon.md"), out.join("horizon.json"));
    set.put(&mp, md.as_bytes());
    set.put(
        &jp,
        serde_json::to_string_pretty(
            &serde_json::json!({"single": h.1, "joint": h.2, "hotspot": h.3}),
        )
        .unwrap_or_default()
        .as_bytes(),
    );
    let mut said: Vec<String> = note.into_iter().collect();
    said.extend([mp.display().to_string(), jp.display().to_string()]);
    Ok(said)
}

//! Godot 4 in the engine check, in f64 only (no Godot binary runs here): its formulas
//! (`crate::engines::godot`) with our Godot files against the truth, at the pixel points
//! of an engine that did render.

use super::compute::{errors, EngineResult, GodotScene};
use crate::engines::EngineScenes;
use crate::engines::Rect;
use crate::error::{Error, Result};
use crate::integrate::{Figure, Quad};

/// Godot 4 in f64 with our files (lut1, lut2 texels as f64) at the pixel points of an
/// engine already judged, against the truth computed there (reused, not integrated again):
/// per scene, its formulas and its texels' exact value.
pub fn godot(
    s: &EngineScenes,
    judged: &EngineResult,
    l1: &[[f64; 4]],
    l2: &[[f64; 4]],
) -> Result<Vec<GodotScene>> {
    use crate::engines::godot::{godot_exact, godot_value, lookup as godot_lookup};
    let mut out = Vec::new();
    for (sc, done) in s.scenes.iter().zip(&judged.scenes) {
        let light = Rect::of(&sc.light).ok_or_else(|| {
            Error::InvalidArgument(format!("engines: scene {}: degenerate light", sc.name))
        })?;
        let truth: Vec<Figure<Quad>> = done.truth.iter().map(|(_, b)| *b).collect();
        let g = godot_lookup(l1, l2, sc.roughness, sc.view_deg.to_radians().cos());
        let fv: Vec<f64> = done
            .truth
            .iter()
            .map(|(x, _)| godot_value(&g, &light, x))
            .collect();
        let ev: Vec<f64> = done
            .truth
            .iter()
            .map(|(x, _)| godot_exact(&g, &light, x))
            .collect();
        out.push(GodotScene {
            name: sc.name.clone(),
            formulas: errors(&fv, &truth),
            table_share: errors(&ev, &truth),
        });
    }
    Ok(out)
}

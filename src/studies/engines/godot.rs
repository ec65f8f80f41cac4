//! Godot 4 in the engine check, in f64 only (no Godot binary runs here): its formulas
//! (`crate::engines::godot`) with our Godot files against the truth, at the pixel points
//! of an engine that did render.

use super::{errors, lobe, truth_value, Engine, EngineRun, Errors, Rect, TRUTH_REL};
use crate::engines::EngineScenes;
use crate::error::{Error, Result};
use crate::ltc::lobe_error::Bounded;
use nalgebra::Vector3;
use serde::Serialize;

/// Godot 4 on one scene, in f64 only (no Godot binary here): its formulas with our
/// files (results/textures/godot/) against the truth, and the same texels with the exact
/// edge integral (the table's share).
#[derive(Clone, Debug, Serialize)]
pub struct GodotScene {
    pub name: String,
    /// Godot's lookup and `ltc_evaluate_specular` (Hill's edge fit) against the truth.
    pub formulas: Errors,
    /// Godot's lookup with the exact edge integral against the truth.
    pub table_share: Errors,
}

/// Godot 4 in f64 with our files (lut1, lut2 texels as f64) at the points of `run`'s
/// first path: per scene, its formulas and its texels' exact value against the truth.
pub fn godot(
    s: &EngineScenes,
    run: &EngineRun,
    engine: Engine,
    l1: &[[f64; 4]],
    l2: &[[f64; 4]],
) -> Result<Vec<GodotScene>> {
    use crate::engines::godot::{godot_exact, godot_value, lookup as godot_lookup};
    let mut out = Vec::new();
    for (k, sc) in s.scenes.iter().enumerate() {
        let light = Rect::of(&sc.light).ok_or_else(|| {
            Error::InvalidArgument(format!("engines: scene {}: degenerate light", sc.name))
        })?;
        let t = lobe(sc.roughness, sc.view_deg)?;
        let pos = &run.paths[engine.paths()[0]][k].positions;
        let pts: Vec<Vector3<f64>> = (0..s.width * s.height)
            .filter(|&p| pos[4 * p + 3] > 0.5)
            .map(|p| Vector3::new(pos[4 * p], pos[4 * p + 1], pos[4 * p + 2]))
            .collect();
        // the same points and label as that engine's truth: the memo shares it
        let truth: Vec<Bounded> = crate::memo::map_items(
            &format!("engine truth {} {}", engine.name(), sc.name),
            &pts,
            |x| Ok(truth_value(&t, &light, x, TRUTH_REL)),
        )?;
        let g = godot_lookup(l1, l2, sc.roughness, sc.view_deg.to_radians().cos());
        let fv: Vec<f64> = pts.iter().map(|x| godot_value(&g, &light, x)).collect();
        let ev: Vec<f64> = pts.iter().map(|x| godot_exact(&g, &light, x)).collect();
        out.push(GodotScene {
            name: sc.name.clone(),
            formulas: errors(&fv, &truth),
            table_share: errors(&ev, &truth),
        });
    }
    Ok(out)
}

//! The engine-check scenes (engines/three/scenes.json), read strictly: every number
//! finite and bounded, every size bounded, a typed one-line error otherwise.

use crate::error::{Error, Result};
use nalgebra::Vector3;
use serde::Deserialize;

type V3 = Vector3<f64>;

/// A rectangular light: centre, the point it faces, the up vector of its frame, size.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightSpec {
    pub center: [f64; 3],
    pub look_at: [f64; 3],
    pub up: [f64; 3],
    pub width: f64,
    pub height: f64,
}

/// One scene: the plane's perceptual roughness, the view angle from the normal, the light.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    pub roughness: f64,
    pub view_deg: f64,
    pub light: LightSpec,
}

/// The whole file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EngineScenes {
    #[serde(default)]
    pub comment: String,
    pub width: usize,
    pub height: usize,
    pub plane_half: f64,
    pub scenes: Vec<Scene>,
}

/// Where the scenes live, relative to the repository root.
pub const PATH: &str = "engines/three/scenes.json";

impl EngineScenes {
    /// Parse and validate.
    pub fn parse(text: &str) -> Result<EngineScenes> {
        let bad = |m: String| Error::InvalidArgument(format!("{PATH}: {m}"));
        let s: EngineScenes = serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
        if !(1..=512).contains(&s.width) || !(1..=512).contains(&s.height) {
            return Err(bad(format!(
                "image {}×{} outside 1 … 512 a side",
                s.width, s.height
            )));
        }
        if !(s.plane_half.is_finite() && s.plane_half > 0.0 && s.plane_half <= 1e3) {
            return Err(bad("plane_half must be in (0, 1000]".into()));
        }
        if s.scenes.is_empty() || s.scenes.len() > 256 {
            return Err(bad("1 to 256 scenes".into()));
        }
        for sc in &s.scenes {
            let name = crate::error::quoted(&sc.name);
            if !(sc.roughness.is_finite() && (0.0..=1.0).contains(&sc.roughness)) {
                return Err(bad(format!("scene {name}: roughness must be in [0, 1]")));
            }
            if !(sc.view_deg.is_finite() && (0.5..=89.0).contains(&sc.view_deg)) {
                return Err(bad(format!(
                    "scene {name}: view_deg must be in [0.5, 89] (at 0 the engines' T1 = normalize(V − N(V·N)) is undefined)"
                )));
            }
            let l = &sc.light;
            let finite = l
                .center
                .iter()
                .chain(&l.look_at)
                .chain(&l.up)
                .all(|x| x.is_finite() && x.abs() <= 1e3);
            if !finite || !(l.width > 0.0 && l.width <= 1e3 && l.height > 0.0 && l.height <= 1e3) {
                return Err(bad(format!(
                    "scene {name}: the light needs finite coordinates (|x| ≤ 1000) and a positive size"
                )));
            }
            if Rect::of(l).is_none() {
                return Err(bad(format!(
                    "scene {name}: the light's look_at equals its centre or its up vector is parallel to its direction"
                )));
            }
        }
        Ok(s)
    }

    /// Read the file.
    pub fn read(path: &std::path::Path) -> Result<EngineScenes> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
            path: path.display().to_string(),
            msg: e.to_string(),
        })?;
        Self::parse(&text)
    }
}

/// A rectangular light in world space, as three.js builds it: corners c ± hw ± hh, and
/// the unit normal of its lit side.
#[derive(Clone, Copy, Debug)]
pub struct Rect {
    pub c: V3,
    pub hw: V3,
    pub hh: V3,
    pub front: V3,
}

impl Rect {
    /// The light of a scene: `lookAt` makes local z = normalize(centre − target), x =
    /// normalize(up × z), y = z × x; it shines along −z. `None` if degenerate.
    pub fn of(l: &LightSpec) -> Option<Rect> {
        let c = V3::from(l.center);
        let z = c - V3::from(l.look_at);
        let z = z.try_normalize(1e-12)?;
        let x = V3::from(l.up).cross(&z).try_normalize(1e-12)?;
        let y = z.cross(&x);
        Some(Rect {
            c,
            hw: x * (0.5 * l.width),
            hh: y * (0.5 * l.height),
            front: -z,
        })
    }
    /// The corners in three.js's order (counter-clockwise seen from the lit side).
    pub fn corners(&self) -> [V3; 4] {
        [
            self.c + self.hw - self.hh,
            self.c - self.hw - self.hh,
            self.c - self.hw + self.hh,
            self.c + self.hw + self.hh,
        ]
    }
    /// Whether `x` is on the lit side.
    pub fn lights(&self, x: &V3) -> bool {
        (x - self.c).dot(&self.front) > 0.0
    }
}

//! Engine checks: what an engine renders with an LTC table, against the truth.
//!
//! The scenes (`engines/three/scenes.json`, read here and by the three.js harness): a
//! metallic white GGX plane z = 0 (F0 = 1, so Schlick's Fresnel is 1 and diffuse is 0)
//! under one rectangular light of unit radiance, seen by an orthographic camera from
//! v = (sin θ, 0, cos θ). For each pixel the engine's harness reports its radiance and its
//! world position; here
//!
//! - the truth is L·∫_P f(l) dω with f = D·G2/(4 v_z) (height-correlated Smith G2), the
//!   exact GGX lobe, integrated over the light's rectangle in its own (u, v) parameters by
//!   adaptive cubature (`integrate::cubature`) with a break where the rectangle crosses
//!   the horizon — deterministic, ± its error bar;
//! - the table's own value is norm·∫_P γ_M with M⁻¹ and norm looked up from the table the
//!   engine's path holds (bilinear at uv = (r, √(1 − v_z))·63/64 + 0.5/64) and the exact
//!   edge integral with the polygon clipped in the LTC's space (`ltc::polygon`);
//! - the engine's error splits into the table's share (table value against the truth)
//!   and the shader's share (engine against the table value: its edge approximation, its
//!   horizon handling, f16 filtering and f32 arithmetic).
//!
//! Light conventions as three.js r187 (`RectAreaLight`): `lookAt` turns the light's −z
//! toward the target, the rectangle spans ±width/2 along its local x and ±height/2 along
//! its local y, it shines toward −z only (a point behind it gets 0), and its uniform
//! colour is colour × intensity (1 here).

pub mod godot;
pub mod scenes;
pub mod truth;

pub use scenes::Rect;
pub use scenes::{EngineScenes, Scene};
pub use truth::{table_value, truth_value};

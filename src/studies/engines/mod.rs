//! `engines`: three.js r187 (engines/three, headless Chromium, WebGL2) and Bevy 0.19.1
//! (engines/bevy-check, headless wgpu) render the engine-check scenes with their shipped
//! LTC table and with ours, on every path each engine has (three.js: its float and its
//! half-float textures; Bevy: its RGBA16F array); this study judges every pixel against
//! the truth (`crate::engines`) and splits each error into the table's share and the
//! shader's share. Compute ([`compute`]) → render ([`report`]) → the CLI publishes
//! results/engines.{md,json,svg}. The sheen check (`sheen`, `sheen_report`): three.js with
//! and without our RectAreaLightSheen recipe, judged the same way → results/engines-sheen.{md,json}.

mod compute;
pub mod files;
pub mod godot;
pub mod inputs;
pub mod report;
pub mod sheen;
pub mod sheen_report;
mod summary;

pub use compute::{
    bevy_held, compact_held, compute, three_held, Engine, EngineResult, EngineRun, EngineScene,
    EnginesResult, Errors, Held, Inputs, PathResult, SceneResult, COMPACT, TRUTH_REL,
};

pub use compute::GodotScene;
pub use files::{judge_files, run, EngineFiles, BEVY_OURS};
pub use summary::{PathSummary, Summary, Worse};

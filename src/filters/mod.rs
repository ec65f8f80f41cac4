//! Footprint roughness filters: footprint statistics of normal maps,
//! the filters of the engines and papers (f64 reference + f32 shading form), the exact
//! footprint-averaged ground truth, and the study behind results/filters.md.

pub mod choice;
pub mod footprint;
pub mod plan;
pub mod registry;
pub mod rules;
pub mod study;
pub mod truth;

//! results/fits/render.json: the rendered evidence (one entry per example scene, each
//! view's methods with their measured errors). Written by the render study; the part
//! other reports read is typed here, the rest ([`Render::detail`]) is the study's own.

use crate::fit::spec::FitSpec;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What other code reads of results/fits/render.json.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Render {
    pub spec: FitSpec,
    pub command: String,
    pub renders: Vec<SceneRun>,
    #[serde(flatten)]
    pub detail: BTreeMap<String, serde_json::Value>,
}

impl super::ResultFile for Render {
    const NAME: &'static str = super::names::RENDER;
}

/// One scene's renders.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SceneRun {
    pub scene: Named,
    pub views: Vec<ViewRun>,
    #[serde(flatten)]
    pub detail: BTreeMap<String, serde_json::Value>,
}

/// Anything with a name (the scene, as its TOML gave it).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Named {
    pub name: String,
    #[serde(flatten)]
    pub detail: BTreeMap<String, serde_json::Value>,
}

/// One view (scale or frame) and every method's measures in it.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ViewRun {
    pub methods: Vec<MethodRun>,
    #[serde(flatten)]
    pub detail: BTreeMap<String, serde_json::Value>,
}

/// One method in one view.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MethodRun {
    pub key: String,
    pub measures: Measures,
    #[serde(flatten)]
    pub detail: BTreeMap<String, serde_json::Value>,
}

/// A method's measures against the truth; the relative MSE is typed.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Measures {
    pub rel_mse: Value,
    #[serde(flatten)]
    pub detail: BTreeMap<String, serde_json::Value>,
}

/// A measured value (its error bar and kind stay in `detail`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Value {
    #[serde(deserialize_with = "super::f64_or_nan")]
    pub value: f64,
    #[serde(flatten)]
    pub detail: BTreeMap<String, serde_json::Value>,
}

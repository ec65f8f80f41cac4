//! results/fits/render.json: the rendered evidence. One entry per example scene, each
//! view's methods with their measures against the truth, the flicker along a camera path,
//! and the truth's own checks against closed forms. The `render SCENE.toml` command writes
//! one [`SceneRun`] per scene.

use crate::fit::spec::FitSpec;
use crate::integrate::Figure;
use crate::render::check::CheckResult;
use crate::render::measure::{Flicker, Measures};
use crate::render::scene::Scene;
use serde::{Deserialize, Serialize};

/// The file.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Render {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    /// The truth against closed forms.
    pub checks: Vec<CheckResult>,
    pub renders: Vec<SceneRun>,
    /// Seed 002 Fig 11's claim judged in the glint scene under SGs (absent without one).
    #[serde(default)]
    pub fig11: Option<Fig11>,
    /// The SHA-256 of the GGX LTC table the methods shaded with
    /// (`render::methods::ltc_table_sha256`); `None` in a file from before it was kept.
    #[serde(default)]
    pub ltc_table_sha256: Option<String>,
}

/// Seed 002 §5.4's claim (Fig 11): the prefiltered query has "much lower noise" than the
/// point query, at no visible bias; judged on one rendered scene by the relative MSE
/// against the truth at equal draws per pixel.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Fig11 {
    pub scene: String,
    /// Eq 8's ε and Eq 9's side scale.
    pub eps: f64,
    pub scale: f64,
    pub rows: Vec<Fig11Row>,
    /// The plain mip (no noise) for comparison.
    pub mip: Figure,
    /// "holds", "holds with a caveat" or "refuted".
    pub verdict: String,
    /// Why, in one sentence.
    pub reason: String,
}

/// One CP rank at one number of draws: both estimators' relative MSE.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Fig11Row {
    pub rank: usize,
    pub draws: usize,
    pub point: Figure,
    pub prefiltered: Figure,
}

impl super::ResultFile for Render {
    const NAME: &'static str = super::names::RENDER;
}

/// One scene's renders.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SceneRun {
    /// The scene as its TOML gave it.
    pub scene: Scene,
    pub views: Vec<ViewRun>,
    /// Per method, its flicker along the camera path (empty for a still scene).
    pub flicker: Vec<FlickerRun>,
    /// The truth's own frame-to-frame change, when the scene has a path.
    pub truth_change: Option<Figure>,
    /// Extra per-method numbers (the CP models' error and storage).
    pub notes: Vec<String>,
}

/// One view (a scale of the map or a frame of the path) and every method's measures.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ViewRun {
    pub scale: f64,
    pub frame: usize,
    pub methods: Vec<MethodRun>,
}

/// One method in one view.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MethodRun {
    pub key: String,
    pub label: String,
    pub measures: Measures,
}

/// One method's flicker along a camera path.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FlickerRun {
    pub key: String,
    pub label: String,
    pub flicker: Flicker,
}

/// The refitted GGX constants of results/fits/filters.json, as the renderer's methods
/// take them (every family; a method that needs a missing one fails when it is built).
pub fn constants(
    results: &std::path::Path,
) -> crate::error::Result<crate::render::methods::Constants> {
    let v: super::filters::Filters = super::require(results)?;
    Ok(crate::render::methods::Constants {
        fitted: v
            .fitted
            .iter()
            .filter(|f| f.ndf == "GGX")
            .map(|f| (f.family.clone(), f.constant))
            .collect(),
        y_mi: f32::NAN,
    })
}

/// results/fits/render-truth-work.json (on request): the render truth's accuracy against
/// its work, per scene, at each draw scale of texels per replicate, against the truth that
/// shades every texel.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TruthWork {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub scenes: Vec<TruthWorkScene>,
}

impl super::ResultFile for TruthWork {
    const NAME: &'static str = super::names::RENDER_TRUTH_WORK;
}

/// One scene: its truth samples per pixel, the every-texel reference first, then one point
/// per draw scale.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TruthWorkScene {
    pub scene: String,
    pub samples: usize,
    /// The scene file's `truth_draws` (absent: every texel).
    pub chosen: Option<usize>,
    /// The smallest draw scale that passes (absent: none does).
    pub smallest_passing: Option<f64>,
    /// The scene's choice takes at least the smallest passing scale's draws, or every texel.
    pub supported: bool,
    pub points: Vec<TruthWorkPoint>,
}

/// One truth of a scene: its draws, its work and its figures per view.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TruthWorkPoint {
    /// × (n/2) texels per replicate; `None`: every texel (the reference).
    pub draw_scale: Option<f64>,
    pub draws: Option<usize>,
    /// Texel shadings per pixel over every view (`render::truth::Work::shadings`).
    pub shadings_per_pixel: f64,
    pub views: Vec<TruthWorkView>,
    /// Every check of the rule held (the reference: true).
    pub passes: bool,
    /// The checks that failed, view by view.
    pub failures: Vec<String>,
}

/// One view of one truth.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TruthWorkView {
    pub scale: f64,
    pub frame: usize,
    pub shadings_per_pixel: f64,
    /// Covered pixels whose texels were drawn.
    pub drawn_pixels: usize,
    pub pixels: usize,
    /// The mean squared standard error of a covered pixel (the truth's variance), ± its s.e.
    pub truth_variance: Figure,
    /// mean((t − t_ref)² − s.e.² − s.e._ref²) over the covered pixels that drew: 0 when both
    /// truths are unbiased and their errors honest (the reference: none).
    pub excess: Option<Figure>,
    pub methods: Vec<TruthWorkMethod>,
}

/// A method's figures against one truth.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TruthWorkMethod {
    pub key: String,
    pub rel_mse: Figure,
    pub flip: Figure,
}

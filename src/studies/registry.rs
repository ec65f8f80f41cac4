//! The registry of studies, as data: one entry per fits/*.toml. Each study declares
//! itself in its own module (`study::study!`: its name, the studies it follows, whether
//! the main job leaves it out, its entry point); the list below is the one place that
//! names them all.

use crate::study::Study;

use super::{
    filters, leadr_grids, ltc_aniso, ltc_between_sample, ltc_compact, ltc_ggx, ltc_judge_tolerance,
    ltc_lobe_cross, ltc_lobes, ltc_optimisers, ltc_work, multiscale_alpha_me,
    multiscale_convolution, render, render_truth_work, smith_lambda, tensor, tensor_envsg,
    tensor_scale, tensor_wang, tensor_wave, visibility,
};

/// Every study, as data.
pub static STUDIES: &[&dyn Study] = &[
    &leadr_grids::LeadrGrids,
    &ltc_lobes::LtcDiffuse,
    &ltc_ggx::LtcGgx,
    &ltc_lobes::LtcSheen,
    &multiscale_alpha_me::MultiscaleAlphaMe,
    &multiscale_convolution::MultiscaleConvolution,
    &smith_lambda::SmithLambda,
    &tensor::Tensor,
    &tensor_envsg::TensorEnvSg,
    &tensor_scale::TensorScale,
    &tensor_wang::TensorWang,
    &tensor_wave::TensorWave,
    &visibility::Visibility,
    &ltc_aniso::LtcAniso,
    &ltc_aniso::LtcAnisoWork,
    &ltc_optimisers::LtcGgxOptimisers,
    &ltc_lobe_cross::LtcLobeCross,
    &ltc_work::LtcWorkStudy,
    &ltc_judge_tolerance::LtcJudgeTolerance,
    &ltc_between_sample::LtcBetweenSample,
    &ltc_compact::LtcCompactStudy,
    &render::RenderStudy,
    &render_truth_work::RenderTruthWork,
    &filters::Filters,
];

/// The study named `name`.
pub fn find(name: &str) -> Option<&'static dyn Study> {
    STUDIES.iter().copied().find(|s| s.name() == name)
}

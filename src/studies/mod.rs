//! The registry of studies (one per fits/*.toml) and the `regen` driver. Only the CLI
//! (and tests) use it; the studies themselves live with their topics and never import it.
//!
//! Each entry (`registry`) adapts a topic's entry point to [`crate::study::Study`]; an unknown spec name is a typed
//! error. Order: studies without `after` first, then those with, each group by name.

pub mod convergence;
pub mod engines;
pub mod filters;
pub mod leadr_grids;
pub mod ltc_aniso;
pub mod ltc_between;
pub mod ltc_between_sample;
pub mod ltc_compact;
pub mod ltc_compare;
pub mod ltc_error_map;
pub mod ltc_ggx;
pub mod ltc_judge_tolerance;
pub mod ltc_lobe_cross;
pub mod ltc_lobes;
pub mod ltc_optimisers;
pub mod ltc_work;
pub mod ltc_work_tables;
pub mod multiscale_alpha_me;
pub mod multiscale_convolution;
pub mod performance;
mod registry;
pub mod render;
pub mod render_truth_work;
mod run;
pub mod smith_lambda;
pub mod tensor;
pub mod tensor_envsg;
pub mod tensor_scale;
pub mod tensor_wang;
pub mod tensor_wave;
pub mod visibility;

pub use registry::{find, STUDIES};

pub use run::{check_sharded, merge, regen, regen_timed, regen_with, shard, RunOptions, StudyTime};

//! Reports: SVG plots and heat maps (plotters), the markdown table writer and progress lines. Studies compute and format;
//! this module only draws what it is given and says where a run is.

pub mod plot;
pub mod table;
pub mod table3;

/// One progress line per stage on stderr, with the time since the first stage: long jobs
/// say where they are also when stderr is not a terminal (`| tee log`), where indicatif
/// hides its bars.
pub fn stage(msg: &str) {
    crate::progress::stamp(msg);
}

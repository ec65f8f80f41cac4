//! Reports: SVG plots and heat maps (plotters), the markdown table writer and progress lines. Studies compute and format;
//! this module only draws what it is given and says where a run is.

pub mod plot;
pub mod table;

/// One progress line per stage on stderr, with the time since the first stage: long jobs
/// say where they are also when stderr is not a terminal (`| tee log`), where indicatif
/// hides its bars.
pub fn stage(msg: &str) {
    crate::progress::stamp(msg);
}

/// An estimate's relative error against an MC truth with its standard error, as
/// "+1.2 % ± 0.3" (the ± is the truth's s.e. relative to it); "—" for a zero truth.
pub fn rel_vs_mc(x: f64, mc: f64, se: f64) -> String {
    if mc > 0.0 {
        format!("{:+.1} % ± {:.1}", 100.0 * (x / mc - 1.0), 100.0 * se / mc)
    } else {
        "—".into()
    }
}

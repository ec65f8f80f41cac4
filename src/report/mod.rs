//! Reports: convergence study of the engines and the criterion performance summary.

pub mod convergence;
pub mod performance;
pub mod plot;

/// One progress line per stage on stderr, with the time since the first stage: long jobs
/// say where they are also when stderr is not a terminal (`| tee log`), where indicatif
/// hides its bars.
pub fn stage(msg: &str) {
    use std::sync::OnceLock;
    static START: OnceLock<std::time::Instant> = OnceLock::new();
    let t0 = START.get_or_init(std::time::Instant::now);
    eprintln!("[{:>7.1} s] {msg}", t0.elapsed().as_secs_f64());
}

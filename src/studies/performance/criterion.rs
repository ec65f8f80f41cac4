//! The criterion results as measured times (point estimate and confidence interval per
//! benchmark), and how a time or a ratio is written.

use crate::error::{Error, Result};
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Deserialize)]
pub(super) struct BenchId {
    group_id: String,
    function_id: Option<String>,
    value_str: Option<String>,
}

#[derive(Deserialize)]
pub(super) struct Interval {
    lower_bound: f64,
    upper_bound: f64,
}

#[derive(Deserialize)]
pub(super) struct Stat {
    point_estimate: f64,
    confidence_interval: Interval,
}

#[derive(Deserialize)]
pub(super) struct Estimates {
    mean: Stat,
}

/// One timed benchmark.
pub struct Timed {
    pub group: String,
    pub function: String,
    pub param: String,
    pub mean_ns: f64,
    pub lo_ns: f64,
    pub hi_ns: f64,
}

pub(super) fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.file_name().is_some_and(|n| n == "benchmark.json")
                && p.parent().is_some_and(|d| d.ends_with("new"))
            {
                out.push(p);
            }
        }
    }
}

/// All benchmarks criterion has results for.
pub fn read_criterion(dir: &Path) -> Result<Vec<Timed>> {
    let mut files = Vec::new();
    walk(dir, &mut files);
    if files.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "no criterion results under '{}': run `cargo bench` first",
            dir.display()
        )));
    }
    let io = |p: &Path, e: String| Error::Io {
        path: p.display().to_string(),
        msg: e,
    };
    let mut out = Vec::new();
    for f in files {
        let id: BenchId =
            serde_json::from_str(&std::fs::read_to_string(&f).map_err(|e| io(&f, e.to_string()))?)
                .map_err(|e| io(&f, e.to_string()))?;
        let ef = f.with_file_name("estimates.json");
        let est: Estimates = serde_json::from_str(
            &std::fs::read_to_string(&ef).map_err(|e| io(&ef, e.to_string()))?,
        )
        .map_err(|e| io(&ef, e.to_string()))?;
        // a time is a positive finite number of nanoseconds, its interval around it
        let (m, lo, hi) = (
            est.mean.point_estimate,
            est.mean.confidence_interval.lower_bound,
            est.mean.confidence_interval.upper_bound,
        );
        if !(m.is_finite() && m > 0.0 && lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo) {
            return Err(io(
                &ef,
                format!(
                    "criterion estimate is not a positive time (mean {m:e} ns, interval [{lo:e}, {hi:e}])"
                ),
            ));
        }
        out.push(Timed {
            group: id.group_id,
            function: id.function_id.unwrap_or_default(),
            param: id.value_str.unwrap_or_default(),
            mean_ns: est.mean.point_estimate,
            lo_ns: est.mean.confidence_interval.lower_bound,
            hi_ns: est.mean.confidence_interval.upper_bound,
        });
    }
    out.sort_by(|a, b| (&a.group, &a.function, &a.param).cmp(&(&b.group, &b.function, &b.param)));
    Ok(out)
}

/// A speed-up ratio, or "—" where a time is missing.
pub(super) fn fmt_ratio(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2}×")
    } else {
        "—".into()
    }
}

pub(super) fn fmt_time(ns: f64) -> String {
    if !ns.is_finite() {
        return "—".into();
    }
    if ns >= 1e9 {
        format!("{:.3} s", ns / 1e9)
    } else if ns >= 1e6 {
        format!("{:.3} ms", ns / 1e6)
    } else if ns >= 1e3 {
        format!("{:.3} µs", ns / 1e3)
    } else {
        format!("{ns:.1} ns")
    }
}

/// A criterion mean with its 95 % interval.
pub(super) fn interval(t: &Timed) -> String {
    format!(
        "{} ({} – {})",
        fmt_time(t.mean_ns),
        fmt_time(t.lo_ns),
        fmt_time(t.hi_ns)
    )
}

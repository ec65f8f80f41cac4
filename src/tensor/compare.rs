//! Our CP-ALS against TensorLy's `parafac` (an established implementation)
//! on the same P-NDF cluster tensors, rank, tolerance, iteration cap and convergence rule
//! (stop when the relative error changes by less than the tolerance). Both run on one
//! core: ours is serial, and numpy's BLAS is pinned with OMP/OPENBLAS/MKL_NUM_THREADS=1.
//! `cargo run --release -- tensorly-compare` writes results/tensor-tensorly.json, which
//! `regen --only tensor` renders into results/tensor.md. Needs python3 with numpy and
//! tensorly; without them it says so and writes nothing.

use super::cluster::cluster_tensors;
use super::cp::{cp_als, AlsOptions, Tensor3};
use crate::error::{Error, Result};
use crate::filters::footprint::{NormalMap, Procedural};
use crate::integrate::Preset;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// The script that runs TensorLy (relative to the repository root).
pub const SCRIPT: &str = "benches/tensorly_compare.py";

/// One tensor at one rank, both implementations.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Row {
    pub map: String,
    pub cluster: usize,
    pub shape: [usize; 3],
    pub rank: usize,
    pub ours_error: f64,
    pub ours_iterations: usize,
    pub ours_seconds: f64,
    pub tensorly_error: f64,
    pub tensorly_iterations: usize,
    pub tensorly_seconds: f64,
}

/// The comparison over every row of a [`Report`].
#[derive(Clone, Copy, Debug)]
pub struct ReportSummary {
    /// Rows where our error exceeds TensorLy's by more than 0.1 % relative.
    pub worse: usize,
    /// Mean of (ours − TensorLy) relative error.
    pub mean_error_difference: f64,
    /// Geometric mean and smallest of TensorLy's time over ours.
    pub geometric_mean_speedup: f64,
    pub smallest_speedup: f64,
}

/// What `tensorly-compare` writes.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    pub command: String,
    pub preset: String,
    pub tensorly_version: String,
    pub python: String,
    pub tol: f64,
    pub max_iters: usize,
    pub repeats: usize,
    pub rows: Vec<Row>,
}

impl Report {
    /// Every row compared at once: how often ours is worse, the mean error difference and
    /// the speed-ups.
    pub fn summary(&self) -> ReportSummary {
        let n = self.rows.len().max(1) as f64;
        let ratios: Vec<f64> = self
            .rows
            .iter()
            .map(|x| x.tensorly_seconds / x.ours_seconds)
            .collect();
        ReportSummary {
            worse: self
                .rows
                .iter()
                .filter(|x| x.ours_error > x.tensorly_error * 1.001)
                .count(),
            mean_error_difference: self
                .rows
                .iter()
                .map(|x| x.ours_error - x.tensorly_error)
                .sum::<f64>()
                / n,
            geometric_mean_speedup: (ratios.iter().map(|x| x.ln()).sum::<f64>() / n).exp(),
            smallest_speedup: ratios.iter().cloned().fold(f64::INFINITY, f64::min),
        }
    }
}

fn python_env(cmd: &mut Command) -> &mut Command {
    cmd.env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1")
        .env("MKL_NUM_THREADS", "1")
}

/// `Ok(version)` when `python` can import numpy and tensorly, `Err(reason)` otherwise.
pub fn tensorly_available(python: &str) -> std::result::Result<String, String> {
    let out = Command::new(python)
        .arg("-c")
        .arg("import numpy, tensorly; print(tensorly.__version__)")
        .output()
        .map_err(|e| format!("cannot run '{python}': {e}"))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
    } else {
        Err(String::from_utf8_lossy(&out.stderr)
            .lines()
            .last()
            .unwrap_or("numpy or tensorly missing")
            .to_string())
    }
}

/// TensorLy's parafac on `t` (written to `dir`) from the start `init` (row-major
/// factors, see [`super::cp::initial_factors`]): (error, iterations, fastest seconds).
#[allow(clippy::too_many_arguments)]
pub fn run_tensorly(
    python: &str,
    dir: &Path,
    t: &Tensor3,
    init: &[Vec<f64>; 3],
    rank: usize,
    tol: f64,
    max_iters: usize,
    repeats: usize,
) -> Result<(f64, usize, f64)> {
    let path = dir.join(format!(
        "tensor-{}x{}x{}.json",
        t.shape[0], t.shape[1], t.shape[2]
    ));
    let io = |e: std::io::Error| Error::Io {
        path: path.display().to_string(),
        msg: e.to_string(),
    };
    std::fs::write(
        &path,
        serde_json::json!({"shape": t.shape, "data": t.data, "init": init}).to_string(),
    )
    .map_err(io)?;
    let out = python_env(Command::new(python).arg(SCRIPT).arg(&path))
        .args([
            rank.to_string(),
            format!("{tol:e}"),
            max_iters.to_string(),
            repeats.to_string(),
        ])
        .output()
        .map_err(io)?;
    if !out.status.success() {
        return Err(Error::InvalidArgument(format!(
            "{SCRIPT} failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    let v: serde_json::Value = serde_json::from_slice(&out.stdout)
        .map_err(|e| Error::InvalidArgument(format!("{SCRIPT} printed no JSON: {e}")))?;
    let get = |k: &str| {
        v[k].as_f64()
            .ok_or_else(|| Error::InvalidArgument(format!("{SCRIPT}: no '{k}' in its output")))
    };
    Ok((
        get("rel_error")?,
        get("iterations")? as usize,
        get("seconds")?,
    ))
}

/// Ours on `t`: (error, iterations, fastest seconds over `repeats` identical runs).
pub fn run_ours(t: &Tensor3, o: &AlsOptions, repeats: usize) -> Result<(f64, usize, f64)> {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let cp = cp_als(t, o)?;
        best = best.min(start.elapsed().as_secs_f64());
        last = Some(cp);
    }
    let cp = last.expect("one run");
    Ok((cp.rel_error, cp.iterations, best))
}

/// Build the tensors of the preset, run both sides, write results/tensor-tensorly.json.
pub fn run(
    set: &mut crate::io::Outputs,
    results: &Path,
    python: &str,
    preset: Preset,
) -> Result<Report> {
    let version = tensorly_available(python).map_err(|why| {
        Error::InvalidArgument(format!(
            "TensorLy comparison needs python3 with numpy and tensorly (`pip install numpy tensorly`): {why}"
        ))
    })?;
    let (size, res, ranks, repeats): (usize, usize, Vec<usize>, usize) = match preset {
        Preset::Quick => (32, 32, vec![4, 8], 1),
        Preset::Default => (64, 64, vec![8, 16, 32], 3),
        Preset::Precise => (128, 128, vec![8, 16, 32], 5),
    };
    let (tol, max_iters, stride, t, sigma_r) = (1e-4, 500usize, 8usize, 16usize, 0.02);
    let dir = std::env::temp_dir().join(format!("ndfbench-tensorly-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| Error::Io {
        path: dir.display().to_string(),
        msg: e.to_string(),
    })?;
    let maps = [
        Procedural::IsotropicNoise,
        Procedural::BrushedMetal,
        Procedural::Flakes,
    ];
    let bar = indicatif::ProgressBar::new((maps.len() * ranks.len()) as u64);
    bar.set_message("TensorLy vs ours");
    let mut rows = Vec::new();
    let outcome = (|| -> Result<()> {
        for kind in maps {
            let map = NormalMap::procedural(kind, size, 3)?;
            let tensors = cluster_tensors(&map, res, stride, t, sigma_r)?;
            // the largest cluster (most blocks): the hardest tensor of the map
            let (k, tt) = tensors
                .iter()
                .enumerate()
                .max_by_key(|(_, x)| x.shape[2])
                .ok_or_else(|| Error::InvalidArgument("no non-empty block".into()))?;
            for &rank in &ranks {
                let o = AlsOptions {
                    rank,
                    tol,
                    max_iters,
                    restarts: 1,
                    seed: 5,
                    nonnegative: false,
                };
                let (oe, oi, os) = run_ours(tt, &o, repeats)?;
                let init =
                    super::cp::initial_factors(tt.shape, rank, super::cp::restart_seed(o.seed, 0));
                let (te, ti, ts) =
                    run_tensorly(python, &dir, tt, &init, rank, tol, max_iters, repeats)?;
                rows.push(Row {
                    map: kind.name().to_string(),
                    cluster: k,
                    shape: tt.shape,
                    rank,
                    ours_error: oe,
                    ours_iterations: oi,
                    ours_seconds: os,
                    tensorly_error: te,
                    tensorly_iterations: ti,
                    tensorly_seconds: ts,
                });
                bar.inc(1);
            }
        }
        Ok(())
    })();
    bar.finish_and_clear();
    std::fs::remove_dir_all(&dir).ok();
    outcome?;
    let py = Command::new(python)
        .arg("--version")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    let report = Report {
        command: "cargo run --release -- tensorly-compare".into(),
        preset: preset.name().into(),
        tensorly_version: version,
        python: py,
        tol,
        max_iters,
        repeats,
        rows,
    };
    set.put(
        &results.join("tensor-tensorly.json"),
        serde_json::to_string_pretty(&report)
            .expect("json")
            .as_bytes(),
    );
    Ok(report)
}

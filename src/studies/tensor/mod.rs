//! `regen --only tensor`: P-NDF images of procedural maps over a two-level footprint
//! pyramid, blocked and clustered (seed 002 §4.1–4.2), CP-compressed at several ranks;
//! results/tensor.md and results/fits/tensor.json. Compute ([`compute`]), then render
//! ([`report`]). `prefilter --rank` compresses a user's map the same way ([`prefilter_tensor`]).
//!
//! - **Model:** Σ_r C_r X_r ⊗ Y_r ⊗ Z_r (seed 002 Eq 5), unit-norm factors, per spatial
//!   cluster of four procedural maps (isotropic noise, brushed metal, flakes, sharp bumps).
//! - **Optimiser:** alternating least squares (MTTKRP over non-zero fibres, a shared
//!   partial product, Cholesky of the R×R Gram product with a pseudo-inverse fallback;
//!   stop when the relative error changes by < `als_tolerance`), 2 seeded restarts;
//!   baseline TensorLy's parafac from the same start (`tensorly-compare`).
//! - **Metric:** relative reconstruction error ‖T − T̂‖/‖T‖ in f64 per cluster, measured
//!   on the compressed tensors themselves (compression, not generalisation).

use crate::error::Result;
use crate::filters::footprint::NormalMap;
use crate::integrate::Preset;
use crate::io::Outputs;
use crate::report::plot::{loglog_svg, Panel, Series};
use crate::report::table::Table;
use crate::study::FitOutcome;
use crate::tensor::cluster::cluster_tensors;
use crate::tensor::cp::{cp_als, AlsOptions};
use rayon::prelude::*;
use std::path::Path;

mod compute;
pub mod report;

use compute::Computed;

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &Path) -> Result<()> {
        set.put(results.join("tensor-rank.svg"), report::rank_svg(&self)?);
        set.put(results.join("tensor.md"), report::markdown(&self));
        crate::results::put(
            set,
            results,
            &crate::results::tensor::Tensor {
                spec: self.spec.clone(),
                command: crate::results::command(&self.spec.name),
                preset: self.preset.name().into(),
                rows: self.rows.clone(),
            },
        )?;
        Ok(())
    }
    /// Passed when every reconstruction error is finite (the study measures; it sets no
    /// bar on the error).
    fn outcome(&self) -> FitOutcome {
        FitOutcome::measured(
            &self.spec,
            self.worst,
            format!(
                "{} maps × ranks {:?}: worst relative reconstruction error {:.2} %",
                self.kinds,
                self.s.ranks,
                100.0 * self.worst
            ),
        )
    }
}

/// fits/tensor.toml as this build compiled it in: `prefilter --rank` reads its numbers.
const SPEC: &str = include_str!("../../../fits/tensor.toml");

/// `prefilter --rank R`: compress one map's P-NDF blocks at rank R; writes
/// DIR/tensor-<name>.json (per cluster: shape, weights, factors, error) and
/// DIR/tensor-<name>.md. Every check happens before anything is written.
pub fn prefilter_tensor(
    set: &mut crate::io::Outputs,
    map: &NormalMap,
    out: &Path,
    rank: usize,
    preset: Preset,
) -> Result<String> {
    // the tensor study's block side, image size, ALS settings and σ_r (fits/tensor.toml,
    // compiled in); the stride follows the map
    let spec = crate::fit::spec::FitSpec::parse(SPEC, "fits/tensor.toml (compiled in)")?;
    let s: compute::Settings = spec.params(preset)?;
    let t = s.t;
    if rank == 0 || rank > t * t {
        return Err(crate::error::Error::InvalidArgument(format!(
            "--rank {rank}: a {t}×{t} block allows ranks 1…{}",
            t * t
        )));
    }
    if map.width < t || map.height < t {
        return Err(crate::error::Error::InvalidArgument(format!(
            "map {} is {}×{}: tensor prefiltering needs at least {t}×{t} texels",
            map.name, map.width, map.height
        )));
    }
    let (res, iters) = (s.res, s.iters);
    let stride = (map.width / 8).clamp(2, 32);
    let tensors = cluster_tensors(map, res, stride, t, s.sigma_r)?;
    let fit = |r: usize| -> Result<Vec<crate::tensor::cp::Cp>> {
        tensors
            .par_iter()
            .map(|tt| {
                cp_als(
                    tt,
                    &AlsOptions {
                        rank: r.min(tt.shape[2] * t),
                        tol: s.als_tolerance,
                        max_iters: iters,
                        restarts: 2,
                        seed: spec.seed,
                        // exact hierarchical sampling needs a non-negative reconstruction
                        nonnegative: true,
                    },
                )
            })
            .collect::<Result<Vec<_>>>()
    };
    // error against rank: R/4, R/2 and R (the plot), R stored
    let mut sweep: Vec<usize> = vec![(rank / 4).max(1), (rank / 2).max(1), rank];
    sweep.dedup();
    let dense: usize = tensors.iter().map(|t| t.data.len()).sum();
    let mut rows = Vec::new();
    let mut fits = Vec::new();
    for &r in &sweep {
        let f = fit(r)?;
        let stored: usize = f.iter().map(|c| c.storage()).sum();
        let mean = f.iter().map(|c| c.rel_error).sum::<f64>() / f.len().max(1) as f64;
        let max = f.iter().map(|c| c.rel_error).fold(0.0, f64::max);
        rows.push((r, mean, max, stored as f64 / dense.max(1) as f64));
        if r == rank {
            fits = f;
        }
    }
    let stored: usize = fits.iter().map(|c| c.storage()).sum();
    let mean = fits.iter().map(|c| c.rel_error).sum::<f64>() / fits.len().max(1) as f64;
    let max = fits.iter().map(|c| c.rel_error).fold(0.0, f64::max);
    let mut md = format!(
        "# Tensor-compressed P-NDF of {}\n\nWritten by `cargo run --release -- prefilter … --rank {rank}` (preset {}). {}×{} texels, stride {stride}, the full footprint pyramid, {res}² images, {t}² blocks, {} clusters. Non-negative CP (HALS, so the hierarchical sampler is exact), rank {rank}: relative reconstruction error mean {:.2} %, max {:.2} %; compression {:.2} % of the non-empty blocks ({stored} of {dense} numbers).\n\n",
        map.name, preset.name(), map.width, map.height, fits.len(), 100.0 * mean, 100.0 * max, 100.0 * stored as f64 / dense.max(1) as f64
    );
    let mut tb = Table::new(["R", "mean rel. error", "max rel. error", "compression"]);
    for (r, m, x, c) in &rows {
        tb.row([
            r.to_string(),
            format!("{:.2} %", 100.0 * m),
            format!("{:.2} %", 100.0 * x),
            format!("{:.2} %", 100.0 * c),
        ]);
    }
    md.push_str(&tb.to_string());
    md.push_str(&format!(
        "\nThe cost of the P-NDF images and of CP is measured by the criterion benches (results/performance.md), not by this run. ![error against rank](tensor-{}-rank.svg)\n",
        map.name
    ));
    let svg = loglog_svg(
        &[Panel {
            title: format!("{}: non-negative CP error against rank", map.name),
            x_label: "rank R".into(),
            y_label: "mean ‖T − T̂‖/‖T‖".into(),
            series: vec![Series {
                name: map.name.clone(),
                points: rows.iter().map(|r| (r.0 as f64, r.1)).collect(),
            }],
        }],
        560,
        380,
    )?;
    let json = serde_json::json!({"map": map.name, "rank": rank, "block": t, "image": res, "stride": stride, "clusters": fits});
    let jp = out.join(format!("tensor-{}.json", map.name));
    let mp = out.join(format!("tensor-{}.md", map.name));
    let sp = out.join(format!("tensor-{}-rank.svg", map.name));
    set.put(&jp, serde_json::to_string(&json).expect("json").as_bytes());
    set.put(&sp, svg.as_bytes());
    set.put(&mp, md.as_bytes());
    Ok(format!(
        "wrote {}, {} and {}: rank {rank}, mean error {:.2} %, compression {:.2} %",
        jp.display(),
        sp.display(),
        mp.display(),
        100.0 * mean,
        100.0 * stored as f64 / dense.max(1) as f64
    ))
}

crate::study::study! {
    /// The seed 002 tensor study, as the registry holds it.
    Tensor = "tensor", after [], on request false, params compute::Settings, computes compute::compute
}

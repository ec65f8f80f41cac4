//! Fit specifications (fits/*.toml) and the `regen` driver.
//!
//! A spec names the model form, the domain, the training and held-out points, the
//! metric, the optimiser and its settings, the seed and the tolerance on held-out error.
//! `regen` runs every spec (or `--only NAME`), writes results/fits/<name>.json and the
//! fit's report, and fails loudly when a held-out error misses its tolerance.

pub mod spec;

use crate::error::Result;
use crate::integrate::Preset;
use std::path::Path;

/// What one fit produced.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FitOutcome {
    pub name: String,
    pub held_out_max_rel: f64,
    pub tolerance: f64,
    pub passed: bool,
    pub summary: String,
}

/// Run the fits whose name contains `only` (all when None).
pub fn regen(
    fits_dir: &Path,
    results: &Path,
    only: Option<&str>,
    preset: Preset,
) -> Result<Vec<FitOutcome>> {
    let specs = spec::load_dir(fits_dir)?;
    let mut out = Vec::new();
    // `--only filters` is the footprint-filter group: the LEADR grids and the Λ refit run first,
    // because results/filters.md embeds their reports.
    let group = ["leadr-grids", "smith-lambda", "filters"];
    let selected: Vec<&spec::FitSpec> = match only {
        Some("filters") => group
            .iter()
            .filter_map(|g| specs.iter().find(|s| s.name == *g))
            .collect(),
        _ => {
            let mut v: Vec<&spec::FitSpec> = specs
                .iter()
                .filter(|s| only.is_none_or(|o| s.name.contains(o)))
                .collect();
            // filters last (it embeds the other two reports)
            v.sort_by_key(|s| s.name == "filters");
            v
        }
    };
    for s in selected {
        // one study = one output set, published in one step (crate::io)
        let set = crate::io::begin_set(&s.name, &crate::io::results_manifest(results, &s.name))?;
        crate::report::stage(&format!("regen {}: started", s.name));
        let t = std::time::Instant::now();
        let o = match s.name.as_str() {
            "leadr-grids" => crate::leadr::regen(s, results)?,
            "smith-lambda" => crate::microfacet::lambda_fit::regen(s, results)?,
            "filters" => crate::filters::regen::run(s, results, preset)?,
            "ltc-ggx" => crate::ltc_regen::run(s, results, preset)?,
            "tensor" => crate::tensor::regen::run(s, results, preset)?,
            "multiscale-convolution" => {
                crate::multiscale::regen_convolution::run(s, &specs, results, preset)?
            }
            _ => crate::multiscale::regen::run(s, results, preset)?,
        };
        set.commit()?;
        crate::report::stage(&format!(
            "regen {}: done in {:.1} s",
            s.name,
            t.elapsed().as_secs_f64()
        ));
        out.push(o);
    }
    if out.is_empty() {
        return Err(crate::error::Error::InvalidArgument(format!(
            "no fit spec in '{}' matches {:?}",
            fits_dir.display(),
            only
        )));
    }
    Ok(out)
}

/// Minimise a 1D function: evaluate it on `xs` (sorted), then refine with Brent's method
/// (argmin) inside the bracket of the best grid point. `tol` = (eps, t) of Brent.
pub fn scan_brent(f: &dyn Fn(f64) -> f64, xs: &[f64], tol: (f64, f64), max_iters: u64) -> f64 {
    use argmin::core::{CostFunction, Executor, State};
    use argmin::solver::brent::BrentOpt;
    struct C<'a>(&'a dyn Fn(f64) -> f64);
    impl CostFunction for C<'_> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, x: &f64) -> std::result::Result<f64, argmin::core::Error> {
            Ok((self.0)(*x))
        }
    }
    let (mut bi, mut bv) = (0, f64::INFINITY);
    for (i, &x) in xs.iter().enumerate() {
        let v = f(x);
        if v < bv {
            bv = v;
            bi = i;
        }
    }
    let (a, b) = (xs[bi.saturating_sub(1)], xs[(bi + 1).min(xs.len() - 1)]);
    Executor::new(C(f), BrentOpt::new(a, b).set_tolerance(tol.0, tol.1))
        .configure(|s| s.max_iters(max_iters))
        .run()
        .ok()
        .and_then(|r| r.state().get_best_param().copied())
        .unwrap_or(xs[bi])
}

/// Write results/fits/<name>.json atomically.
pub fn write_result(results: &Path, name: &str, value: &serde_json::Value) -> Result<()> {
    crate::io::write_atomic(
        &results.join("fits").join(format!("{name}.json")),
        serde_json::to_string_pretty(value)
            .expect("a JSON value serialises")
            .as_bytes(),
    )
}

/// Read results/fits/<name>.json if present and well formed.
pub fn read_result(results: &Path, name: &str) -> Option<serde_json::Value> {
    let text =
        crate::io::read_to_string(&results.join("fits").join(format!("{name}.json"))).ok()?;
    serde_json::from_str(&text).ok()
}

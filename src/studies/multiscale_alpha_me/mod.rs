//! `regen --only multiscale-alpha-me`: fit α_me(‖b̄‖), audit seed 000 Eq 5, write
//! results/fits/multiscale-alpha-me.json, results/multiscale-alpha-me.md and its plots. Compute
//! ([`compute`]: the fits, their errors and the plotted curves), then render (plots
//! ([`plots`]) and report ([`report`])).
//!
//! - **Model** (seed 000 §3.3, Eq 4–5): the inverse of the closed-form ‖b̄‖(α) of the
//!   isotropic LTC M = diag(α, α, 1). With y = 1 − ‖b̄‖ ≤ 1/3: α = √(y / R(s)),
//!   s = ln(1/y), R(s) = s/2 + ln 2/2 − 1 + ln(s)/2 + Σ_{k=1..terms} c_k s^−k; with
//!   y > 1/3: α = (π/2) g(b)/b, g(b) = 1 + Σ_{k=1..terms_large} d_k b^k (exact limits
//!   α → 0 and α ~ π/(2‖b̄‖)).
//! - **Points:** `training_points` log-uniform in α over [`alpha_min`, `alpha_max`], both
//!   ends included; `held_out_points` log-uniform, half a step off.
//! - **Metric:** relative error in α, fitted as weighted linear least squares (SVD) on
//!   R = y/α² (weights 1/R) for α ≤ 1 and on g = 2‖b̄‖α/π (weights 1/g) for α ≥ 1, α = 1
//!   pinned with weight 1e6 in both.
//! - **Baselines:** Eq 5 as printed; its form refitted by Nelder–Mead (argmin, at most
//!   `refit_max_iters` iterations, tolerance `refit_tolerance`); a `table_entries`-entry
//!   table in s; Newton on the closed form.

use crate::error::Result;
use crate::io::Outputs;
use crate::study::{Ctx, FitOutcome};
use std::path::Path;

mod compute;
mod plots;
mod report;

pub use compute::whole_range;
use compute::{compute, Computed};

/// What fits/multiscale-alpha-me.toml sets: the α_me fit's settings, which live with the
/// model (the convolution study reads them too).
pub use crate::multiscale::alpha_me::Settings as Params;

/// The α_me fit's parameters (default preset) from the multiscale-alpha-me spec of `fits`,
/// for the readers outside the study (`eval`).
pub fn params_in(fits: &Path) -> Result<Params> {
    crate::fit::spec::load_dir(fits)?
        .into_iter()
        .find(|s| s.name == "multiscale-alpha-me")
        .ok_or_else(|| {
            crate::error::Error::InvalidArgument(format!(
                "no multiscale-alpha-me spec in '{}'",
                fits.display()
            ))
        })?
        .params(crate::integrate::Preset::Default)
}

/// Compute the multiscale α_me fit the context's spec sets.
fn run(c: &Ctx) -> Result<Computed> {
    compute(c.spec, &c.params()?)
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &Path) -> Result<()> {
        let spec = &self.result.spec;
        let (svg_err, svg_mrl) = plots::render(&self.curves)?;
        crate::results::put(set, results, &self.result)?;
        set.put(results.join("multiscale-alpha-error.svg"), svg_err);
        set.put(results.join("multiscale-alpha-me.svg"), svg_mrl);
        set.put(
            results.join("multiscale-alpha-me.md"),
            report::markdown(spec, &self.params, &self),
        );
        Ok(())
    }
    fn outcome(&self) -> FitOutcome {
        let r = &self.result;
        let spec = &r.spec;
        FitOutcome::judged(
            spec,
            r.ours.held_out.max_rel,
            format!(
                "ours {:.2e} max rel (tol {:.0e}); paper Eq 5 {:.2e}; paper form refit {:.2e}; table {:.2e}",
                r.ours.held_out.max_rel,
                spec.tolerance.max_rel,
                r.paper_eq5.held_out.max_rel,
                r.paper_form_refit.held_out.max_rel,
                r.table.held_out.max_rel
            ),
        )
    }
}

pub use crate::results::alpha_me::WholeRange;

crate::study::study! {
    /// The α_me study, as the registry holds it.
    MultiscaleAlphaMe = "multiscale-alpha-me", after [], on request false, params Params, computes run
}

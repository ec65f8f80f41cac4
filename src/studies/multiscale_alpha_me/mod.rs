//! `regen --only multiscale-alpha-me`: fit α_me(‖b̄‖), audit seed 000 Eq 5, write
//! results/fits/multiscale-alpha-me.json, results/multiscale-alpha-me.md and its plots. Compute
//! ([`compute`]: the fits, their errors and the plotted curves), then render (plots
//! ([`plots`]) and report ([`report`])).

use crate::error::Result;
use crate::io::Outputs;
use crate::study::{Ctx, FitOutcome};
use std::path::Path;

mod compute;
mod plots;
mod report;

pub use compute::whole_range;
use compute::{compute, Computed};

/// Compute the multiscale α_me fit described by the context's spec.
fn run(c: &Ctx) -> Result<Computed> {
    compute(c.spec)
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
            report::markdown(spec, &self),
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
    MultiscaleAlphaMe = "multiscale-alpha-me", after [], on request false, computes run
}

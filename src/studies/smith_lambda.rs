//! The `smith-lambda` study (its spec in fits/): the model in `crate::microfacet::lambda_fit`
//! fitted and measured ([`compute`]), then reported ([`render`]).
//!
//! - **Model:** Λ(ν) = (1 − ν/ν_c)² (1 + a1 ν + a2 ν²) / (b1 ν + b2 ν² + b3 ν³) for ν < ν_c,
//!   else 0: six numbers against Walter et al.'s five (seed 001 §3.2), fitted to the exact
//!   Beckmann Λ(ν) = (e^(−ν²)/(√π ν) − erfc ν)/2.
//! - **Points:** `points` log-uniform in ν over [`nu_min`, `nu_max`], both ends included;
//!   held out: the `points` − 1 midpoints (half a step off).
//! - **Metric:** max |G1_fit − G1_exact| with G1 = 1/(1 + Λ), optimised through its L8
//!   norm by Nelder–Mead (argmin) with restarts, at most `max_iters` iterations each.
//! - **Baseline:** Walter et al. 2007 as printed in seed 001 §3.2, and as its listing
//!   clamps ν.
//! - **Tolerance:** the spec's `max_rel` bounds the held-out max |ΔG1|.

use crate::error::Result;
use crate::io::Outputs;
use crate::microfacet::lambda;
use crate::microfacet::lambda_fit::*;
use crate::report::table::Table;
use crate::results::smith_lambda::{HeldOut, Limits, Parameters, SmithLambda as Fitted};
use crate::study::{Ctx, FitOutcome};

/// What the study computed: the typed result and the held-out |ΔG1| curves it plots.
pub struct Computed {
    pub result: Fitted,
    /// (ν, |ΔG1|) on the held-out ν: Walter printed, Walter listing, ours.
    pub curves: [Vec<(f64, f64)>; 3],
}

/// What fits/smith-lambda.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Training points (log-uniform in ν, both ends included).
    pub points: usize,
    pub nu_min: f64,
    pub nu_max: f64,
    /// Nelder–Mead iterations per start.
    pub max_iters: u64,
}

impl crate::fit::spec::Params for Params {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::within;
        within("points", self.points, 8, 100_000)?;
        within("nu_min", self.nu_min, 1e-6, 1e3)?;
        within("nu_max", self.nu_max, 1e-6, 1e3)?;
        within("max_iters", self.max_iters, 1, 100_000)?;
        if self.nu_min < self.nu_max {
            Ok(())
        } else {
            Err(format!(
                "nu_min = {:e} must be below nu_max = {:e}",
                self.nu_min, self.nu_max
            ))
        }
    }
}

/// Fit, judge on held-out ν, and measure Walter et al.'s ends (nothing is formatted).
pub fn compute(c: &Ctx) -> Result<Computed> {
    let spec = c.spec;
    let pa: Params = c.params()?;
    let (train, held) = grids(pa.points, pa.nu_min, pa.nu_max);
    let (p, iters) = fit(&train, pa.max_iters)?;
    let ours_f = |n: f64| rational(&p, n);
    let curve = |f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> {
        held.iter().map(|&n| (n, dg1(f, n).max(1e-12))).collect()
    };
    let ours = worst(&ours_f, &held);
    let exact_b1 = 2.0 * std::f64::consts::PI.sqrt();
    let result = Fitted {
        spec: spec.clone(),
        command: crate::results::command(&spec.name),
        parameters: Parameters {
            a1: p[0],
            a2: p[1],
            b1: p[2],
            b2: p[3],
            b3: p[4],
            nu_c: p[5],
        },
        iterations: iters as usize,
        held_out: HeldOut {
            ours,
            walter_printed: worst(&lambda::walter_printed, &held),
            walter_listing: worst(&lambda::walter_listing, &held),
        },
        training: worst(&ours_f, &train),
        passed: ours.max_dg1 <= spec.tolerance.max_rel,
        limits: Limits {
            exact_b1,
            walter_b1: lambda::WALTER_B1,
            walter_b1_rel_miss: 1.0 - lambda::WALTER_B1 / exact_b1,
            walter_numerator_root: lambda::walter_numerator_root(),
            walter_cut: lambda::WALTER_CUT,
            exact_lambda_at_cut: lambda::beckmann(lambda::WALTER_CUT),
        },
    };
    Ok(Computed {
        result,
        curves: [
            curve(&lambda::walter_printed),
            curve(&lambda::walter_listing),
            curve(&ours_f),
        ],
    })
}

/// results/smith-lambda.{json,md,svg} of a computed study (formats only).
fn render(set: &mut Outputs, results: &std::path::Path, c: &Computed) -> Result<()> {
    use crate::report::plot::{loglog_svg, Panel, Series};
    let r = &c.result;
    let printed = format!("Walter (printed, cut at {})", r.limits.walter_cut);
    let names = [
        printed.as_str(),
        "Walter (listing, ν clamped)",
        "ours (6 numbers)",
    ];
    let svg = loglog_svg(
        &[Panel {
            title: "|ΔG1| of Beckmann Λ approximations (held-out ν)".into(),
            x_label: "ν = cot θ / α".into(),
            y_label: "|G1_approx − G1|".into(),
            series: names
                .iter()
                .zip(&c.curves)
                .map(|(n, pts)| Series {
                    name: (*n).into(),
                    points: pts.clone(),
                })
                .collect(),
        }],
        900,
        520,
    )?;
    set.put(&results.join("smith-lambda.svg"), svg.as_bytes());
    crate::results::put(set, results, r)?;
    let (h, p, l) = (&r.held_out, r.parameters.array(), &r.limits);
    let tol = r.spec.tolerance.max_rel;
    let mut md =
        String::from("# Beckmann Smith Λ: a better rational approximation (seed 001 §3.2)\n\n");
    md.push_str("Written by `cargo run --release -- regen --only smith-lambda` from `fits/smith-lambda.toml`. The reference is the exact \
Λ(ν) = (e^(−ν²)/(√π ν) − erfc ν)/2 (checked against Smith's integral to 1e-11 in results/proofs.md). Errors are |ΔG1| = \
|1/(1 + Λ̃) − 1/(1 + Λ)| on held-out ν (log-uniform in [1e-3, 10], half a step off the training grid). The approximation is a \
function of ν alone, so it serves the non-centred (LEAN/LEADR) Λ too: there ν = (cot θ − μ(φ))/(σ(φ)√2) (seed 001 §3.2) and \
nothing else changes — no separate fit is needed.\n\n");
    let mut t = Table::new(["form", "numbers", "held-out max \\|ΔG1\\|", "at ν"]);
    let printed = format!("Walter (printed: Λ = 0 for ν ≥ {})", l.walter_cut);
    for (form, n, w, bold) in [
        (printed.as_str(), 5, &h.walter_printed, false),
        (
            "Walter (shader listing: ν clamped to [0.001, 1.599])",
            5,
            &h.walter_listing,
            false,
        ),
        (
            "ours: (1 − ν/ν_c)²(1 + a₁ν + a₂ν²)/(b₁ν + b₂ν² + b₃ν³)",
            6,
            &h.ours,
            true,
        ),
    ] {
        let e = format!("{:.3e}", w.max_dg1);
        let e = if bold { format!("**{e}**") } else { e };
        t.row([
            form.to_string(),
            n.to_string(),
            e,
            format!("{:.4}", w.at_nu),
        ]);
    }
    md.push_str(&t.to_string());
    md.push('\n');
    md.push_str(&format!(
        "Goal: |ΔG1| ≤ {tol:.0e} with at most two more coefficients than Walter's — **{}**.\n\n",
        if r.passed { "met" } else { "MISSED" }
    ));
    md.push_str(&format!("Parameters: a₁ = {:.10}, a₂ = {:.10}, b₁ = {:.10}, b₂ = {:.10}, b₃ = {:.10}, ν_c = {:.10} (argmin Nelder–Mead, {} iterations over 6 restarts, L⁸ surrogate of the max). b₁ ≈ 2√π = {:.4} recovers the exact ν → 0 limit Λ ≈ 1/(2√π ν) (Walter's {} misses it by {:.2} %); the squared factor closes the curve at ν_c with zero value and slope, so there is no negative band and no jump (Walter's numerator changes sign at ν = {:.3} and his cut at {} drops Λ({}) = {:.1e} at once).\n\n", p[0], p[1], p[2], p[3], p[4], p[5], r.iterations, l.exact_b1, l.walter_b1, 100.0 * l.walter_b1_rel_miss, l.walter_numerator_root, l.walter_cut, l.walter_cut, l.exact_lambda_at_cut));
    md.push_str("Cost next to accuracy: results/performance.md (bench group `smith-lambda`).\n\n![|ΔG1|](smith-lambda.svg)\n");
    set.put(&results.join("smith-lambda.md"), md.as_bytes());
    Ok(())
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        render(set, results, self)
    }
    fn outcome(&self) -> FitOutcome {
        let r = &self.result;
        let h = &r.held_out;
        FitOutcome::judged(
            &r.spec,
            h.ours.max_dg1,
            format!(
                "ours max |ΔG1| {:.2e} (tol {:.0e}); Walter printed {:.2e}, listing {:.2e}",
                h.ours.max_dg1,
                r.spec.tolerance.max_rel,
                h.walter_printed.max_dg1,
                h.walter_listing.max_dg1
            ),
        )
    }
}

crate::study::study! {
    /// The Smith Λ refit, as the registry holds it.
    SmithLambda = "smith-lambda", after [], on request false, params Params, computes compute
}

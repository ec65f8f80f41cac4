//! results/multiscale-alpha-me.md: the held-out table, the whole-range check, the audit of Eq 5
//! and our form.

use super::compute::Computed;
use crate::fit::spec::FitSpec;
use crate::multiscale::alpha_me::HeldOut;
use crate::report::table::Table;
use crate::results::alpha_me::WholeRange;

/// The report.
pub(super) fn markdown(
    spec: &FitSpec,
    pa: &crate::multiscale::alpha_me::Settings,
    k: &Computed,
) -> String {
    let Computed {
        lo,
        hi,
        ref sign_alpha,
        ref pole_alpha,
        eq5_at: [(a0, e0), (a1, e1)],
        ref result,
        ..
    } = *k;
    let (passed, c, refit) = (result.passed, &result.ours, &result.paper_form_refit);
    let (h_ours, h_refit, h_paper) = (&c.held_out, &refit.held_out, &result.paper_eq5.held_out);
    let (h_table, h_newton) = (&result.table.held_out, &result.newton_closed_form.held_out);
    let whole = &c.whole_range;
    let (at_one, at_two_thirds) = (
        result.eq5_audit.alpha_at_b_1,
        result.eq5_audit.alpha_at_b_2_3,
    );
    let sign_alpha: Vec<String> = sign_alpha
        .iter()
        .map(|(b, a)| format!("‖b̄‖ = {b:.9} (exact α there = {a:.4e})"))
        .collect();
    let pole_alpha: Vec<String> = pole_alpha
        .iter()
        .map(|(b, a)| format!("‖b̄‖ = {b:.6} (exact α there = {a:.4})"))
        .collect();
    let mut md = String::from("# Multi-scale LTC: α_me from ‖b̄‖ (seed 000 §3.3)\n\n");
    md.push_str("Written by `cargo run --release -- regen --only multiscale-alpha-me` from `fits/multiscale-alpha-me.toml`. \
Ground truth is the closed form ‖b̄‖(α) = (1 − α² artanh(k)/k)/(1 − α²), k = √(1 − α²) (proofs/mrl-closed-form.md; \
checked against quadrature of Eq 4 to ≤ 1e-10 in results/proofs.md), inverted by safeguarded Newton. \
Errors are relative errors in α on held-out points (log-uniform, half a step off the training grid).\n\n");
    md.push_str(&format!(
        "## Methods on the fit domain α ∈ [{lo}, {hi}] ({} held-out points)\n\n",
        pa.held_out_points
    ));
    let mut t = Table::new([
        "method".to_string(),
        "max rel. error".into(),
        "RMS rel. error".into(),
        "worst at α".into(),
        format!("rel. error at α = {lo}"),
        format!("at α = {hi}"),
        "cost".into(),
    ]);
    t.row(row(
        "paper Eq 5 (as printed)",
        &h_paper,
        "see performance.md",
    ));
    t.row(row(
        "paper's form, refitted (argmin Nelder–Mead)",
        &h_refit,
        "see performance.md",
    ));
    t.row(row(
        &format!(
            "ours: √(y/R(s)) for α ≤ 1 ({} coefficients), (π/2)g(b)/b above ({})",
            pa.terms, pa.terms_large
        ),
        &h_ours,
        "see performance.md",
    ));
    t.row(row(
        &format!(
            "lookup table, {} entries, linear in (s, ln α)",
            pa.table_entries
        ),
        &h_table,
        "see performance.md",
    ));
    t.row(row(
        "Newton on the closed form",
        &h_newton,
        "see performance.md",
    ));
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\nGoal: max relative error ≤ {:.0e} on held-out points — ours: **{}** ({:.2e}).\n\n",
        spec.tolerance.max_rel,
        if passed { "met" } else { "MISSED" },
        h_ours.max_rel
    ));
    md.push_str(&whole_range_md(&whole));
    md.push_str("## Audit of Eq 5\n\n");
    md.push_str(&format!("- At ‖b̄‖ → 1 (α → 0) Eq 5 tends to {at_one:.5}: **negative**. Its numerator changes sign at {}: every footprint smoother than that gets a negative α_me.\n", sign_alpha.join(", ")));
    md.push_str(&format!(
        "- At α = {a0:e} (fit-domain edge) Eq 5 is off by {:.1} % (relative); at α = {a1} by {:.1} %.\n",
        100.0 * e0,
        100.0 * e1
    ));
    md.push_str(&format!(
        "- At ‖b̄‖ = 2/3 (exact α = 1, where the paper clamps) Eq 5 gives {at_two_thirds:.5}.\n"
    ));
    md.push_str(&format!("- Poles of Eq 5 in (0, 1): {} — past it (rougher footprints, α > 1) the rational is meaningless; the paper clamps α at 1, i.e. uses only ‖b̄‖ ≳ 0.667.\n", if pole_alpha.is_empty() { "none".into() } else { pole_alpha.join(", ") }));
    md.push_str(&format!("- Max relative error of Eq 5 over α ∈ [{lo}, {hi}]: {:.3e} (at α = {:.4e}); it is only accurate where Fig. 2 of the paper shows it (α ≳ 0.05). The absolute error stays ≈ 2e-3 as α → 0 because Eq 5 has no α → 0 limit: a rational function of ‖b̄‖ cannot follow 1 − ‖b̄‖ = α²(ln(2/α) − 1).\n", h_paper.max_rel, h_paper.worst_alpha));
    md.push_str(&format!("- Refitting the same form ({} coefficients, argmin Nelder–Mead, {} iterations, objective {:.3e}) reaches only {:.3e} max relative error: the form, not the fit, is the limit.\n\n", refit.coefficients.len(), refit.iterations, refit.objective, h_refit.max_rel));
    md.push_str("## Our form\n\nα = √(y/R(s)) with y = 1 − ‖b̄‖, s = ln(1/y) and R(s) = s/2 + (ln 2)/2 − 1 + ½ ln s + Σ c_k s^(−k). \
The fixed terms are the exact α → 0 asymptote (1 − ‖b̄‖ = α²(ln(2/α) − 1) ⇒ R = s/2 + ½ ln R + ln 2 − 1); \
the point ‖b̄‖ = 2/3 ↦ α = 1 is pinned. R = y/α² is known exactly at every training point, so the c_k come from one \
weighted linear least-squares solve (nalgebra SVD), not an iterative optimiser. Pass y = 1 − ‖b̄‖ (the mip chain can \
store it directly) to keep precision as ‖b̄‖ → 1.\n\n");
    md.push_str("Above α = 1 (y > 1/3) the same pinned point starts the second branch α = (π/2) g(b)/b, b = ‖b̄‖, \
g(b) = 1 + Σ d_k b^k: g(0) = 1 is the exact α → ∞ asymptote ‖b̄‖ ~ π/(2α), and g − 1 = 2bα/π − 1 is again linear in the \
d_k (weights 1/g). Pass b itself where it is small, or y ≥ ½, for which b = 1 − y is exact in binary arithmetic.\n\n");
    md.push_str(&format!(
        "Coefficients c_1…c_{}: `{:?}`\n\nCoefficients d_1…d_{}: `{:?}`\n\n",
        pa.terms, c.coefficients, pa.terms_large, c.coefficients_large
    ));
    md.push_str("![α_me against 1 − ‖b̄‖](multiscale-alpha-me.svg)\n\n![errors](multiscale-alpha-error.svg)\n\n");
    md.push_str("## Overall roughness (Eq 6–7)\n\nThe spherical convolution γ_me ∗ γ_mi, its one-LTC fits under four metrics, the \
product identity of mean resultant lengths (proofs/mrl-product.md), the Eq 7 refit and the engines' rules are in \
[multiscale-convolution.md](multiscale-convolution.md) (`regen --only multiscale-convolution`).\n");
    md
}

pub(super) fn row(name: &str, h: &HeldOut, cost: &str) -> [String; 7] {
    [
        name.to_string(),
        format!("{:.3e}", h.max_rel),
        format!("{:.3e}", h.rms_rel),
        format!("{:.4e}", h.worst_alpha),
        format!("{:+.3e}", h.rel_at_min),
        format!("{:+.3e}", h.rel_at_max),
        cost.to_string(),
    ]
}

pub(super) fn whole_range_md(w: &WholeRange) -> String {
    let mut t = Table::new([
        "form",
        "max rel. error, α ∈ [1e-4, 1e2]",
        "max rel. error, whole range",
        "worst at α",
    ]);
    let e = |x: f64| format!("{x:.3e}");
    t.row([
        "f64".to_string(),
        e(w.in_range_f64_max_rel),
        e(w.f64_max_rel),
        e(w.f64_worst_alpha),
    ]);
    t.row([
        "f32 (generated `alpha_me`, f32 coefficients; inputs that are normal f32)".to_string(),
        e(w.in_range_f32_max_rel),
        e(w.f32_max_rel),
        e(w.f32_worst_alpha),
    ]);
    format!(
        "## Over the whole input range\n\nThe same form evaluated over y = 1 − ‖b̄‖ from 1e-300 to 1/3 and over ‖b̄‖ \
from 1e-300 to 2/3 ({} points, exact α from {:.2e} to {:.2e}), against Newton on the closed form at the same input. \
Outside α ∈ [1e-4, 1e2] both branches follow their exact asymptotes.\n\n{t}\n\
Total: every input gives a finite α ≥ 0 (y = 0 ↦ the α → 0 end, y = 1 ↦ π/(2m) with m the smallest normal number, \
NaN and values outside [0, 1] are clamped first): **{}**.\n\n",
        w.points,
        w.alpha_range[0],
        w.alpha_range[1],
        if w.total { "yes" } else { "NO" }
    )
}

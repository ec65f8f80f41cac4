//! The report of the overall-α study: the metric spread, the models against the
//! closed-form target, Eq 7 recomputed, and the models against each metric.

use super::compute::{metric_value, models, stats, Computed, Row, Stats};
use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::multiscale::overall::{alpha_moment, improved, Metric, CAPS};
use crate::report::table::Table;

/// One model against the unclipped-moment target (results/fits/multiscale-convolution.json
/// `models`).
#[derive(serde::Serialize)]
pub(super) struct ModelRow {
    model: &'static str,
    held_out: Stats,
    held_out_target_le_1: Stats,
    limit_me0: f64,
    limit_mi0: f64,
}

/// The sections up to Eq 7; returns the markdown, the models' JSON rows and the largest
/// metric spread (factor, α_mi, α_me).
#[allow(clippy::type_complexity)]
pub(super) fn models_section(
    spec: &FitSpec,
    c: &Computed,
) -> Result<(String, Vec<ModelRow>, (f64, f64, f64))> {
    let Computed {
        ref g,
        lo,
        hi,
        ref held_axis,
        ref held,
        ref held_clamp,
        ref c7,
        sse7,
        sse_paper,
        ref ci,
        ours,
        m,
        ref fits,
        passed_moment,
        ..
    } = *c;
    let models = models(c);
    let limit = |f: &dyn Fn(f64, f64) -> f64| -> (f64, f64) {
        let mut a = 0.0f64;
        let mut b = 0.0f64;
        for &t in held_axis {
            a = a.max(((f(t, 1e-9) - t) / t).abs());
            b = b.max(((f(1e-9, t) - t) / t).abs());
        }
        (a, b)
    };
    let mut md = String::from(
        "# Multi-scale LTC: overall roughness of the footprint (seed 000 §3.4–3.5, Eq 6–7)\n\n",
    );
    md.push_str("Written by `cargo run --release -- regen --only multiscale-convolution` from `fits/multiscale-convolution.toml`. \
The convolution c = γ_me ∗ γ_mi (Eq 6) is computed by nested adaptive quadrature (proofs/mrl-product.md, checked against \
Monte Carlo in results/proofs.md); one isotropic LTC γ_α is fitted to it under a selectable metric:\n\n\
- **moment (unclipped)**: ρ(α) = ρ(α_me)·ρ(α_mi) — closed form by the product identity, so α = ρ⁻¹(‖b̄‖·ρ(α_mi)): \
the mip chain's ‖b̄‖ times the micro lobe's ρ, through the same inverse as α_me (results/multiscale-alpha-me.md). No Eq 7 needed.\n\
- **moment (clipped)**: the same on the clipped, renormalised distribution (normals rotated below the horizon dropped).\n\
- **L2**: min_α ∫(c − γ_α)² over the sphere (c tabulated on Gauss–Legendre nodes, Brent via argmin).\n\
- **caps**: min_α Σ ((E_c − E_α)/E_c)² over 9 spherical-cap lights (axis θ, half-angle r) = ");
    md.push_str(
        &CAPS
            .iter()
            .map(|(t, r)| format!("({t}, {r})"))
            .collect::<Vec<_>>()
            .join(", "),
    );
    md.push_str(" rad, and 4 convex spherical quads: ");
    md.push_str(
        &crate::multiscale::overall::polygons()
            .iter()
            .map(|p| p.name)
            .collect::<Vec<_>>()
            .join("; "),
    );
    md.push_str(". The cap energy of c is a 1D integral over θ of c(θ) times the arc of the cap at θ; polygon energies integrate c (Gauss–Legendre table with barycentric interpolation) and γ_α over the polygon by adaptive sphere quadrature with the edges' great circles as kink circles. The last column of the next table is the worst relative quadrature error estimate of the convolution's light energies.\n\n");
    md.push_str(&format!("## How much the best α depends on the metric ({m}×{m} grid, log-spaced in [{lo}, {hi}]²)\n\n"));
    let mut t = Table::new([
        "α_mi",
        "α_me",
        "moment (unclipped)",
        "moment (clipped)",
        "L2",
        "caps",
        "max/min",
        "cap quad. rel. error",
    ]);
    let mut spread_max = (1.0f64, 0.0, 0.0);
    for p in fits {
        let v: Vec<f64> = Metric::ALL.iter().map(|&k| metric_value(p, k)).collect();
        let (mn, mx) = v
            .iter()
            .fold((f64::INFINITY, 0.0f64), |a, &x| (a.0.min(x), a.1.max(x)));
        if mx / mn > spread_max.0 {
            spread_max = (mx / mn, p.alpha_mi, p.alpha_me);
        }
        t.row([
            format!("{:.3}", p.alpha_mi),
            format!("{:.3}", p.alpha_me),
            format!("{:.4}", v[0]),
            format!("{:.4}", v[1]),
            format!("{:.4}", v[2]),
            format!("{:.4}", v[3]),
            format!("{:.3}", mx / mn),
            format!("{:.1e}", p.cap_quad_rel_error),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!("\nLargest disagreement between metrics: a factor {:.3} at (α_mi, α_me) = ({:.3}, {:.3}). The unclipped moment keeps the mass that rotates below the horizon and so over-estimates α for rough pairs; the clipped moment, L2 and cap metrics agree much more closely with each other.\n\n", spread_max.0, spread_max.1, spread_max.2));
    md.push_str(&format!("## Models against the unclipped-moment target (closed form; {}² training points, {}² held-out points)\n\n", g.dense_points, g.dense_points - 1));
    let mut t = Table::new([
        "model",
        "held-out max rel.",
        "RMS rel.",
        "worst at (α_mi, α_me)",
        "max rel. where target α ≤ 1",
        "limit α(α_mi, 0) = α_mi (max rel. dev.)",
        "limit α(0, α_me) = α_me",
    ]);
    let mut model_json = Vec::new();
    for (name, f) in &models {
        let s = stats(&held, f.as_ref());
        let sc = stats(&held_clamp, f.as_ref());
        let (l1, l2) = limit(f.as_ref());
        t.row([
            name.to_string(),
            format!("{:.3e}", s.max_rel),
            format!("{:.3e}", s.rms_rel),
            format!("({:.3}, {:.3})", s.worst.0, s.worst.1),
            format!("{:.3e}", sc.max_rel),
            format!("{l1:.2e}"),
            format!("{l2:.2e}"),
        ]);
        model_json.push(ModelRow {
            model: name,
            held_out: s,
            held_out_target_le_1: sc,
            limit_me0: l1,
            limit_mi0: l2,
        });
    }
    md.push_str(&t.to_string());
    md.push_str(&format!("\nGoal: max relative error ≤ {:.0} % over [0.01, 1]². Ours (the product identity through the α_me fit; no fitted coefficients of its own) on the {} held-out points whose target α lies in the α_me fit's domain ({} left out; the paper clamps at α = 1, the fit does not need to): **{}** ({:.2e}). The 6-coefficient polynomial α² = α_mi² + α_me² + α_mi α_me P(α_mi, α_me) (both limits exact) reaches {:.2e} on all held-out points, including the corner where the unclipped moment sends α to {:.2}.\n\n", 100.0 * spec.tolerance.max_rel, held_clamp.len(), held.len() - held_clamp.len(), if passed_moment { "met" } else { "MISSED" }, ours.max_rel, stats(&held, &|x, y| improved(&ci, x, y)).max_rel, alpha_moment(hi, hi)?));
    md.push_str(&format!("## Eq 7 recomputed\n\nPaper: α = 0.07 α_mi² + 0.94 α_mi + α_me − 0.83 α_mi α_me, SSE 0.6492 (grid and metric not stated).\n\nRefit of the same basis by linear least squares on our {n}×{n} log-spaced grid against the unclipped-moment target: α = {:.4} α_mi² + {:.4} α_mi + {:.4} α_me {:+.4} α_mi α_me, SSE {:.4} (the paper's coefficients give SSE {:.4} on the same grid). SSE scales with the number and placement of grid points and with the metric, so 0.6492 cannot be compared across grids; the paper's own limits are off: Eq 7 gives α(α_mi, 0) = 0.07α_mi² + 0.94α_mi ≠ α_mi (6 % low at α_mi = 0.01, 1 % high at α_mi = 1).\n\n", c7[0], c7[1], c7[2], c7[3], sse7, sse_paper, n = g.dense_points));
    Ok((md, model_json, spread_max))
}

/// The models against each metric, and whether the study passes.
pub(super) fn per_metric_section(spec: &FitSpec, c: &Computed) -> (String, bool) {
    let Computed {
        m,
        ref fits,
        ref per_metric_ours,
        ref per_metric_corr,
        passed_moment,
        ..
    } = *c;
    let models = models(c);
    let mut md = String::new();
    // models against the quadrature metrics (in-sample on the metric grid)
    md.push_str("## Models against each metric (metric grid, in-sample)\n\n");
    let mut t = Table::new(std::iter::once("model").chain(Metric::ALL.iter().map(|k| k.name())));
    // per-metric refits, in-sample on the metric grid and held-out on the offset grid
    for (name, f) in &models {
        let cells: Vec<String> = Metric::ALL
            .iter()
            .map(|&k| {
                let pts: Vec<(f64, f64, f64)> = fits
                    .iter()
                    .map(|p| (p.alpha_mi, p.alpha_me, metric_value(p, k)))
                    .filter(|p| p.2 <= 1.0)
                    .collect();
                format!("{:.2e}", stats(&pts, f.as_ref()).max_rel)
            })
            .collect();
        t.row(std::iter::once(name.to_string()).chain(cells));
    }
    md.push_str(&t.to_string());
    let tol = spec.tolerance.max_rel;
    // the per-metric models have 10 coefficients: they are only judged (and gate `regen`)
    // when the metric grid has at least twice as many points (not at the quick preset)
    let gate = m * m >= 20;
    let metrics_ok = per_metric_corr.iter().all(|r| r.3.max_rel <= tol);
    let passed = passed_moment && (metrics_ok || !gate);
    let cells = |rows: &[Row]| -> String {
        rows.iter()
            .map(|(_, _, s, h)| format!("{:.2e} / {:.2e}", s.max_rel, h.max_rel))
            .collect::<Vec<_>>()
            .join(" | ")
    };
    md.push_str(&format!(
        "| polynomial, refitted to each metric: in-sample / held-out | {} |\n",
        cells(&per_metric_ours)
    ));
    md.push_str(&format!(
        "| **ours per metric**: α_mom·exp(Σ c_i b_i), 10 basis functions vanishing at both limits (see `overall::corrected`): in-sample / held-out | {} |\n\n",
        cells(&per_metric_corr)
    ));
    let hm = m - 1;
    md.push_str(&format!(
        "Goal: ≤ {:.0} % under every metric — ours per metric on held-out points: {}.\n\nHeld-out: the {hm}×{hm} grid half a step off the metric grid (all its points, α > 1 included). Rows without a refit are \
judged on the metric-grid points whose α ≤ 1 (the paper's clamp). α_mom = ρ⁻¹(ρ_me ρ_mi) (Newton on the closed form) \
carries both limits; every basis function of the per-metric correction vanishes at either limit.\n\n",
        100.0 * tol,
        match (gate, metrics_ok) {
            (false, _) => "not judged (metric grid too small for 10 coefficients at this preset)",
            (true, true) => "met for every metric",
            (true, false) => "MISSED for at least one metric",
        }
    ));
    (md, passed)
}

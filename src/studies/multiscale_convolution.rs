//! `regen --only multiscale-convolution`: overall α(α_mi, α_me) under four metrics, the
//! paper's Eq 7 and its refit, engine rules, and a model with both limits built in.

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::multiscale::alpha_me::{held_out_alphas, training_alphas};
use crate::multiscale::overall::{
    alpha_moment, corrected, eq7, fit_corrected, fit_improved, fit_pair, improved, refit_eq7,
    sum_of_squares, vmf, Metric, PairFit, CAPS,
};
use crate::report::plot::{loglog_svg, Panel, Series};
use crate::study::FitOutcome;
use serde_json::json;
use std::path::Path;

#[derive(Clone, Copy, Debug, serde::Serialize)]
struct Stats {
    max_rel: f64,
    rms_rel: f64,
    worst: (f64, f64),
}

fn stats(pts: &[(f64, f64, f64)], f: &dyn Fn(f64, f64) -> f64) -> Stats {
    let mut s = Stats {
        max_rel: 0.0,
        rms_rel: 0.0,
        worst: (0.0, 0.0),
    };
    let mut ss = 0.0;
    for &(x, y, a) in pts {
        let e = ((f(x, y) - a) / a).abs();
        let e = if e.is_nan() { f64::INFINITY } else { e };
        ss += e * e;
        if e > s.max_rel {
            s.max_rel = e;
            s.worst = (x, y);
        }
    }
    s.rms_rel = (ss / pts.len() as f64).sqrt();
    s
}

fn grid(axis: &[f64]) -> Vec<(f64, f64)> {
    axis.iter()
        .flat_map(|&x| axis.iter().map(move |&y| (x, y)))
        .collect()
}

fn metric_value(p: &PairFit, m: Metric) -> f64 {
    match m {
        Metric::MomentUnclipped => p.moment_unclipped,
        Metric::MomentClipped => p.moment_clipped,
        Metric::L2 => p.l2,
        Metric::Caps => p.caps,
    }
}

/// `all` is every spec of the fits directory: the α_me spec is taken from it.
pub fn run(spec: &FitSpec, all: &[FitSpec], results: &Path, preset: Preset) -> Result<FitOutcome> {
    let g = spec
        .grid
        .clone()
        .ok_or_else(|| Error::InvalidArgument(format!("{}: needs a [grid]", spec.name)))?;
    let (lo, hi) = (spec.domain.alpha_min, spec.domain.alpha_max);
    // dense closed-form target (unclipped moment metric)
    let train_axis = training_alphas(g.dense_points, lo, hi);
    let held_axis = held_out_alphas(g.dense_points - 1, lo, hi);
    let target = |pts: Vec<(f64, f64)>| -> Result<Vec<(f64, f64, f64)>> {
        pts.into_iter()
            .map(|(x, y)| Ok((x, y, alpha_moment(x, y)?)))
            .collect()
    };
    let train = target(grid(&train_axis))?;
    let held = target(grid(&held_axis))?;
    let (c7, sse7) = refit_eq7(&train)?;
    let sse_paper: f64 = train.iter().map(|&(x, y, a)| (eq7(x, y) - a).powi(2)).sum();
    let ci = fit_improved(&train)?;
    // ours: the product identity through the α_me fit of fits/multiscale-alpha-me.toml,
    // α = α_me-fit(1 − ρ_me ρ_mi) — both limits hold up to that fit's error
    let me_spec = all
        .iter()
        .find(|s| s.name == "multiscale-alpha-me")
        .cloned()
        .ok_or_else(|| {
            Error::InvalidArgument(format!(
                "{} needs the multiscale-alpha-me spec in the same fits directory",
                spec.name
            ))
        })?;
    let c_me = crate::multiscale::alpha_me::fit_ours(
        me_spec.terms,
        me_spec.terms_large,
        &training_alphas(
            me_spec.training.points,
            me_spec.domain.alpha_min,
            me_spec.domain.alpha_max,
        ),
    )?;
    let product = move |x: f64, y: f64| {
        let (ym, yi) = (
            crate::multiscale::mrl::mrl_pair(y).1,
            crate::multiscale::mrl::mrl_pair(x).1,
        );
        c_me.eval(ym + yi - ym * yi)
    };
    let product2 = product.clone();
    // judge ours on the α_me fit's domain (now [1e-4, 1e2]: every held-out target here)
    let held_clamp: Vec<(f64, f64, f64)> = held
        .iter()
        .copied()
        .filter(|p| p.2 <= me_spec.domain.alpha_max)
        .collect();
    let ours = stats(&held_clamp, &product2);
    let eq7r = |x: f64, y: f64| c7[0] * x * x + c7[1] * x + c7[2] * y + c7[3] * x * y;
    let models: Vec<(&str, Box<dyn Fn(f64, f64) -> f64>)> = vec![
        ("paper Eq 7", Box::new(eq7)),
        ("Eq 7 form, refitted (linear LS)", Box::new(eq7r)),
        ("α² = α_mi² + α_me²", Box::new(sum_of_squares)),
        ("vMF α² + 2/κ", Box::new(|x, y| vmf(x, y, 2.0))),
        ("vMF α² + 1/κ", Box::new(|x, y| vmf(x, y, 1.0))),
        ("vMF α² + 1/(2κ)", Box::new(|x, y| vmf(x, y, 0.5))),
        (
            "polynomial α² = α_mi² + α_me² + α_mi α_me P (6 coefficients, both limits exact)",
            Box::new(|x, y| improved(&ci, x, y)),
        ),
        (
            "ours: α_me-fit(1 − ρ(α_me)ρ(α_mi)) (product identity)",
            Box::new(product),
        ),
    ];
    let limit = |f: &dyn Fn(f64, f64) -> f64| -> (f64, f64) {
        let mut a = 0.0f64;
        let mut b = 0.0f64;
        for &t in &held_axis {
            a = a.max(((f(t, 1e-9) - t) / t).abs());
            b = b.max(((f(1e-9, t) - t) / t).abs());
        }
        (a, b)
    };
    // per-point fits under every metric (expensive)
    let m = if preset == Preset::Quick {
        g.metric_points.min(3)
    } else {
        g.metric_points
    };
    let axis = training_alphas(m, lo, hi);
    let pairs = grid(&axis);
    let pb = indicatif::ProgressBar::new((pairs.len() + (m - 1) * (m - 1)) as u64);
    pb.set_message("convolution fits");
    let mut fits = Vec::new();
    for &(x, y) in &pairs {
        fits.push(fit_pair(x, y)?);
        pb.inc(1);
    }
    // held-out metric points: the (m−1)² grid half a step off
    let held_metric_axis = held_out_alphas(m - 1, lo, hi);
    let mut held_fits = Vec::new();
    for &(x, y) in &grid(&held_metric_axis) {
        held_fits.push(fit_pair(x, y)?);
        pb.inc(1);
    }
    pb.finish_and_clear();
    let passed_moment = ours.max_rel <= spec.tolerance.max_rel;

    let mut md = String::from(
        "# Multi-scale LTC: overall roughness of the footprint (seed 000 §3.4–3.5, Eq 6–7)\n\n",
    );
    md.push_str("Written by `cargo run --release -- regen --only multiscale-convolution` from `fits/multiscale-convolution.toml`. \
The convolution c = γ_me ∗ γ_mi (Eq 6) is computed by nested adaptive quadrature (proofs/mrl-product.md, checked against \
Monte Carlo in results/proofs.md); one isotropic LTC γ_α is fitted to it under a selectable metric:\n\n\
- **moment (unclipped)**: ρ(α) = ρ(α_me)·ρ(α_mi) — closed form by the product identity, so α = ρ⁻¹(‖b̄‖·ρ(α_mi)): \
the mip chain's ‖b̄‖ times the micro lobe's ρ, through the same inverse as α_me (results/multiscale.md). No Eq 7 needed.\n\
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
    md.push_str(&format!("## How much the best α depends on the metric ({m}×{m} grid, log-spaced in [{lo}, {hi}]²)\n\n| α_mi | α_me | moment (unclipped) | moment (clipped) | L2 | caps | max/min | cap quad. rel. error |\n|---|---|---|---|---|---|---|---|\n"));
    let mut spread_max = (1.0f64, 0.0, 0.0);
    for p in &fits {
        let v: Vec<f64> = Metric::ALL.iter().map(|&k| metric_value(p, k)).collect();
        let (mn, mx) = v
            .iter()
            .fold((f64::INFINITY, 0.0f64), |a, &x| (a.0.min(x), a.1.max(x)));
        if mx / mn > spread_max.0 {
            spread_max = (mx / mn, p.alpha_mi, p.alpha_me);
        }
        md.push_str(&format!(
            "| {:.3} | {:.3} | {:.4} | {:.4} | {:.4} | {:.4} | {:.3} | {:.1e} |\n",
            p.alpha_mi,
            p.alpha_me,
            v[0],
            v[1],
            v[2],
            v[3],
            mx / mn,
            p.cap_quad_rel_error
        ));
    }
    md.push_str(&format!("\nLargest disagreement between metrics: a factor {:.3} at (α_mi, α_me) = ({:.3}, {:.3}). The unclipped moment keeps the mass that rotates below the horizon and so over-estimates α for rough pairs; the clipped moment, L2 and cap metrics agree much more closely with each other.\n\n", spread_max.0, spread_max.1, spread_max.2));
    md.push_str(&format!("## Models against the unclipped-moment target (closed form; {}² training points, {}² held-out points)\n\n| model | held-out max rel. | RMS rel. | worst at (α_mi, α_me) | max rel. where target α ≤ 1 | limit α(α_mi, 0) = α_mi (max rel. dev.) | limit α(0, α_me) = α_me |\n|---|---|---|---|---|---|---|\n", g.dense_points, g.dense_points - 1));
    let mut model_json = Vec::new();
    for (name, f) in &models {
        let s = stats(&held, f.as_ref());
        let sc = stats(&held_clamp, f.as_ref());
        let (l1, l2) = limit(f.as_ref());
        md.push_str(&format!(
            "| {name} | {:.3e} | {:.3e} | ({:.3}, {:.3}) | {:.3e} | {:.2e} | {:.2e} |\n",
            s.max_rel, s.rms_rel, s.worst.0, s.worst.1, sc.max_rel, l1, l2
        ));
        model_json.push(json!({"model": name, "held_out": s, "held_out_target_le_1": sc, "limit_me0": l1, "limit_mi0": l2}));
    }
    md.push_str(&format!("\nGoal: max relative error ≤ {:.0} % over [0.01, 1]². Ours (the product identity through the α_me fit; no fitted coefficients of its own) on the {} held-out points whose target α lies in the α_me fit's domain ({} left out; the paper clamps at α = 1, the fit does not need to): **{}** ({:.2e}). The 6-coefficient polynomial α² = α_mi² + α_me² + α_mi α_me P(α_mi, α_me) (both limits exact) reaches {:.2e} on all held-out points, including the corner where the unclipped moment sends α to {:.2}.\n\n", 100.0 * spec.tolerance.max_rel, held_clamp.len(), held.len() - held_clamp.len(), if passed_moment { "met" } else { "MISSED" }, ours.max_rel, stats(&held, &|x, y| improved(&ci, x, y)).max_rel, alpha_moment(hi, hi)?));
    md.push_str(&format!("## Eq 7 recomputed\n\nPaper: α = 0.07 α_mi² + 0.94 α_mi + α_me − 0.83 α_mi α_me, SSE 0.6492 (grid and metric not stated).\n\nRefit of the same basis by linear least squares on our {n}×{n} log-spaced grid against the unclipped-moment target: α = {:.4} α_mi² + {:.4} α_mi + {:.4} α_me {:+.4} α_mi α_me, SSE {:.4} (the paper's coefficients give SSE {:.4} on the same grid). SSE scales with the number and placement of grid points and with the metric, so 0.6492 cannot be compared across grids; the paper's own limits are off: Eq 7 gives α(α_mi, 0) = 0.07α_mi² + 0.94α_mi ≠ α_mi (6 % low at α_mi = 0.01, 1 % high at α_mi = 1).\n\n", c7[0], c7[1], c7[2], c7[3], sse7, sse_paper, n = g.dense_points));
    // models against the quadrature metrics (in-sample on the metric grid)
    md.push_str("## Models against each metric (metric grid, in-sample)\n\n| model | ");
    md.push_str(
        &Metric::ALL
            .iter()
            .map(|k| k.name())
            .collect::<Vec<_>>()
            .join(" | "),
    );
    md.push_str(" |\n|---|---|---|---|---|\n");
    // per-metric refits, in-sample on the metric grid and held-out on the offset grid
    type Row = (Metric, Vec<f64>, Stats, Stats);
    let mut per_metric_ours: Vec<Row> = Vec::new();
    let mut per_metric_corr: Vec<Row> = Vec::new();
    for k in Metric::ALL {
        let pts: Vec<(f64, f64, f64)> = fits
            .iter()
            .map(|p| (p.alpha_mi, p.alpha_me, metric_value(p, k)))
            .collect();
        let hpts: Vec<(f64, f64, f64)> = held_fits
            .iter()
            .map(|p| (p.alpha_mi, p.alpha_me, metric_value(p, k)))
            .collect();
        let c = fit_improved(&pts)?;
        let (si, sh) = (
            stats(&pts, &|x, y| improved(&c, x, y)),
            stats(&hpts, &|x, y| improved(&c, x, y)),
        );
        per_metric_ours.push((k, c, si, sh));
        let c = fit_corrected(&pts)?;
        let (si, sh) = (
            stats(&pts, &|x, y| corrected(&c, x, y)),
            stats(&hpts, &|x, y| corrected(&c, x, y)),
        );
        per_metric_corr.push((k, c, si, sh));
    }
    for (name, f) in &models {
        md.push_str(&format!("| {name} | "));
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
        md.push_str(&cells.join(" | "));
        md.push_str(" |\n");
    }
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
    // slices plot
    let slices: Vec<Panel> = [0.03, 0.3, 1.0]
        .iter()
        .map(|&mi| {
            let ys = held_out_alphas(60, lo, hi);
            let curve =
                |f: &dyn Fn(f64, f64) -> f64| ys.iter().map(|&y| (y, f(mi, y))).collect::<Vec<_>>();
            let mut series: Vec<Series> = vec![Series {
                name: "moment (closed form)".into(),
                points: curve(&|x, y| alpha_moment(x, y).unwrap_or(f64::NAN)),
            }];
            for (name, f) in models
                .iter()
                .filter(|m| m.0 != "Eq 7 form, refitted (linear LS)")
            {
                series.push(Series {
                    name: name.to_string(),
                    points: curve(f.as_ref()),
                });
            }
            Panel {
                title: format!("α_mi = {mi}"),
                x_label: "α_me".into(),
                y_label: "overall α".into(),
                series,
            }
        })
        .collect();
    let svg = loglog_svg(&slices, 1500, 520)?;
    crate::io::write_atomic(&results.join("multiscale-convolution.svg"), svg.as_bytes())?;
    md.push_str("![slices of the overall α](multiscale-convolution.svg)\n\n");
    // maps on the held-out grid: the target surface and each model's relative error
    let map = |f: &dyn Fn(f64, f64) -> f64| -> Vec<Vec<f64>> {
        held_axis
            .iter()
            .map(|&y| held_axis.iter().map(|&x| f(x, y)).collect())
            .collect()
    };
    let rel = |f: &dyn Fn(f64, f64) -> f64| {
        map(&|x, y| {
            let a = alpha_moment(x, y).unwrap_or(f64::NAN);
            ((f(x, y) - a) / a).abs()
        })
    };
    let heat = |title: &str, values: Vec<Vec<f64>>, r: (f64, f64)| crate::report::plot::HeatPanel {
        title: title.to_string(),
        x: held_axis.clone(),
        y: held_axis.clone(),
        values,
        log_range: r,
        x_label: "α_mi".into(),
        y_label: "α_me".into(),
        log_axes: true,
        y_down: false,
        colour_label: format!("log10 {title}"),
    };
    let maps = crate::report::plot::heatmap_svg(
        &[
            heat(
                "α (unclipped moment)",
                map(&|x, y| alpha_moment(x, y).unwrap_or(f64::NAN)),
                (-2.0, 0.5),
            ),
            heat("|rel. error| Eq 7", rel(&eq7), (-5.0, 0.0)),
            heat("|rel. error| α²-sum", rel(&sum_of_squares), (-5.0, 0.0)),
            heat(
                "|rel. error| polynomial",
                rel(&|x, y| improved(&ci, x, y)),
                (-5.0, 0.0),
            ),
            heat("|rel. error| ours", rel(&product2), (-5.0, 0.0)),
        ],
        2000,
        430,
    )?;
    crate::io::write_atomic(
        &results.join("multiscale-convolution-maps.svg"),
        maps.as_bytes(),
    )?;
    md.push_str("Maps over the held-out grid (unclipped-moment target; colour = log10, range in each title; ours degrades only where the target α > 1, outside the α_me fit's domain):\n\n![maps](multiscale-convolution-maps.svg)\n");
    crate::io::write_atomic(&results.join("multiscale-convolution.md"), md.as_bytes())?;
    let json = json!({
        "spec": spec,
        "command": "cargo run --release -- regen --only multiscale-convolution",
        "ours": {"coefficients": ci, "held_out": ours},
        "eq7_refit": {"coefficients": c7, "sse": sse7, "sse_paper_coefficients_same_grid": sse_paper},
        "models": model_json,
        "metric_grid": fits,
        "per_metric_polynomial": per_metric_ours.iter().map(|(k, c, s, h)| json!({"metric": k, "coefficients": c, "in_sample": s, "held_out": h})).collect::<Vec<_>>(),
        "per_metric_corrected": per_metric_corr.iter().map(|(k, c, s, h)| json!({"metric": k, "coefficients": c, "in_sample": s, "held_out": h})).collect::<Vec<_>>(),
        "metric_grid_held_out": held_fits,
        "passed": passed,
    });
    crate::results::write_result(results, &spec.name, &json)?;
    Ok(FitOutcome {
        name: spec.name.clone(),
        held_out_max_rel: ours.max_rel,
        tolerance: spec.tolerance.max_rel,
        passed,
        summary: format!(
            "ours {:.2e} max rel on the moment target (tol {:.0e}); per metric held-out {}; metric spread up to ×{:.3}",
            ours.max_rel,
            spec.tolerance.max_rel,
            per_metric_corr.iter().map(|r| format!("{:.2e}", r.3.max_rel)).collect::<Vec<_>>().join("/"),
            spread_max.0
        ),
    })
}

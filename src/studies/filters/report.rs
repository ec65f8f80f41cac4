//! The report of the footprint study: results/filters.md section by section, and the
//! plots. Each function renders numbers computed elsewhere; none computes a fit.

use super::cases::{aggregate, MapCase, ScreenCase};
use super::constants::Fitted;
use super::plan::{kind_name, pct, Plan, KINDS};
use crate::error::Result;
use crate::filters::footprint::NormalMap;
use crate::filters::registry::{screen_index, MAP, SCREEN};
use crate::filters::study::PixelFilter;
use crate::filters::truth::CaseResult;
use crate::integrate::Preset;
use crate::microfacet::NdfKind;
use crate::report::plot::{loglog_svg, Panel, Series};
use crate::report::table::Table;
use std::path::Path;

/// The energy, L2 and peak columns of one NDF for one filter.
fn agg_cells(a: &super::cases::Agg) -> [String; 3] {
    [
        pct(a.energy_mean, a.energy_se),
        format!("{:.1} % ± {:.1}", 100.0 * a.l2_mean, 100.0 * a.l2_se),
        pct(a.peak_mean, a.peak_se),
    ]
}

/// The per-NDF columns of the map and kernel tables.
const NDF_COLUMNS: [&str; 6] = [
    "GGX energy",
    "GGX L2",
    "GGX peak",
    "Beckmann energy",
    "Beckmann L2",
    "Beckmann peak",
];

/// The title, the method and the plan.
pub(super) fn intro(preset: Preset, plan: &Plan) -> String {
    let mut md =
        String::from("# Footprint roughness filters against the footprint-averaged BRDF\n\n");
    md.push_str(&format!(
        "Written by `cargo run --release -- regen --only filters` (preset {}) from `fits/filters.toml`. Every number is a mean over cases \
± its standard error; the Monte Carlo noise of single cases is listed separately.\n\n",
        preset.name()
    ));
    md.push_str("## Method\n\n\
- **Truth** (seed 004 Eq 11 under Hypothesis 1): the footprint average of the per-texel cosine-weighted specular lobe D·G2/(4 n_x·v) \
(GGX or Beckmann, height-correlated Smith G2, F = 1) around each texel's own normal, for a point light in every direction l.\n\
- **Metrics**, over all light directions of the upper hemisphere: relative error of the integrated highlight energy ∫f dl, relative \
L2 error of the lobe ‖f − f_truth‖/‖f_truth‖, and the relative error of the lobe's maximum (searched over the sampled directions and the mirror directions of the mean normal, ≤ 64 texel normals and the filter's normal: a lower bound on each maximum, no standard error). \
Integrals by importance sampling from a defensive mixture (45 % the truth's texel VNDFs, 45 % the filters' lobes, 10 % cosine), \
ratio estimators with delta-method standard errors.\n\
- **Maps** (procedural, periodic): isotropic noise and brushed metal (slope rms 0.25), flakes (Voronoi cells, normals within 25°), \
sharp bumps (spherical caps with 45° rims on a flat plane). Mip level L = box average of 2^L × 2^L texels of the linearly mip-mapped \
statistics (unnormalised mean normal; E[x̃], E[ỹ], E[x̃²], E[ỹ²], E[x̃ỹ]).\n");
    md.push_str(&format!(
        "- Plan: {}² maps, levels {:?}, {} footprints per level, base α {:?}, views (θ, φ) {:?}°, {} light samples per case.\n\n",
        plan.map_size, plan.levels, plan.footprints_per_level, plan.alphas, plan.views_deg, plan.samples
    ));
    md
}

/// The markdown section of one map (table, worst cases, plot); returns its JSON rows.
pub(super) fn map_section(
    set: &mut crate::io::Outputs,
    md: &mut String,
    m: usize,
    map: &NormalMap,
    map_cases: &[MapCase],
    plan: &Plan,
    svg_dir: &Path,
) -> Result<Vec<serde_json::Value>> {
    md.push_str(&format!("## Map: {}\n\n", map.name));
    let mut t = Table::new(std::iter::once("filter").chain(NDF_COLUMNS));
    let mut row_json = Vec::new();
    for (fi, name) in MAP.iter().map(|f| f.label).enumerate() {
        let mut cells = Vec::new();
        let mut aj = Vec::new();
        for &kind in &KINDS {
            let rs: Vec<&CaseResult> = map_cases
                .iter()
                .filter(|c| c.map == m && c.kind == kind)
                .map(|c| &c.results[fi])
                .collect();
            let a = aggregate(&rs);
            cells.extend(agg_cells(&a));
            aj.push(serde_json::json!({"ndf": kind_name(kind), "all": a}));
        }
        t.row(std::iter::once(name.to_string()).chain(cells));
        row_json.push(serde_json::json!({"filter": name, "by_ndf": aj}));
    }
    md.push_str(&t.to_string());
    let mc = map_cases
        .iter()
        .filter(|c| c.map == m)
        .flat_map(|c| c.results.iter().map(|r| r.l2.se))
        .filter(|x| x.is_finite())
        .fold(0.0, f64::max);
    // the cases with the largest energy errors, with their own Monte Carlo errors
    let mut worst: Vec<(f64, &MapCase, usize)> = map_cases
        .iter()
        .filter(|c| c.map == m)
        .flat_map(|c| (0..MAP.len()).map(move |fi| (c.results[fi].energy.value.abs(), c, fi)))
        .filter(|w| w.0.is_finite())
        .collect();
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    md.push_str("\nLargest energy errors on this map (single cases, ± Monte Carlo s.e.):\n\n");
    let mut t = Table::new([
        "filter",
        "NDF",
        "base α",
        "level",
        "‖μ‖",
        "view (θ, φ)",
        "energy",
        "L2",
    ]);
    for (_, c, fi) in worst.iter().take(4) {
        let r = &c.results[*fi];
        t.row([
            MAP[*fi].label.to_string(),
            kind_name(c.kind).to_string(),
            c.alpha.to_string(),
            c.level.to_string(),
            format!("{:.4}", c.stats.mrl()),
            format!("{:?}", plan.views_deg[c.view]),
            pct(r.energy.value, r.energy.se),
            format!("{:.1} % ± {:.1}", 100.0 * r.l2.value, 100.0 * r.l2.se),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!("\nLargest single-case Monte Carlo s.e. of an L2 error on this map: {:.2} %. L2 error against footprint size (GGX, all α and views): ![{}](filters-{}.svg)\n\n", 100.0 * mc, map.name, map.name));
    // per-level plot
    let series: Vec<Series> = MAP
        .iter()
        .map(|f| f.label)
        .enumerate()
        .map(|(fi, name)| Series {
            name: name.to_string(),
            points: plan
                .levels
                .iter()
                .map(|&lv| {
                    let rs: Vec<&CaseResult> = map_cases
                        .iter()
                        .filter(|c| c.map == m && c.kind == NdfKind::Ggx && c.level == lv)
                        .map(|c| &c.results[fi])
                        .collect();
                    ((1usize << lv) as f64, aggregate(&rs).l2_mean.max(1e-6))
                })
                .collect(),
        })
        .collect();
    let svg = loglog_svg(
        &[Panel {
            title: format!("{}: lobe L2 error vs footprint (GGX)", map.name),
            x_label: "footprint width (texels)".into(),
            y_label: "relative L2 error".into(),
            series,
        }],
        900,
        560,
    )?;
    set.put(
        &svg_dir.join(format!("filters-{}.svg", map.name)),
        svg.as_bytes(),
    );
    Ok(row_json)
}

/// The screen-space kernel section (tables per pixel filter, the L2-vs-κ plot, the
/// clamp table); returns its JSON rows.
pub(super) fn screen_section(
    set: &mut crate::io::Outputs,
    md: &mut String,
    plan: &Plan,
    screen_cases: &[ScreenCase],
    results: &Path,
) -> Result<Vec<serde_json::Value>> {
    md.push_str(&format!("## Screen-space kernels on synthetic curved surfaces\n\nThe pixel sees a surface whose normal is normalize(z + R_30° diag(κ, a·κ)·p) at screen offset p (pixels): curvature × distance gives κ rad/px, anisotropy a ∈ {:?}; (α, κ) ∈ {:?}; views θ ∈ {:?}° (φ = 20°). Derivatives are quad finite differences (ddx = n(1,0) − n(0,0)) exactly as a GPU forms them. The truth averages the exact per-normal lobe over the pixel footprint: a Gaussian of variance 0.25 px² (the kernels' own σ²) or the 1×1 box, by a tensor midpoint rule fine enough that neighbouring nodes' normals differ by < α/2 (up to 64² nodes).\n\n", plan.anisotropy, plan.screen_pairs, plan.screen_views_deg));
    let mut json_screen = Vec::new();
    for pixel in [PixelFilter::Gaussian, PixelFilter::Box] {
        md.push_str(&format!(
            "### Pixel footprint: {}\n\n",
            if pixel == PixelFilter::Gaussian {
                "Gaussian σ² = 0.25 px²"
            } else {
                "1×1 box"
            }
        ));
        let mut t = Table::new(std::iter::once("kernel").chain(NDF_COLUMNS));
        for (fi, name) in SCREEN.iter().map(|f| f.label).enumerate() {
            let mut cells = Vec::new();
            for &kind in &KINDS {
                let rs: Vec<&CaseResult> = screen_cases
                    .iter()
                    .filter(|c| c.kind == kind && c.pixel == pixel)
                    .map(|c| &c.results[fi])
                    .collect();
                let a = aggregate(&rs);
                cells.extend(agg_cells(&a));
                json_screen.push(serde_json::json!({"pixel": format!("{pixel:?}"), "ndf": kind_name(kind), "kernel": name, "all": a}));
            }
            t.row(std::iter::once(name.to_string()).chain(cells));
        }
        md.push_str(&t.to_string());
        md.push('\n');
    }
    // L2 vs κ plot (GGX, Gaussian pixel)
    let mut kappas: Vec<f64> = plan.screen_pairs.iter().map(|p| p.1).collect();
    kappas.sort_by(f64::total_cmp);
    kappas.dedup();
    let kseries: Vec<Series> = SCREEN
        .iter()
        .map(|f| f.label)
        .enumerate()
        .map(|(fi, name)| Series {
            name: name.to_string(),
            points: kappas
                .iter()
                .map(|&k| {
                    let rs: Vec<&CaseResult> = screen_cases
                        .iter()
                        .filter(|c| {
                            c.kind == NdfKind::Ggx
                                && c.pixel == PixelFilter::Gaussian
                                && c.field.kappa_u == k
                        })
                        .map(|c| &c.results[fi])
                        .collect();
                    (k, aggregate(&rs).l2_mean.max(1e-6))
                })
                .collect(),
        })
        .collect();
    let svg = loglog_svg(
        &[Panel {
            title: "screen-space kernels: lobe L2 error vs curvature (GGX, Gaussian pixel)".into(),
            x_label: "κ (rad / pixel)".into(),
            y_label: "relative L2 error".into(),
            series: kseries,
        }],
        900,
        560,
    )?;
    set.put(&results.join("filters-screen.svg"), svg.as_bytes());
    md.push_str("L2 error against curvature per kernel (GGX, Gaussian pixel): ![screen](filters-screen.svg)\n\n");
    // by κ table for the clamp question
    md.push_str("### The clamp δ = 0.18, by curvature (GGX, Gaussian pixel; L2 error, mean ± s.e. over the α paired with that κ, both anisotropies and all views)\n\n");
    // the kernels of the clamp question, by registry key, with their column names
    let clamp_cols = [
        ("none", "none"),
        ("tokuyoshi-deferred", "Eq 13 (δ 0.18)"),
        ("eq13-unclamped", "Eq 13 unclamped"),
        ("eigen-eq10", "Eq 10"),
        ("eq10-unclamped", "Eq 10 unclamped"),
        ("godot", "Godot (on α)"),
        ("filament", "Filament"),
    ];
    let mut t = Table::new(std::iter::once("κ (rad/px)").chain(clamp_cols.iter().map(|c| c.1)));
    for &k in &kappas {
        let cell = |fi: usize| {
            let rs: Vec<&CaseResult> = screen_cases
                .iter()
                .filter(|c| {
                    c.kind == NdfKind::Ggx
                        && c.pixel == PixelFilter::Gaussian
                        && c.field.kappa_u == k
                })
                .map(|c| &c.results[fi])
                .collect();
            let a = aggregate(&rs);
            format!("{:.1} % ± {:.1}", 100.0 * a.l2_mean, 100.0 * a.l2_se)
        };
        t.row(
            std::iter::once(k.to_string())
                .chain(clamp_cols.iter().map(|c| cell(screen_index(c.0)))),
        );
    }
    md.push_str(&t.to_string());
    Ok(json_screen)
}

/// The fitted-constant table; returns its JSON rows.
pub(super) fn fits_section(
    md: &mut String,
    fits: &[Fitted],
) -> Vec<crate::results::filters::FittedConstant> {
    md.push_str("\n## Fitted constants (argmin scan + Brent on the mean L2 error; train = even footprints / views, held-out = odd)\n\n");
    let mut t = Table::new([
        "family",
        "NDF",
        "fitted constant",
        "train mean L2",
        "held-out mean L2",
        "held-out energy",
    ]);
    let mut json_fits = Vec::new();
    for f in fits {
        let (fam, kind, c, tr, ho) = (f.family, &f.kind, f.constant, f.train_mean_l2, &f.held_out);
        t.row([
            fam.to_string(),
            kind_name(*kind).to_string(),
            format!("{c:.4}"),
            format!("{:.2} %", 100.0 * tr),
            format!("{:.2} % ± {:.2}", 100.0 * ho.l2_mean, 100.0 * ho.l2_se),
            pct(ho.energy_mean, ho.energy_se),
        ]);
        json_fits.push(crate::results::filters::FittedConstant {
            family: fam.into(),
            ndf: kind_name(*kind).into(),
            constant: c,
            train_mean_l2: tr,
            held_out: *ho,
        });
    }
    md.push_str(&t.to_string());
    json_fits
}

pub(super) const LISTING3_NOTE: &str = "\n## Seed 003 Listing 3 as printed\n\n`neighboringDir = 0.5 − 2·frac(pixelPosition·0.5)` with \
`avgNormal = normal + ddx_fine(normal)·dir.x + ddy_fine(normal)·dir.y` gives the four pixels of a 2×2 quad the same `avgNormal` up to \
the mixed second difference n₁₁ − n₁₀ − n₀₁ + n₀₀ (with pixel centres at .5 the top row and left column agree exactly, so coarse \
derivatives of `avgNormalProjected` are exactly zero; fine ones are that second difference, O(κ²) instead of O(κ)). As printed, the \
listing therefore adds (almost) no roughness (tests/filters.rs, `listing3_as_printed_is_quad_constant`). The row \"Kaplanyan rect \
(Listing 3, intended)\" projects each pixel's own normal in the tangent frame of the quad-average normal, as the text of Kaplanyan et al. \
describes.\n";

/// Summaries of the LEADR grid study and the Λ refit (their own reports are regenerated
/// by the same `regen --only filters`).
pub(super) fn embed(results: &Path) -> String {
    let mut s = String::new();
    for (file, title) in [
        ("leadr-grids.md", "LEADR numerical integration"),
        ("smith-lambda.md", "Smith Λ approximations"),
    ] {
        if let Ok(t) = std::fs::read_to_string(&results.join(file)) {
            s.push_str(&format!("\n## {title} (from results/{file})\n"));
            for line in t.lines().skip(1) {
                if let Some(h) = line.strip_prefix("## ") {
                    s.push_str(&format!("### {h}\n"));
                } else {
                    s.push_str(line);
                    s.push('\n');
                }
            }
        }
    }
    s
}

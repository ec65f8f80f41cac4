//! The report of the footprint study: results/filters.md section by section, and the
//! plots. Each function renders numbers computed elsewhere; none computes a fit.

use super::compute::{Curve, MapSection, ScreenSection, CLAMP_COLUMNS};
use super::constants::Fitted;
use super::plan::{kind_name, Plan};
use crate::error::Result;
use crate::filters::study::PixelFilter;
use crate::integrate::Preset;
use crate::report::plot::{loglog_svg, Panel, Series};
use crate::report::table::Table;

/// The energy, L2 and peak columns of one NDF for one filter.
fn agg_cells(a: &super::cases::Agg) -> [String; 3] {
    [a.energy.pct_signed(1), a.l2.pct(1), a.peak.pct_signed(1)]
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

/// A map's section of results/filters.md (table, worst cases, plot).
pub(super) fn map_section(md: &mut String, s: &MapSection, plan: &Plan) {
    md.push_str(&format!("## Map: {}\n\n", s.name));
    let mut t = Table::new(std::iter::once("filter").chain(NDF_COLUMNS));
    for r in &s.rows {
        t.row(std::iter::once(r.label.to_string()).chain(r.by_ndf.iter().flat_map(agg_cells)));
    }
    md.push_str(&t.to_string());
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
    for w in &s.worst {
        t.row([
            w.filter.to_string(),
            kind_name(w.kind).to_string(),
            w.alpha.to_string(),
            w.level.to_string(),
            format!("{:.4}", w.stats.mrl()),
            format!("{:?}", plan.views_deg[w.view]),
            w.energy.pct_signed(1),
            w.l2.pct(1),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!("\nLargest single-case Monte Carlo s.e. of an L2 error on this map: {:.2} %. L2 error against footprint size (GGX, all α and views): ![{}](filters-{}.svg)\n\n", 100.0 * s.mc_se_max, s.name, s.name));
}

fn series(curves: &[Curve]) -> Vec<Series> {
    curves
        .iter()
        .map(|(name, points)| Series {
            name: name.to_string(),
            points: points.clone(),
        })
        .collect()
}

/// results/filters-<map>.svg.
pub(super) fn map_svg(s: &MapSection) -> Result<String> {
    loglog_svg(
        &[Panel {
            title: format!("{}: lobe L2 error vs footprint (GGX)", s.name),
            x_label: "footprint width (texels)".into(),
            y_label: "relative L2 error".into(),
            series: series(&s.curves),
        }],
        900,
        560,
    )
}

/// results/filters-screen.svg.
pub(super) fn screen_svg(s: &ScreenSection) -> Result<String> {
    loglog_svg(
        &[Panel {
            title: "screen-space kernels: lobe L2 error vs curvature (GGX, Gaussian pixel)".into(),
            x_label: "κ (rad / pixel)".into(),
            y_label: "relative L2 error".into(),
            series: series(&s.curves),
        }],
        900,
        560,
    )
}

/// The screen-space section of results/filters.md.
pub(super) fn screen_section(md: &mut String, plan: &Plan, s: &ScreenSection) {
    md.push_str(&format!("## Screen-space kernels on synthetic curved surfaces\n\nThe pixel sees a surface whose normal is normalize(z + R_30° diag(κ, a·κ)·p) at screen offset p (pixels): curvature × distance gives κ rad/px, anisotropy a ∈ {:?}; (α, κ) ∈ {:?}; views θ ∈ {:?}° (φ = 20°). Derivatives are quad finite differences (ddx = n(1,0) − n(0,0)) exactly as a GPU forms them. The truth averages the exact per-normal lobe over the pixel footprint: a Gaussian of variance 0.25 px² (the kernels' own σ²) or the 1×1 box, by a tensor midpoint rule fine enough that neighbouring nodes' normals differ by < α/2 (up to 64² nodes).\n\n", plan.anisotropy, plan.screen_pairs, plan.screen_views_deg));
    for (pixel, rows) in &s.tables {
        md.push_str(&format!(
            "### Pixel footprint: {}\n\n",
            if *pixel == PixelFilter::Gaussian {
                "Gaussian σ² = 0.25 px²"
            } else {
                "1×1 box"
            }
        ));
        let mut t = Table::new(std::iter::once("kernel").chain(NDF_COLUMNS));
        for r in rows {
            t.row(std::iter::once(r.label.to_string()).chain(r.by_ndf.iter().flat_map(agg_cells)));
        }
        md.push_str(&t.to_string());
        md.push('\n');
    }
    md.push_str("L2 error against curvature per kernel (GGX, Gaussian pixel): ![screen](filters-screen.svg)\n\n");
    md.push_str("### The clamp δ = 0.18, by curvature (GGX, Gaussian pixel; L2 error, mean ± s.e. over the α paired with that κ, both anisotropies and all views)\n\n");
    let mut t = Table::new(std::iter::once("κ (rad/px)").chain(CLAMP_COLUMNS.iter().map(|c| c.1)));
    for (k, cells) in &s.clamp {
        t.row(std::iter::once(k.to_string()).chain(cells.iter().map(|a| a.l2.pct(1))));
    }
    md.push_str(&t.to_string());
}

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
            ho.l2.pct(2),
            ho.energy.pct_signed(1),
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
/// The LEADR and Λ reports, their headings one level down.
pub(super) fn embed(reports: &[(&str, &str, String)]) -> String {
    let mut s = String::new();
    for (file, title, t) in reports {
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
    s
}

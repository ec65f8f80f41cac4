//! results/visibility.md and its Pareto plots, from the study's [`super::summary::Summary`]
//! and measured cases: [`markdown`] and [`pareto_svg`] only format.

use super::compute::{Measured, ASHIKHMIN_WIDTH};
use super::summary::{HorizonSummary, MethodRow, Summary};
use crate::error::Result;
use crate::integrate::Preset;
use crate::report::plot::{loglog_svg_legend, Panel, Series};
use crate::report::table::Table;
fn table(md: &mut String, head: &str, groups: &[String], rows: &[MethodRow]) {
    let mut t = Table::new(
        [head, "params", "all", "max"]
            .into_iter()
            .chain(groups.iter().map(|g| g.as_str())),
    );
    for r in rows {
        t.row(
            [
                r.name.clone(),
                r.params.to_string(),
                r.all.sci(2, 1),
                format!("{:.2e}", r.max),
            ]
            .into_iter()
            .chain(r.groups.iter().map(|g| g.sci(2, 1))),
        );
    }
    md.push_str(&t.to_string());
}

/// The horizon tables alone (the `horizon` command on a user's height map).
pub fn horizon_markdown(h: &HorizonSummary) -> String {
    let mut md = String::from("### V_A(v)\n\n");
    table(&mut md, "method", &h.0, &h.1);
    md.push_str("\n### V_A(l, v)\n\n");
    table(
        &mut md,
        "joint form",
        &["at l = v".into(), "l ≠ v".into()],
        &h.2,
    );
    md
}

pub fn markdown(s: &Summary, m: &Measured, preset: Preset) -> String {
    let mut md = String::from(
        "# Visibility and procedural pre-filtering, measured (seed 004 §4–6, §8.1)\n\n",
    );
    md.push_str(&format!(
        "Written by `cargo run --release -- regen --only visibility` (preset {}) from `fits/visibility.toml`. Every number is a mean \
over cases ± its standard error (absolute errors of visible or lit fractions unless stated).\n\n",
        preset.name()
    ));
    md.push_str(&format!(
        "## Horizon maps (§4)\n\n**Truth**: two {n}² periodic height fields (noise: 48 waves, slope rms 0.5; bumps: spherical caps on flat ground). \
Each texel's horizon toward an azimuth is marched in 0.25-texel steps out to 32 texels on the bilinear heights; a footprint (2^L × 2^L texels, \
L = {:?}, {} per level and map) sees v in the fraction V_A(v) of its texels whose horizon at v's own azimuth lies below v (Eq 26), and \
V_A(l, v) = Σ V(l)V(v)/Σ V(v) (Eq 23). Views at 10°, 25° and 45° elevation, random azimuths; lights at v itself (the hotspot), 5° off v, and random. \
**Stored**: the four texture-axis azimuths, interpolated linearly in azimuth.\n\n### V_A(v)\n\n",
        m.plan.levels,
        m.plan.footprints,
        n = m.plan.height_size
    ));
    table(&mut md, "method", &s.horizon_groups, &s.horizon_single);
    md.push_str("\nThe Legendre rows are Nowrouzezahrai & Snyder's expansion of the step in sin e (Eq 29–30), clamped to [0, 1]; its error against the order \
is the column \"all\" down the rows (Gibbs ringing at the step keeps the maximum high). The two diagnostic rows read every texel's \
horizon at the view's own azimuth instead of interpolating four stored ones: the difference is what the four azimuths cost.\n\n### V_A(l, v)\n\n");
    table(
        &mut md,
        "joint form",
        &["at l = v".into(), "l ≠ v".into()],
        &s.horizon_joint,
    );
    md.push_str(&format!(
        "\nAt l = v the truth is 1 (every visible texel is lit). Eq 28 reproduces it wherever V_A(v) > 0 (worst |Eq 28 − 1| {:.1e}); Fournier's and \
the plain product give V_A(v) instead. Ashikhmin's β = exp(−γ²/(2·{ASHIKHMIN_WIDTH}²)) interpolates between them.\n\n",
        s.eq28_hotspot_max
    ));
    md.push_str(&format!(
        "## Shadow maps (§5)\n\n**Truth**: percentage-closer filtering over the footprint (Eq 31–32) with each texel's own receiver depth, {n}² shadow map \
of an orthographic light, four occluder scenes (a half-plane at depth 0.5; three overlapping rectangles at 0.3/0.5/0.7; a fence of 2-texel bars \
every 6 texels; a sphere of radius 0.3 centred at 0.5) over a parallel receiver (depth 0.9) and a tilted one (0.8 → 0.95 across the map). Footprints \
of 2^L texels, L = {:?}, {} per level and scene. Methods read the footprint's box-filtered parameters at the mean receiver depth d̄ (Eq 33).\n\n### Stored in f32\n\n",
        m.plan.shadow_levels,
        m.plan.shadow_footprints,
        n = m.plan.shadow_size
    ));
    let mut rows = vec![s.eq33_cost.clone()];
    rows.extend(s.shadow_f32.iter().cloned());
    table(&mut md, "method", &s.shadow_groups, &rows);
    md.push_str("\n### Stored in binary16\n\n");
    table(&mut md, "method", &s.shadow_groups, &s.shadow_f16);
    md.push_str("\n### VSM light bleeding, ESM divergence, precision limits\n\n");
    let mut t = Table::new(["scene", "VSM lit fraction where PCF = 0", "footprints"]);
    for (n, b, k) in &s.bleeding {
        t.row([n.clone(), b.sci(2, 1), k.to_string()]);
    }
    md.push_str(&t.to_string());
    md.push_str("\nVSM is exact for one planar occluder parallel to the receiver (proofs/vsm-single-plane.md); with overlapping layers the bound leaks light.\n\n");
    let mut t = Table::new([
        "ESM c",
        "error where some texel is deeper than d̄ (d < Z)",
        "elsewhere",
    ]);
    for (c, a, b) in &s.esm_divergence {
        t.row([c.to_string(), a.sci(2, 1), b.sci(2, 1)]);
    }
    md.push_str(&t.to_string());
    let mut t = Table::new(["warp", "largest c, f32", "largest c, binary16"]);
    for (n, a, b) in &s.precision {
        t.row([n.to_string(), format!("{a:.2}"), format!("{b:.2}")]);
    }
    md.push('\n');
    md.push_str(&t.to_string());
    md.push_str("\nBeyond these c the stored warp overflows to ∞ (the binary16 rows above show what the larger c cost).\n\n");
    md.push_str(&procedural_section(m));
    md.push_str("\n![error against parameters per texel](visibility.svg)\n\nns per lookup: results/performance.md (\"Visibility lookups\").\n");
    md
}

fn procedural_section(m: &Measured) -> String {
    let mut md = String::from("## Procedural maps (§6)\n\n### Colour: Fig. 6's pulse train ⌊2x⌋ mod 2, box footprints\n\nThe truth sums the pulses cell by cell; \
analytic integration uses F(b) − F(a) (proofs/box-filter-analytic-integration.md).\n\n");
    let mut t = Table::new([
        "width",
        "point sample",
        "global fading",
        "analytic F(b) − F(a)",
    ]);
    for r in &m.colour {
        t.row([
            r.width.to_string(),
            r.pulse[0].sci(2, 1),
            r.pulse[1].sci(2, 1),
            r.pulse[2].sci(2, 1),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\n### The 2D grid f(x)f(y) under a sheared footprint\n\nThe separable product of 1D analytic averages over the footprint's bounding box, against the exact clipped areas.\n\n");
    let mut t = Table::new(["scale", "rotation", "anisotropy", "mean absolute error"]);
    for (s, r, a, e) in &m.grid {
        t.row([s.to_string(), format!("{r}°"), a.to_string(), e.sci(2, 1)]);
    }
    md.push_str(&t.to_string());
    md.push_str("\n### Frequency clamping of a spectral sum (8 octaves, amplitude 2^−i)\n\nTerms with f·w ≤ c/2 kept, faded to 0 at f·w = c; widths 2^−8…2^−1; truth: each term's exact box average (sinc).\n\n");
    let mut t = Table::new(["threshold c", "mean absolute error"]);
    for (c, e) in &m.spectral {
        let n = if *c == 0.0 {
            "none (point sample)".to_string()
        } else {
            c.to_string()
        };
        t.row([n, e.sci(2, 1)]);
    }
    md.push_str(&t.to_string());
    md.push_str("\n### Procedural normals (§6.2): 32 height waves, slope rms 0.3, GGX α 0.1\n\nRelative L2 lobe error against the footprint-averaged BRDF \
(the footprint's normals sampled on a grid), views 0° and 60°.\n\n");
    let mut t = Table::new([
        "footprint width",
        "clamped normal only",
        "+ clamped terms' covariance (Bruneton et al.)",
        "box-averaged normal + vMF 2/κ",
    ]);
    for r in &m.normals {
        t.row([
            r.width.to_string(),
            r.l2[0].sci(2, 1),
            r.l2[1].sci(2, 1),
            r.l2[2].sci(2, 1),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\n## Correlations (§8.1): what Hypothesis 1's separation costs\n\nBumps height field, GGX α 0.3; relative L2 over the light hemisphere of the separated form against the joint footprint average (24 × 48 Gauss–Legendre light directions).\n\n");
    let mut t = Table::new([
        "footprint",
        "view elevation",
        "colour tied to slope: (Σk)(Σρ) vs Σkρ",
        "visibility tied to normals: V_A(l,v)·ρ_A vs ΣV(l)V(v)ρ/ΣV(v)",
    ]);
    for (l, e, c, v) in &m.correlation {
        t.row([
            format!("{0}×{0}", 1usize << l),
            format!("{e}°"),
            c.sci(2, 1),
            v.sci(2, 1),
        ]);
    }
    md.push_str(&t.to_string());
    md
}

pub fn pareto_svg(s: &Summary) -> Result<String> {
    let pts = |rows: &[MethodRow], f: &dyn Fn(&str) -> bool| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| f(&r.name))
            .map(|r| (r.params as f64, r.all.value))
            .collect()
    };
    let horizon = Panel {
        title: "Horizon maps: V_A(v)".into(),
        x_label: "parameters per texel".into(),
        y_label: "mean |error| of the visible fraction".into(),
        series: vec![
            Series {
                name: "Fournier ramp".into(),
                points: pts(&s.horizon_single, &|n| n.starts_with("Fournier")),
            },
            Series {
                name: "Tan et al. erf".into(),
                points: pts(&s.horizon_single, &|n| n.starts_with("Tan")),
            },
            Series {
                name: "Legendre".into(),
                points: pts(&s.horizon_single, &|n| n.starts_with("Legendre")),
            },
        ],
    };
    let best = |pre: &str| -> Vec<(f64, f64)> {
        let v: Vec<&MethodRow> = s
            .shadow_f32
            .iter()
            .filter(|r| r.name.starts_with(pre))
            .collect();
        v.iter()
            .min_by(|a, b| a.all.value.total_cmp(&b.all.value))
            .map(|r| vec![(r.params as f64, r.all.value)])
            .unwrap_or_default()
    };
    let shadow = Panel {
        title: "Shadow maps (f32): lit fraction".into(),
        x_label: "parameters per texel".into(),
        y_label: "mean |error| against PCF".into(),
        series: vec![
            Series {
                name: "VSM".into(),
                points: pts(&s.shadow_f32, &|n| n.starts_with("VSM")),
            },
            Series {
                name: "CSM".into(),
                points: pts(&s.shadow_f32, &|n| {
                    n.starts_with("CSM") && !n.contains("offset")
                }),
            },
            Series {
                name: "CSM, offset + scale".into(),
                points: pts(&s.shadow_f32, &|n| n.contains("offset")),
            },
            Series {
                name: "ESM (best c)".into(),
                points: best("ESM"),
            },
            Series {
                name: "EVSM (best c)".into(),
                points: best("EVSM"),
            },
        ],
    };
    loglog_svg_legend(
        &[horizon, shadow],
        1400,
        600,
        plotters::prelude::SeriesLabelPosition::UpperRight,
    )
}

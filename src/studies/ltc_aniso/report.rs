//! The anisotropic table's report: markdown, the design study's plot and the error heat
//! map, from the design study (`design`) and the summary (`summary`). Formats only.

use super::compute::Plan;
use super::design::{Design, DIMS};
use super::summary::{HeatMaps, MeanMax, Summary};
use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::report::table::Table;

fn pct(x: f64) -> String {
    format!("{:.2} %", 100.0 * x)
}

/// results/ltc-aniso.md.
pub(super) fn markdown(
    spec: &FitSpec,
    preset: Preset,
    pl: &Plan,
    s: &Summary,
    command: &str,
) -> String {
    let g = pl.grid;
    let mut md = format!(
        "# Anisotropic GGX LTC table\n\nWritten by `{command}` (preset {}) from `fits/{}.toml`. Target: the cosine-weighted anisotropic GGX BRDF (height-correlated Smith G2, F = 1) with α_x along a tangent at azimuth φ from T1 and α_y across it, in the frame engines build for their LTC lookup (T1 = the view projected on the tangent plane). The lobe is not symmetric about the view plane, so M⁻¹ takes the general production form of `ltc::aniso`: M⁻¹ ∝ [[a, 0, c], [e, 1, g], [b, h, d]] (the rotation about z the clamped cosine ignores zeroes one entry, the scale another: seven numbers; e = g = h = 0 is the isotropic form).\n\n## Design\n\n- **Parameterisation:** (r_x = √α_x, r_y = √α_y, φ, t = √(1 − cos θ)), each uniform: the isotropic table's two coordinates plus the second roughness and the tangent's azimuth. α = max(r², {}).\n- **Symmetry:** the tangent is a line (φ ≡ φ + π) and the mirror y → −y maps φ to π − φ with M⁻¹ → S·M⁻¹·S (S = diag(1, −1, 1): e, g, h change sign), so φ ∈ [0, π/2] covers every case. Swapping α_x and α_y is a quarter turn of the tangent, (α_y, α_x, π/2 − φ) = S·(α_x, α_y, φ)·S: only cells with α_x ≥ α_y are fitted ({} of {}), the others are their mirrors.\n- **Fit:** Nelder–Mead (argmin) on the relative L2 ({s}×{s} stratified samples per technique, the LTC and the VNDF; ≤ {} iterations) from three starts — the isotropic table's entries at √(α_x α_y) (results/fits/ltc-ggx.json), the same stretched toward the tangent, the isotropic table at max(α_x, α_y) — the best on a validation set kept, and only if it beats its start there; norm and fresnel by nested adaptive quadrature in half-vector space with the polar grid stretched along the roughness ellipse (tolerance 1e-7). Fit cost: results/performance.md (criterion's time per cell; the main job's wall clock per study).\n- **Storage:** one RGBA16F 2D array texture, width n_r (r_x), height n_t (t), 3 layers per (r_y, φ) node: (a, b, c, d), (norm, fresnel, 0, 0), (e, g, h, 0). The sampler interpolates (r_x, t) in hardware; the lookup blends the four (r_y, φ) neighbours itself: 12 fetches (`ltc_aniso.wgsl`; its f64 reference `AnisoTable::lookup`). A 3D texture would interpolate a third coordinate in hardware but cannot hold the fourth; array layers keep every API (WebGPU included) and one layout. The texture is kept non-square (n_t ≠ n_r): wgpu's GL backend (Bevy on WebGL2) creates a square 2D texture whose layer count is a multiple of 6 as a cube-map array (wgpu-hal's `get_info_from_desc`), and 3·n_r·n_φ layers is one whenever n_r·n_φ is even.\n\n",
        preset.name(),
        spec.name,
        g.alpha_min,
        s.cells_fitted,
        g.cells(),
        pl.iters,
        s = pl.samples
    );
    md.push_str(&format!("## The size/error trade\n\nDense lines of {} nodes through the domain along each coordinate (others at the base points {}), every node fitted as a table cell is; then every coarser spacing of the same nodes, the dropped nodes interpolated linearly (entries and norm, as the lookup does). Mean held-out relative L2 at the dropped nodes, and of the fits there (converged integrals, each within the error bar stated below):\n\n", pl.line, s.design.bases.iter().map(|b| format!("(r_x {:.2}, r_y {:.2}, φ {:.0}°, t {:.2})", b[0], b[1], b[2].to_degrees(), b[3])).collect::<Vec<_>>().join(" and ")));
    let mut t = Table::new([
        "dimension",
        "nodes over its range",
        "interpolated",
        "fitted",
        "penalty",
    ]);
    for p in &s.design.penalties {
        t.row([
            DIMS[p.dim].to_string(),
            p.n.to_string(),
            pct(p.interpolated),
            pct(p.fitted),
            format!("{:+.2} points", 100.0 * (p.interpolated - p.fitted)),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!("\n![penalties](ltc-aniso.svg)\n\nPredicted RMS error of a table between its cells: the fits' RMS at the cells ({}) and each dimension's penalty at its resolution added in squares (e² = e_fit² + Σ_d (e_interp,d² − e_fit,d²), the errors of independent perturbations adding in squares); beyond the study's finest spacing the penalty is extrapolated by h² (marked *):\n\n", pct(s.fit_rms)));
    let mut t = Table::new([
        "r_x × r_y × φ × t",
        "texels",
        "RGBA16F bytes",
        "predicted RMS rel. L2",
    ]);
    for p in &s.predictions {
        t.row([
            format!("{}×{}×{}×{}", p.size[0], p.size[1], p.size[2], p.size[3]),
            p.texels.to_string(),
            format!("{:.1} KiB", p.bytes_f16 as f64 / 1024.0),
            format!(
                "{}{}",
                pct(p.predicted_mean),
                if p.extrapolated { " *" } else { "" }
            ),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\nThe shipped table ({}×{}×{}×{}) measured at {} random cases between its cells (below): RMS {} (mean {}), against its prediction {} in the first row.\n\n",
        g.n_r, g.n_r, g.n_phi, g.n_t, s.between_table.count, pct(s.between_rms), pct(s.between_table.mean.value), pct(s.predictions[0].predicted_mean)
    ));
    md.push_str(&format!(
        "## Against what engines do today\n\n![cell errors](ltc-aniso-error.svg)\n\nEvery figure below is a held-out integral of `ltc::lobe_error` (relative L2 ‖f − norm·γ_M‖/‖f‖, and relative L1 where named), converged to its tolerance: the largest error bar of any cell's or case's figure is {:.1e} (as a fraction), far below the spread across cases, so a mean's ± is the standard error of the random sample of cases.\n\nAt the table's cells (mean / max over {} fitted cells): this fit {} / {} (relative L1 {} / {}); the isotropic table at α = √(α_x α_y) {} / {}; at max(α_x, α_y) {} / {}.\n\nAt {} random cases between cells (α_x, α_y uniform in √α, φ uniform on [0, π), θ uniform in t), each with the lookup a shader does (the interpolated norm included):\n\n",
        s.bar_max,
        s.cells.ours.count, pct(s.cells.ours.mean.value), pct(s.cells.ours.max), pct(s.cells_l1.mean.value), pct(s.cells_l1.max), pct(s.cells.iso_geo.mean.value), pct(s.cells.iso_geo.max), pct(s.cells.iso_max.mean.value), pct(s.cells.iso_max.max),
        s.between_table.count,
    ));
    let mut t = Table::new(["", "mean ± s.e.", "max"]);
    for (name, m) in [
        ("this table (f64)", &s.between_table),
        ("this table (f64), relative L1", &s.between_table_l1),
        (
            "this table (binary16, as stored in the texture)",
            &s.between_table_f16,
        ),
        ("isotropic table at √(α_x α_y)", &s.between_iso_geo),
        ("isotropic table at max(α_x, α_y)", &s.between_iso_max),
    ] {
        t.row([name.to_string(), m.mean.pct(2), pct(m.max)]);
    }
    md.push_str(&t.to_string());
    md.push_str("\nBy anisotropy (mean ± s.e. / max):\n\n");
    let mut t = Table::new([
        "α_max/α_min",
        "cases",
        "this table",
        "isotropic at √(α_x α_y)",
        "isotropic at max",
    ]);
    let both = |m: &MeanMax| format!("{} / {}", m.mean.pct(2), pct(m.max));
    for b in &s.by_anisotropy {
        t.row([
            b.label.to_string(),
            b.ours.count.to_string(),
            both(&b.ours),
            both(&b.iso_geo),
            both(&b.iso_max),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\nThe isotropic substitutes cannot turn their lobe toward the tangent, so their error grows with the anisotropy; at α_max/α_min ≤ 1.5 they are the isotropic table itself, and the anisotropic table's own interpolation error is what it pays for the extra dimensions.\n");
    md
}

/// results/ltc-aniso.svg: the interpolation penalty of each dimension against its
/// resolution.
pub(super) fn plot(d: &Design, pl: &Plan) -> Result<String> {
    use crate::report::plot::{loglog_svg, Panel, Series};
    let series = (0..4)
        .map(|dim| Series {
            name: DIMS[dim].into(),
            points: d
                .penalties
                .iter()
                .filter(|p| p.dim == dim)
                .map(|p| (p.n as f64, (p.interpolated - p.fitted).max(1e-6)))
                .collect(),
        })
        .collect();
    loglog_svg(
        &[Panel {
            title: format!(
                "interpolation penalty per dimension ({} node lines)",
                pl.line
            ),
            x_label: "nodes over the dimension's range".into(),
            y_label: "mean rel. L2 interpolated − fitted".into(),
            series,
        }],
        720,
        480,
    )
}

/// The polygon-light section.
pub(super) fn polygon_section(rows: &[super::compute::PolygonRow], mc: usize) -> String {
    let mut md = format!("\n## Polygon lights\n\nThe table as a shader reads it (binary16, interpolated at the case) × the quad (exact edges), and the isotropic table at √(α_x α_y), against MC of the true lobe over the quad (MIS of light-area and VNDF sampling, {mc} samples each, ± standard error); the error also as a fraction of the lobe's albedo:\n\n");
    let mut t = Table::new([
        "α_x",
        "α_y",
        "φ",
        "θ",
        "light",
        "MC truth",
        "this table",
        "rel. error",
        "error / albedo",
        "isotropic at √(α_x α_y)",
        "rel. error",
    ]);
    for r in rows {
        let c = &r.check;
        let rel = |x: f64| c.mc.rel_error_of(x);
        t.row([
            format!("{:.3}", r.case.ax),
            format!("{:.3}", r.case.ay),
            format!("{:.0}°", r.case.phi.to_degrees()),
            format!("{:.0}°", r.case.theta.to_degrees()),
            c.light.to_string(),
            c.mc.sci(4, 1),
            format!("{:.4e}", c.ltc_exact),
            rel(c.ltc_exact),
            format!(
                "{:+.2} %",
                100.0 * (c.ltc_exact - c.mc.value) / r.albedo.max(1e-300)
            ),
            format!("{:.4e}", r.iso_geo_exact),
            rel(r.iso_geo_exact),
        ]);
    }
    md.push_str(&t.to_string());
    md
}

/// results/ltc-aniso-error.svg: the fitted cells' held-out error, averaged over (φ, t)
/// on the (r_x, r_y) plane (fitted cells have r_x ≥ r_y; the mirror half is grey) and
/// over (r_x, r_y) on the (φ, t) plane.
pub(super) fn heatmap(h: &HeatMaps, pl: &Plan) -> Result<String> {
    use crate::report::plot::{heatmap_svg, HeatPanel};
    let g = pl.grid;
    let axis = |n: usize, top: f64| {
        (0..n)
            .map(|i| top * i as f64 / (n - 1) as f64)
            .collect::<Vec<f64>>()
    };
    heatmap_svg(
        &[
            HeatPanel {
                title: "mean over φ and θ (α_x ≥ α_y fitted)".into(),
                x: axis(g.n_r, 1.0),
                y: axis(g.n_r, 1.0),
                values: h.rx_ry.clone(),
                log_range: (-2.0, 0.3),
                x_label: "r_x = √α_x".into(),
                y_label: "r_y = √α_y".into(),
                log_axes: false,
                y_down: false,
                colour_label: "log10 relative L2 (held out)".into(),
            },
            HeatPanel {
                title: "mean over α_x and α_y".into(),
                x: axis(g.n_phi, 90.0),
                y: axis(g.n_t, 1.0),
                values: h.phi_t.clone(),
                log_range: (-2.0, 0.3),
                x_label: "φ (degrees)".into(),
                y_label: "t = √(1 − cos θ)  (t = 0: normal incidence, top)".into(),
                log_axes: false,
                y_down: true,
                colour_label: "log10 relative L2 (held out)".into(),
            },
        ],
        1300,
        620,
    )
}

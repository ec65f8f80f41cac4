//! The report of a table family: markdown and heat maps of what `measures` computed.
//! Formats only.

use super::compute::{Family, Fitted, Plan};
use super::measures::{Report, TableReport};
use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::{Figure, Preset};
use crate::ltc::held::Stats;
use crate::report::table::Table as MdTable;
use crate::studies::ltc_between::report::words as between_words;

fn table_section(
    md: &mut String,
    f: &Fitted,
    st: &Stats,
    r: &TableReport,
    file: &str,
    tol: crate::ltc::lobe_error::Tolerance,
) {
    md.push_str(&format!(
        "## {} (results/fits/{file}.json)\n\nTarget: {}.\n\nHeld-out error of every cell, as integrals over the whole sphere (`ltc::lobe_error`: adaptive cubature on charts that follow the lobe and the LTC, each figure ± the half-width its integrals' errors allow; {}, met in {} of {} cells). Relative L2 ‖f − norm·γ_M‖/‖f‖: mean {}, max {} at α = {:.3}, θ = {:.1}°. Relative L1 ∫|f − norm·γ_M|/∫f: mean {}, max {}. Mean Nelder–Mead iterations {:.0}. Bilinear pass: {} of {} cells moved. Fit cost: results/performance.md (criterion's time per cell; the main job's wall clock per study).\n\n",
        f.lobe.short(), f.lobe.describe(), tol.describe(), st.converged, st.cells, st.l2.mean.pct(2), st.l2.max.pct(1), st.worst_cell.0, st.worst_cell.1, st.l1.mean.pct(2), st.l1.max.pct(1), st.mean_iters,
        f.bilinear.cells_moved, f.table.grid.n * f.table.grid.n
    ));
    md.push_str(&format!("{}\n\n", r.sampled.sentence(st.l2.mean.value)));
    md.push_str("Worst cells:\n\n");
    let mut t = MdTable::new([
        "α", "θ", "a", "b", "c", "d", "norm", "fresnel", "rel. L2", "rel. L1",
    ]);
    for c in &r.worst {
        t.row([
            format!("{:.2e}", c.alpha),
            format!("{:.2}°", c.theta_deg),
            format!("{:.4e}", c.inv[0]),
            format!("{:+.4e}", c.inv[1]),
            format!("{:+.4e}", c.inv[2]),
            format!("{:.4e}", c.inv[3]),
            format!("{:.5}", c.norm),
            format!("{:.5}", c.fresnel),
            c.l2.pct(2),
            c.l1.pct(2),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\n{}\n\n",
        between_words(&r.between, "absent 1024")
    ));
    md.push_str("Storage precision (change of the held-out relative L2 per cell against the f64 table, ± the sum of the two figures' error bars; 0.01 = one point):\n\n");
    let mut t = MdTable::new([
        "storage",
        "mean change",
        "largest change",
        "where (α, θ)",
        "cells with a non-positive determinant",
    ]);
    for (s, name) in r.storage.iter().zip([
        "f32",
        "binary16, each entry to nearest",
        "binary16 as stored (neighbours chosen by the training L2, determinant and b's sign kept)",
    ]) {
        t.row([
            name.to_string(),
            s.mean_change.sci_signed(2, 1),
            s.largest_change.sci_signed(2, 1),
            format!("({:.2e}, {:.1}°)", s.at.0, s.at.1),
            s.mirrored.to_string(),
        ]);
    }
    md.push_str(&t.to_string());
    if r.storage_left_out > 0 {
        md.push_str(&format!("\n{} cells have an albedo below binary16's normal range (6.1e-5) and are left out above: binary16 stores their weight as a subnormal or 0, which is what they are worth on screen.\n", r.storage_left_out));
    }
    md.push_str(&format!(
        "\nnorm (the directional albedo, stored as the weight) by nested adaptive Gauss–Kronrod (tolerance {:e} absolute; largest error estimate {:.1e}, an absolute error to read against the cell's albedo); against stratified MC of the lobe's own sampler ({}² samples) on {} cells: largest difference {:.2} standard errors ({} cells with an albedo below {:e} left out). tests/ltc_targets.rs checks the quadrature against an independent Gauss–Legendre product rule.\n\n",
        crate::ltc::fit::ALBEDO_TOL, r.norm_error_max, super::measures::NORM_MC_SIDE, r.norm_mc_cells, r.norm_vs_mc_max_se, r.norm_mc_left_out, super::measures::NORM_MC_MIN
    ));
    let fx = &r.facts;
    md.push_str(&format!(
        "What the BRDF does that an engine may not expect: its albedo exceeds 1 in {} of {} cells (largest {:.3} at α = {:.3}, θ = {:.2}°: {}); the fitted LTC puts {:.1} % of its mass below the horizon on average and up to {:.1} % (at α = {:.3}, θ = {:.1}°), mass a horizon-clipped shader loses — (1 − M_zz/‖M_z·‖)/2 in closed form, the clamped cosine's share of the half-space that M maps below the horizon.\n\n",
        fx.albedo_above_one, st.cells, fx.albedo_max, fx.albedo_max_at.0, fx.albedo_max_at.1,
        f.lobe.why_above_one(),
        100.0 * fx.below_horizon_mean, 100.0 * fx.below_horizon_max, fx.below_horizon_at.0, fx.below_horizon_at.1
    ));
    md.push_str("Polygon lights: the fitted cell's norm × the LTC integral of M⁻¹P against MC of the true lobe over the quad (MIS of light-area and lobe sampling, ± standard error; the relative error's first-order bias, (s.e./truth)², is below its own s.e. on every row whose s.e. is under 10 %):\n\n");
    let mut t = MdTable::new([
        "α",
        "θ",
        "light",
        "MC truth",
        "LTC (exact edges)",
        "rel. error",
        "error / albedo",
        "LTC (rational edges)",
        "rel. error",
    ]);
    for (a, th, norm, p) in &r.polygons {
        let rel = |x: f64| p.mc.rel_error_of(x);
        t.row([
            format!("{a:.3}"),
            format!("{th:.1}°"),
            p.light.to_string(),
            p.mc.sci(4, 1),
            format!("{:.4e}", p.ltc_exact),
            rel(p.ltc_exact),
            Figure::with_se((p.ltc_exact - p.mc.value) / norm, p.mc.error / norm).pct_signed(3),
            format!("{:.4e}", p.ltc_rational),
            rel(p.ltc_rational),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\nThe relative error of a light that catches almost none of the lobe (a sheen lobe seen near normal incidence puts its energy at grazing directions) is large however small the absolute one; the error / albedo column is the misplaced energy as a fraction of the cell's whole albedo.\n\n");
}

/// results/<family>.md.
#[allow(clippy::too_many_arguments)]
pub(super) fn markdown(
    fam: &Family,
    spec: &FitSpec,
    preset: Preset,
    pl: &Plan,
    main: &Fitted,
    variant: &Fitted,
    r: &Report,
    held: &[Stats; 2],
    command: &str,
) -> String {
    let mut md = format!(
        "# {}\n\nWritten by `{command}` (preset {}) from `fits/{}.toml`. Both tables go through the fitter of the GGX table (`ltc::fit`, generic over the target): grid {n}×{n} in (r = √α, t = √(1 − cos θ)), α = max(r², {}), θ clamped to {}°; Nelder–Mead (argmin, ≤ {it} iterations per stage) on the cubic metric with {s}×{s} stratified samples per technique (the LTC and the lobe's own sampler{nodes}), warm-started from the rougher neighbour (rayon over θ columns), then an L2 polish ({polish}, kept where a validation set agrees), one bilinear pass (`ltc::smooth`) and the binary16 storage (`ltc::storage`). Layout and production form as the GGX table: M⁻¹ ∝ [[a, 0, c], [0, 1, 0], [b, 0, d]], texture 1 = (a, b, c, d), texture 2 = (norm, fresnel, 0, 0). Engine files: results/textures/ (README).\n\n![error](./{}-error.svg)\n\n",
        fam.title,
        preset.name(),
        spec.name,
        pl.alpha_min,
        crate::ltc::hemisphere::THETA_MAX_DEG,
        fam.name,
        n = pl.n,
        s = pl.samples,
        polish = pl.polish.describe(pl.samples),
        nodes = pl.nodes.describe(),
        it = pl.max_iters
    );
    table_section(&mut md, main, &held[0], &r.main, fam.name, pl.tolerance());
    table_section(
        &mut md,
        variant,
        &held[1],
        &r.variant,
        fam.variant_name,
        pl.tolerance(),
    );
    md.push_str(CROSS);
    md
}

/// Where the cost of shading one lobe with the other's table went: a study of its own,
/// run on request.
const CROSS: &str = "## One lobe shaded with the other's table, or with none\n\nRun on request, not part of the tables' fit: `cargo run --release -- regen --only ltc-lobe-cross` (results/ltc-lobe-cross.md) judges, cell by cell on the same held-out integrals, each family's main table against its variant's lobe and the variant's table against the main lobe, the clamped cosine with weight 1 and with the table's norm, and a table with its norm clamped to 1.\n\n";

/// results/<family>-error.svg: both tables' held-out error.
pub(super) fn heatmaps(main: &Fitted, variant: &Fitted) -> Result<String> {
    use crate::report::plot::heatmap_svg;
    use crate::studies::ltc_error_map::ltc_error_panel;
    let panel = |f: &Fitted| ltc_error_panel(&f.table, &format!("{}: relative L2", f.lobe.short()));
    heatmap_svg(&[panel(main), panel(variant)], 1300, 620)
}

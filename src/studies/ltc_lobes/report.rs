//! The report of a table family, the GGX table's measures for each table: held-out
//! relative L2 per cell and the worst cells, the error between cells (the bilinear
//! interpolation a shader samples), what f32 and binary16 storage cost, the albedo by
//! quadrature against Monte Carlo, the polygon integral against MC of the true lobe
//! (a light straddling the horizon included), and the cost of shading one lobe with the
//! other's table. Compute (`compute`) → markdown (`markdown`) → heat maps (`heatmaps`).

use super::{Family, Fitted, Plan};
use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::ltc::compare::{cell_error_of, midpoint_error_of, Shipped};
use crate::ltc::fit::{held_out_stats, inverse_from_production, Cell, Table};
use crate::ltc::lobes::Lobe;
use crate::ltc::polygon::{check_cell, PolygonCheck};
use crate::ltc::target::LtcTarget;
use serde::Serialize;

/// One cell, as reported among the worst.
#[derive(Clone, Debug, Serialize)]
pub struct CellRow {
    pub alpha: f64,
    pub theta_deg: f64,
    pub inv: [f64; 4],
    pub norm: f64,
    pub fresnel: f64,
    pub err_l2: f64,
}

/// (mean, max, (α, θ°) of the max) of a set of per-place errors.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Spread {
    pub mean: f64,
    pub max: f64,
    pub at: (f64, f64),
    pub count: usize,
}

fn spread(v: &[(f64, (f64, f64))]) -> Spread {
    let ok: Vec<&(f64, (f64, f64))> = v.iter().filter(|x| x.0.is_finite()).collect();
    let worst = ok
        .iter()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|x| **x)
        .unwrap_or((f64::NAN, (f64::NAN, f64::NAN)));
    Spread {
        mean: ok.iter().map(|x| x.0).sum::<f64>() / ok.len().max(1) as f64,
        max: worst.0,
        at: worst.1,
        count: ok.len(),
    }
}

/// The change of the held-out relative L2 that a storage precision costs.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct StorageCost {
    pub mean_change: f64,
    pub largest_change: f64,
    pub at: (f64, f64),
    pub singular: usize,
}

/// The smallest normal binary16 number.
const F16_NORMAL_MIN: f64 = 6.103515625e-5;

/// One table's measures.
#[derive(Clone, Debug, Serialize)]
pub struct TableReport {
    pub worst: Vec<CellRow>,
    /// The production inverse interpolated at every square centre.
    pub between: Spread,
    /// f32, binary16 to nearest, binary16 as stored.
    pub storage: [StorageCost; 3],
    /// Cells with an albedo below binary16's normal range (left out of `storage`).
    pub storage_left_out: usize,
    /// Largest quadrature error estimate of the norm.
    pub norm_error_max: f64,
    /// Largest |quadrature − MC| in units of the MC standard error over the checked cells.
    pub norm_vs_mc_max_se: f64,
    pub norm_mc_cells: usize,
    /// Cells with an albedo below 1e-6, left out of the MC check.
    pub norm_mc_left_out: usize,
    /// (α, θ°, the cell's albedo, the check).
    pub polygons: Vec<(f64, f64, f64, PolygonCheck)>,
}

/// The cost of shading one lobe with the other's table.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Cross {
    /// The main table against the variant's lobe.
    pub main_table_for_variant: Spread,
    /// The variant's table against the main lobe.
    pub variant_table_for_main: Spread,
    /// The clamped cosine (M = I) with weight 1 against the main lobe: Lambert, what an
    /// engine without this table shades area lights with.
    pub cosine_unit_for_main: Spread,
    /// The clamped cosine with the main table's norm (energy-correct Lambert).
    pub cosine_norm_for_main: Spread,
}

/// Everything the report shows.
pub struct Report {
    pub main: TableReport,
    pub variant: TableReport,
    pub cross: Cross,
}

fn flat(t: &Table) -> Vec<&Cell> {
    t.cells.iter().flatten().collect()
}

/// The table in the shipped layout (for the between-cell measure).
fn as_shipped(t: &Table) -> Shipped {
    let n = t.grid.n;
    Shipped {
        n,
        mat: (0..n * n).map(|k| t.cells[k / n][k % n].inv).collect(),
        mag: (0..n * n)
            .map(|k| [t.cells[k / n][k % n].norm, 0.0])
            .collect(),
    }
}

/// Every cell of `t` against `lobe` at its (α, θ): the held-out relative L2 of the
/// entries `entries(cell)`; NaN where singular.
fn against(
    label: &str,
    t: &Table,
    lobe: Lobe,
    n: usize,
    entries: &(dyn Fn(&Cell) -> [f64; 6] + Sync),
) -> Result<Vec<(f64, (f64, f64))>> {
    let cells = flat(t);
    let errs: Vec<Option<f64>> = crate::memo::map_items(label, &cells, |c| {
        let e = entries(c);
        let tgt = lobe.target(c.alpha, c.theta)?;
        Ok(cell_error_of(&tgt, &[e[0], e[1], e[2], e[3]], e[4], n)
            .ok()
            .map(|x| x.0))
    })?;
    Ok(errs
        .into_iter()
        .zip(&cells)
        .map(|(v, c)| (v.unwrap_or(f64::NAN), (c.alpha, c.theta.to_degrees())))
        .collect())
}

fn table_report(f: &Fitted, pl: &Plan) -> Result<TableReport> {
    use crate::codegen::table::rounded;
    let t = &f.table;
    let n = t.grid.n;
    let held = 2 * pl.samples;
    let mut cells = flat(t);
    cells.sort_by(|a, b| b.err_l2.total_cmp(&a.err_l2));
    let worst = cells
        .iter()
        .take(6)
        .map(|c| CellRow {
            alpha: c.alpha,
            theta_deg: c.theta.to_degrees(),
            inv: c.inv,
            norm: c.norm,
            fresnel: c.fresnel,
            err_l2: c.err_l2,
        })
        .collect();
    // between cells: every square centre
    let sh = as_shipped(t);
    let target = |a: f64, th: f64| f.lobe.target(a, th);
    let squares: Vec<(usize, usize)> = (0..n - 1)
        .flat_map(|j| (0..n - 1).map(move |i| (i, j)))
        .collect();
    let mid_errs: Vec<Option<f64>> =
        crate::memo::map_items("lobe table between cells", &squares, |&(i, j)| {
            midpoint_error_of(&sh, i, j, held, t.grid.alpha_min, &target)
        })?;
    let mids: Vec<(f64, (f64, f64))> = squares
        .iter()
        .zip(mid_errs)
        .map(|(&(i, j), e)| {
            let r = (i as f64 + 0.5) / (n - 1) as f64;
            let tt = (j as f64 + 0.5) / (n - 1) as f64;
            let alpha = (r * r).max(t.grid.alpha_min);
            (
                e.unwrap_or(f64::NAN),
                (alpha, (1.0 - tt * tt).clamp(0.0, 1.0).acos().to_degrees()),
            )
        })
        .collect();
    // storage: f64, f32, f16 nearest, f16 stored
    let full = |c: &Cell| [c.inv[0], c.inv[1], c.inv[2], c.inv[3], c.norm, c.fresnel];
    let base = against("lobe table f64", t, f.lobe, held, &full)?;
    let mut storage = Vec::new();
    for pick in 0..3 {
        let e = against(
            &format!("lobe table storage {pick}"),
            t,
            f.lobe,
            held,
            &|c: &Cell| match pick {
                0 => rounded(&full(c), false),
                1 => rounded(&full(c), true),
                _ => c.half,
            },
        )?;
        let (mut sum, mut cnt, mut worst, mut at, mut sing) = (0.0, 0usize, 0.0f64, (0.0, 0.0), 0);
        for ((b, s), c) in base.iter().zip(&e).zip(flat(t)) {
            // an albedo below binary16's normal range is stored as (nearly) nothing
            if c.norm < F16_NORMAL_MIN {
                continue;
            }
            match (b.0.is_finite(), s.0.is_finite()) {
                (true, true) => {
                    let d = s.0 - b.0;
                    sum += d;
                    cnt += 1;
                    if d.abs() > worst.abs() {
                        (worst, at) = (d, b.1);
                    }
                }
                (true, false) => sing += 1,
                _ => {}
            }
        }
        storage.push(StorageCost {
            mean_change: sum / cnt.max(1) as f64,
            largest_change: worst,
            at,
            singular: sing,
        });
    }
    // the norm by quadrature against stratified MC (256² samples of the lobe's sampler)
    let step = (n / 8).max(1);
    let probe: Vec<&Cell> = (0..n)
        .step_by(step)
        .flat_map(|j| (0..n).step_by(step).map(move |i| (i, j)))
        .map(|(i, j)| &t.cells[j][i])
        .collect();
    let zs: Vec<Option<f64>> = crate::memo::map_items("lobe norm against MC", &probe, |c| {
        let tgt = f.lobe.target(c.alpha, c.theta)?;
        let (m, _, se, _) = tgt.moments(256);
        // cells whose albedo is below 1e-6 (sheen seen head-on at the smallest α) are
        // left out: their energy is invisible and their MC has almost no samples
        Ok((c.norm >= 1e-6).then(|| (m - c.norm).abs() / se.max(1e-300)))
    })?;
    // polygons: four cells × four lights
    let mut polygons = Vec::new();
    for (ai, tj) in [
        (n / 2, n / 4),
        (n / 4, n / 2),
        (n - 1, 3 * n / 4),
        (n / 8 + 1, n - 1),
    ] {
        let c = &t.cells[tj.min(n - 1)][ai.min(n - 1)];
        let tgt = f.lobe.target(c.alpha, c.theta)?;
        let minv = inverse_from_production(&c.inv);
        for p in check_cell(&tgt, &minv, c.norm, c.theta, pl.mc)? {
            polygons.push((c.alpha, c.theta.to_degrees(), c.norm, p));
        }
    }
    Ok(TableReport {
        worst,
        between: spread(&mids),
        storage: [storage[0], storage[1], storage[2]],
        storage_left_out: flat(t).iter().filter(|c| c.norm < F16_NORMAL_MIN).count(),
        norm_error_max: flat(t).iter().map(|c| c.norm_se).fold(0.0, f64::max),
        norm_vs_mc_max_se: zs.iter().flatten().cloned().fold(0.0, f64::max),
        norm_mc_cells: zs.iter().flatten().count(),
        norm_mc_left_out: zs.iter().filter(|z| z.is_none()).count(),
        polygons,
    })
}

/// All measures of both tables of a family.
pub(super) fn compute(fam: &Family, main: &Fitted, variant: &Fitted, pl: &Plan) -> Result<Report> {
    let held = 2 * pl.samples;
    let full = |c: &Cell| [c.inv[0], c.inv[1], c.inv[2], c.inv[3], c.norm, c.fresnel];
    Ok(Report {
        main: table_report(main, pl)?,
        variant: table_report(variant, pl)?,
        cross: Cross {
            main_table_for_variant: spread(&against(
                "main table for the variant",
                &main.table,
                fam.variant,
                held,
                &full,
            )?),
            variant_table_for_main: spread(&against(
                "variant table for the main lobe",
                &variant.table,
                fam.main,
                held,
                &full,
            )?),
            cosine_unit_for_main: spread(&against(
                "cosine, unit norm",
                &main.table,
                fam.main,
                held,
                &|_| [1.0, 0.0, 0.0, 1.0, 1.0, 0.0],
            )?),
            cosine_norm_for_main: spread(&against(
                "cosine, fitted norm",
                &main.table,
                fam.main,
                held,
                &|c| [1.0, 0.0, 0.0, 1.0, c.norm, 0.0],
            )?),
        },
    })
}

fn pct(x: f64) -> String {
    format!("{:.2} %", 100.0 * x)
}

fn table_section(md: &mut String, f: &Fitted, r: &TableReport, file: &str) {
    let st = held_out_stats(&f.table);
    md.push_str(&format!(
        "## {} (results/fits/{file}.json)\n\nTarget: {}.\n\nHeld-out relative L2 ‖f − norm·γ_M‖/‖f‖ (a fresh, twice finer sample set per cell): mean {}, max {} at α = {:.3}, θ = {:.1}°; mean cubic metric {:.2e}; mean Nelder–Mead iterations {:.0}. Bilinear pass: {} of {} cells moved. Fit cost: results/performance.md (criterion's time per cell; the main job's wall clock per study).\n\n",
        f.lobe.short(), f.lobe.describe(), pct(st.mean_l2), pct(st.max_l2), st.worst_cell.0, st.worst_cell.1, st.mean_cubic, st.mean_iters,
        f.bilinear.cells_moved, f.table.grid.n * f.table.grid.n
    ));
    md.push_str("Worst cells:\n\n| α | θ | a | b | c | d | norm | fresnel | rel. L2 |\n|---|---|---|---|---|---|---|---|---|\n");
    for c in &r.worst {
        md.push_str(&format!(
            "| {:.2e} | {:.2}° | {:.4e} | {:+.4e} | {:+.4e} | {:.4e} | {:.5} | {:.5} | {} |\n",
            c.alpha,
            c.theta_deg,
            c.inv[0],
            c.inv[1],
            c.inv[2],
            c.inv[3],
            c.norm,
            c.fresnel,
            pct(c.err_l2)
        ));
    }
    md.push_str(&format!(
        "\nBetween cells (what a shader sampling the table bilinearly sees): the production inverse interpolated at the centres of all {} squares, judged against the lobe there with its exact norm: mean {}, max {} at α = {:.3}, θ = {:.1}°.\n\n",
        r.between.count, pct(r.between.mean), pct(r.between.max), r.between.at.0, r.between.at.1
    ));
    md.push_str("Storage precision (change of the held-out relative L2 per cell against the f64 table; 0.01 = one point):\n\n| storage | mean change | largest change | where (α, θ) | singular cells |\n|---|---|---|---|---|\n");
    for (s, name) in r.storage.iter().zip([
        "f32",
        "binary16, each entry to nearest",
        "binary16 as stored (neighbours chosen by the training L2)",
    ]) {
        md.push_str(&format!(
            "| {name} | {:+.2e} | {:+.2e} | ({:.2e}, {:.1}°) | {} |\n",
            s.mean_change, s.largest_change, s.at.0, s.at.1, s.singular
        ));
    }
    if r.storage_left_out > 0 {
        md.push_str(&format!("\n{} cells have an albedo below binary16's normal range (6.1e-5) and are left out above: binary16 stores their weight as a subnormal or 0, which is what they are worth on screen.\n", r.storage_left_out));
    }
    md.push_str(&format!(
        "\nnorm (the directional albedo, stored as the weight) by nested adaptive Gauss–Kronrod (tolerance 1e-9; largest error estimate {:.1e}); against stratified MC of the lobe's own sampler (256² samples) on {} cells: largest difference {:.2} standard errors ({} cells with an albedo below 1e-6 left out). tests/ltc_targets.rs checks the quadrature against an independent Gauss–Legendre product rule to 1e-6 (relative, with an absolute floor of 1e-12).\n\n",
        r.norm_error_max, r.norm_mc_cells, r.norm_vs_mc_max_se, r.norm_mc_left_out
    ));
    md.push_str("Polygon lights: the fitted cell's norm × the LTC integral of M⁻¹P against MC of the true lobe over the quad (MIS of light-area and lobe sampling, ± standard error):\n\n| α | θ | light | MC truth | LTC (exact edges) | rel. error | error / albedo | LTC (rational edges) | rel. error |\n|---|---|---|---|---|---|---|---|---|\n");
    for (a, th, norm, p) in &r.polygons {
        let rel = |x: f64| crate::report::rel_vs_mc(x, p.mc, p.mc_se);
        md.push_str(&format!(
            "| {a:.3} | {th:.1}° | {} | {:.4e} ± {:.1e} | {:.4e} | {} | {:+.3} % ± {:.3} | {:.4e} | {} |\n",
            p.light, p.mc, p.mc_se, p.ltc_exact, rel(p.ltc_exact), 100.0 * (p.ltc_exact - p.mc) / norm, 100.0 * p.mc_se / norm, p.ltc_rational, rel(p.ltc_rational)
        ));
    }
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
    command: &str,
) -> String {
    let mut md = format!(
        "# {}\n\nWritten by `{command}` (preset {}) from `fits/{}.toml`. Both tables go through the fitter of the GGX table (`ltc::fit`, generic over the target): grid {n}×{n} in (r = √α, t = √(1 − cos θ)), α = max(r², {}), θ clamped to 89.99°; Nelder–Mead (argmin) on the cubic metric with {s}×{s} stratified samples per technique (the LTC and the lobe's own sampler), warm-started from the rougher neighbour (rayon over θ columns), then an L2 polish, one bilinear pass (`ltc::smooth`) and the binary16 storage (`ltc::storage`). Layout and production form as the GGX table: M⁻¹ ∝ [[a, 0, c], [0, 1, 0], [b, 0, d]], texture 1 = (a, b, c, d), texture 2 = (norm, fresnel, 0, 0). Engine files: results/textures/ (README).\n\n![error](./{}-error.svg)\n\n",
        fam.title,
        preset.name(),
        spec.name,
        spec.domain.alpha_min,
        fam.name,
        n = pl.n,
        s = pl.samples
    );
    table_section(&mut md, main, &r.main, fam.name);
    table_section(&mut md, variant, &r.variant, fam.variant_name);
    md.push_str(&format!(
        "## One lobe shaded with the other's table\n\nHeld-out relative L2 per cell, with the table's own norm:\n\n| table | judged against | mean | max | where (α, θ) |\n|---|---|---|---|---|\n| {} | {} | {} | {} | ({:.3}, {:.1}°) |\n| {} | {} | {} | {} | ({:.3}, {:.1}°) |\n\n",
        main.lobe.short(), variant.lobe.short(), pct(r.cross.main_table_for_variant.mean), pct(r.cross.main_table_for_variant.max), r.cross.main_table_for_variant.at.0, r.cross.main_table_for_variant.at.1,
        variant.lobe.short(), main.lobe.short(), pct(r.cross.variant_table_for_main.mean), pct(r.cross.variant_table_for_main.max), r.cross.variant_table_for_main.at.0, r.cross.variant_table_for_main.at.1,
    ));
    let c = &r.cross;
    let unit = if matches!(main.lobe, Lobe::BurleyPaper | Lobe::BurleyEngines) {
        format!(
            "with weight 1 (Lambert, as Bevy shades area lights' diffuse) mean {}, max {} at ({:.3}, {:.1}°); ",
            pct(c.cosine_unit_for_main.mean), pct(c.cosine_unit_for_main.max), c.cosine_unit_for_main.at.0, c.cosine_unit_for_main.at.1
        )
    } else {
        String::new()
    };
    md.push_str(&format!(
        "Without a table: the clamped cosine (M = I) against the {} lobe — {unit}with the table's norm (energy-correct) mean {}, max {} at ({:.3}, {:.1}°).\n\n",
        main.lobe.short(),
        pct(c.cosine_norm_for_main.mean), pct(c.cosine_norm_for_main.max), c.cosine_norm_for_main.at.0, c.cosine_norm_for_main.at.1,
    ));
    md
}

/// results/<family>-error.svg: both tables' held-out error.
pub(super) fn heatmaps(main: &Fitted, variant: &Fitted) -> Result<String> {
    use crate::report::plot::{heatmap_svg, ltc_error_panel};
    let panel = |f: &Fitted| ltc_error_panel(&f.table, &format!("{}: relative L2", f.lobe.short()));
    heatmap_svg(&[panel(main), panel(variant)], 1300, 620)
}

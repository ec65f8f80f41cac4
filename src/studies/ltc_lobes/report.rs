//! The report of a table family, the GGX table's measures for each table: held-out
//! relative L2 per cell and the worst cells, the error between cells (the bilinear
//! interpolation a shader samples), what f32 and binary16 storage cost, the albedo by
//! quadrature against Monte Carlo, the polygon integral against MC of the true lobe
//! (a light straddling the horizon included), and the cost of shading one lobe with the
//! other's table. Compute (`compute`) → markdown (`markdown`) → heat maps (`heatmaps`).

use super::compute::{Family, Fitted, Plan};
use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::ltc::compare::{cell_error_of, midpoint_error_of, Shipped};
use crate::ltc::fit::{inverse_from_production, Cell, Table};
use crate::ltc::held::held_out_stats;
use crate::ltc::lobe_error::{Bounded, LobeError, Spread};
use crate::ltc::lobes::Lobe;
use crate::ltc::polygon::{check_cell, PolygonCheck};
use crate::ltc::target::LtcTarget;
use crate::memo::Memo;
use crate::report::table::Table as MdTable;
use serde::Serialize;

/// One cell, as reported among the worst.
#[derive(Clone, Debug, Serialize)]
pub struct CellRow {
    pub alpha: f64,
    pub theta_deg: f64,
    pub inv: [f64; 4],
    pub norm: f64,
    pub fresnel: f64,
    pub l2: Bounded,
    pub l1: Bounded,
}

/// Both held-out figures over a set of places, with where the largest relative L2 is.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Located {
    pub l2: Spread,
    pub l1: Spread,
    /// (α, θ°) of the largest relative L2.
    pub at: (f64, f64),
}

fn located(v: &[(Option<LobeError>, (f64, f64))]) -> Located {
    let l2 = Spread::of(v.iter().map(|x| x.0.as_ref().map(|e| &e.l2)));
    let l1 = Spread::of(v.iter().map(|x| x.0.as_ref().map(|e| &e.l1)));
    Located {
        l2,
        l1,
        at: v
            .get(l2.argmax)
            .map(|x| x.1)
            .unwrap_or((f64::NAN, f64::NAN)),
    }
}

/// The change of the held-out relative L2 that a storage precision costs, each change
/// ± the sum of the two figures' error bars.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct StorageCost {
    pub mean_change: f64,
    pub mean_bar: f64,
    pub largest_change: f64,
    pub largest_bar: f64,
    pub at: (f64, f64),
    /// Cells whose stored matrix has a non-positive determinant (a mirrored lobe).
    pub mirrored: usize,
}

/// What the BRDF itself does that engines may not expect.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Facts {
    /// Cells whose albedo (the stored norm) exceeds 1.
    pub albedo_above_one: usize,
    pub albedo_max: f64,
    /// (α, θ°) of the largest albedo.
    pub albedo_max_at: (f64, f64),
    /// The LTC's mass below the horizon, (1 − M_zz/‖M_z·‖)/2 (closed form; a
    /// horizon-clipped shader loses it): mean and largest over the cells.
    pub below_horizon_mean: f64,
    pub below_horizon_max: f64,
    pub below_horizon_at: (f64, f64),
}

/// The albedo below which a lobe's relative error is left out of the between-cell means
/// (a ten-thousandth of a white light's energy).
pub const VISIBLE_ALBEDO: f64 = 1e-4;

/// The smallest normal binary16 number.
const F16_NORMAL_MIN: f64 = 6.103515625e-5;

/// One table's measures.
#[derive(Clone, Debug, Serialize)]
pub struct TableReport {
    pub worst: Vec<CellRow>,
    /// The production inverse interpolated at every square centre whose lobe has an
    /// albedo of at least [`VISIBLE_ALBEDO`].
    pub between: Located,
    /// Squares left out of `between` (albedo below [`VISIBLE_ALBEDO`]).
    pub between_left_out: usize,
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
    pub facts: Facts,
    /// The earlier sampled estimate of the cells' relative L2, to say what changed.
    pub sampled: crate::ltc::held::Sampled,
}

/// The cost of shading one lobe with the other's table, or with no table.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Cross {
    /// The main table against the variant's lobe.
    pub main_table_for_variant: Located,
    /// The variant's table against the main lobe.
    pub variant_table_for_main: Located,
    /// The clamped cosine (M = I) with weight 1 against the main lobe: Lambert, what an
    /// engine without this table shades area lights with.
    pub cosine_unit_for_main: Located,
    /// The clamped cosine with the main table's norm (energy-correct Lambert).
    pub cosine_norm_for_main: Located,
    /// The main table with its norm clamped to ≤ 1 (a bounded table), on the cells whose
    /// albedo exceeds 1, and the same cells with the true norm.
    pub bounded_main: Located,
    pub true_main_where_bounded: Located,
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

fn full(c: &Cell) -> ([f64; 4], f64) {
    (c.inv, c.norm)
}

/// Every cell of `t` against `lobe` at its (α, θ): the held-out figures of each of the
/// entries `entries(cell)` (judged together, in one cubature per cell).
fn against(
    label: &str,
    t: &Table,
    lobe: Lobe,
    entries: &(dyn Fn(usize, usize, &Cell) -> Vec<([f64; 4], f64)> + Sync),
) -> Result<Vec<Vec<(Option<LobeError>, (f64, f64))>>> {
    let cells = flat(t);
    let n = t.grid.n;
    let errs: Vec<Vec<Option<LobeError>>> = crate::memo::map(label, cells.len(), |k| {
        let c = cells[k];
        let tgt = lobe.target(c.alpha, c.theta)?;
        let (albedo, _, _) = tgt.albedo(1e-8);
        Ok(cell_error_of(&tgt, albedo, &entries(k % n, k / n, c)))
    })?;
    let k = errs.first().map_or(0, |e| e.len());
    Ok((0..k)
        .map(|q| {
            errs.iter()
                .zip(&cells)
                .map(|(e, c)| (e[q], (c.alpha, c.theta.to_degrees())))
                .collect()
        })
        .collect())
}

/// The LTC's mass below the horizon: with (Mω)_z = m·ω (m the third row of M), the
/// clamped cosine's share of the half-space m·ω < 0 is (1 − m_z/|m|)/2.
pub fn below_horizon(inv: &[f64; 4]) -> f64 {
    match inverse_from_production(inv).try_inverse() {
        Some(m) => {
            let r = m.row(2);
            0.5 * (1.0 - r[2] / r.norm())
        }
        None => f64::NAN,
    }
}

fn facts(t: &Table) -> Facts {
    let cells = flat(t);
    let at = |c: &Cell| (c.alpha, c.theta.to_degrees());
    let top = cells
        .iter()
        .max_by(|a, b| a.norm.total_cmp(&b.norm))
        .copied();
    let below: Vec<f64> = cells.iter().map(|c| below_horizon(&c.inv)).collect();
    let k = (0..below.len())
        .max_by(|a, b| below[*a].total_cmp(&below[*b]))
        .unwrap_or(0);
    Facts {
        albedo_above_one: cells.iter().filter(|c| c.norm > 1.0).count(),
        albedo_max: top.map_or(f64::NAN, |c| c.norm),
        albedo_max_at: top.map_or((f64::NAN, f64::NAN), at),
        below_horizon_mean: below.iter().sum::<f64>() / below.len().max(1) as f64,
        below_horizon_max: below.get(k).copied().unwrap_or(f64::NAN),
        below_horizon_at: cells.get(k).map_or((f64::NAN, f64::NAN), |c| at(c)),
    }
}

fn storage_costs(t: &Table) -> [StorageCost; 3] {
    use crate::ltc::lobe_error::Held;
    let cells = flat(t);
    std::array::from_fn(|pick| {
        let (mut sum, mut bars, mut cnt) = (0.0, 0.0, 0usize);
        let (mut worst, mut worst_bar, mut at) = (0.0f64, 0.0, (0.0, 0.0));
        for c in &cells {
            // an albedo below binary16's normal range is stored as (nearly) nothing
            if c.norm < F16_NORMAL_MIN {
                continue;
            }
            let Some(Held {
                f64: Some(a),
                f32,
                f16_nearest,
                f16,
            }) = c.held
            else {
                continue;
            };
            if let Some(b) = [f32, f16_nearest, f16][pick] {
                let d = b.l2.value - a.l2.value;
                let bar = a.l2.error + b.l2.error;
                sum += d;
                bars += bar;
                cnt += 1;
                if d.abs() > worst.abs() {
                    (worst, worst_bar, at) = (d, bar, (c.alpha, c.theta.to_degrees()));
                }
            }
        }
        let entries = |c: &Cell| -> [f64; 4] {
            match pick {
                0 => c.inv.map(|x| x as f32 as f64),
                1 => c.inv.map(|x| half::f16::from_f64(x).to_f64()),
                _ => [c.half[0], c.half[1], c.half[2], c.half[3]],
            }
        };
        let m = cnt.max(1) as f64;
        StorageCost {
            mean_change: sum / m,
            mean_bar: bars / m,
            largest_change: worst,
            largest_bar: worst_bar,
            at,
            mirrored: cells
                .iter()
                .filter(|c| {
                    let v = entries(c);
                    !(v[0] * v[3] - v[1] * v[2] > 0.0)
                })
                .count(),
        }
    })
}

fn table_report(f: &Fitted, pl: &Plan) -> Result<TableReport> {
    let t = &f.table;
    let n = t.grid.n;
    let mut cells = flat(t);
    let l2 = |c: &Cell| c.l2().map_or(f64::NAN, |b| b.value);
    cells.sort_by(|a, b| l2(b).total_cmp(&l2(a)));
    let none = Bounded {
        value: f64::NAN,
        error: f64::NAN,
    };
    let worst = cells
        .iter()
        .take(6)
        .map(|c| {
            let e = c.held.and_then(|h| h.f64);
            CellRow {
                alpha: c.alpha,
                theta_deg: c.theta.to_degrees(),
                inv: c.inv,
                norm: c.norm,
                fresnel: c.fresnel,
                l2: e.map_or(none, |e| e.l2),
                l1: e.map_or(none, |e| e.l1),
            }
        })
        .collect();
    // between cells: every square centre
    let sh = as_shipped(t);
    let target = |a: f64, th: f64| f.lobe.target(a, th);
    let squares: Vec<(usize, usize)> = (0..n - 1)
        .flat_map(|j| (0..n - 1).map(move |i| (i, j)))
        .collect();
    let mid_errs: Vec<(Option<LobeError>, f64)> =
        crate::memo::map_items("lobe table between cells", &squares, |&(i, j)| {
            midpoint_error_of(&sh, i, j, t.grid.alpha_min, &target)
        })?;
    // a lobe with (almost) no energy has no relative error worth a mean: between cells
    // whose albedos differ by orders of magnitude (sheen seen head-on at small α) the
    // interpolated norm dwarfs it
    let between_left_out = mid_errs.iter().filter(|e| e.1 < VISIBLE_ALBEDO).count();
    let mids: Vec<(Option<LobeError>, (f64, f64))> = squares
        .iter()
        .zip(mid_errs)
        .map(|(&(i, j), (e, albedo))| {
            let e = e.filter(|_| albedo >= VISIBLE_ALBEDO);
            let r = (i as f64 + 0.5) / (n - 1) as f64;
            let tt = (j as f64 + 0.5) / (n - 1) as f64;
            let alpha = (r * r).max(t.grid.alpha_min);
            (
                e,
                (alpha, (1.0 - tt * tt).clamp(0.0, 1.0).acos().to_degrees()),
            )
        })
        .collect();
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
        between: located(&mids),
        between_left_out,
        storage: storage_costs(t),
        storage_left_out: flat(t).iter().filter(|c| c.norm < F16_NORMAL_MIN).count(),
        norm_error_max: flat(t).iter().map(|c| c.norm_se).fold(0.0, f64::max),
        norm_vs_mc_max_se: zs.iter().flatten().cloned().fold(0.0, f64::max),
        norm_mc_cells: zs.iter().flatten().count(),
        norm_mc_left_out: zs.iter().filter(|z| z.is_none()).count(),
        polygons,
        facts: facts(t),
        sampled: crate::ltc::held::sampled_estimate(&Memo, t, &target, 2 * pl.samples)?,
    })
}

/// All measures of both tables of a family.
pub(super) fn compute(fam: &Family, main: &Fitted, variant: &Fitted, pl: &Plan) -> Result<Report> {
    const COSINE: [f64; 4] = [1.0, 0.0, 0.0, 1.0];
    // against the main lobe, per main cell: the variant's table, Lambert with weight 1,
    // Lambert with the norm, the main table with its norm clamped to 1
    let vt = &variant.table;
    let on_main = against(
        "other tables against the main lobe",
        &main.table,
        fam.main,
        &|i, j, c| {
            let v = &vt.cells[j][i];
            vec![
                full(v),
                (COSINE, 1.0),
                (COSINE, c.norm),
                (c.inv, c.norm.min(1.0)),
                (c.inv, c.norm),
            ]
        },
    )?;
    let mt = &main.table;
    let on_variant = against(
        "main table against the variant lobe",
        vt,
        fam.variant,
        &|i, j, _| vec![full(&mt.cells[j][i])],
    )?;
    let bounded = |k: usize| -> Located {
        let rows: Vec<(Option<LobeError>, (f64, f64))> = on_main[k]
            .iter()
            .zip(flat(&main.table))
            .filter(|(_, c)| c.norm > 1.0)
            .map(|(e, _)| *e)
            .collect();
        located(&rows)
    };
    Ok(Report {
        main: table_report(main, pl)?,
        variant: table_report(variant, pl)?,
        cross: Cross {
            main_table_for_variant: located(&on_variant[0]),
            variant_table_for_main: located(&on_main[0]),
            cosine_unit_for_main: located(&on_main[1]),
            cosine_norm_for_main: located(&on_main[2]),
            bounded_main: bounded(3),
            true_main_where_bounded: bounded(4),
        },
    })
}

fn both(l: &Located) -> String {
    format!(
        "relative L2 mean {}, max {} at ({:.3}, {:.1}°); relative L1 mean {}, max {}",
        l.l2.mean.pct(2),
        l.l2.max.pct(1),
        l.at.0,
        l.at.1,
        l.l1.mean.pct(2),
        l.l1.max.pct(1)
    )
}

fn table_section(md: &mut String, f: &Fitted, r: &TableReport, file: &str) {
    let st = held_out_stats(&f.table);
    let tol = crate::ltc::lobe_error::Tolerance::default();
    md.push_str(&format!(
        "## {} (results/fits/{file}.json)\n\nTarget: {}.\n\nHeld-out error of every cell, as integrals over the whole sphere (`ltc::lobe_error`: adaptive cubature on charts that follow the lobe and the LTC, each figure ± the half-width its integrals' errors allow; tolerance {:e} relative or {:e} absolute, met in {} of {} cells). Relative L2 ‖f − norm·γ_M‖/‖f‖: mean {}, max {} at α = {:.3}, θ = {:.1}°. Relative L1 ∫|f − norm·γ_M|/∫f: mean {}, max {}. Mean Nelder–Mead iterations {:.0}. Bilinear pass: {} of {} cells moved. Fit cost: results/performance.md (criterion's time per cell; the main job's wall clock per study).\n\n",
        f.lobe.short(), f.lobe.describe(), tol.rel, tol.abs, st.converged, st.cells, st.l2.mean.pct(2), st.l2.max.pct(1), st.worst_cell.0, st.worst_cell.1, st.l1.mean.pct(2), st.l1.max.pct(1), st.mean_iters,
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
        "\nBetween cells (what a shader sampling the table bilinearly sees): the production inverse and the norm interpolated at the centres of the squares, judged against the lobe there by the same integrals, over the {} squares whose lobe has an albedo of at least {:e}: {}.{}\n\n",
        r.between.l2.count, VISIBLE_ALBEDO, both(&r.between),
        if r.between_left_out > 0 { format!(" {} squares are left out: their lobe carries almost no energy (sheen seen head-on at small α), and between corners whose albedos differ by orders of magnitude the interpolated norm dwarfs it, so their relative error says nothing about the picture", r.between_left_out) } else { String::new() }
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
            format!("{:+.2e} ± {:.1e}", s.mean_change, s.mean_bar),
            format!("{:+.2e} ± {:.1e}", s.largest_change, s.largest_bar),
            format!("({:.2e}, {:.1}°)", s.at.0, s.at.1),
            s.mirrored.to_string(),
        ]);
    }
    md.push_str(&t.to_string());
    if r.storage_left_out > 0 {
        md.push_str(&format!("\n{} cells have an albedo below binary16's normal range (6.1e-5) and are left out above: binary16 stores their weight as a subnormal or 0, which is what they are worth on screen.\n", r.storage_left_out));
    }
    md.push_str(&format!(
        "\nnorm (the directional albedo, stored as the weight) by nested adaptive Gauss–Kronrod (tolerance 1e-9 absolute; largest error estimate {:.1e}, which is also the tolerance to read against an albedo: a cell whose albedo is below 1e-8 holds it to about 1e-4 relative); against stratified MC of the lobe's own sampler (256² samples) on {} cells: largest difference {:.2} standard errors ({} cells with an albedo below 1e-6 left out). tests/ltc_targets.rs checks the quadrature against an independent Gauss–Legendre product rule to 1e-6 relative with an absolute floor of 1e-12.\n\n",
        r.norm_error_max, r.norm_mc_cells, r.norm_vs_mc_max_se, r.norm_mc_left_out
    ));
    let fx = &r.facts;
    md.push_str(&format!(
        "What the BRDF does that an engine may not expect: its albedo exceeds 1 in {} of {} cells (largest {:.3} at α = {:.3}, θ = {:.2}°: {}); the fitted LTC puts {:.1} % of its mass below the horizon on average and up to {:.1} % (at α = {:.3}, θ = {:.1}°), mass a horizon-clipped shader loses — (1 − M_zz/‖M_z·‖)/2 in closed form, the clamped cosine's share of the half-space that M maps below the horizon.\n\n",
        fx.albedo_above_one, flat(&f.table).len(), fx.albedo_max, fx.albedo_max_at.0, fx.albedo_max_at.1,
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
        let rel = |x: f64| crate::report::rel_vs_mc(x, p.mc, p.mc_se);
        t.row([
            format!("{a:.3}"),
            format!("{th:.1}°"),
            p.light.to_string(),
            format!("{:.4e} ± {:.1e}", p.mc, p.mc_se),
            format!("{:.4e}", p.ltc_exact),
            rel(p.ltc_exact),
            format!(
                "{:+.3} % ± {:.3}",
                100.0 * (p.ltc_exact - p.mc) / norm,
                100.0 * p.mc_se / norm
            ),
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
    let c = &r.cross;
    md.push_str(&format!(
        "## One lobe shaded with the other's table, or with none\n\nHeld-out figures per cell (the same integrals), each table with its own norm:\n\n- the {} table against the {} lobe: {};\n- the {} table against the {} lobe: {};\n",
        main.lobe.short(), variant.lobe.short(), both(&c.main_table_for_variant),
        variant.lobe.short(), main.lobe.short(), both(&c.variant_table_for_main),
    ));
    if matches!(main.lobe, Lobe::BurleyPaper | Lobe::BurleyEngines) {
        md.push_str(&format!(
            "- the clamped cosine (M = I) with weight 1 (Lambert, as Bevy shades area lights' diffuse) against the {} lobe: {};\n",
            main.lobe.short(), both(&c.cosine_unit_for_main)
        ));
    }
    md.push_str(&format!(
        "- the clamped cosine with the table's norm (energy-correct, no table but the norm) against the {} lobe: {}.\n\n",
        main.lobe.short(), both(&c.cosine_norm_for_main)
    ));
    if c.bounded_main.l2.count > 0 {
        md.push_str(&format!(
            "A bounded table (for an engine that wants no weight above 1: the {} table with its norm clamped to 1) differs only on the {} cells whose albedo exceeds 1; there it costs: {} against the true table's {}. The true table stays the one shipped; the bounded one is the same files with the norm channel clamped.\n\n",
            main.lobe.short(), c.bounded_main.l2.count, both(&c.bounded_main), both(&c.true_main_where_bounded)
        ));
    }
    md
}

/// results/<family>-error.svg: both tables' held-out error.
pub(super) fn heatmaps(main: &Fitted, variant: &Fitted) -> Result<String> {
    use crate::report::plot::heatmap_svg;
    use crate::studies::ltc_error_map::ltc_error_panel;
    let panel = |f: &Fitted| ltc_error_panel(&f.table, &format!("{}: relative L2", f.lobe.short()));
    heatmap_svg(&[panel(main), panel(variant)], 1300, 620)
}

//! The per-topic tables of results/performance.md: each study's cost (criterion) next to
//! the error it buys (its results/fits JSON).

use super::criterion::{fmt_ratio, interval, Timed};
use crate::error::Result;
use crate::report::table::Table;
use std::path::Path;

/// Cost next to accuracy for the ways to get α_me from ‖b̄‖ (benches group `alpha-me`,
/// errors from results/fits/multiscale-alpha-me.json).
pub(super) fn alpha_me_table(timed: &[Timed], results: &Path) -> crate::error::Result<String> {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "alpha-me").collect();
    if rows.is_empty() {
        return Ok(String::new());
    }
    let fit: Option<crate::results::alpha_me::AlphaMe> = crate::results::read(results)?;
    let err = |key: &str| -> String {
        fit.as_ref()
            .and_then(|v| v.held_out(key))
            .map(|h| h.max_rel)
            .map(|e| format!("{e:.2e}"))
            .unwrap_or_else(|| "(run regen)".into())
    };
    let mut md = String::from(
        "\n## α_me from ‖b̄‖: cost and accuracy (seed 000 §3.3)\n\nns per evaluation (criterion mean over 1024 inputs, 95 % CI) next to the max relative error in α on the held-out points of results/multiscale-alpha-me.md (α ∈ [1e-3, 1]).\n\n",
    );
    let mut table = Table::new(["method", "ns/eval (95 % CI)", "max rel. error"]);
    for t in rows {
        let key = match t.function.as_str() {
            "paper-eq5" => "paper_eq5",
            "ours" => "ours",
            "table" => "table",
            "newton" => "newton_closed_form",
            _ => continue,
        };
        table.row([t.function.clone(), per_1024(t), err(key)]);
    }
    md.push_str(&table.to_string());
    Ok(md)
}

/// Fit cost per LTC cell and per-pixel cost of each edge form, next to the
/// errors results/fits/ltc-ggx.json records (benches `ltc-fit-cell`, `ltc-polygon`).
/// selfshadow/ltc_code's fitLTC per cell: 150 s of CPU, single-threaded, for the 64×64 GGX
/// table on the machine this workbench's benches run on.
const LTC_CODE_MS_PER_CELL: f64 = 37.0;

/// The LTC fitting section's heading (`bench-report --ltc-fit-only` replaces it).
pub(super) const LTC_HEAD: &str = "\n## LTC fitting and polygon integration";

pub(super) fn ltc_table(timed: &[Timed], results: &Path) -> crate::error::Result<String> {
    let fits: Vec<&Timed> = timed.iter().filter(|t| t.group == "ltc-fit-cell").collect();
    let polys: Vec<&Timed> = timed.iter().filter(|t| t.group == "ltc-polygon").collect();
    let columns = timed.iter().any(|t| t.group == "ltc-fit-column");
    if fits.is_empty() && polys.is_empty() && !columns {
        return Ok(String::new());
    }
    let v: Option<crate::results::ltc::Summary> =
        crate::results::read_named(results, crate::results::names::LTC_GGX)?;
    let edge_err = |form: &str| -> Option<f64> {
        v.as_ref()?
            .edge_approximations
            .iter()
            .find(|e| e.form == form)
            .map(|e| e.max_rel)
    };
    let mut md = String::from(LTC_HEAD);
    md.push_str("\n\n");
    if let Some(held) = v.as_ref().map(|v| &v.held_out) {
        md.push_str(&format!(
            "The whole GGX table: {} for the ltc-ggx study on this machine (table, bilinear pass, held-out judging, reports; alone: a sequential uncached `regen`, see the main job's section), for a held-out relative L2 of mean {}, max {} (results/ltc-ggx.md).\n\n",
            super::main_job::study_cost("ltc-ggx").map_or("—".into(), |c| c.describe()),
            held.l2.mean.pct(2),
            held.l2.max.pct(1)
        ));
    }
    let mut table = Table::new([
        "fit of one table cell (4 parameters, 24×24 samples per technique; Nelder–Mead on moving samples unless the row names fixed nodes or Levenberg–Marquardt)",
        "time (95 % CI)",
        "÷ ltc_code's fitLTC per cell",
    ]);
    for t in &fits {
        table.row([
            t.function.clone(),
            format!(
                "{:.2} ms ({:.2}–{:.2})",
                t.mean_ns / 1e6,
                t.lo_ns / 1e6,
                t.hi_ns / 1e6
            ),
            format!(
                "{:.2}× ({:.2}–{:.2})",
                t.mean_ns / 1e6 / LTC_CODE_MS_PER_CELL,
                t.lo_ns / 1e6 / LTC_CODE_MS_PER_CELL,
                t.hi_ns / 1e6 / LTC_CODE_MS_PER_CELL
            ),
        ]);
    }
    md.push_str(&table.to_string());
    md.push_str(&format!(
        "\nThe anchor: selfshadow/ltc_code's fitLTC (Nelder–Mead on 2×32² samples, f32), run single-threaded over the same 64×64 GGX grid, took 150 s of CPU for the table, {LTC_CODE_MS_PER_CELL} ms per cell (one measurement, no interval, on the host of that day; it warm-starts each cell from its neighbour). Hosts differ (compare this page's cell rows with an earlier run of it), so a ratio is only as good as that anchor. The cells above start cold from (ln α, ln α, 0, 0), which a table cell does not: it starts from its neighbour's fit.\n"
    ));
    md.push_str(&ltc_column_table(timed));
    md.push_str("\nOne pixel: a quad light through one LTC (f64, clipped to the horizon), 256 pixels per iteration from the kernel benchmark inputs. Error: max relative error of the edge factor θ/sin θ over x = cos θ ∈ [−1, 0.999999] (results/ltc-ggx.md; the exact form is the reference, 2e-16 against the closed-form rectangle).\n\n");
    let mut table = Table::new([
        "edge form",
        "ns per pixel (95 % CI)",
        "max rel. error of the edge factor",
    ]);
    for t in &polys {
        let err = match t.function.as_str() {
            "rational" => edge_err("Rational").map_or("—".into(), |e| format!("{e:.2e}")),
            "cubic" => edge_err("Cubic").map_or("—".into(), |e| format!("{e:.2e}")),
            _ => "reference".into(),
        };
        table.row([
            t.function.clone(),
            format!(
                "{:.1} ({:.1}–{:.1})",
                t.mean_ns / 256.0,
                t.lo_ns / 256.0,
                t.hi_ns / 256.0
            ),
            err,
        ]);
    }
    md.push_str(&table.to_string());
    if let Some(h) = v
        .as_ref()
        .and_then(|v| v.sphere_horizon.map(|s| s.energy_weighted_rel))
    {
        md.push_str(&format!("\nThe f32 shading kernel (`ltc_quad`: rational edges, no clipping, clipped-sphere horizon) is in the kernel table above; its horizon approximation costs {:.1} % energy-weighted over the same inputs.\n", 100.0 * h));
    }
    Ok(md)
}

/// One θ column of the GGX table per fitting route (bench `ltc-fit-column`, whose
/// parameter is the column's cell count): criterion's time per column ÷ its cells, next to
/// ltc_code's fitLTC per cell and the whole study's CPU per table cell.
fn ltc_column_table(timed: &[Timed]) -> String {
    let mut cols: Vec<&Timed> = timed
        .iter()
        .filter(|t| t.group == "ltc-fit-column")
        .collect();
    // by column, then the reference first and the routes as they cut its work
    let order = |f: &str| {
        let (route, theta) = f.rsplit_once(", θ ").unwrap_or((f, ""));
        let k = ["reference", "fixed nodes, cubic", "fixed nodes, every"]
            .iter()
            .position(|p| route.starts_with(p));
        (theta.trim_end_matches('°').parse::<f64>().unwrap_or(0.0), k)
    };
    cols.sort_by(|a, b| {
        let (x, y) = (order(&a.function), order(&b.function));
        x.0.total_cmp(&y.0).then(x.1.cmp(&y.1))
    });
    // the column's cell count, from the bench's parameter: none, or not a positive
    // count, and there is no per-cell figure to give
    let Some(cells) = cols
        .first()
        .and_then(|t| t.param.parse::<f64>().ok())
        .filter(|c| c.is_finite() && *c >= 1.0)
    else {
        return String::new();
    };
    let mut md = format!(
        "\nOne whole column of the 64² table per route, as the table fits it (`ltc::fit::fit_column`: {cells:.0} cells from rough to smooth, each warm-started from its rougher neighbour, with its moments, albedo, cubic stage, L2 polish and rounded storage; 24² samples per technique, ≤ 400 iterations per stage), one thread; per cell = criterion's time per column ÷ {cells:.0}. Not in it: the table's bilinear pass and chosen binary16 storage, its held-out judge and reports.\n\n"
    );
    let mut table = Table::new([
        "route, θ of the column",
        "per cell (95 % CI)",
        "÷ ltc_code's fitLTC per cell",
    ]);
    for t in &cols {
        let per = |ns: f64| ns / 1e6 / cells;
        table.row([
            t.function.clone(),
            format!(
                "{:.2} ms ({:.2}–{:.2})",
                per(t.mean_ns),
                per(t.lo_ns),
                per(t.hi_ns)
            ),
            format!(
                "{:.2}× ({:.2}–{:.2})",
                per(t.mean_ns) / LTC_CODE_MS_PER_CELL,
                per(t.lo_ns) / LTC_CODE_MS_PER_CELL,
                per(t.hi_ns) / LTC_CODE_MS_PER_CELL
            ),
        ]);
    }
    md.push_str(&table.to_string());
    if let Some(cpu) = super::main_job::study_cost("ltc-ggx").and_then(|c| c.cpu_s) {
        md.push_str(&format!(
            "\nThe whole ltc-ggx study, everything included (the table's fit, bilinear pass and storage, the held-out judge, the between-cell figures, every other section of results/ltc-ggx.md), took {cpu:.0} s of CPU alone: {:.1} ms per table cell ({:.2}× fitLTC's).\n",
            1e3 * cpu / (cells * cells),
            1e3 * cpu / (cells * cells) / LTC_CODE_MS_PER_CELL
        ));
    }
    md
}

/// Seed 002 range queries: time against box size, O(R) SAT vs the naive sum, and one
/// importance sample (benches `tensor-range`, `tensor-sample`).
pub(super) fn tensor_table(timed: &[Timed]) -> String {
    let rows: Vec<&Timed> = timed
        .iter()
        .filter(|t| t.group == "tensor-range" || t.group == "tensor-sample")
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## Tensor range queries\n\nRank 16, 256 × 256 block; box w × w from one texel to the whole block. The SAT query is O(R) whatever w; the naive sum of the reconstruction is O(R·w²).\n\n");
    let mut table = Table::new(["box w", "SAT query (ns)", "naive (ns)"]);
    let sat: Vec<&&Timed> = rows
        .iter()
        .filter(|t| t.group == "tensor-range" && t.function == "sat")
        .collect();
    let mut ws: Vec<u64> = sat.iter().filter_map(|t| t.param.parse().ok()).collect();
    ws.sort();
    for w in &ws {
        let get = |f: &str| {
            rows.iter()
                .find(|t| t.group == "tensor-range" && t.function == f && t.param == w.to_string())
                .map(|t| t.mean_ns)
        };
        table.row([
            w.to_string(),
            get("sat").map_or("—".into(), |v| format!("{v:.1}")),
            get("naive").map_or("—".into(), |v| format!("{v:.0}")),
        ]);
    }
    let mut times: Vec<f64> = sat.iter().map(|t| t.mean_ns).collect();
    let mut levels: Vec<&&Timed> = rows
        .iter()
        .filter(|t| t.group == "tensor-range" && t.function == "sat-level")
        .collect();
    levels.sort_by(|a, b| a.param.cmp(&b.param));
    for l in &levels {
        table.row([
            format!("64 at level {}", l.param),
            format!("{:.1}", l.mean_ns),
            "—".into(),
        ]);
        times.push(l.mean_ns);
    }
    md.push_str(&table.to_string());
    if let (Some(lo), Some(hi)) = (
        times.iter().cloned().reduce(f64::min),
        times.iter().cloned().reduce(f64::max),
    ) {
        md.push_str(&format!(
            "\nLargest / smallest SAT query time over box sizes and levels: {:.3} (goal ≤ 1.2).\n",
            hi / lo
        ));
    }
    if let Some(s) = rows.iter().find(|t| t.group == "tensor-sample") {
        md.push_str(&format!("One hierarchical importance sample (16 × 16 block, R = 16: 4 levels × 4 range queries + tent): {:.0} ns.\n", s.mean_ns));
    }
    md
}

/// Seed 002 §5.5: one NDF value of a footprint on the Wang-tiled map against Eq 2 over the
/// explicit map's window (bench `tensor-wang`).
pub(super) fn wang_table(timed: &[Timed]) -> String {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "tensor-wang").collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## Wang tiles: one NDF value per footprint\n\nThe tensor-wang study's tiles (32², 32² images; stride 4: σ_P = 1.73 texels, a 15² window; stride 8: σ_P = 3.46, a 29² window), one value at one h: the colour hash and one rank-8 point query (Eq 6) per covered tile, against Eq 2 summed over the window's texels of the explicit map (results/tensor-wang.md has the errors).\n\n");
    let mut table = Table::new(["query", "tiles covered", "time (95 % CI)"]);
    for t in rows {
        table.row([t.function.clone(), t.param.clone(), interval(t)]);
    }
    md.push_str(&table.to_string());
    md
}

/// SIMD kernels: pixels/s of each backend per batch size, the ratio, and each kernel's
/// measured error next to its speed (benches `kernel-*`; accuracy measured here on 2^16
/// of the benchmark inputs).
pub(super) fn kernels_table(
    set: &mut crate::io::Outputs,
    timed: &[Timed],
    results: &Path,
) -> Result<String> {
    let rows: Vec<&Timed> = timed
        .iter()
        .filter(|t| t.group.starts_with("kernel-"))
        .collect();
    if rows.is_empty() {
        return Ok(String::new());
    }
    let mut md = String::from(
        "\n## SIMD shading kernels\n\nStructure-of-arrays f32 batches. `per-pixel` = the generated scalar twin called once per pixel (not inlined: no auto-vectorisation, the one-pixel-at-a-time baseline); `scalar` = the same twin in a plain loop, which LLVM auto-vectorises for SSE2 where it can; `avx2` = the AVX2+FMA path chosen at run time. Mpx/s = 10⁶ pixels per second (criterion mean). Ratios: avx2 over per-pixel, and avx2 over the auto-vectorised loop. Errors on 2^16 benchmark inputs: max relative error against the f64 reference (absolute for ltc-quad, whose values are form factors in [0, 1]), and max distance to the scalar twin in ulp.\n\n",
    );
    let mut table = Table::new([
        "kernel",
        "batch",
        "per-pixel Mpx/s",
        "scalar loop Mpx/s",
        "avx2 Mpx/s",
        "avx2 / per-pixel",
        "avx2 / scalar loop",
        "max rel. error (avx2 vs f64)",
        "max ulp (avx2 vs scalar)",
    ]);
    let mut groups: Vec<&str> = rows.iter().map(|t| t.group.as_str()).collect();
    groups.dedup();
    let mut plot = Vec::new();
    for grp in groups {
        let (err, ulp) = if crate::kernels::Backend::Avx2.available() {
            crate::kernels::accuracy(grp, crate::kernels::Backend::Avx2, 1 << 16)?
        } else {
            (f64::NAN, f64::NAN)
        };
        let mut params: Vec<u64> = rows
            .iter()
            .filter(|t| t.group == grp)
            .filter_map(|t| t.param.parse().ok())
            .collect();
        params.sort();
        params.dedup();
        let mut pts = Vec::new();
        for p in params {
            let get = |f: &str| {
                rows.iter()
                    .find(|t| t.group == grp && t.function == f && t.param == p.to_string())
                    .map(|t| p as f64 / t.mean_ns * 1e3)
            };
            let (pp, s, a) = (get("per-pixel"), get("scalar"), get("avx2"));
            let r = |x: Option<f64>| match (x, a) {
                (Some(x), Some(a)) => a / x,
                _ => f64::NAN,
            };
            pts.push((p as f64, r(pp)));
            let f = |x: Option<f64>| x.map_or("—".to_string(), |v| format!("{v:.0}"));
            table.row([
                grp.trim_start_matches("kernel-").to_string(),
                p.to_string(),
                f(pp),
                f(s),
                f(a),
                fmt_ratio(r(pp)),
                fmt_ratio(r(s)),
                if err.is_finite() {
                    format!("{err:.1e}")
                } else {
                    "—".into()
                },
                if ulp.is_finite() {
                    format!("{ulp:.0}")
                } else {
                    "—".into()
                },
            ]);
        }
        plot.push(crate::report::plot::Series {
            name: grp.trim_start_matches("kernel-").to_string(),
            points: pts,
        });
    }
    md.push_str(&table.to_string());
    let svg = crate::report::plot::loglog_svg(
        &[crate::report::plot::Panel {
            title: "AVX2 speed-up over the per-pixel scalar baseline".into(),
            x_label: "batch (pixels)".into(),
            y_label: "ratio".into(),
            series: plot,
        }],
        800,
        480,
    )?;
    set.put(&results.join("kernels-speedup.svg"), svg.as_bytes());
    md.push_str("\n![speed-up](kernels-speedup.svg)\n");
    Ok(md)
}

/// Cost next to accuracy for the footprint filters (bench group `filters`; errors from
/// results/fits/filters.json).
pub(super) fn filters_table(timed: &[Timed], results: &Path) -> crate::error::Result<String> {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "filters").collect();
    if rows.is_empty() {
        return Ok(String::new());
    }
    let fit: Option<crate::results::filters::Filters> = crate::results::read(results)?;
    let mut md = String::from(
        "\n## Footprint filters: cost and accuracy\n\nns per evaluation of the f32 roughness update alone (1024 inputs; the shading that follows is the same GGX evaluation for every isotropic filter, and an anisotropic-matrix GGX for LEAN and the forward kernel) next to the mean relative L2 lobe error against the footprint-averaged BRDF (GGX; results/filters.md: maps for mean-normal/LEAN filters, the Gaussian-pixel screen study for kernels).\n\n",
    );
    let mut table = Table::new(["filter", "ns/eval (95 % CI)", "mean L2 error"]);
    for t in rows {
        let (name, err) = fit
            .as_ref()
            .and_then(|v| v.summary.get(t.function.as_str()))
            .map(|e| (e.name.clone(), format!("{} ({})", e.l2.pct(1), e.study)))
            .unwrap_or_else(|| (t.function.clone(), "(run regen)".into()));
        table.row([name, per_1024(t), err]);
    }
    md.push_str(&table.to_string());
    Ok(md)
}

/// Cost next to accuracy for the Beckmann Λ forms (bench group `smith-lambda`; errors from
/// results/fits/smith-lambda.json).
pub(super) fn smith_lambda_table(timed: &[Timed], results: &Path) -> crate::error::Result<String> {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "smith-lambda").collect();
    if rows.is_empty() {
        return Ok(String::new());
    }
    let fit: Option<crate::results::smith_lambda::SmithLambda> = crate::results::read(results)?;
    let err = |key: &str| -> String {
        fit.as_ref()
            .and_then(|v| match key {
                "ours" => Some(v.held_out.ours),
                "walter_printed" => Some(v.held_out.walter_printed),
                "walter_listing" => Some(v.held_out.walter_listing),
                _ => None,
            })
            .map(|w| w.max_dg1)
            .map(|e| format!("{e:.2e}"))
            .unwrap_or_else(|| "(run regen)".into())
    };
    let mut md = String::from(
        "\n## Beckmann Smith Λ: cost and accuracy (seed 001 §3.2)\n\nns per evaluation of Λ(ν) (1024 log-spaced ν in [1e-3, 10]) next to the held-out max |ΔG1| of results/smith-lambda.md.\n\n",
    );
    let mut table = Table::new(["form", "ns/eval (95 % CI)", "max \\|ΔG1\\|"]);
    for t in rows {
        let e = match t.function.as_str() {
            "exact-erfc" => "0 (reference)".to_string(),
            "walter" => err("walter_printed"),
            "ours" => err("ours"),
            _ => continue,
        };
        table.row([t.function.clone(), per_1024(t), e]);
    }
    md.push_str(&table.to_string());
    Ok(md)
}

/// LEADR grid cost against N next to the held-out errors of results/fits/leadr-grids.json.
pub(super) fn leadr_table(timed: &[Timed], results: &Path) -> crate::error::Result<String> {
    let mut rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "leadr").collect();
    if rows.is_empty() {
        return Ok(String::new());
    }
    rows.sort_by_key(|t| t.param.parse::<usize>().unwrap_or(0));
    let fit: Option<crate::results::leadr_grids::LeadrGrids> = crate::results::read(results)?;
    let err = |n: usize, fam: &str, kind: &str| -> String {
        fit.as_ref()
            .and_then(|v| v.rows.iter().find(|x| x.n == n))
            .and_then(|r| {
                let f = match kind {
                    "specular" => r.specular,
                    _ => r.diffuse,
                };
                match fam {
                    "paper" => Some(f.paper),
                    "fitted" => Some(f.fitted),
                    "gauss_hermite" => Some(f.gauss_hermite),
                    _ => None,
                }
            })
            .map(|e| e.1)
            .map(|e| format!("{e:.2e}"))
            .unwrap_or_else(|| "–".into())
    };
    let mut md = String::from(
        "\n## LEADR N×N grids: cost and accuracy (seed 001 §3.4–3.5)\n\nTime of one N×N estimate (criterion mean, 95 % CI; the cost per grid point is the same for every family) next to the held-out max relative error of results/leadr-grids.md.\n\n",
    );
    let mut table = Table::new([
        "N",
        "ns per estimate (95 % CI)",
        "ns per grid point",
        "specular: paper h / fitted h / Gauss–Hermite",
        "diffuse: paper h / fitted h / Gauss–Hermite",
    ]);
    for t in rows {
        let n: usize = t.param.parse().unwrap_or(0);
        let fams = |kind: &str| {
            format!(
                "{} / {} / {}",
                err(n, "paper", kind),
                err(n, "fitted", kind),
                err(n, "gauss_hermite", kind)
            )
        };
        table.row([
            n.to_string(),
            format!("{:.1} ({:.1} – {:.1})", t.mean_ns, t.lo_ns, t.hi_ns),
            format!("{:.2}", t.mean_ns / (n * n).max(1) as f64),
            fams("specular"),
            fams("diffuse"),
        ]);
    }
    md.push_str(&table.to_string());
    Ok(md)
}

/// A 1024-input bench's mean and 95 % interval per input, in ns.
fn per_1024(t: &Timed) -> String {
    format!(
        "{:.2} ({:.2} – {:.2})",
        t.mean_ns / 1024.0,
        t.lo_ns / 1024.0,
        t.hi_ns / 1024.0
    )
}

//! `bench-report`: read criterion's estimates (target/criterion/**/new/) and write
//! results/performance.md with time per call next to the error each configuration
//! reaches (recomputed deterministically, same seed as the bench).

use super::convergence::{integrands, run_engine, Engine};
use super::plot::{loglog_svg, Panel, Series};
use crate::error::{Error, Result};
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Deserialize)]
struct BenchId {
    group_id: String,
    function_id: Option<String>,
    value_str: Option<String>,
}

#[derive(Deserialize)]
struct Interval {
    lower_bound: f64,
    upper_bound: f64,
}
#[derive(Deserialize)]
struct Stat {
    point_estimate: f64,
    confidence_interval: Interval,
}
#[derive(Deserialize)]
struct Estimates {
    mean: Stat,
}

/// One timed benchmark.
pub struct Timed {
    pub group: String,
    pub function: String,
    pub param: String,
    pub mean_ns: f64,
    pub lo_ns: f64,
    pub hi_ns: f64,
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.file_name().is_some_and(|n| n == "benchmark.json")
                && p.parent().is_some_and(|d| d.ends_with("new"))
            {
                out.push(p);
            }
        }
    }
}

/// All benchmarks criterion has results for.
pub fn read_criterion(dir: &Path) -> Result<Vec<Timed>> {
    let mut files = Vec::new();
    walk(dir, &mut files);
    if files.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "no criterion results under '{}': run `cargo bench` first",
            dir.display()
        )));
    }
    let io = |p: &Path, e: String| Error::Io {
        path: p.display().to_string(),
        msg: e,
    };
    let mut out = Vec::new();
    for f in files {
        let id: BenchId =
            serde_json::from_str(&std::fs::read_to_string(&f).map_err(|e| io(&f, e.to_string()))?)
                .map_err(|e| io(&f, e.to_string()))?;
        let ef = f.with_file_name("estimates.json");
        let est: Estimates = serde_json::from_str(
            &std::fs::read_to_string(&ef).map_err(|e| io(&ef, e.to_string()))?,
        )
        .map_err(|e| io(&ef, e.to_string()))?;
        // a time is a positive finite number of nanoseconds, its interval around it
        let (m, lo, hi) = (
            est.mean.point_estimate,
            est.mean.confidence_interval.lower_bound,
            est.mean.confidence_interval.upper_bound,
        );
        if !(m.is_finite() && m > 0.0 && lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo) {
            return Err(io(
                &ef,
                format!(
                    "criterion estimate is not a positive time (mean {m:e} ns, interval [{lo:e}, {hi:e}])"
                ),
            ));
        }
        out.push(Timed {
            group: id.group_id,
            function: id.function_id.unwrap_or_default(),
            param: id.value_str.unwrap_or_default(),
            mean_ns: est.mean.point_estimate,
            lo_ns: est.mean.confidence_interval.lower_bound,
            hi_ns: est.mean.confidence_interval.upper_bound,
        });
    }
    out.sort_by(|a, b| (&a.group, &a.function, &a.param).cmp(&(&b.group, &b.function, &b.param)));
    Ok(out)
}

/// A speed-up ratio, or "—" where a time is missing.
fn fmt_ratio(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2}×")
    } else {
        "—".into()
    }
}

fn fmt_time(ns: f64) -> String {
    if !ns.is_finite() {
        return "—".into();
    }
    if ns >= 1e9 {
        format!("{:.3} s", ns / 1e9)
    } else if ns >= 1e6 {
        format!("{:.3} ms", ns / 1e6)
    } else if ns >= 1e3 {
        format!("{:.3} µs", ns / 1e3)
    } else {
        format!("{ns:.1} ns")
    }
}

/// Write results/performance.md.
pub fn run(criterion: &Path, results: &Path) -> Result<String> {
    let timed = read_criterion(criterion)?;
    write_costs(&timed, results)?;
    let igs = integrands();
    let mut md = String::from("# Performance\n\n");
    md.push_str(
        "Written by `cargo bench --bench engines && cargo run --release -- bench-report`. Times are criterion's mean \
with its 95 % confidence interval, on the machine that ran the benches (see the machine line). The error columns \
are recomputed deterministically for the same configuration and seed, so every cost stands next to the accuracy \
it buys.\n\n",
    );
    md.push_str(&format!(
        "Machine: {} logical cores reported by the OS.\n\n",
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(0)
    ));
    md.push_str("## Engines: time and error per integral\n\n| integrand | engine | setting | evals | time per integral (95 % CI) | ns/eval | \\|error\\| | reported error |\n|---|---|---|---|---|---|---|---|\n");
    let mut ns_per_eval: Vec<(String, Engine, f64)> = Vec::new();
    for t in timed.iter().filter(|t| t.group.starts_with("engines/")) {
        let key = t.group.trim_start_matches("engines/");
        let (Some(ig), Some(e), Ok(level)) = (
            igs.iter().find(|i| i.key == key),
            Engine::from_name(&t.function),
            t.param.parse::<u64>(),
        ) else {
            continue;
        };
        let est = run_engine(ig, e, level, 7);
        ns_per_eval.push((ig.key.to_string(), e, t.mean_ns / est.evals as f64));
        md.push_str(&format!(
            "| {} | {} | {} | {} | {} ({} – {}) | {:.1} | {:.2e} | {:.2e} |\n",
            ig.title,
            e.name(),
            level,
            est.evals,
            fmt_time(t.mean_ns),
            fmt_time(t.lo_ns),
            fmt_time(t.hi_ns),
            t.mean_ns / est.evals as f64,
            (est.value - ig.exact).abs(),
            est.error
        ));
    }
    md.push_str(&error_vs_time(results, &ns_per_eval)?);
    let scaling: Vec<&Timed> = timed
        .iter()
        .filter(|t| t.group.starts_with("rayon-scaling"))
        .collect();
    if !scaling.is_empty() {
        md.push_str("\n## Rayon scaling (MC, MIS, 2^20 tuples, same result bit for bit at every thread count)\n\n| threads | time (95 % CI) | speed-up vs 1 thread |\n|---|---|---|\n");
        let base = scaling.iter().find(|t| t.param == "1").map(|t| t.mean_ns);
        for t in &scaling {
            md.push_str(&format!(
                "| {} | {} ({} – {}) | {} |\n",
                t.param,
                fmt_time(t.mean_ns),
                fmt_time(t.lo_ns),
                fmt_time(t.hi_ns),
                base.map(|b| fmt_ratio(b / t.mean_ns))
                    .unwrap_or_else(|| "–".into())
            ));
        }
    }
    md.push_str(&alpha_me_table(&timed, results));
    md.push_str(&smith_lambda_table(&timed, results));
    md.push_str(&leadr_table(&timed, results));
    md.push_str(&filters_table(&timed, results));
    md.push_str(&kernels_table(&timed, results)?);
    md.push_str(&tensor_table(&timed));
    md.push_str(&ltc_table(&timed, results));
    let other: Vec<&Timed> = timed
        .iter()
        .filter(|t| {
            !t.group.starts_with("engines/")
                && !t.group.starts_with("rayon-scaling")
                && t.group != "alpha-me"
                && t.group != "filters"
                && !t.group.starts_with("kernel-")
                && !t.group.starts_with("tensor-")
                && !t.group.starts_with("ltc-")
        })
        .collect();
    if !other.is_empty() {
        md.push_str("\n## Other benchmarks\n\n| group | function | parameter | time (95 % CI) |\n|---|---|---|---|\n");
        for t in other {
            md.push_str(&format!(
                "| {} | {} | {} | {} ({} – {}) |\n",
                t.group,
                t.function,
                t.param,
                fmt_time(t.mean_ns),
                fmt_time(t.lo_ns),
                fmt_time(t.hi_ns)
            ));
        }
    }
    // a benchmark missing from a partial criterion directory shows as "—", never as NaN
    let md = missing_as_dash(&md);
    crate::io::write_atomic(&results.join("performance.md"), md.as_bytes())?;
    Ok(format!(
        "wrote {}/performance.md ({} benchmarks)",
        results.display(),
        timed.len()
    ))
}

/// Error against (estimated) time: the convergence study's points (results/convergence.json)
/// with time = evaluations × the measured ns/eval of that engine on that integrand.
fn error_vs_time(results: &Path, ns: &[(String, Engine, f64)]) -> Result<String> {
    #[derive(Deserialize)]
    struct Row {
        integrand: String,
        engine: Engine,
        evals: u64,
        abs_error: f64,
    }
    let path = results.join("convergence.json");
    let Ok(text) = crate::io::read_to_string(&path) else {
        return Ok("\n(no results/convergence.json: run `cargo run --release -- convergence` for the error-vs-time table)\n".into());
    };
    let rows: Vec<Row> = serde_json::from_str(&text).map_err(|e| Error::Io {
        path: path.display().to_string(),
        msg: e.to_string(),
    })?;
    let igs = integrands();
    let mut md = String::from(
        "\n## Error against time\n\nTime of each convergence-study point = its evaluations × the ns/eval measured above for \
that engine and integrand (cost is linear in evaluations for every engine here; the adaptive rule's heap work is \
included in its measured ns/eval). Plot: [error-vs-time.svg](error-vs-time.svg).\n\n| integrand | engine | est. time to \\|error\\| ≤ 1e-6 | best \\|error\\| | at est. time |\n|---|---|---|---|---|\n",
    );
    let mut panels = Vec::new();
    for ig in &igs {
        let mut series = Vec::new();
        for e in Engine::ALL {
            let Some(&(_, _, c)) = ns.iter().find(|(k, en, _)| k == ig.key && *en == e) else {
                continue;
            };
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.integrand == ig.key && r.engine == e)
                .map(|r| (r.evals as f64 * c * 1e-9, r.abs_error))
                .collect();
            let reach = pts
                .iter()
                .find(|p| p.1 <= 1e-6)
                .map(|p| fmt_time(p.0 * 1e9))
                .unwrap_or_else(|| "not reached".into());
            if let Some(best) = pts.iter().min_by(|a, b| a.1.total_cmp(&b.1)) {
                let err = if best.1 == 0.0 {
                    "0 (exact in f64)".to_string()
                } else {
                    format!("{:.2e}", best.1)
                };
                md.push_str(&format!(
                    "| {} | {} | {} | {} | {} |\n",
                    ig.title,
                    e.name(),
                    reach,
                    err,
                    fmt_time(best.0 * 1e9)
                ));
            }
            // zero errors are drawn at 1e-17 (log axis)
            series.push(Series {
                name: e.name().to_string(),
                points: pts.iter().map(|p| (p.0, p.1.max(1e-17))).collect(),
            });
        }
        panels.push(Panel {
            title: ig.title.to_string(),
            x_label: "seconds (estimated)".into(),
            y_label: "|error|".into(),
            series,
        });
    }
    let svg = loglog_svg(&panels, 1500, 480)?;
    crate::io::write_atomic(&results.join("error-vs-time.svg"), svg.as_bytes())?;
    Ok(md)
}

/// Cost next to accuracy for the ways to get α_me from ‖b̄‖ (benches group `alpha-me`,
/// errors from results/fits/multiscale-alpha-me.json).
fn alpha_me_table(timed: &[Timed], results: &Path) -> String {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "alpha-me").collect();
    if rows.is_empty() {
        return String::new();
    }
    let fit = crate::results::read_result(results, "multiscale-alpha-me");
    let err = |key: &str| -> String {
        fit.as_ref()
            .and_then(|v| v[key]["held_out"]["max_rel"].as_f64())
            .map(|e| format!("{e:.2e}"))
            .unwrap_or_else(|| "(run regen)".into())
    };
    let mut md = String::from(
        "\n## α_me from ‖b̄‖: cost and accuracy (seed 000 §3.3)\n\nns per evaluation (criterion mean over 1024 inputs, 95 % CI) next to the max relative error in α on the held-out points of results/multiscale.md (α ∈ [1e-3, 1]).\n\n| method | ns/eval (95 % CI) | max rel. error |\n|---|---|---|\n",
    );
    for t in rows {
        let key = match t.function.as_str() {
            "paper-eq5" => "paper_eq5",
            "ours" => "ours",
            "table" => "table",
            "newton" => "newton_closed_form",
            _ => continue,
        };
        md.push_str(&format!(
            "| {} | {:.2} ({:.2} – {:.2}) | {} |\n",
            t.function,
            t.mean_ns / 1024.0,
            t.lo_ns / 1024.0,
            t.hi_ns / 1024.0,
            err(key)
        ));
    }
    md
}

/// results/costs.json: ns per evaluation of the footprint filters (f32 forms, group
/// `filters`) and ns per pixel of each kernel backend at a 4096-pixel batch — the cost
/// side of the speed/accuracy tables `scene` chooses from. Entries keep what earlier
/// runs measured when this run lacks them.
fn write_costs(timed: &[Timed], results: &Path) -> Result<()> {
    let path = results.join("costs.json");
    let mut costs: serde_json::Map<String, serde_json::Value> = crate::io::read_to_string(&path)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or_default();
    for t in timed {
        if t.group == "filters" {
            costs.insert(
                format!("filters/{}", t.function),
                serde_json::json!(t.mean_ns / 1024.0),
            );
        } else if t.group == "ltc-polygon" {
            costs.insert(
                format!("ltc-polygon/{}", t.function),
                serde_json::json!(t.mean_ns / 256.0),
            );
        } else if t.group == "ltc-fit-cell" {
            costs.insert(
                format!("ltc-fit-cell/{}", t.function),
                serde_json::json!(t.mean_ns),
            );
        } else if t.group.starts_with("tensor-") {
            let key = if t.param.is_empty() {
                format!("{}/{}", t.group, t.function)
            } else {
                format!("{}/{}/{}", t.group, t.function, t.param)
            };
            costs.insert(key, serde_json::json!(t.mean_ns));
        } else if t.group.starts_with("kernel-") && t.param == "4096" {
            costs.insert(
                format!("{}/{}", t.group, t.function),
                serde_json::json!(t.mean_ns / 4096.0),
            );
        }
    }
    costs.insert(
        "_note".into(),
        serde_json::json!("ns per evaluation (filters: f32 roughness update; kernels: per pixel at a 4096-pixel batch; tensor-*: per query or sample); written by bench-report"),
    );
    crate::io::write_atomic(
        &path,
        serde_json::to_string_pretty(&serde_json::Value::Object(costs))
            .expect("json")
            .as_bytes(),
    )
}

/// Fit cost per LTC cell and per-pixel cost of each edge form, next to the
/// errors results/fits/ltc-ggx.json records (benches `ltc-fit-cell`, `ltc-polygon`).
fn ltc_table(timed: &[Timed], results: &Path) -> String {
    let fits: Vec<&Timed> = timed.iter().filter(|t| t.group == "ltc-fit-cell").collect();
    let polys: Vec<&Timed> = timed.iter().filter(|t| t.group == "ltc-polygon").collect();
    if fits.is_empty() && polys.is_empty() {
        return String::new();
    }
    let v = crate::results::read_result(results, "ltc-ggx");
    let edge_err = |form: &str| -> Option<f64> {
        v.as_ref()?["edge_approximations"]
            .as_array()?
            .iter()
            .find(|e| e["form"].as_str() == Some(form))?["max_rel"]
            .as_f64()
    };
    let mut md = String::from("\n## LTC fitting and polygon integration\n\n");
    if let Some(ft) = v.as_ref().map(|v| &v["fit_time"]).filter(|f| f.is_object()) {
        let g = |k: &str| ft[k].as_f64().unwrap_or(f64::NAN);
        let held = v.as_ref().map(|v| &v["held_out"]);
        md.push_str(&format!(
            "The whole GGX table (results/fits/ltc-ggx.json `fit_time`, wall clock of the run that wrote it, not criterion): {:.0} s for {} cells on {} threads, {:.0} ms of one thread per cell (cubic fit, L2 polish), for a held-out relative L2 of mean {:.2} %, max {:.1} % (results/ltc.md).\n\n",
            g("seconds"),
            g("cells"),
            g("threads"),
            g("per_cell_ms"),
            100.0 * held.and_then(|h| h["mean_l2"].as_f64()).unwrap_or(f64::NAN),
            100.0 * held.and_then(|h| h["max_l2"].as_f64()).unwrap_or(f64::NAN)
        ));
    }
    md.push_str("| fit of one table cell (Nelder–Mead, 4 parameters, 24×24 samples per technique) | time (95 % CI) |\n|---|---|\n");
    for t in &fits {
        md.push_str(&format!(
            "| {} | {:.2} ms ({:.2}–{:.2}) |\n",
            t.function,
            t.mean_ns / 1e6,
            t.lo_ns / 1e6,
            t.hi_ns / 1e6
        ));
    }
    md.push_str("\nOne pixel: a quad light through one LTC (f64, clipped to the horizon), 256 pixels per iteration from the kernel benchmark inputs. Error: max relative error of the edge factor θ/sin θ over x = cos θ ∈ [−1, 0.999999] (results/ltc.md; the exact form is the reference, 2e-16 against the closed-form rectangle).\n\n| edge form | ns per pixel (95 % CI) | max rel. error of the edge factor |\n|---|---|---|\n");
    for t in &polys {
        let err = match t.function.as_str() {
            "rational" => edge_err("Rational").map_or("—".into(), |e| format!("{e:.2e}")),
            "cubic" => edge_err("Cubic").map_or("—".into(), |e| format!("{e:.2e}")),
            _ => "reference".into(),
        };
        md.push_str(&format!(
            "| {} | {:.1} ({:.1}–{:.1}) | {err} |\n",
            t.function,
            t.mean_ns / 256.0,
            t.lo_ns / 256.0,
            t.hi_ns / 256.0
        ));
    }
    if let Some(h) = v
        .as_ref()
        .and_then(|v| v["sphere_horizon"]["energy_weighted_rel"].as_f64())
    {
        md.push_str(&format!("\nThe f32 shading kernel (`ltc_quad`: rational edges, no clipping, clipped-sphere horizon) is in the kernel table above; its horizon approximation costs {:.1} % energy-weighted over the same inputs.\n", 100.0 * h));
    }
    md
}

/// Seed 002 range queries: time against box size, O(R) SAT vs the naive sum, and one
/// importance sample (benches `tensor-range`, `tensor-sample`).
fn tensor_table(timed: &[Timed]) -> String {
    let rows: Vec<&Timed> = timed
        .iter()
        .filter(|t| t.group.starts_with("tensor-"))
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## Tensor range queries\n\nRank 16, 256 × 256 block; box w × w from one texel to the whole block. The SAT query is O(R) whatever w; the naive sum of the reconstruction is O(R·w²).\n\n| box w | SAT query (ns) | naive (ns) |\n|---|---|---|\n");
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
        md.push_str(&format!(
            "| {w} | {} | {} |\n",
            get("sat").map_or("—".into(), |v| format!("{v:.1}")),
            get("naive").map_or("—".into(), |v| format!("{v:.0}"))
        ));
    }
    let mut times: Vec<f64> = sat.iter().map(|t| t.mean_ns).collect();
    let mut levels: Vec<&&Timed> = rows
        .iter()
        .filter(|t| t.group == "tensor-range" && t.function == "sat-level")
        .collect();
    levels.sort_by(|a, b| a.param.cmp(&b.param));
    for l in &levels {
        md.push_str(&format!(
            "| 64 at level {} | {:.1} | — |\n",
            l.param, l.mean_ns
        ));
        times.push(l.mean_ns);
    }
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

/// SIMD kernels: pixels/s of each backend per batch size, the ratio, and each kernel's
/// measured error next to its speed (benches `kernel-*`; accuracy measured here on 2^16
/// of the benchmark inputs).
fn kernels_table(timed: &[Timed], results: &Path) -> Result<String> {
    let rows: Vec<&Timed> = timed
        .iter()
        .filter(|t| t.group.starts_with("kernel-"))
        .collect();
    if rows.is_empty() {
        return Ok(String::new());
    }
    let mut md = String::from(
        "\n## SIMD shading kernels\n\nStructure-of-arrays f32 batches. `per-pixel` = the generated scalar twin called once per pixel (not inlined: no auto-vectorisation, the one-pixel-at-a-time baseline); `scalar` = the same twin in a plain loop, which LLVM auto-vectorises for SSE2 where it can; `avx2` = the AVX2+FMA path chosen at run time. Mpx/s = 10⁶ pixels per second (criterion mean). Ratios: avx2 over per-pixel, and avx2 over the auto-vectorised loop. Errors on 2^16 benchmark inputs: max relative error against the f64 reference (absolute for ltc-quad, whose values are form factors in [0, 1]), and max distance to the scalar twin in ulp.\n\n| kernel | batch | per-pixel Mpx/s | scalar loop Mpx/s | avx2 Mpx/s | avx2 / per-pixel | avx2 / scalar loop | max rel. error (avx2 vs f64) | max ulp (avx2 vs scalar) |\n|---|---|---|---|---|---|---|---|---|\n",
    );
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
            md.push_str(&format!(
                "| {} | {p} | {} | {} | {} | {} | {} | {} | {} |\n",
                grp.trim_start_matches("kernel-"),
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
                }
            ));
        }
        plot.push(crate::report::plot::Series {
            name: grp.trim_start_matches("kernel-").to_string(),
            points: pts,
        });
    }
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
    crate::io::write_atomic(&results.join("kernels-speedup.svg"), svg.as_bytes())?;
    md.push_str("\n![speed-up](kernels-speedup.svg)\n");
    Ok(md)
}

/// Cost next to accuracy for the footprint filters (bench group `filters`; errors from
/// results/fits/filters.json).
fn filters_table(timed: &[Timed], results: &Path) -> String {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "filters").collect();
    if rows.is_empty() {
        return String::new();
    }
    let fit = crate::results::read_result(results, "filters");
    let mut md = String::from(
        "\n## Footprint filters: cost and accuracy\n\nns per evaluation of the f32 roughness update alone (1024 inputs; the shading that follows is the same GGX evaluation for every isotropic filter, and an anisotropic-matrix GGX for LEAN and the forward kernel) next to the mean relative L2 lobe error against the footprint-averaged BRDF (GGX; results/filters.md: maps for mean-normal/LEAN filters, the Gaussian-pixel screen study for kernels).\n\n| filter | ns/eval (95 % CI) | mean L2 error |\n|---|---|---|\n",
    );
    for t in rows {
        let (name, err) = fit
            .as_ref()
            .map(|v| &v["summary"][t.function.as_str()])
            .map(|e| {
                (
                    e["name"].as_str().unwrap_or(&t.function).to_string(),
                    match (e["l2_mean"].as_f64(), e["l2_se"].as_f64()) {
                        (Some(m), Some(s)) => format!(
                            "{:.1} % ± {:.1} ({})",
                            100.0 * m,
                            100.0 * s,
                            e["study"].as_str().unwrap_or("")
                        ),
                        _ => "(run regen)".into(),
                    },
                )
            })
            .unwrap_or_else(|| (t.function.clone(), "(run regen)".into()));
        md.push_str(&format!(
            "| {name} | {:.2} ({:.2} – {:.2}) | {err} |\n",
            t.mean_ns / 1024.0,
            t.lo_ns / 1024.0,
            t.hi_ns / 1024.0
        ));
    }
    md
}

/// Cost next to accuracy for the Beckmann Λ forms (bench group `smith-lambda`; errors from
/// results/fits/smith-lambda.json).
fn smith_lambda_table(timed: &[Timed], results: &Path) -> String {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "smith-lambda").collect();
    if rows.is_empty() {
        return String::new();
    }
    let fit = crate::results::read_result(results, "smith-lambda");
    let err = |key: &str| -> String {
        fit.as_ref()
            .and_then(|v| v["held_out"][key]["max_dg1"].as_f64())
            .map(|e| format!("{e:.2e}"))
            .unwrap_or_else(|| "(run regen)".into())
    };
    let mut md = String::from(
        "\n## Beckmann Smith Λ: cost and accuracy (seed 001 §3.2)\n\nns per evaluation of Λ(ν) (1024 log-spaced ν in [1e-3, 10]) next to the held-out max |ΔG1| of results/smith-lambda.md.\n\n| form | ns/eval (95 % CI) | max \\|ΔG1\\| |\n|---|---|---|\n",
    );
    for t in rows {
        let e = match t.function.as_str() {
            "exact-erfc" => "0 (reference)".to_string(),
            "walter" => err("walter_printed"),
            "ours" => err("ours"),
            _ => continue,
        };
        md.push_str(&format!(
            "| {} | {:.2} ({:.2} – {:.2}) | {} |\n",
            t.function,
            t.mean_ns / 1024.0,
            t.lo_ns / 1024.0,
            t.hi_ns / 1024.0,
            e
        ));
    }
    md
}

/// LEADR grid cost against N next to the held-out errors of results/fits/leadr-grids.json.
fn leadr_table(timed: &[Timed], results: &Path) -> String {
    let mut rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "leadr").collect();
    if rows.is_empty() {
        return String::new();
    }
    rows.sort_by_key(|t| t.param.parse::<usize>().unwrap_or(0));
    let fit = crate::results::read_result(results, "leadr-grids");
    let err = |n: usize, fam: &str, kind: &str| -> String {
        fit.as_ref()
            .and_then(|v| {
                v["rows"].as_array().and_then(|r| {
                    r.iter()
                        .find(|x| x["n"].as_u64() == Some(n as u64))
                        .cloned()
                })
            })
            .and_then(|r| r[kind][fam][1].as_f64())
            .map(|e| format!("{e:.2e}"))
            .unwrap_or_else(|| "–".into())
    };
    let mut md = String::from(
        "\n## LEADR N×N grids: cost and accuracy (seed 001 §3.4–3.5)\n\nTime of one N×N estimate (criterion mean, 95 % CI; the cost per grid point is the same for every family) next to the held-out max relative error of results/leadr.md.\n\n| N | ns per estimate (95 % CI) | ns per grid point | specular: paper h / fitted h / Gauss–Hermite | diffuse: paper h / fitted h / Gauss–Hermite |\n|---|---|---|---|---|\n",
    );
    for t in rows {
        let n: usize = t.param.parse().unwrap_or(0);
        md.push_str(&format!(
            "| {n} | {:.1} ({:.1} – {:.1}) | {:.2} | {} / {} / {} | {} / {} / {} |\n",
            t.mean_ns,
            t.lo_ns,
            t.hi_ns,
            t.mean_ns / (n * n).max(1) as f64,
            err(n, "paper", "specular"),
            err(n, "fitted", "specular"),
            err(n, "gauss_hermite", "specular"),
            err(n, "paper", "diffuse"),
            err(n, "fitted", "diffuse"),
            err(n, "gauss_hermite", "diffuse")
        ));
    }
    md
}

/// Replace every formatted non-number ("NaN", "inf", "-inf" as whole words, with an
/// optional unit or × after them) by "—".
pub fn missing_as_dash(md: &str) -> String {
    let mut out = String::with_capacity(md.len());
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        let core = word.trim_end_matches(['×', '%']);
        if matches!(core, "NaN" | "inf" | "-inf" | "NaN×" | "+inf") {
            out.push('—');
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    for ch in md.chars() {
        if ch.is_whitespace() || ch == '|' || ch == '(' || ch == ')' || ch == ',' {
            flush(&mut word, &mut out);
            out.push(ch);
        } else {
            word.push(ch);
        }
    }
    flush(&mut word, &mut out);
    out
}

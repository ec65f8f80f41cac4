//! `bench-report`: read criterion's estimates (target/criterion/**/new/) and write
//! results/performance.md with time per call next to the error each configuration
//! reaches (recomputed deterministically, same seed as the bench).

use super::convergence::{integrands, run_engine, Engine};
use crate::error::Result;
use crate::report::plot::{loglog_svg, Panel, Series};
use serde::Deserialize;
use std::path::Path;

mod compact;
mod criterion;
mod deliverables;
mod main_job;
mod section;
mod tables;
mod wave;

use crate::report::table::Table;
use criterion::{fmt_ratio, fmt_time, interval};
pub use criterion::{read_criterion, Timed};
use main_job::main_job_table;
pub use main_job::{
    main_job_times_path, refresh_main_job, sequential_times_path, write_main_job_times,
    write_sequential_times, JobStage, BEFORE_PATH,
};
use tables::{
    alpha_me_table, filters_table, kernels_table, leadr_table, ltc_table, smith_lambda_table,
    tensor_table, wang_table,
};

/// Replace only the compact LTC tables' section of an existing results/performance.md
/// (and its plot, results/ltc-compact-cost.svg) from criterion's `ltc-compact` group and
/// results/fits/ltc-compact.json: after the compact study is rerun, without the rest of
/// the benches. Without that group's results or the study's file, an error.
pub fn refresh_compact(
    set: &mut crate::io::Outputs,
    criterion: &Path,
    results: &Path,
) -> Result<String> {
    let timed = read_criterion(criterion)?;
    let section = compact::ltc_compact_table(set, &timed, results)?;
    if section.is_empty() {
        return Err(crate::error::Error::InvalidArgument(format!(
            "bench-report --compact-only: needs criterion's ltc-compact group under {} (cargo bench --bench deliverables -- ltc-compact) and {}",
            criterion.display(),
            results.join("fits/ltc-compact.json").display()
        )));
    }
    section::replace_section(set, results, compact::HEAD, &section)
}

/// Replace only the LTC fitting and polygon section of an existing
/// results/performance.md from criterion's `ltc-fit-cell`, `ltc-fit-column` and
/// `ltc-polygon` groups (`cargo bench --bench engines -- ltc-`), without the rest of the
/// benches. Without any of those groups' results, an error.
pub fn refresh_ltc_fit(
    set: &mut crate::io::Outputs,
    criterion: &Path,
    results: &Path,
) -> Result<String> {
    let timed = read_criterion(criterion)?;
    let section = ltc_table(&timed, results)?;
    if section.is_empty() {
        return Err(crate::error::Error::InvalidArgument(format!(
            "bench-report --ltc-fit-only: needs criterion's ltc-fit-cell, ltc-fit-column or ltc-polygon group under {} (cargo bench --bench engines -- ltc-)",
            criterion.display()
        )));
    }
    section::replace_section(set, results, tables::LTC_HEAD, &section)
}

/// results/performance.md (and costs.json, the plots) into `set`.
pub fn run(set: &mut crate::io::Outputs, criterion: &Path, results: &Path) -> Result<String> {
    let timed = read_criterion(criterion)?;
    write_costs(set, &timed, results)?;
    let igs = integrands();
    let mut md = String::from("# Performance\n\n");
    md.push_str(
        "Written by `cargo bench --bench engines && cargo run --release -- bench-report`. Times are criterion's mean \
with its 95 % confidence interval, on the machine that ran the benches (see the machine line). The error columns \
are recomputed deterministically for the same configuration and seed, so every cost stands next to the accuracy \
it buys. Criterion's own browsable report of every benchmark (distributions, regressions against the last run) is \
left by `cargo bench` under `target/criterion/report/index.html`; this page is its summary.\n\n",
    );
    md.push_str(&format!(
        "Machine: {} logical cores reported by the OS.\n\n",
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(0)
    ));
    md.push_str("## Engines: time and error per integral\n\n");
    let mut table = Table::new([
        "integrand",
        "engine",
        "setting",
        "evals",
        "time per integral (95 % CI)",
        "ns/eval",
        "\\|error\\|",
        "reported error",
    ]);
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
        table.row([
            ig.title.to_string(),
            e.name().to_string(),
            level.to_string(),
            est.evals.to_string(),
            interval(t),
            format!("{:.1}", t.mean_ns / est.evals as f64),
            format!("{:.2e}", (est.value - ig.exact).abs()),
            format!("{:.2e}", est.error),
        ]);
    }
    md.push_str(&table.to_string());
    md.push_str(&error_vs_time(set, results, &ns_per_eval)?);
    let scaling: Vec<&Timed> = timed
        .iter()
        .filter(|t| t.group.starts_with("rayon-scaling"))
        .collect();
    if !scaling.is_empty() {
        md.push_str("\n## Rayon scaling (MC, MIS, 2^20 tuples, same result bit for bit at every thread count)\n\n");
        let mut table = Table::new(["threads", "time (95 % CI)", "speed-up vs 1 thread"]);
        let base = scaling.iter().find(|t| t.param == "1").map(|t| t.mean_ns);
        for t in &scaling {
            table.row([
                t.param.clone(),
                interval(t),
                base.map(|b| fmt_ratio(b / t.mean_ns))
                    .unwrap_or_else(|| "–".into()),
            ]);
        }
        md.push_str(&table.to_string());
    }
    md.push_str(&alpha_me_table(&timed, results)?);
    md.push_str(&smith_lambda_table(&timed, results)?);
    md.push_str(&leadr_table(&timed, results)?);
    md.push_str(&filters_table(&timed, results)?);
    md.push_str(&kernels_table(set, &timed, results)?);
    md.push_str(&tensor_table(&timed));
    md.push_str(&wang_table(&timed));
    md.push_str(&wave::wave_table(&timed, results)?);
    md.push_str(&crate::report::table3::markdown(
        &|key| {
            timed
                .iter()
                .find(|t| {
                    t.group == "tensor-brdf"
                        && (if t.param.is_empty() {
                            t.function.clone()
                        } else {
                            format!("{}/{}", t.function, t.param)
                        }) == key
                })
                .map(|t| crate::report::table3::Timing {
                    mean: t.mean_ns,
                    lo: t.lo_ns,
                    hi: t.hi_ns,
                })
        },
        &crate::tensor::brdf::table3_cp_errors()?,
    ));
    md.push_str(&ltc_table(&timed, results)?);
    md.push_str(&deliverables::shaders_table(&timed));
    md.push_str(&deliverables::prefilter_table(&timed));
    md.push_str(&deliverables::ltc_tables_table(&timed, results)?);
    md.push_str(&compact::ltc_compact_table(set, &timed, results)?);
    md.push_str(&deliverables::render_table(&timed, results)?);
    md.push_str(&deliverables::survey_table(&timed, results)?);
    md.push_str(&deliverables::visibility_table(&timed));
    md.push_str(&main_job_table(results)?);
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
                && t.group != "render"
                && t.group != "survey"
                && t.group != "visibility"
                && !t.group.starts_with("shaders/")
                && t.group != "prefilter"
        })
        .collect();
    if !other.is_empty() {
        md.push_str("\n## Other benchmarks\n\n");
        let mut table = Table::new(["group", "function", "parameter", "time (95 % CI)"]);
        for t in other {
            table.row([
                t.group.clone(),
                t.function.clone(),
                t.param.clone(),
                interval(t),
            ]);
        }
        md.push_str(&table.to_string());
    }
    // a benchmark missing from a partial criterion directory shows as "—", never as NaN
    let md = missing_as_dash(&md);
    set.put(&results.join("performance.md"), md.as_bytes());
    Ok(format!(
        "wrote {}/performance.md ({} benchmarks)",
        results.display(),
        timed.len()
    ))
}

/// Error against (estimated) time: the convergence study's points (results/convergence.json)
/// with time = evaluations × the measured ns/eval of that engine on that integrand.
fn error_vs_time(
    set: &mut crate::io::Outputs,
    results: &Path,
    ns: &[(String, Engine, f64)],
) -> Result<String> {
    #[derive(Deserialize)]
    struct Row {
        integrand: String,
        engine: Engine,
        evals: u64,
        abs_error: f64,
    }
    let redo = "run `cargo run --release -- convergence`";
    let Some(rows) = crate::results::read_typed::<Vec<Row>>(
        &results.join("convergence.json"),
        "the convergence study's rows",
        redo,
    )?
    else {
        return Ok(format!(
            "\n(no results/convergence.json: {redo} for the error-vs-time table)\n"
        ));
    };
    let igs = integrands();
    let mut md = String::from(
        "\n## Error against time\n\nTime of each convergence-study point = its evaluations × the ns/eval measured above for \
that engine and integrand (cost is linear in evaluations for every engine here; the adaptive rule's heap work is \
included in its measured ns/eval). Plot: [error-vs-time.svg](error-vs-time.svg).\n\n",
    );
    let mut table = Table::new([
        "integrand",
        "engine",
        "est. time to \\|error\\| ≤ 1e-6",
        "best \\|error\\|",
        "at est. time",
    ]);
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
                table.row([
                    ig.title.to_string(),
                    e.name().to_string(),
                    reach,
                    err,
                    fmt_time(best.0 * 1e9),
                ]);
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
    md.push_str(&table.to_string());
    let svg = loglog_svg(&panels, 1500, 480)?;
    set.put(&results.join("error-vs-time.svg"), svg.as_bytes());
    Ok(md)
}

/// results/costs.json: ns per evaluation of the footprint filters (f32 forms, group
/// `filters`) and ns per pixel of each kernel backend at a 4096-pixel batch — the cost
/// side of the speed/accuracy tables `scene` chooses from. Entries keep what earlier
/// runs measured when this run lacks them.
fn write_costs(set: &mut crate::io::Outputs, timed: &[Timed], results: &Path) -> Result<()> {
    use crate::results::costs;
    let mut c = costs::read(results)?.unwrap_or_default();
    for t in timed {
        let (key, ns) = if t.group == "filters" {
            // `scene`'s automatic choice compares costs by their intervals
            let key = format!("filters/{}", t.function);
            c.ns.insert(format!("{key}/lo"), t.lo_ns / 1024.0);
            c.ns.insert(format!("{key}/hi"), t.hi_ns / 1024.0);
            (key, t.mean_ns / 1024.0)
        } else if t.group == "ltc-polygon" {
            (format!("ltc-polygon/{}", t.function), t.mean_ns / 256.0)
        } else if t.group == "ltc-fit-cell" {
            (format!("ltc-fit-cell/{}", t.function), t.mean_ns)
        } else if t.group.starts_with("tensor-") {
            let key = if t.param.is_empty() {
                format!("{}/{}", t.group, t.function)
            } else {
                format!("{}/{}/{}", t.group, t.function, t.param)
            };
            if t.group == "tensor-brdf" {
                // Table 3's ratios carry the intervals of both times
                c.ns.insert(format!("{key}/lo"), t.lo_ns);
                c.ns.insert(format!("{key}/hi"), t.hi_ns);
            }
            (key, t.mean_ns)
        } else if t.group.starts_with("kernel-") && t.param == "4096" {
            (format!("{}/{}", t.group, t.function), t.mean_ns / 4096.0)
        } else {
            continue;
        };
        c.ns.insert(key, ns);
    }
    c.note = "ns per evaluation (filters: f32 roughness update; kernels: per pixel at a 4096-pixel batch; tensor-*: per query or sample; key/lo and key/hi: its 95 % confidence interval, where kept); written by bench-report".into();
    costs::put(set, results, &c)
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

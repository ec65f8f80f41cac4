//! Command-line front end of the workbench: parses `cli::command::Cli` and dispatches.

use clap::Parser;
use ndfbench::cli::command::{Cli, Cmd};
use ndfbench::integrate::Preset;
use ndfbench::io::{in_set, results_manifest};
use ndfbench::{cli, verify};
use std::process::ExitCode;

fn run_verify(
    preset: Preset,
    only: Option<&str>,
    results: &std::path::Path,
) -> Result<bool, ndfbench::Error> {
    let checks = verify::select(only)?;
    let n = checks.len();
    ndfbench::report::stage(&format!("verify: {n} checks at the {preset:?} preset"));
    // a bar on a terminal, a plain line at least every 10 s otherwise
    let pb = ndfbench::progress::Progress::new("verify", n as u64);
    let outcomes = verify::run(preset, checks, |o| {
        pb.inc(1);
        pb.suspend(|| {
            println!(
                "{:<5} {:<28} worst {:.3e} ({}) tol {:.1e}  {:.1}s",
                if o.passed { "pass" } else { "FAIL" },
                o.id,
                o.worst_error,
                o.error_kind,
                o.tolerance,
                o.seconds
            )
        });
    });
    pb.finish();
    let ok = outcomes.iter().all(|o| o.passed);
    ndfbench::report::stage("verify: done");
    if only.is_none() {
        in_set("proofs", &results_manifest(results, "proofs"), |set| {
            verify::write_results(set, &outcomes, preset, results)
        })?;
        eprintln!("wrote {}/proofs.md", results.display());
    }
    println!(
        "{} of {} proofs pass",
        outcomes.iter().filter(|o| o.passed).count(),
        outcomes.len()
    );
    Ok(ok)
}

/// Whether `fits` is the shipped specs' directory (the default `--fits`): only a run of
/// those measures what results/performance.md quotes, so only it keeps a profile.
fn shipped_specs(fits: &std::path::Path) -> bool {
    fits == std::path::Path::new("fits")
}

fn run_regen(
    only: Option<&str>,
    preset: Preset,
    fits: &std::path::Path,
    results: &std::path::Path,
    opts: &ndfbench::studies::RunOptions,
) -> Result<bool, ndfbench::Error> {
    let start = std::time::Instant::now();
    let mut times = Vec::new();
    let ok = run_regen_timed(only, preset, fits, results, opts, &mut times)?;
    // every study of the shipped specs at the default preset, one at a time, nothing from
    // a cache (each study's own cost, as performance.md quotes it) or everything from it
    // (each study's cost besides its memoised maps); a quick or custom run would otherwise
    // stand in for the default one
    let canonical = preset == Preset::Default && shipped_specs(fits);
    if canonical && only.is_none() && !opts.parallel {
        ndfbench::studies::performance::write_sequential_times(
            &times,
            start.elapsed().as_secs_f64(),
        );
    }
    Ok(ok)
}

/// [`run_regen`], appending each study's and each generation step's wall-clock seconds.
fn run_regen_timed(
    only: Option<&str>,
    preset: Preset,
    fits: &std::path::Path,
    results: &std::path::Path,
    opts: &ndfbench::studies::RunOptions,
    times: &mut Vec<ndfbench::studies::performance::JobStage>,
) -> Result<bool, ndfbench::Error> {
    let (out, t) = ndfbench::studies::regen_with(fits, results, only, preset, opts)?;
    times.extend(t.iter().map(|t| {
        let maps: Vec<(usize, usize)> = t.maps.iter().map(|m| (m.items, m.computed)).collect();
        ndfbench::studies::performance::JobStage::of_study(
            &t.study,
            t.seconds,
            t.cpu_seconds,
            &maps,
        )
    }));
    let t0 = std::time::Instant::now();
    // generated WGSL (and, for the canonical results/, the Rust twins) follow the fits
    ndfbench::report::stage("codegen");
    match in_set("codegen", &results_manifest(results, "codegen"), |set| {
        ndfbench::codegen::write_all(set, results)
    }) {
        Ok(paths) => eprintln!("generated {}", paths.join(", ")),
        Err(e) => eprintln!("codegen skipped: {e}"),
    }
    match in_set("scenes", &results_manifest(results, "scenes"), |set| {
        ndfbench::scene::regen_examples(set, results)
    }) {
        Ok(n) if !n.is_empty() => eprintln!("rebuilt example scenes {}", n.join(", ")),
        Ok(_) => {}
        Err(e) => eprintln!("example scenes skipped: {e}"),
    }
    // every generated shader through naga's back ends and the validators
    match in_set("shaders", &results_manifest(results, "shaders"), |set| {
        ndfbench::codegen::shaders::write(set, results)
    }) {
        Ok(paths) => eprintln!("translated and validated {} shader files", paths.len()),
        Err(e) => eprintln!("shader translation skipped: {e}"),
    }
    times.push(ndfbench::studies::performance::JobStage::since(
        "codegen, scenes, shaders",
        t0,
    ));
    for o in &out {
        println!(
            "{:<5} {:<24} {}",
            if o.passed { "pass" } else { "FAIL" },
            o.name,
            o.summary
        );
    }
    Ok(out.iter().all(|o| o.passed))
}

/// Write a generated document (the CLI reference, results/README.md) and say so.
fn write_doc(out: &std::path::Path, text: &str) -> Result<bool, ndfbench::Error> {
    ndfbench::io::write_atomic(out, text.as_bytes())?;
    eprintln!("wrote {}", out.display());
    Ok(true)
}

/// Print to stdout; a closed pipe (e.g. `| head`) is not an error worth a panic.
fn out(s: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stdout(), "{s}");
}

/// The main job: every study (parallel, cached), verify, the convergence study, the profile.
fn run_main_job(cli: &Cli) -> Result<bool, ndfbench::Error> {
    let start = std::time::Instant::now();
    let mut times = Vec::new();
    let opts = ndfbench::studies::RunOptions {
        cache: (!cli.no_cache).then(|| cli.cache.clone()),
        parallel: true,
    };
    let fits_ok = run_regen_timed(
        None,
        Preset::Default,
        &cli.fits,
        &cli.results,
        &opts,
        &mut times,
    )?;
    let t = std::time::Instant::now();
    let ok = run_verify(Preset::Default, None, &cli.results)? && fits_ok;
    times.push(ndfbench::studies::performance::JobStage::since(
        "verify (every proof)",
        t,
    ));
    ndfbench::report::stage("convergence study: started");
    let t = std::time::Instant::now();
    let conv = in_set(
        "convergence",
        &results_manifest(&cli.results, "convergence"),
        |set| ndfbench::studies::convergence::run(set, Preset::Default, &cli.results),
    )?;
    times.push(ndfbench::studies::performance::JobStage::since(
        "convergence study",
        t,
    ));
    println!("{conv}");
    ndfbench::studies::performance::write_main_job_times(
        &times,
        start.elapsed().as_secs_f64(),
        shipped_specs(&cli.fits),
    );
    Ok(ok)
}

/// `engines`: the engines' renders of the engine-check scenes judged against the truth.
fn run_engines(cmd: &Cmd, cli: &Cli) -> Result<bool, ndfbench::Error> {
    let Cmd::Engines {
        three_shipped,
        three_ours,
        three_compact,
        shipped,
        bevy_shipped,
        bevy_ours,
        bevy_table,
        scenes,
        out: dir,
    } = cmd
    else {
        return Ok(true);
    };
    use ndfbench::studies::engines::{Engine, EngineFiles};
    let mut files = Vec::new();
    let mut command = String::from("cargo run --release -- engines");
    for (engine, a, b, c, table, flag) in [
        (
            Engine::Three,
            three_shipped,
            three_ours,
            three_compact,
            shipped,
            "three",
        ),
        (
            Engine::Bevy,
            bevy_shipped,
            bevy_ours,
            &None,
            bevy_table,
            "bevy",
        ),
    ] {
        if let (Some(a), Some(b)) = (a, b) {
            command.push_str(&format!(
                " --{flag}-shipped {} --{flag}-ours {}",
                a.display(),
                b.display()
            ));
            if let Some(c) = c {
                command.push_str(&format!(" --{flag}-compact {}", c.display()));
            }
            files.push(EngineFiles {
                engine,
                shipped_run: a,
                ours_run: b,
                shipped_table: table,
                compact_run: c.as_deref(),
            });
        }
    }
    in_set("engines", &dir.join(".sets").join("engines.json"), |set| {
        ndfbench::studies::engines::run(set, scenes, &files, &cli.results, dir, &command)
    })
    .map(|s| {
        println!("{s}");
        true
    })
}

/// `engines-sheen`: three.js's sheen runs judged against the truth.
fn run_engines_sheen(
    three: &[std::path::PathBuf],
    out: &std::path::Path,
    cli: &Cli,
) -> Result<bool, ndfbench::Error> {
    let runs: Vec<String> = three
        .iter()
        .map(|p| format!("--three {}", p.display()))
        .collect();
    let command = format!("cargo run --release -- engines-sheen {}", runs.join(" "));
    in_set(
        "engines-sheen",
        &out.join(".sets").join("engines-sheen.json"),
        |set| {
            ndfbench::studies::engines::sheen_report::run(set, three, &cli.results, out, &command)
        },
    )
    .map(|s| {
        println!("{s}");
        true
    })
}

/// `regen` (whole, cached, parallel or one shard), `merge` and `slurm`.
fn run_batch(cmd: &Cmd, cli: &Cli) -> Result<bool, ndfbench::Error> {
    match *cmd {
        Cmd::Regen {
            ref only,
            preset,
            shard: Some(ref spec),
            ref shard_dir,
            ..
        } => ndfbench::cli::batch::shard(
            &cli.fits,
            &cli.results,
            only.as_deref(),
            preset,
            spec,
            shard_dir,
        ),
        Cmd::Regen {
            ref only,
            preset,
            cached,
            parallel,
            ..
        } => {
            let opts = ndfbench::studies::RunOptions {
                cache: cached.then(|| cli.cache.clone()),
                parallel,
            };
            run_regen(only.as_deref(), preset, &cli.fits, &cli.results, &opts)
        }
        Cmd::Merge { ref shards } => ndfbench::cli::batch::merge(&cli.fits, &cli.results, shards),
        Cmd::Slurm(ref a) => ndfbench::cli::batch::slurm(a, &cli.fits, &cli.results),
        _ => Ok(true),
    }
}

/// Which part of results/performance.md a `bench-report` writes: all of it, or one
/// section of the existing page.
#[derive(Clone, Copy)]
enum ReportOnly {
    All,
    MainJob,
    Compact,
    LtcFit,
}

/// `bench-report`: results/performance.md from criterion's output (or only one of its
/// sections), then the example scenes, which quote its costs.
fn run_bench_report(
    criterion: &std::path::Path,
    only: ReportOnly,
    results: &std::path::Path,
) -> Result<bool, ndfbench::Error> {
    use ndfbench::studies::performance as perf;
    let s = in_set(
        "performance",
        &results_manifest(results, "performance"),
        |set| match only {
            ReportOnly::MainJob => perf::refresh_main_job(set, results),
            ReportOnly::Compact => perf::refresh_compact(set, criterion, results),
            ReportOnly::LtcFit => perf::refresh_ltc_fit(set, criterion, results),
            ReportOnly::All => perf::run(set, criterion, results),
        },
    )?;
    println!("{s}");
    if let Err(e) = in_set("scenes", &results_manifest(results, "scenes"), |set| {
        ndfbench::scene::regen_examples(set, results)
    }) {
        eprintln!("example scenes skipped: {e}");
    }
    Ok(true)
}

fn main() -> ExitCode {
    // clap's own errors (bad flags, unparsable numbers) exit 2 with their first line only;
    // --help and --version print as usual
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                e.exit();
            }
            let text = e.render().to_string();
            let first = text.lines().next().unwrap_or("error: bad arguments");
            eprintln!("{}", ndfbench::error::one_line(first));
            return ExitCode::from(2);
        }
    };
    let res: Result<bool, ndfbench::Error> = match cli.cmd {
        None => run_main_job(&cli),
        Some(ref c @ (Cmd::Regen { .. } | Cmd::Merge { .. } | Cmd::Slurm(_))) => run_batch(c, &cli),
        Some(Cmd::Verify { preset, only }) => run_verify(preset, only.as_deref(), &cli.results),
        Some(Cmd::Convergence { preset }) => in_set(
            "convergence",
            &results_manifest(&cli.results, "convergence"),
            |set| ndfbench::studies::convergence::run(set, preset, &cli.results),
        )
        .map(|s| {
            println!("{s}");
            true
        }),
        Some(Cmd::Eval(args)) => cli::eval(&args, &cli.fits, &cli.results).map(|json| {
            out(&json);
            true
        }),
        Some(Cmd::Prefilter(a)) => ndfbench::cli::prefilter::run(a, &cli.results),
        Some(Cmd::Scene { file, out: dir }) => {
            in_set("scene", &dir.join(".manifest.json"), |set| {
                ndfbench::scene::run(set, &file, &dir, &cli.results)
            })
            .map(|w| {
                println!("wrote {}", w.join(", "));
                true
            })
        }
        Some(Cmd::Render {
            file,
            out: dir,
            preset,
        }) => in_set("render", &dir.join(".manifest.json"), |set| {
            ndfbench::studies::render::render_file(set, &file, &dir, &cli.results, preset)
        })
        .map(|w| {
            println!("wrote {}", w.join(", "));
            true
        }),
        Some(Cmd::Horizon {
            input,
            scale,
            out: dir,
            preset,
        }) => in_set("horizon", &dir.join(".manifest.json"), |set| {
            ndfbench::studies::visibility::horizon_file(set, &input, scale, &dir, preset)
        })
        .map(|w| {
            let (notes, paths): (Vec<_>, Vec<_>) =
                w.into_iter().partition(|x| x.starts_with("height map"));
            for n in notes {
                eprintln!("{n}");
            }
            println!("wrote {}", paths.join(", "));
            true
        }),
        Some(Cmd::LtcCompare {
            shipped,
            mat,
            mag,
            norm_ours,
            source,
            bevy,
            out: dir,
        }) => in_set(
            "ltc-compare",
            &dir.join(".sets").join("ltc-compare.json"),
            |set| {
                ndfbench::studies::ltc_compare::run(
                    set,
                    &ndfbench::studies::ltc_compare::Inputs {
                        shipped: &shipped,
                        mat: &mat,
                        mag: &mag,
                        norm_ours,
                        source: source.as_deref(),
                        bevy: bevy.as_deref(),
                    },
                    &cli.results,
                    &dir,
                )
            },
        )
        .map(|s| {
            println!("{s}");
            true
        }),
        Some(ref c @ Cmd::Engines { .. }) => run_engines(c, &cli),
        Some(Cmd::EnginesSheen { ref three, ref out }) => run_engines_sheen(three, out, &cli),
        Some(Cmd::TensorlyCompare { python, preset }) => in_set(
            "tensorly-compare",
            &results_manifest(&cli.results, "tensorly-compare"),
            |set| ndfbench::tensor::compare::run(set, &cli.results, &python, preset),
        )
        .map(|r| {
            print!("{}", ndfbench::studies::tensor::report::tensorly_table(&r));
            true
        }),
        Some(Cmd::CliReference { out }) => write_doc(&out, &ndfbench::cli::command::reference()),
        Some(Cmd::ResultsReadme) => write_doc(
            &cli.results.join("README.md"),
            &ndfbench::results::index::readme(),
        ),
        Some(Cmd::BenchReport {
            ref criterion,
            main_job_only,
            compact_only,
            ltc_fit_only,
        }) => {
            let only = match (main_job_only, compact_only, ltc_fit_only) {
                (true, _, _) => ReportOnly::MainJob,
                (_, true, _) => ReportOnly::Compact,
                (_, _, true) => ReportOnly::LtcFit,
                _ => ReportOnly::All,
            };
            run_bench_report(criterion, only, &cli.results)
        }
    };
    match res {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {}", ndfbench::error::one_line(&e.to_string()));
            ExitCode::from(2)
        }
    }
}

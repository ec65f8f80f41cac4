//! The main job's wall clock per stage: kept by every run under target/ (cold and warm),
//! beside the committed profile from before the studies ran in parallel, and shown as one
//! section of results/performance.md (`bench-report`, or `--main-job-only` to refresh just
//! that section).

use crate::error::Result;
use crate::report::table::Table;
use std::path::{Path, PathBuf};

/// Where a sequential `regen` of every study leaves its profile: each study alone, so its
/// CPU seconds are its own. Uncached (`warm` false): what each study costs from nothing.
/// Warm (every memoised map from the cache): what each study costs whatever its fitters
/// cost, the floor a faster fitter cannot remove.
pub fn sequential_times_path(warm: bool) -> PathBuf {
    target_dir().join(if warm { SEQUENTIAL_WARM } else { SEQUENTIAL })
}

/// The kept profiles' file names under the target directory.
const SEQUENTIAL: &str = "regen-sequential.json";
const SEQUENTIAL_WARM: &str = "regen-sequential-warm.json";
const COLD: &str = "main-job-cold.json";
const WARM: &str = "main-job-warm.json";

/// Cargo's target directory (`CARGO_TARGET_DIR`, else `target`): where local profiles live.
fn target_dir() -> PathBuf {
    PathBuf::from(std::env::var("CARGO_TARGET_DIR").unwrap_or_else(|_| "target".into()))
}

/// Keep a sequential `regen`'s profile for `bench-report` (best-effort, as
/// [`write_main_job_times`]): a cold run's (no memoised map from a cache: uncached, or
/// an empty cache filled as it goes), or a warm one's (every memoised map from the
/// cache); a run that computed some maps and found others is neither, and is not kept.
pub fn write_sequential_times(stages: &[JobStage], total: f64) {
    let Some(warm) = sequential_kind(stages) else {
        eprintln!("sequential profile not kept: some maps were computed and others came from the cache (neither a study's whole cost nor its floor)");
        return;
    };
    let cpu = crate::progress::process_cpu_seconds();
    keep(&sequential_times_path(warm), stages, total, cpu, warm);
}

/// Write a profile (the process's CPU seconds `cpu` at its end) to `p`; a failure is
/// said, never fatal.
fn keep(p: &Path, stages: &[JobStage], total: f64, cpu: Option<f64>, warm: bool) {
    let json = Profile {
        total_s: total,
        threads: rayon::current_num_threads(),
        warm,
        cpu_s: cpu,
        note: None,
        stages: stages.to_vec(),
    };
    if let Err(e) = crate::io::write_atomic(
        p,
        serde_json::to_string_pretty(&json)
            .unwrap_or_default()
            .as_bytes(),
    ) {
        eprintln!("profile not kept ({}): {e}", p.display());
    }
}

/// Which sequential profile a run's stages are: `Some(false)` cold (no memoised map
/// from a cache), `Some(true)` warm (every one from it), `None` a mix (kept as neither).
fn sequential_kind(stages: &[JobStage]) -> Option<bool> {
    let computed = stages.iter().any(|s| s.computed > 0);
    let reused = stages.iter().any(|s| s.reused > 0);
    match (computed, reused) {
        (_, false) => Some(false),
        (false, true) => Some(true),
        (true, true) => None,
    }
}

/// Where the main job leaves its wall-clock profile (build output, not results/: it
/// changes on every run): `target/main-job-cold.json` when it computed any memoised map,
/// `target/main-job-warm.json` when every one came from the cache.
pub fn main_job_times_path(warm: bool) -> PathBuf {
    target_dir().join(if warm { WARM } else { COLD })
}

/// The committed profile of the main job before it ran studies in parallel and cached
/// (sequential, uncached; measured on the 2-core development machine).
pub const BEFORE_PATH: &str = "main-job-before.json";

/// One stage of the main job: its wall clock and how many memoised items it computed
/// and took from the cache.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct JobStage {
    pub stage: String,
    pub seconds: f64,
    #[serde(default)]
    pub computed: usize,
    #[serde(default)]
    pub reused: usize,
    /// The process's CPU seconds during the stage, where it ran alone (a sequential run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cpu_s: Option<f64>,
}

/// A main job's wall-clock profile as kept on disk (target/main-job-{cold,warm}.json,
/// results/main-job-before.json).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Profile {
    pub total_s: f64,
    pub threads: usize,
    #[serde(default)]
    pub warm: bool,
    /// CPU seconds the process spent (user + system, every thread; `None` where the OS
    /// does not say, and in profiles from before it was kept).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cpu_s: Option<f64>,
    /// How and when it was measured (the kept "before" profile).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    pub stages: Vec<JobStage>,
}

impl JobStage {
    /// A stage without memoised maps, timed from `t0`.
    pub fn since(name: &str, t0: std::time::Instant) -> JobStage {
        JobStage {
            stage: name.into(),
            seconds: t0.elapsed().as_secs_f64(),
            computed: 0,
            reused: 0,
            cpu_s: None,
        }
    }
    /// A study's stage: its seconds, its CPU seconds where it ran alone and, per memoised
    /// map, (items, items computed).
    pub fn of_study(
        study: &str,
        seconds: f64,
        cpu_s: Option<f64>,
        maps: &[(usize, usize)],
    ) -> JobStage {
        JobStage {
            stage: study.into(),
            seconds,
            computed: maps.iter().map(|m| m.1).sum(),
            reused: maps.iter().map(|m| m.0 - m.1).sum(),
            cpu_s,
        }
    }
}

/// Print the main job's time per stage and, with `keep_it` (a run of the shipped specs),
/// keep it for `bench-report` (best-effort: a failure to write is reported, never fatal).
pub fn write_main_job_times(stages: &[JobStage], total: f64, keep_it: bool) {
    let warm = stages.iter().all(|s| s.computed == 0) && stages.iter().any(|s| s.reused > 0);
    let mut sorted: Vec<&JobStage> = stages.iter().collect();
    sorted.sort_by(|a, b| b.seconds.total_cmp(&a.seconds));
    let cpu = crate::progress::process_cpu_seconds();
    println!(
        "main job: {total:.0} s in all{} ({}); by stage (longest first):",
        cpu.map_or(String::new(), |c| format!(", {c:.0} s of CPU")),
        if warm {
            "every memoised map from the cache"
        } else {
            "cold: maps computed"
        }
    );
    for s in &sorted {
        println!(
            "  {:<28} {:>8.1} s  ({:>4.1} %)  {} items computed, {} from the cache",
            s.stage,
            s.seconds,
            100.0 * s.seconds / total.max(1e-9),
            s.computed,
            s.reused
        );
    }
    // the figure printed above is the one kept
    if keep_it {
        keep(&main_job_times_path(warm), stages, total, cpu, warm);
    }
}

/// A kept profile; `None` when the file is absent, or unreadable (said on stderr: a
/// profile is a local measurement, not a result, so the report goes on without it).
fn profile(path: &Path) -> Option<Profile> {
    let text = std::fs::read_to_string(path).ok()?;
    match serde_json::from_str(&text) {
        Ok(p) => Some(p),
        Err(e) => {
            eprintln!("{}: not a main-job profile ({e}); left out", path.display());
            None
        }
    }
}

/// What one study cost on this machine, as the sections that quote it say it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyCost {
    pub seconds: f64,
    /// Its own CPU seconds (only where it ran alone).
    pub cpu_s: Option<f64>,
    /// Run alone (a sequential `regen` that took nothing from a cache), or overlapping others in the parallel
    /// main job.
    pub alone: bool,
}

impl StudyCost {
    /// "99 s alone, 189 s of CPU", or "245 s in the parallel cold main job".
    pub fn describe(&self) -> String {
        match (self.alone, self.cpu_s) {
            (true, Some(c)) => format!("{:.0} s alone, {c:.0} s of CPU", self.seconds),
            (true, None) => format!("{:.0} s alone", self.seconds),
            (false, _) => format!("{:.0} s in the parallel cold main job", self.seconds),
        }
    }
}

/// What `study` cost: run alone in the last cold sequential `regen` where that profile
/// is kept (its wall clock and its own CPU), else its wall clock in the last cold main
/// job, where studies overlap and one study's time says little about its own cost.
pub fn study_cost(study: &str) -> Option<StudyCost> {
    study_cost_in(&target_dir(), study)
}

/// [`study_cost`] from the profiles kept under `target`.
fn study_cost_in(target: &Path, study: &str) -> Option<StudyCost> {
    let find = |p: Profile| p.stages.into_iter().find(|s| s.stage == study);
    if let Some(s) = profile(&target.join(SEQUENTIAL)).and_then(find) {
        return Some(StudyCost {
            seconds: s.seconds,
            cpu_s: s.cpu_s,
            alone: true,
        });
    }
    profile(&target.join(COLD))
        .and_then(find)
        .map(|s| StudyCost {
            seconds: s.seconds,
            cpu_s: None,
            alone: false,
        })
}

/// The main job's profile: before (committed), the last cold run and the last warm run
/// on this machine (kept under target/), stage by stage.
/// Replace only the main job's section of an existing results/performance.md with the
/// profiles now in target/ (no benches needed; the criterion tables stay as they were
/// measured). An absent page or section is an error.
pub fn refresh_main_job(set: &mut crate::io::Outputs, results: &Path) -> Result<String> {
    super::section::replace_section(
        set,
        results,
        "\n## Main job: wall clock per stage",
        &main_job_table(results)?,
    )
}

pub(super) fn main_job_table(results: &Path) -> Result<String> {
    let cols = [
        (
            "before: sequential, no cache",
            profile(&results.join(BEFORE_PATH)),
        ),
        (
            "after: cold (parallel, maps computed)",
            profile(&main_job_times_path(false)),
        ),
        (
            "after: warm (parallel, maps from the cache)",
            profile(&main_job_times_path(true)),
        ),
        (
            "each study alone: sequential `regen`, nothing from a cache; CPU in parentheses",
            profile(&sequential_times_path(false)),
        ),
        (
            "each study alone, warm: sequential `regen`, every map from the cache; CPU in parentheses",
            profile(&sequential_times_path(true)),
        ),
    ];
    if cols.iter().all(|c| c.1.is_none()) {
        return Ok(String::new());
    }
    let mut names: Vec<(String, f64)> = Vec::new();
    for (_, p) in &cols {
        for st in p.iter().flat_map(|p| p.stages.iter()) {
            match names.iter_mut().find(|(m, _)| *m == st.stage) {
                Some(e) => e.1 = e.1.max(st.seconds),
                None => names.push((st.stage.clone(), st.seconds)),
            }
        }
    }
    names.sort_by(|a, b| b.1.total_cmp(&a.1));
    let cell = |p: &Option<Profile>, n: &str| -> String {
        p.as_ref()
            .and_then(|p| p.stages.iter().find(|s| s.stage == n))
            .map_or("—".into(), |s| match s.cpu_s {
                Some(c) => format!("{:.1} ({c:.0})", s.seconds),
                None => format!("{:.1}", s.seconds),
            })
    };
    let mut md = String::from("\n## Main job: wall clock per stage\n\n`cargo run --release` on this machine (wall clock, not criterion). *Before*: the sequential, uncached main job (results/main-job-before.json, kept as measured). *After*: studies whose inputs are ready run at the same time on their own threads (sharing the rayon pool), and every memoised map is looked up in the cache under the hash of the code, the spec, the preset and the inputs (`target/ndfbench-cache`; `--no-cache` computes everything); *cold* is a run that computed its maps (`target/main-job-cold.json`), *warm* one that found all of them (`target/main-job-warm.json`). The total's CPU seconds are the process's user and system time over every thread (`getrusage`), where the profile kept them. With studies in parallel the stages overlap, so they add up to more than the total, and one study's time says little about its own cost; the last two columns are sequential `regen`s of every study (the studies only, without verify and the convergence study), where each study ran alone, with the CPU seconds it used in parentheses: one that took nothing from a cache (`target/regen-sequential.json`, uncached or filling an empty cache: what each study costs from nothing), one with every memoised map from the cache (`target/regen-sequential-warm.json`: what each study costs besides its memoised maps — its reports, its unmemoised measurements — which no faster fitter removes).\n\n");
    let mut t = Table::new(
        std::iter::once("stage".to_string()).chain(cols.iter().map(|(h, _)| format!("{h} (s)"))),
    );
    t.row(
        std::iter::once("**total**".to_string()).chain(cols.iter().map(|(_, p)| {
            format!(
                "**{}**",
                p.as_ref().map_or("—".into(), |p| match p.cpu_s {
                    Some(c) => format!("{:.0} ({} threads, {c:.0} s of CPU)", p.total_s, p.threads),
                    None => format!("{:.0} ({} threads)", p.total_s, p.threads),
                })
            )
        })),
    );
    for (n, _) in &names {
        t.row(std::iter::once(n.clone()).chain(cols.iter().map(|(_, p)| cell(p, n))));
    }
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\nThe *after* columns were measured on {} ({} logical cores), the machine that wrote this section; *before* on the development machine of its time. The study costs quoted in the sections above come from the last full `bench-report`, which may have run on another machine: compare a study's cost only within one column, or within one section.\n",
        cpu_model(),
        std::thread::available_parallelism().map_or(0, |n| n.get())
    ));
    md.push_str(&fits_work_line(results)?);
    Ok(md)
}

/// The processor's model name as the OS reports it (Linux: /proc/cpuinfo), or a phrase
/// saying it is unknown.
fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, m)| m.trim().to_string())
        })
        .filter(|m| !m.is_empty())
        .unwrap_or_else(|| "a processor whose model the OS does not report".into())
}

/// Whether the LTC fits do more work than their accuracy needs, from the on-request
/// `ltc-work` study (results/fits/ltc-work.json), when it has run: per table, its cheaper
/// routes and how many are no worse than the reference route's own spread. A file that
/// does not read as its type is an error; a table without its published draw is left out.
fn fits_work_line(results: &Path) -> Result<String> {
    let Some(w) = crate::results::read::<crate::results::ltc::LtcWork>(results)? else {
        return Ok(String::new());
    };
    // the anisotropic table's work study (ltc-aniso-work), where it has run
    let aniso = crate::results::read::<crate::results::ltc_aniso::AnisoWork>(results)?;
    let mut parts = Vec::new();
    let mut refitted = 0;
    for t in w.tables.iter().chain(aniso.as_ref().map(|a| &a.work)) {
        let Some(d0) = t.draws.first() else { continue };
        refitted = t.draws.len() - 1;
        // a route at the reference's own settings on moving samples is a check
        let cheaper: Vec<_> = t
            .routes
            .iter()
            .filter(|(r, _)| {
                r.nodes() != crate::ltc::fit::Nodes::Moving
                    || (r.samples, r.max_iters) != (d0.samples, d0.max_iters)
            })
            .collect();
        let ok = cheaper.iter().filter(|(_, v)| v.no_worse).count();
        parts.push(format!(
            "{} ({}², ≤ {} iterations): {} of {} cheaper routes no worse",
            t.table,
            d0.samples,
            d0.max_iters,
            ok,
            cheaper.len()
        ));
    }
    if parts.is_empty() {
        return Ok(String::new());
    }
    Ok(format!(
        "\nCan the LTC fits do less work? results/ltc-work.md (on request, preset {}) (and results/ltc-aniso-work.md for the anisotropic table) refits each table's reference route (its published settings on moving samples) on {refitted} other draws of its training samples and judges cheaper routes (fewer samples, lower caps, or trials on fixed nodes, which evaluate no target) against that spread, each statistic within its one-sided 95 % prediction bound: {}.\n",
        w.preset,
        parts.join("; ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ltc-work line is read, not trusted: no file, no line; a file that is not its
    /// type, an error naming it; a table without its published draw, left out (no panic),
    /// and the committed file gives one part per table.
    #[test]
    fn the_fits_work_line_reads_its_file_as_its_type() {
        let dir = std::env::temp_dir().join(format!("ndfbench-fits-work-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("fits")).unwrap();
        assert_eq!(fits_work_line(&dir).unwrap(), "");
        let file = dir.join("fits/ltc-work.json");
        std::fs::write(&file, "not json").unwrap();
        let e = fits_work_line(&dir).unwrap_err().to_string();
        assert!(e.contains("ltc-work"), "{e}");
        let committed = std::fs::read_to_string("results/fits/ltc-work.json").unwrap();
        let mut v: serde_json::Value = serde_json::from_str(&committed).unwrap();
        let tables = v["tables"].as_array().unwrap().len();
        std::fs::write(&file, &committed).unwrap();
        let line = fits_work_line(&dir).unwrap();
        assert_eq!(line.matches("cheaper routes no worse").count(), tables);
        for t in v["tables"].as_array_mut().unwrap() {
            t["draws"] = serde_json::json!([]);
        }
        std::fs::write(&file, serde_json::to_string(&v).unwrap()).unwrap();
        assert_eq!(fits_work_line(&dir).unwrap(), "");
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A sequential run is kept as cold when no map came from a cache (uncached, or
    /// filling an empty one), as warm when every map did, and not at all when it mixed
    /// the two (its CPU would be neither a study's whole cost nor its floor).
    #[test]
    fn a_sequential_profile_is_cold_warm_or_not_kept() {
        let st = |computed, reused| JobStage {
            stage: "s".into(),
            seconds: 1.0,
            computed,
            reused,
            cpu_s: None,
        };
        assert_eq!(sequential_kind(&[]), Some(false));
        assert_eq!(sequential_kind(&[st(0, 0), st(5, 0)]), Some(false));
        assert_eq!(sequential_kind(&[st(0, 0), st(0, 5)]), Some(true));
        assert_eq!(sequential_kind(&[st(5, 0), st(0, 5)]), None);
        assert_eq!(sequential_kind(&[st(2, 3)]), None);
    }

    /// A study's cost comes from the sequential profile (alone, its own CPU) where that
    /// holds it, else from the cold main job (said to overlap), else nothing.
    #[test]
    fn a_study_cost_says_where_it_was_measured() {
        let dir = std::env::temp_dir().join(format!("ndfbench-study-cost-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(study_cost_in(&dir, "ltc-ggx"), None);
        std::fs::write(
            dir.join(COLD),
            r#"{"total_s": 649.0, "threads": 2, "stages": [
                {"stage": "ltc-ggx", "seconds": 244.7}, {"stage": "ltc-sheen", "seconds": 479.7}]}"#,
        )
        .unwrap();
        let cold = study_cost_in(&dir, "ltc-ggx").unwrap();
        assert_eq!(cold.describe(), "245 s in the parallel cold main job");
        std::fs::write(
            dir.join(SEQUENTIAL),
            r#"{"total_s": 669.0, "threads": 2, "stages": [
                {"stage": "ltc-ggx", "seconds": 99.1, "cpu_s": 188.6}]}"#,
        )
        .unwrap();
        assert_eq!(
            study_cost_in(&dir, "ltc-ggx").unwrap().describe(),
            "99 s alone, 189 s of CPU"
        );
        // a study the sequential profile lacks still falls back to the cold job
        assert_eq!(
            study_cost_in(&dir, "ltc-sheen").unwrap().describe(),
            "480 s in the parallel cold main job"
        );
        assert_eq!(study_cost_in(&dir, "render"), None);
        // an unreadable profile is left out, not an error
        std::fs::write(dir.join(SEQUENTIAL), "not json").unwrap();
        assert_eq!(
            study_cost_in(&dir, "ltc-ggx").unwrap().describe(),
            "245 s in the parallel cold main job"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}

//! The `regen` driver: which studies run, in what order, under which memo mode
//! (`crate::memo`: plain, cached, one shard, merged shards), each published as one output
//! set. Independent studies may run at the same time (each on its own thread, sharing the
//! rayon pool); their outputs do not depend on it.

use super::registry::{find, STUDIES};
use crate::error::{Error, Result};
use crate::fit::spec::{self, FitSpec};
use crate::integrate::Preset;
use crate::memo::{self, shards::Identity, MapLog, Mode, Scope};
use crate::study::{Ctx, FitOutcome};
use std::path::{Path, PathBuf};

/// How [`regen_with`] runs its studies.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// The result cache directory (None: every map is computed).
    pub cache: Option<PathBuf>,
    /// Run studies whose inputs are ready at the same time.
    pub parallel: bool,
}

/// One study's wall clock and what its memoised maps did.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StudyTime {
    pub study: String,
    pub seconds: f64,
    /// The process's CPU seconds while it ran, where it ran alone (studies one at a time;
    /// `None` when studies ran at the same time, whose CPU cannot be told apart).
    pub cpu_seconds: Option<f64>,
    pub maps: Vec<MapLog>,
}

/// What identifies a study's run: the code it reaches, its spec, its inputs (every spec, since a
/// study may read another's settings, and the published manifests of the studies it
/// follows), the preset.
pub fn identity(spec: &FitSpec, specs: &[FitSpec], results: &Path, preset: Preset) -> Identity {
    let json = |s: &FitSpec| serde_json::to_vec(s).unwrap_or_default();
    let mut inputs: Vec<Vec<u8>> = specs.iter().map(json).collect();
    if let Some(st) = find(&spec.name) {
        for a in st.after() {
            let m = crate::io::results_manifest(results, a);
            inputs.push(a.as_bytes().to_vec());
            inputs.push(std::fs::read(&m).unwrap_or_else(|_| b"absent".to_vec()));
        }
    }
    let parts: Vec<&[u8]> = inputs.iter().map(Vec::as_slice).collect();
    Identity {
        study: spec.name.clone(),
        // the code the study reaches, not every source file (memo::deps)
        code: find(&spec.name)
            .map_or(memo::CODE_HASH, |s| memo::code_hash_of(s.module()))
            .to_string(),
        spec: memo::key(&[&json(spec)]),
        inputs: memo::key(&parts),
        preset: preset.name().to_string(),
    }
}

fn scope_key(id: &Identity) -> String {
    memo::key(&[
        id.study.as_bytes(),
        id.code.as_bytes(),
        id.spec.as_bytes(),
        id.inputs.as_bytes(),
        id.preset.as_bytes(),
    ])
}

/// Every spec, each naming a study.
fn load_specs(fits_dir: &Path) -> Result<Vec<FitSpec>> {
    let specs = spec::load_dir(fits_dir)?;
    // every spec must name a study: a typo is an error, not some other fit
    for s in &specs {
        if let Some(study) = find(&s.name) {
            study.check(s)?;
        } else {
            return Err(Error::InvalidArgument(format!(
                "{}: spec '{}' names no study (known: {})",
                fits_dir.display(),
                s.name,
                STUDIES
                    .iter()
                    .map(|s| s.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    Ok(specs)
}

/// The names of `specs`, comma-separated (for messages that list the valid ones).
fn spec_names(specs: &[FitSpec]) -> String {
    specs
        .iter()
        .map(|s| s.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The specs `only` selects, in run order: studies without `after` first, each group by
/// name. `only` is one exact study name or several joined by commas; a study that follows
/// others brings them along (they run first). Without `only`, every study but those run
/// on request only (`Study::on_request`). A name that is no study is an error listing the
/// valid ones.
fn select<'a>(specs: &'a [FitSpec], only: Option<&str>) -> Result<Vec<&'a FitSpec>> {
    let wanted: Option<Vec<&str>> = match only {
        None => None,
        Some(list) => {
            let mut names = Vec::new();
            for name in list.split(',').map(str::trim) {
                let Some(study) = find(name).filter(|_| specs.iter().any(|s| s.name == name))
                else {
                    return Err(Error::InvalidArgument(format!(
                        "--only {}: not a study with a spec here (valid: {})",
                        crate::error::quoted(name),
                        spec_names(specs)
                    )));
                };
                names.extend_from_slice(study.after());
                names.push(study.name());
            }
            Some(names)
        }
    };
    let mut selected: Vec<&FitSpec> = specs
        .iter()
        .filter(|s| match &wanted {
            Some(w) => w.contains(&s.name.as_str()),
            None => !find(&s.name).is_some_and(|x| x.on_request()),
        })
        .collect();
    selected.sort_by_key(|s| {
        let follows = find(&s.name).is_some_and(|x| !x.after().is_empty());
        (follows, s.name.clone())
    });
    Ok(selected)
}

/// Run one study under `mode` inside its own output set; committed only when it returns.
fn run_one(
    s: &FitSpec,
    specs: &[FitSpec],
    results: &Path,
    preset: Preset,
    mode: Mode,
    commit: bool,
) -> (Result<FitOutcome>, Scope, f64) {
    let id = identity(s, specs, results, preset);
    let scope = Scope::new(&s.name, scope_key(&id), mode);
    let t = std::time::Instant::now();
    let (r, scope) = memo::run_in(scope, || -> Result<FitOutcome> {
        let study = find(&s.name)
            .ok_or_else(|| Error::InvalidArgument(format!("spec '{}' names no study", s.name)))?;
        crate::report::stage(&format!("regen {}: started", s.name));
        // the study's own line while it runs (between its maps too)
        let _running = crate::progress::Progress::study(s.name.clone());
        // one study = one output set: computed, rendered as data, then published here in
        // one step (crate::io)
        let computed = study.compute(&Ctx {
            spec: s,
            specs,
            results,
            preset,
        })?;
        let o = computed.outcome();
        let mut set = crate::io::Outputs::new();
        computed.render(&mut set, results)?;
        if commit {
            set.publish(&s.name, &crate::io::results_manifest(results, &s.name))?;
        }
        Ok(o)
    });
    (r, scope, t.elapsed().as_secs_f64())
}

/// Run the studies `only` selects (exact names, comma-separated; all but the on-request
/// ones when None) and publish each one's output set.
pub fn regen(
    fits_dir: &Path,
    results: &Path,
    only: Option<&str>,
    preset: Preset,
) -> Result<Vec<FitOutcome>> {
    regen_timed(fits_dir, results, only, preset).map(|(o, _)| o)
}

/// [`regen`], with each study's wall-clock seconds (in run order).
pub fn regen_timed(
    fits_dir: &Path,
    results: &Path,
    only: Option<&str>,
    preset: Preset,
) -> Result<(Vec<FitOutcome>, Vec<(String, f64)>)> {
    let (o, t) = regen_with(fits_dir, results, only, preset, &RunOptions::default())?;
    Ok((o, t.into_iter().map(|t| (t.study, t.seconds)).collect()))
}

/// [`regen`] with a cache and/or independent studies at the same time. Outcomes and
/// times come back in run order whatever the schedule.
pub fn regen_with(
    fits_dir: &Path,
    results: &Path,
    only: Option<&str>,
    preset: Preset,
    opts: &RunOptions,
) -> Result<(Vec<FitOutcome>, Vec<StudyTime>)> {
    let specs = load_specs(fits_dir)?;
    let selected = select(&specs, only)?;
    if selected.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "no fit spec in {} selects a study",
            crate::error::quoted(&fits_dir.display().to_string())
        )));
    }
    let mode = || match &opts.cache {
        Some(d) => Mode::Cache(memo::cache::Cache::new(d)),
        None => Mode::Plain,
    };
    let cpu = crate::progress::process_cpu_seconds;
    let runs = schedule(&selected, opts.parallel, &|s: &FitSpec| {
        let c0 = cpu().filter(|_| !opts.parallel);
        let (r, scope, secs) = run_one(s, &specs, results, preset, mode(), true);
        let cpu_seconds = c0.and_then(|c0| Some(cpu()? - c0));
        if r.is_ok() {
            let used = cpu_seconds.map_or(String::new(), |c| format!(" ({c:.1} s of CPU)"));
            crate::report::stage(&format!("regen {}: done in {secs:.1} s{used}", s.name));
        }
        (
            r,
            StudyTime {
                study: s.name.clone(),
                seconds: secs,
                cpu_seconds,
                maps: scope.log,
            },
        )
    });
    let mut out = Vec::new();
    let mut times = Vec::new();
    for (r, t) in runs {
        out.push(r?);
        times.push(t);
    }
    Ok((out, times))
}

type Done = (Result<FitOutcome>, StudyTime);

/// Run `job` on every selected spec, a study only after the selected studies it follows;
/// with `parallel`, every study whose predecessors are done starts at once on its own
/// thread. After a failure nothing new starts. Results in the order of `selected`.
fn schedule(
    selected: &[&FitSpec],
    parallel: bool,
    job: &(dyn Fn(&FitSpec) -> Done + Sync),
) -> Vec<Done> {
    let n = selected.len();
    let deps: Vec<Vec<usize>> = selected
        .iter()
        .map(|s| {
            let after = find(&s.name).map(|x| x.after()).unwrap_or(&[]);
            (0..n)
                .filter(|&j| after.contains(&selected[j].name.as_str()))
                .collect()
        })
        .collect();
    let mut slots: Vec<Option<Done>> = (0..n).map(|_| None).collect();
    if !parallel {
        for (i, s) in selected.iter().enumerate() {
            let d = job(s);
            let failed = d.0.is_err();
            slots[i] = Some(d);
            if failed {
                break;
            }
        }
        return slots.into_iter().flatten().collect();
    }
    let (tx, rx) = std::sync::mpsc::channel::<(usize, Done)>();
    std::thread::scope(|sc| {
        let mut started = vec![false; n];
        let mut running = 0usize;
        let mut failed = false;
        loop {
            if !failed {
                for i in 0..n {
                    let ready = deps[i]
                        .iter()
                        .all(|&j| matches!(&slots[j], Some((Ok(_), _))));
                    if !started[i] && ready {
                        started[i] = true;
                        running += 1;
                        let tx = tx.clone();
                        let s = selected[i];
                        sc.spawn(move || {
                            let _ = tx.send((i, job(s)));
                        });
                    }
                }
            }
            if running == 0 {
                break;
            }
            let Ok((i, d)) = rx.recv() else { break };
            running -= 1;
            failed |= d.0.is_err();
            slots[i] = Some(d);
        }
    });
    slots.into_iter().flatten().collect()
}

/// Compute shard `k` of `n` of the study `name` (its first memoised map) and write it into
/// `dir`; nothing else is written. The studies it follows must already be in `results`.
/// The spec a sharded run of `name` runs: the study's exact name among the specs of
/// the fits folder (every spec parsed and naming a study). `regen --shard` and `slurm`
/// both validate through this one function.
fn sharded_spec<'a>(specs: &'a [FitSpec], name: &str) -> Result<&'a FitSpec> {
    specs.iter().find(|s| s.name == name).ok_or_else(|| {
        Error::Shard(format!(
            "--shard needs --only with a study's exact name; {} is none (known: {})",
            crate::error::quoted(name),
            spec_names(specs)
        ))
    })
}

/// Validate a sharded run of `name` as `regen --shard` does, without running it.
pub fn check_sharded(fits_dir: &Path, name: &str) -> Result<()> {
    sharded_spec(&load_specs(fits_dir)?, name).map(|_| ())
}

pub fn shard(
    fits_dir: &Path,
    results: &Path,
    name: &str,
    preset: Preset,
    (k, n): (usize, usize),
    dir: &Path,
) -> Result<PathBuf> {
    let specs = load_specs(fits_dir)?;
    let s = sharded_spec(&specs, name)?;
    let id = identity(s, &specs, results, preset);
    let (r, scope, _) = run_one(s, &specs, results, preset, Mode::Shard { k, n }, false);
    match r {
        Err(Error::ShardDone) => {}
        Err(e) => return Err(e),
        Ok(_) => {
            return Err(Error::Shard(format!(
                "study '{name}' has no memoised map to shard; run it whole"
            )))
        }
    }
    let part = scope
        .part
        .ok_or_else(|| Error::Shard(format!("study '{name}': no shard was computed")))?;
    memo::shards::write(dir, &id, k, n, part)
}

/// Merge a complete, consistent set of shard files (files or directories) into the
/// study's output set, exactly what the unsharded run writes; the study and preset come
/// from the shards. Any refusal (missing, duplicated, foreign, corrupt) writes nothing.
pub fn merge(fits_dir: &Path, results: &Path, paths: &[PathBuf]) -> Result<(FitOutcome, f64)> {
    let specs = load_specs(fits_dir)?;
    let (name, preset) = memo::shards::peek(paths)?;
    let preset = Preset::parse(&preset)
        .ok_or_else(|| Error::Shard(format!("shards name an unknown preset '{preset}'")))?;
    let s = specs.iter().find(|s| s.name == name).ok_or_else(|| {
        Error::Shard(format!(
            "the shards are of study '{name}', which no spec in '{}' names",
            fits_dir.display()
        ))
    })?;
    let id = identity(s, &specs, results, preset);
    let part = memo::shards::load_set(paths, &id)?;
    let shard_seconds = part.seconds;
    let (r, _, _) = run_one(s, &specs, results, preset, Mode::Merge(part), true);
    Ok((r?, shard_seconds))
}

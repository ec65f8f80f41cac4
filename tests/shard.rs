//! Sharded and cached runs give the bits of the unsharded run: shards of one quick study
//! merged at N = 1, 2 and 3 are byte-identical to it; a missing, duplicated or foreign
//! shard is a typed error naming it and writes nothing; a cache hit equals recomputation;
//! and, where a local Slurm answers, an 8-task job array merged by a dependent job does too.

use ndfbench::integrate::Preset;
use ndfbench::studies::{self, RunOptions};
use ndfbench::Error;
use std::path::{Path, PathBuf};

const STUDY: &str = "ltc-diffuse";
const FILES: [&str; 4] = [
    "fits/ltc-diffuse.json",
    "fits/ltc-diffuse-engines.json",
    "ltc-diffuse.md",
    "ltc-diffuse-error.svg",
];

fn fits() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fits")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ndfb-shard-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn files(dir: &Path) -> Vec<Vec<u8>> {
    FILES
        .iter()
        .map(|f| {
            std::fs::read(dir.join(f)).unwrap_or_else(|e| panic!("{}: {e}", dir.join(f).display()))
        })
        .collect()
}

fn unsharded(name: &str) -> (PathBuf, Vec<Vec<u8>>) {
    let d = tmp(&format!("whole-{name}"));
    studies::regen(&fits(), &d, Some(STUDY), Preset::Quick).unwrap();
    let f = files(&d);
    (d, f)
}

fn shards(results: &Path, n: usize, name: &str) -> PathBuf {
    let dir = tmp(name);
    for k in 0..n {
        studies::shard(&fits(), results, STUDY, Preset::Quick, (k, n), &dir).unwrap();
    }
    dir
}

#[test]
fn merged_shards_are_byte_identical_at_every_count() {
    let (_, whole) = unsharded("merge");
    for n in 1..=3 {
        let results = tmp(&format!("merged-{n}"));
        let dir = shards(&results, n, &format!("shards-{n}"));
        let count = std::fs::read_dir(&dir).unwrap().count();
        assert_eq!(count, n, "one file per shard");
        // nothing but the shard files is written by --shard
        assert!(!results.join("ltc-diffuse.md").exists());
        studies::merge(&fits(), &results, &[dir]).unwrap();
        let merged = files(&results);
        for (f, (a, b)) in FILES.iter().zip(whole.iter().zip(&merged)) {
            assert!(
                a == b,
                "{f} differs between the unsharded run and {n} merged shards"
            );
        }
    }
}

fn refused(paths: &[PathBuf], what: &str, naming: &str) {
    let out = tmp(&format!("refused-{what}"));
    match studies::merge(&fits(), &out, paths) {
        Err(Error::Shard(m)) => {
            assert!(m.contains(what), "'{m}' should say {what}");
            assert!(m.contains(naming), "'{m}' should name {naming}");
            assert!(!m.contains('\n') && m.len() < 600, "one line: {m}");
        }
        other => panic!("{what}: expected a shard error, got {other:?}"),
    }
    assert_eq!(
        std::fs::read_dir(&out).unwrap().count(),
        0,
        "{what}: something was written"
    );
}

#[test]
fn missing_duplicated_and_foreign_shards_are_refused() {
    let base = tmp("set");
    let dir = shards(&base, 3, "set-shards");
    let p = |k: usize| dir.join(format!("{STUDY}.shard-{k}-of-3.json"));
    // missing: shard 1 of 3 left out
    refused(&[p(0), p(2)], "missing", "1/3");
    // duplicated: shard 0 under a second name
    let copy = tmp("dup").join("copy.shard-0.json");
    std::fs::copy(p(0), &copy).unwrap();
    refused(
        &[p(0), p(1), p(2), copy.clone()],
        "duplicated",
        "copy.shard-0.json",
    );
    // foreign: another spec's shard (its spec hash changed), and another study's
    let text = std::fs::read_to_string(p(2)).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let spec = v["spec"].as_str().unwrap().to_string();
    let alien = tmp("foreign").join("alien.shard-2.json");
    std::fs::write(&alien, text.replace(&spec, &"0".repeat(64))).unwrap();
    refused(
        &[p(0), p(1), alien.clone()],
        "foreign",
        "alien.shard-2.json",
    );
    let other = tmp("other").join("other.shard-2.json");
    std::fs::write(
        &other,
        text.replace("\"study\":\"ltc-diffuse\"", "\"study\":\"ltc-sheen\""),
    )
    .unwrap();
    refused(
        &[p(0), p(1), other.clone()],
        "foreign",
        "other.shard-2.json",
    );
    // a shard whose items are not its own, and a file that is no shard
    let bad = tmp("corrupt").join("bad.shard-1.json");
    std::fs::write(
        &bad,
        std::fs::read_to_string(p(1))
            .unwrap()
            .replace("\"shard\":1", "\"shard\":0"),
    )
    .unwrap();
    refused(
        &[bad.clone(), p(1), p(2)],
        "not exactly",
        "bad.shard-1.json",
    );
    let junk = tmp("junk").join("junk.shard-0.json");
    std::fs::write(&junk, "{\"format\": 3").unwrap();
    refused(&[junk.clone()], "not a shard file", "junk.shard-0.json");
    assert!(matches!(
        ndfbench::memo::shards::parse_spec("3/3"),
        Err(Error::Shard(_))
    ));
    assert!(matches!(
        ndfbench::memo::shards::parse_spec("0/0"),
        Err(Error::Shard(_))
    ));
    assert!(ndfbench::memo::shards::parse_spec("2/9").is_ok());
}

#[test]
fn a_cache_hit_equals_recomputation() {
    let (_, whole) = unsharded("cache");
    let cache = tmp("cache");
    let opts = RunOptions {
        cache: Some(cache.clone()),
        parallel: true,
    };
    let cold = tmp("cold");
    let (_, t1) = studies::regen_with(&fits(), &cold, Some(STUDY), Preset::Quick, &opts).unwrap();
    let warm = tmp("warm");
    let (_, t2) = studies::regen_with(&fits(), &warm, Some(STUDY), Preset::Quick, &opts).unwrap();
    assert!(
        t1[0].maps.iter().all(|m| m.source != "cache hit"),
        "cold run hit an empty cache"
    );
    assert!(
        !t2[0].maps.is_empty() && t2[0].maps.iter().all(|m| m.source == "cache hit"),
        "{:?}",
        t2[0].maps
    );
    assert!(t2[0].maps.iter().all(|m| m.computed == 0));
    for (dir, what) in [(&cold, "cold"), (&warm, "warm")] {
        for (f, (a, b)) in FILES.iter().zip(whole.iter().zip(&files(dir))) {
            assert!(
                a == b,
                "{f}: the {what} cached run differs from the plain run"
            );
        }
    }
    // a corrupted entry is a miss, recomputed and identical
    let entries: Vec<PathBuf> = std::fs::read_dir(cache.join(STUDY))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    assert!(!entries.is_empty());
    std::fs::write(&entries[0], "not json").unwrap();
    let again = tmp("again");
    let (_, t3) = studies::regen_with(&fits(), &again, Some(STUDY), Preset::Quick, &opts).unwrap();
    assert_eq!(
        t3[0]
            .maps
            .iter()
            .filter(|m| m.source != "cache hit")
            .count(),
        1
    );
    for (f, (a, b)) in FILES.iter().zip(whole.iter().zip(&files(&again))) {
        assert!(a == b, "{f}: the run after a corrupted entry differs");
    }
}

fn slurm_up() -> Result<(), String> {
    let ok = |c: &str, a: &[&str]| {
        std::process::Command::new(c)
            .args(a)
            .output()
            .map(|o| o.status.success())
            .unwrap_or(false)
    };
    if !ok("sbatch", &["--version"]) {
        return Err("sbatch not found".into());
    }
    if !ok("sinfo", &["-h"]) {
        return Err("sinfo fails: no slurmctld answers".into());
    }
    Ok(())
}

#[test]
fn an_eight_task_slurm_array_merges_to_the_unsharded_run() {
    if let Err(why) = slurm_up() {
        eprintln!("skipped: Slurm cannot run here ({why}); .ci/run installs slurm-wlm and munge where it can");
        return;
    }
    let (_, whole) = unsharded("slurm");
    let results = tmp("slurm-results");
    let out = tmp("slurm");
    let bin = env!("CARGO_BIN_EXE_ndfbench");
    let st = std::process::Command::new(bin)
        .args([
            "--fits",
            fits().to_str().unwrap(),
            "--results",
            results.to_str().unwrap(),
        ])
        .args([
            "slurm",
            "--only",
            STUDY,
            "--shards",
            "8",
            "--max-running",
            "4",
            "--preset",
            "quick",
            "--out",
            out.to_str().unwrap(),
        ])
        .status()
        .unwrap();
    assert!(st.success());
    let run = std::process::Command::new("sh")
        .arg(out.join("submit.sh"))
        .arg("--wait")
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "submission failed: {}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(std::fs::read_dir(out.join("shards")).unwrap().count(), 8);
    for (f, (a, b)) in FILES.iter().zip(whole.iter().zip(&files(&results))) {
        assert!(a == b, "{f}: the Slurm run differs from the unsharded run");
    }
}

/// The binary's answer to bad batch arguments: exit 2, one line, nothing written.
#[test]
fn bad_batch_arguments_exit_2_with_one_line() {
    let bin = env!("CARGO_BIN_EXE_ndfbench");
    let out = tmp("cli");
    let cases: Vec<Vec<String>> = vec![
        vec!["merge".into(), out.join("absent").display().to_string()],
        vec!["merge".into(), out.display().to_string()],
        vec![
            "regen".into(),
            "--only".into(),
            STUDY.into(),
            "--shard".into(),
            "3/3".into(),
        ],
        vec![
            "regen".into(),
            "--only".into(),
            STUDY.into(),
            "--shard".into(),
            "NaN/1e300".into(),
        ],
        vec![
            "regen".into(),
            "--only".into(),
            STUDY.into(),
            "--shard".into(),
            "0/1000000000000".into(),
        ],
        vec!["regen".into(), "--shard".into(), "0/2".into()],
        vec![
            "slurm".into(),
            "--only".into(),
            STUDY.into(),
            "--shards".into(),
            "0".into(),
            "--out".into(),
            out.join("s").display().to_string(),
        ],
        vec![
            "slurm".into(),
            "--only".into(),
            "a;rm".into(),
            "--shards".into(),
            "2".into(),
            "--out".into(),
            out.join("s").display().to_string(),
        ],
    ];
    for args in &cases {
        let o = std::process::Command::new(bin)
            .args([
                "--fits",
                fits().to_str().unwrap(),
                "--results",
                out.join("r").to_str().unwrap(),
            ])
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    }
    // nothing but the (empty) directory itself
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 0);
}

/// The JSON with every wall-clock field (`seconds`, `pndf_seconds`) taken out.
fn without_clocks(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(m) => {
            m.retain(|k, _| !k.ends_with("seconds"));
            m.values_mut().for_each(without_clocks);
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(without_clocks),
        _ => {}
    }
}

/// Seed 002 at scale shards by cluster: two shards of its quick stand-in merge to the
/// unsharded run's numbers (every field but the wall clock each cluster measured), and
/// neither `regen` without `--only` nor a name that merely contains it runs it.
#[test]
fn the_paper_scale_study_shards_by_cluster() {
    let name = "tensor-scale";
    let whole = tmp("scale-whole");
    let o = studies::regen(&fits(), &whole, Some(name), Preset::Quick).unwrap();
    assert_eq!(o.len(), 1);
    let merged = tmp("scale-merged");
    let dir = tmp("scale-shards");
    for k in 0..2 {
        studies::shard(&fits(), &merged, name, Preset::Quick, (k, 2), &dir).unwrap();
    }
    studies::merge(&fits(), &merged, &[dir]).unwrap();
    let read = |d: &Path| -> serde_json::Value {
        let mut v: serde_json::Value =
            serde_json::from_slice(&std::fs::read(d.join("fits/tensor-scale.json")).unwrap())
                .unwrap();
        without_clocks(&mut v);
        v
    };
    let (a, b) = (read(&whole), read(&merged));
    assert_eq!(
        a["clusters"].as_array().map(Vec::len),
        Some(32),
        "16 clusters × 2 maps"
    );
    assert!(a == b, "the merged clusters differ from the unsharded run");
    // the on-request study is left out of every other selection
    let d = tmp("scale-substring");
    let o = studies::regen(&fits(), &d, Some("tensor"), Preset::Quick).unwrap();
    assert!(
        o.iter().all(|x| x.name != name),
        "a substring selected {name}"
    );
    assert!(!d.join("tensor-scale.md").exists());
}

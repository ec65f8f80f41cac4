//! Sharded and cached runs give the bits of the unsharded run: shards of one quick study
//! merged at N = 1, 2 and 3 are byte-identical to it; a missing, duplicated or foreign
//! shard is a typed error naming it and writes nothing; a cache hit equals recomputation;
//! and, where a local Slurm answers, an 8-task job array merged by a dependent job does too.

mod common;

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
    common::scratch("shard", name)
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
    let (_, t) = studies::regen_with(
        &fits(),
        &d,
        Some(STUDY),
        Preset::Quick,
        &RunOptions::default(),
    )
    .unwrap();
    // one study at a time: each has its own CPU seconds (getrusage, on Unix)
    assert!(
        !cfg!(unix) || t.iter().all(|t| t.cpu_seconds.is_some_and(|c| c >= 0.0)),
        "{t:?}"
    );
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

/// A file edited as another run would have written it: its content sealed again (the
/// foreign-shard cases below test what the identity check catches behind the seal).
fn reseal(text: &str) -> String {
    let v: serde_json::Value = serde_json::from_str(text).unwrap();
    serde_json::to_string(&ndfbench::memo::seal::seal(v)).unwrap()
}

/// Mutations of one class each at the first place in `text` after `from` where the class
/// applies: a digit changed, a sign added, an exponent added, a key renamed, the
/// structure changed (an array item duplicated). Each result is still valid JSON.
fn mutations(text: &str, from: &str) -> Vec<(&'static str, String)> {
    let start = text.find(from).expect("the region") + from.len();
    let b = text.as_bytes();
    let digit = (start..b.len())
        .find(|&i| b[i].is_ascii_digit() && b[i] != b'9')
        .unwrap();
    let mut out = Vec::new();
    let mut d = text.to_string();
    d.replace_range(digit..digit + 1, &((b[digit] + 1) as char).to_string());
    out.push(("digit", d));
    // the start of a number: a digit after '[', ',' or ':'
    let num = (start..b.len())
        .find(|&i| b[i].is_ascii_digit() && matches!(b[i - 1], b'[' | b',' | b':'))
        .unwrap();
    let mut sgn = text.to_string();
    sgn.insert(num, '-');
    out.push(("sign", sgn));
    let end = (num..b.len())
        .find(|&i| !(b[i].is_ascii_digit() || b".eE+-".contains(&b[i])))
        .unwrap();
    let mut ex = text.to_string();
    ex.insert_str(
        end,
        if text[num..end].contains(['e', 'E']) {
            "0"
        } else {
            "e1"
        },
    );
    out.push(("exponent", ex));
    out.push(("key", text.replacen("\"label\"", "\"labex\"", 1)));
    // an array's first item repeated
    let open = (start..b.len()).find(|&i| b[i] == b'[').unwrap() + 1;
    let mut depth = 0i32;
    let end = (open..b.len())
        .find(|&i| {
            match b[i] {
                b'[' | b'{' => depth += 1,
                b']' | b'}' if depth > 0 => depth -= 1,
                b',' | b']' if depth == 0 => return true,
                _ => {}
            }
            false
        })
        .unwrap();
    let mut st = text.to_string();
    st.insert_str(end, &format!(",{}", &text[open..end]));
    out.push(("structure", st));
    for (what, m) in &out {
        assert_ne!(m, text, "{what}");
        serde_json::from_str::<serde_json::Value>(m).unwrap_or_else(|e| panic!("{what}: {e}"));
    }
    out
}

/// Every class of change to a shard file's content is caught by its seal: merge is a
/// typed error naming the file, and writes nothing.
#[test]
fn a_changed_byte_of_a_shard_is_caught() {
    let base = tmp("seal");
    let dir = shards(&base, 2, "seal-shards");
    let p = |k: usize| dir.join(format!("{STUDY}.shard-{k}-of-2.json"));
    let text = std::fs::read_to_string(p(1)).unwrap();
    for (what, m) in mutations(&text, "\"items\":") {
        let bad = tmp(&format!("seal-{what}")).join("edited.shard-1.json");
        std::fs::write(&bad, m).unwrap();
        refused(&[p(0), bad], "SHA-256", "edited.shard-1.json");
    }
}

/// Every class of change to a cache entry is caught by its seal: the entry is discarded
/// (a miss, so the map is computed again) and removed; an intact one is a hit.
#[test]
fn a_changed_byte_of_a_cache_entry_is_a_miss() {
    use ndfbench::memo::cache::{load, store};
    let dir = tmp("cache-seal");
    let values = vec![0.022771234567, -3.5, 1.25e-7, 6.0e22];
    let path = dir.join("entry.json");
    store(&path, "k", "the map", &values);
    let good = std::fs::read_to_string(&path).unwrap();
    assert_eq!(load::<f64>(&path, "k", "the map", 4), Some(values.clone()));
    for (what, m) in mutations(&good, "\"values\":") {
        std::fs::write(&path, &m).unwrap();
        assert_eq!(load::<f64>(&path, "k", "the map", 4), None, "{what}: {m}");
        assert!(!path.exists(), "{what}: the corrupt entry is removed");
    }
    // the change of the audit: one digit of a value
    std::fs::write(&path, good.replacen("0.022771", "0.722771", 1)).unwrap();
    assert_eq!(load::<f64>(&path, "k", "the map", 4), None);
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
    std::fs::write(&alien, reseal(&text.replace(&spec, &"0".repeat(64)))).unwrap();
    refused(
        &[p(0), p(1), alien.clone()],
        "foreign",
        "alien.shard-2.json",
    );
    let other = tmp("other").join("other.shard-2.json");
    std::fs::write(
        &other,
        reseal(&text.replace("\"study\":\"ltc-diffuse\"", "\"study\":\"ltc-sheen\"")),
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
        reseal(
            &std::fs::read_to_string(p(1))
                .unwrap()
                .replace("\"shard\":1", "\"shard\":0"),
        ),
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
    // studies that may run at the same time have no CPU seconds of their own
    assert!(t1.iter().all(|t| t.cpu_seconds.is_none()), "{t1:?}");
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
    let mut cases = cases;
    // slurm validates the study as regen --shard does; echoed text stays one line; a
    // path Slurm's #SBATCH lines cannot quote is refused
    let slurm = |only: &str, extra: &[&str], dir: String| -> Vec<String> {
        let mut v: Vec<String> = ["slurm", "--only", only, "--shards", "2", "--out"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        v.push(dir);
        v.extend(extra.iter().map(|s| s.to_string()));
        v
    };
    let plain = out.join("s").display().to_string();
    cases.push(slurm("no-such-study", &[], plain.clone()));
    cases.push(slurm("no\nsuch", &[], plain.clone()));
    cases.push(slurm(STUDY, &["--partition", "a\nb"], plain.clone()));
    for weird in [
        "my dir",
        "a\ntouch /tmp/ndfb-injected\n#",
        "q'uote",
        "d\"q",
        "$(touch x)",
        "`touch x`",
        "pct%j",
        "tab\there",
    ] {
        cases.push(slurm(STUDY, &[], out.join(weird).display().to_string()));
    }
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
    assert!(!Path::new("/tmp/ndfb-injected").exists());
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
    // the on-request study is left out of every other selection, and a name that merely
    // starts like it is no selection at all
    let d = tmp("scale-substring");
    assert!(studies::regen(&fits(), &d, Some("tensor-s"), Preset::Quick).is_err());
    let o = studies::regen(&fits(), &d, Some("tensor"), Preset::Quick).unwrap();
    assert!(
        o.iter().all(|x| x.name != name),
        "a substring selected {name}"
    );
    assert!(!d.join("tensor-scale.md").exists());
}

/// The generated scripts run every path they interpolate as one shell word: fits and
/// results folders named with spaces, quotes, `$()`, backticks and a newline reach the
/// program unchanged, and nothing they spell is executed.
#[test]
fn generated_scripts_pass_hostile_paths_as_single_words() {
    use ndfbench::cli::batch::{scripts, SlurmArgs};
    let base = tmp("hostile");
    let odd = base.join("we ird '$(touch INJ1)' `touch INJ2` \"q\"\nline; touch INJ3");
    let (fits_dir, results) = (odd.join("fits"), odd.join("results"));
    std::fs::create_dir_all(&fits_dir).unwrap();
    std::fs::create_dir_all(&results).unwrap();
    // the "program": prints each argument it receives on its own NUL-terminated record
    let exe = base.join("args.sh");
    std::fs::write(
        &exe,
        "#!/bin/sh\nfor a in \"$@\"; do printf '%s\\0' \"$a\"; done\n",
    )
    .unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&exe, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let a = SlurmArgs {
        only: STUDY.into(),
        shards: 2,
        max_running: 0,
        cpus: 1,
        preset: Preset::Quick,
        partition: None,
        out: base.join("out"),
    };
    let files = scripts(&a, &exe, &fits_dir, &results).expect("clean --out is accepted");
    if std::process::Command::new("bash")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("skipped running the scripts: no bash");
        return;
    }
    for (name, text) in files.iter().filter(|f| f.0.ends_with(".sbatch")) {
        let o = std::process::Command::new("bash")
            .arg("-c")
            .arg(text)
            .env("SLURM_ARRAY_TASK_ID", "1")
            .current_dir(&base)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let args: Vec<String> = o
            .stdout
            .split(|b| *b == 0)
            .filter(|a| !a.is_empty())
            .map(|a| String::from_utf8_lossy(a).into_owned())
            .collect();
        assert_eq!(args[0], "--fits", "{name}: {args:?}");
        assert_eq!(Path::new(&args[1]), fits_dir, "{name}");
        assert_eq!(args[2], "--results");
        assert_eq!(Path::new(&args[3]), results, "{name}");
    }
    // shellcheck, where installed (.ci/run installs it best-effort), warns of nothing
    // (its info notes about `$(` inside single quotes are the point of the quoting)
    match std::process::Command::new("shellcheck")
        .arg("--version")
        .output()
    {
        Ok(_) => {
            for (name, text) in &files {
                let p = base.join(name);
                std::fs::write(&p, text).unwrap();
                let o = std::process::Command::new("shellcheck")
                    .args(["-S", "warning"])
                    .arg(&p)
                    .output()
                    .unwrap();
                assert!(
                    o.status.success(),
                    "shellcheck {name}: {}",
                    String::from_utf8_lossy(&o.stdout)
                );
            }
        }
        Err(_) => eprintln!("skipped shellcheck: not installed"),
    }
    for f in ["INJ1", "INJ2", "INJ3"] {
        assert!(
            !base.join(f).exists() && !odd.join(f).exists(),
            "{f} was executed"
        );
    }
}

//! The binary: JSON from `eval`, typed errors with exit status 2, verify's exit status.

mod common;

use common::bin;

#[test]
fn eval_prints_json_with_the_closed_form() {
    let out = bin()
        .args([
            "eval",
            "lambda",
            "--ndf",
            "ggx",
            "--alpha",
            "0.5",
            "--o",
            "0.6,0,0.8",
        ])
        .output()
        .unwrap();
    common::assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // GGX Λ = (√(1 + α² tan²θ) − 1)/2 with tan θ = 0.75 (seed 003 Eq 16)
    let expected = ((1.0f64 + 0.25 * 0.5625).sqrt() - 1.0) / 2.0;
    let got = v["value"].as_f64().unwrap();
    assert!((got - expected).abs() < 1e-15, "{got} vs {expected}");
}

#[test]
fn eval_reports_infinite_lambda_below_the_surface_as_null() {
    let out = bin()
        .args(["eval", "lambda", "--alpha", "0.5", "--o", "0.6,0,-0.8"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["value"].is_null() && v["infinite"].as_bool() == Some(true));
}

#[test]
fn bad_input_exits_2_with_a_clear_message() {
    for args in [
        vec!["eval", "d", "--alpha", "0", "--m", "0,0,1"],
        vec!["eval", "d", "--alpha", "nan", "--m", "0,0,1"],
        vec!["eval", "d", "--matrix", "1,2,1", "--m", "0,0,1"],
        vec!["eval", "d", "--alpha", "0.1", "--m", "0,0,0"],
        vec![
            "eval", "vndf-pdf", "--alpha", "0.1", "--o", "1,0,-1", "--m", "0,0,1",
        ],
        vec!["eval", "d", "--alpha", "0.1"],
    ] {
        let out = bin().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn verify_only_runs_a_subset_and_exits_0() {
    let out = bin()
        .args([
            "verify",
            "--preset",
            "quick",
            "--only",
            "jacobian-reflection",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(s.contains("1 of 1 proofs pass"), "{s}");
}

#[test]
fn eval_filter_vmf_matches_banerjee_by_hand() {
    let out = bin()
        .args([
            "eval", "filter", "--filter", "vmf-2", "--alpha", "0.1", "--b", "0.98",
        ])
        .output()
        .unwrap();
    common::assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // κ = (3r − r³)/(1 − r²) at r = 0.98, α′ = √(α² + 2/κ)
    let r = 0.98f64;
    let kappa = (3.0 * r - r * r * r) / (1.0 - r * r);
    let expected = (0.01 + 2.0 / kappa).sqrt();
    let got = v["value"].as_f64().unwrap();
    assert!((got / expected - 1.0).abs() < 1e-14, "{got} vs {expected}");
    let f32v = v["model"]["f32"].as_f64().unwrap();
    assert!((f32v / expected - 1.0).abs() < 1e-6);
    // a missing input is a typed error, exit status 2
    let out = bin()
        .args([
            "eval",
            "filter",
            "--filter",
            "tokuyoshi-deferred",
            "--alpha",
            "0.1",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--dn-u"));
}

#[test]
fn prefilter_runs_on_a_png_and_rejects_a_broken_one() {
    let dir = common::scratch("cli", "prefilter");
    std::fs::create_dir_all(&dir).unwrap();
    let map = ndfbench::filters::footprint::NormalMap::procedural(
        ndfbench::filters::footprint::Procedural::Flakes,
        16,
        2,
    )
    .unwrap();
    let png = dir.join("flakes16.png");
    std::fs::write(&png, map.png().unwrap()).unwrap();
    let out = bin()
        .args(["prefilter", "--input"])
        .arg(&png)
        .arg("--out")
        .arg(&dir)
        .args(["--study", "--alpha", "0.1", "--preset", "quick"])
        .output()
        .unwrap();
    common::assert_success(&out);
    let md = std::fs::read_to_string(dir.join("prefilter-flakes16.md")).unwrap();
    assert!(md.contains("vMF α² + 2/κ") && md.contains("±"));
    assert!(dir.join("flakes16-alpha-L1.png").exists());
    std::fs::write(dir.join("broken.png"), b"not a png").unwrap();
    let out = bin()
        .args(["prefilter", "--study", "--input"])
        .arg(dir.join("broken.png"))
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.join("prefilter-broken.md").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn prefilter_rank_compresses_and_rejects_bad_input_without_output() {
    let dir = common::scratch("cli", "tensor");
    prefilter_rank_4(&dir, None);
    let md = std::fs::read_to_string(dir.join("tensor-scratches.md")).unwrap();
    assert!(md.contains("relative reconstruction error"));
    // the rank sweep R/4, R/2, R (rank 4: 1, 2, 4) and its plot
    assert!(
        md.contains("| 1 |") && md.contains("| 2 |") && md.contains("| 4 |"),
        "{md}"
    );
    let svg = std::fs::read_to_string(dir.join("tensor-scratches-rank.svg")).unwrap();
    assert!(svg.starts_with("<svg") || svg.contains("<svg"));
    // a rank larger than a 16×16 block allows, a missing file, an unknown generator:
    // exit ≠ 0, a message naming the problem, nothing written
    for (args, needle) in [
        (
            vec!["prefilter", "--generator", "flakes", "--rank", "999"],
            "--rank 999",
        ),
        (
            vec![
                "prefilter",
                "--input",
                "/nonexistent/map.png",
                "--rank",
                "4",
            ],
            "nonexistent",
        ),
        (
            vec!["prefilter", "--generator", "marble", "--rank", "4"],
            "marble",
        ),
    ] {
        let bad = dir.join("bad");
        let out = bin().args(&args).arg("--out").arg(&bad).output().unwrap();
        assert_ne!(out.status.code(), Some(0));
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(needle),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(!bad.exists());
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The process's CPU seconds, as the main job keeps them: present on Unix, finite, and
/// never less after more work.
#[test]
fn the_process_cpu_time_grows_with_work() {
    use ndfbench::progress::process_cpu_seconds;
    let Some(t0) = process_cpu_seconds() else {
        assert!(!cfg!(unix), "getrusage gave nothing on Unix");
        return;
    };
    let mut x = 0u64;
    for i in 0..20_000_000u64 {
        x = x.wrapping_mul(6364136223846793005).wrapping_add(i);
    }
    std::hint::black_box(x);
    let t1 = process_cpu_seconds().unwrap();
    assert!(t0.is_finite() && t0 >= 0.0 && t1 >= t0, "{t0} → {t1}");
}

/// A sequential, uncached `regen` keeps each study's own cost for performance.md only when
/// it ran the shipped specs (`fits/`) at the default preset: a quick or custom run does not
/// overwrite the profile it would misstate.
#[test]
fn only_a_default_regen_keeps_the_sequential_profile() {
    let dir = common::scratch("cli", "sequential-profile");
    std::fs::create_dir_all(dir.join("fits")).unwrap();
    std::fs::create_dir_all(dir.join("other")).unwrap();
    for d in ["fits", "other"] {
        std::fs::copy(
            "fits/smith-lambda.toml",
            dir.join(d).join("smith-lambda.toml"),
        )
        .unwrap();
    }
    let target = dir.join("target");
    let kept = target.join("regen-sequential.json");
    let regen = |extra: &[&str]| {
        let out = bin()
            .current_dir(&dir)
            .args(["--results", "res"])
            .args(extra)
            .arg("regen")
            .env("CARGO_TARGET_DIR", &target)
            .output()
            .unwrap();
        common::assert_success(&out);
    };
    // quick preset, or specs from elsewhere: nothing kept
    let quick = ["--preset", "quick"];
    let out = bin()
        .current_dir(&dir)
        .args(["--results", "res", "regen"])
        .args(quick)
        .env("CARGO_TARGET_DIR", &target)
        .output()
        .unwrap();
    common::assert_success(&out);
    assert!(!kept.exists());
    regen(&["--fits", "other"]);
    assert!(!kept.exists());
    // the shipped specs' directory at the default preset: kept, with the study in it
    regen(&[]);
    let text = std::fs::read_to_string(&kept).unwrap();
    assert!(text.contains("\"stage\": \"smith-lambda\""), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `bench-report --main-job-only` rewrites only the main job's section of an existing
/// performance page (every other line kept byte for byte) and refuses a page without one;
/// `--compact-only` without criterion's results is refused and writes nothing.
#[test]
fn bench_report_refreshes_only_the_main_job_section() {
    let dir = common::scratch("cli", "perf");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let page = "# Performance\n\nkept above\n\n## Main job: wall clock per stage\n\nold table\n\n## After\n\nkept below\n";
    std::fs::write(dir.join("performance.md"), page).unwrap();
    std::fs::copy(
        "results/main-job-before.json",
        dir.join("main-job-before.json"),
    )
    .unwrap();
    // a cold profile as the main job keeps it (CPU seconds included) under the target dir
    let target = dir.join("target");
    std::fs::create_dir_all(&target).unwrap();
    std::fs::write(
        target.join("main-job-cold.json"),
        r#"{"total_s": 633.2, "threads": 2, "warm": false, "cpu_s": 1222.4,
            "stages": [{"stage": "ltc-ggx", "seconds": 90.04, "computed": 3, "reused": 0}]}"#,
    )
    .unwrap();
    // a sequential regen's profile: each study alone, with its own CPU seconds
    std::fs::write(
        target.join("regen-sequential.json"),
        r#"{"total_s": 643.0, "threads": 2, "cpu_s": 1202.3,
            "stages": [{"stage": "ltc-ggx", "seconds": 90.04, "cpu_s": 172.6}]}"#,
    )
    .unwrap();
    // a warm sequential regen's: each study besides its memoised maps
    std::fs::write(
        target.join("regen-sequential-warm.json"),
        r#"{"total_s": 200.0, "threads": 2, "warm": true, "cpu_s": 351.0,
            "stages": [{"stage": "ltc-ggx", "seconds": 20.54, "reused": 3, "cpu_s": 30.2}]}"#,
    )
    .unwrap();
    let refresh = || {
        bin()
            .args([
                "--results",
                dir.to_str().unwrap(),
                "bench-report",
                "--main-job-only",
            ])
            .env("CARGO_TARGET_DIR", &target)
            .output()
            .unwrap()
    };
    let out = refresh();
    common::assert_success(&out);
    let new = std::fs::read_to_string(dir.join("performance.md")).unwrap();
    assert!(new.starts_with("# Performance\n\nkept above\n"));
    assert!(new.ends_with("\n## After\n\nkept below\n"));
    assert!(!new.contains("old table"));
    assert!(new.contains("before: sequential, no cache"));
    // the cold total with its CPU seconds; the kept "before" profile has none
    assert!(new.contains("**633 (2 threads, 1222 s of CPU)**"), "{new}");
    assert!(new.contains("**993 (2 threads)**"), "{new}");
    assert!(
        new.contains("| ltc-ggx | 251.7 | 90.0 | — | 90.0 (173) | 20.5 (30) |"),
        "{new}"
    );
    assert!(new.contains("**643 (2 threads, 1202 s of CPU)**"), "{new}");
    assert!(new.contains("**200 (2 threads, 351 s of CPU)**"), "{new}");
    std::fs::write(dir.join("performance.md"), "# Performance\n\nno section\n").unwrap();
    let out = refresh();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("no section \"Main job: wall clock per stage\""),
        "{err}"
    );
    // --compact-only without criterion's results: exit 2, one line, the page untouched
    let empty = dir.join("criterion");
    std::fs::create_dir_all(&empty).unwrap();
    let out = bin()
        .args([
            "--results",
            dir.to_str().unwrap(),
            "bench-report",
            "--compact-only",
        ])
        .arg("--criterion")
        .arg(&empty)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert_eq!(
        std::fs::read_to_string(dir.join("performance.md")).unwrap(),
        "# Performance\n\nno section\n"
    );
}

/// docs/cli.md is what `cli-reference` writes from the help texts now: the reference a
/// reader opens cannot drift from `--help`.
#[test]
fn the_cli_reference_is_current() {
    let d = common::scratch("cli", "reference");
    let out = d.join("cli.md");
    let st = bin()
        .args(["cli-reference", "--out"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(st.success());
    let now = std::fs::read_to_string(&out).unwrap();
    let committed = std::fs::read_to_string("docs/cli.md").unwrap_or_default();
    assert!(
        now == committed,
        "docs/cli.md is stale: run `cargo run --release -- cli-reference`"
    );
    // every subcommand has its section, with the detail its help carries
    for sub in [
        "regen",
        "verify",
        "prefilter",
        "render",
        "engines",
        "ltc-compare",
        "eval",
    ] {
        assert!(now.contains(&format!("## `ndfbench {sub}`")), "{sub}");
    }
    assert!(
        now.contains("--only takes exact spec names")
            || now.contains("`--only` takes exact spec names")
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// `prefilter --rank` writes the same bytes at any thread count (its report holds no
/// wall-clock time and no thread count).
#[test]
fn prefilter_rank_is_identical_at_one_and_two_threads() {
    let run = |threads: &str| {
        let dir = common::scratch("cli", &format!("tensor-threads-{threads}"));
        prefilter_rank_4(&dir, Some(threads));
        let files = [
            "tensor-scratches.md",
            "tensor-scratches.json",
            "tensor-scratches-rank.svg",
        ]
        .map(|f| std::fs::read(dir.join(f)).unwrap());
        std::fs::remove_dir_all(&dir).ok();
        files
    };
    assert!(
        run("1") == run("2"),
        "prefilter --rank depends on the thread count"
    );
}

/// `prefilter --generator scratches --rank 4 --preset quick --out DIR`, on `threads` rayon
/// threads where given; asserts that it succeeds.
fn prefilter_rank_4(dir: &std::path::Path, threads: Option<&str>) {
    let mut cmd = bin();
    if let Some(t) = threads {
        cmd.env("RAYON_NUM_THREADS", t);
    }
    let out = cmd
        .args([
            "prefilter",
            "--generator",
            "scratches",
            "--rank",
            "4",
            "--preset",
            "quick",
            "--out",
        ])
        .arg(dir)
        .output()
        .unwrap();
    common::assert_success(&out);
}

//! Shared test configuration.

use proptest::prelude::ProptestConfig;
use proptest::test_runner::RngSeed;

/// Proptest configuration with `default_cases` cases, unless `PROPTEST_CASES` is set in
/// the environment, which then wins (CI and users can raise or lower every property's
/// count at once). Properties over the extremes default to ≥ 10 000 cases; the few whose
/// single case costs milliseconds of quadrature or a whole batch state their smaller
/// default where they are declared. The random stream is seeded (the same cases on every
/// run and machine) unless `PROPTEST_RNG_SEED` is set; failures found are kept in the
/// `*.proptest-regressions` files and re-run first.
#[allow(dead_code)]
pub fn config(default_cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default_cases);
    let base = ProptestConfig::default();
    let rng_seed = if std::env::var("PROPTEST_RNG_SEED").is_ok() {
        base.rng_seed
    } else {
        RngSeed::Fixed(0x5eed_2026)
    };
    ProptestConfig {
        cases,
        rng_seed,
        ..base
    }
}

/// The `ndfbench` binary of this build, as a command to run.
#[allow(dead_code)]
pub fn bin() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_ndfbench"))
}

/// A fresh, empty scratch directory for one test: `<temp>/ndfb-<suite>-<name>-<pid>`,
/// emptied first (a previous run of the same process id leaves nothing behind).
#[allow(dead_code)]
pub fn scratch(suite: &str, name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("ndfb-{suite}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Assert that a run of the binary exited 0, showing its stderr when it did not.
#[allow(dead_code)]
pub fn assert_success(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `ndfbench regen ARGS…` on the specs of `fits`, writing under `results`.
#[allow(dead_code)]
pub fn regen_in(
    fits: &std::path::Path,
    results: &std::path::Path,
    args: &[&str],
) -> std::process::Command {
    let mut c = bin();
    c.arg("--fits")
        .arg(fits)
        .arg("--results")
        .arg(results)
        .arg("regen")
        .args(args);
    c
}

/// The study of `spec` computed on the results under `results` at `preset`, with `spec`
/// as the run's only spec.
#[allow(dead_code)]
pub fn compute_study(
    spec: &ndfbench::fit::spec::FitSpec,
    results: &std::path::Path,
    preset: ndfbench::integrate::Preset,
) -> ndfbench::error::Result<Box<dyn ndfbench::study::Computed>> {
    let ctx = ndfbench::study::Ctx {
        spec,
        specs: std::slice::from_ref(spec),
        results,
        preset,
    };
    ndfbench::studies::find(&spec.name)
        .expect("a registered study")
        .compute(&ctx)
}

/// A copy of the folder `from` (files and folders, recursively) at `to`.
#[allow(dead_code)]
pub fn copy_dir(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let dst = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &dst);
        } else {
            std::fs::copy(e.path(), &dst).unwrap();
        }
    }
}

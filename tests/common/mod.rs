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

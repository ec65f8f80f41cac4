//! Shared test configuration.

use proptest::prelude::ProptestConfig;

/// Proptest configuration with `default_cases` cases, unless `PROPTEST_CASES` is set in
/// the environment, which then wins (CI and users can raise or lower every property's
/// count at once). Properties over the extremes default to ≥ 10 000 cases; the few whose
/// single case costs milliseconds of quadrature or a whole batch state their smaller
/// default where they are declared.
#[allow(dead_code)]
pub fn config(default_cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default_cases);
    ProptestConfig {
        cases,
        ..ProptestConfig::default()
    }
}

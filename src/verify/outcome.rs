//! What one check reports: its worst error against its tolerance, the case where it
//! happened, and notes.

use serde::Serialize;

/// What one check found.
#[derive(Clone, Debug, Serialize)]
pub struct Outcome {
    /// Stem of the proof file in proofs/ that states the identity.
    pub id: &'static str,
    pub title: &'static str,
    pub source: &'static str,
    /// Parameter ranges actually tried.
    pub ranges: String,
    pub cases: usize,
    /// Worst error found (meaning given by `error_kind`).
    pub worst_error: f64,
    pub error_kind: &'static str,
    /// Where the worst error occurred.
    pub worst_case: String,
    pub tolerance: f64,
    pub passed: bool,
    /// Wall clock of the check: said on the terminal while verify runs, never written into
    /// results/ (a result is the same on every machine).
    #[serde(skip)]
    pub seconds: f64,
    /// Measured findings worth reading (numbers with their errors).
    pub notes: Vec<String>,
}

/// Running maximum with the case that produced it.
#[derive(Clone, Debug, Default)]
pub struct Worst {
    pub err: f64,
    pub case: String,
    pub n: usize,
}

impl Worst {
    pub fn update(&mut self, err: f64, case: impl FnOnce() -> String) {
        self.n += 1;
        // NaN counts as the worst possible error
        let e = if err.is_nan() { f64::INFINITY } else { err };
        if e > self.err || self.case.is_empty() {
            self.err = e.max(self.err);
            self.case = case();
        }
    }
}

//! results/fits/multiscale-alpha-me.json: α_me(‖b̄‖) (seed 000 Eq 5) — our fit, the
//! paper's form as printed and refitted, a lookup table and Newton on the closed form,
//! each with its held-out error, and the audit of Eq 5.

use crate::fit::spec::FitSpec;
use crate::multiscale::alpha_me::HeldOut;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct AlphaMe {
    pub spec: FitSpec,
    pub command: String,
    pub ours: Ours,
    pub paper_eq5: Method,
    pub paper_form_refit: Refit,
    pub table: TableMethod,
    pub newton_closed_form: NewtonMethod,
    /// What the targets' own error is.
    pub integration_error: String,
    pub eq5_audit: Eq5Audit,
    pub passed: bool,
}

impl AlphaMe {
    /// The held-out errors of each method, by the key the reports use.
    pub fn held_out(&self, method: &str) -> Option<&HeldOut> {
        match method {
            "ours" => Some(&self.ours.held_out),
            "paper_eq5" => Some(&self.paper_eq5.held_out),
            "paper_form_refit" => Some(&self.paper_form_refit.held_out),
            "table" => Some(&self.table.held_out),
            "newton_closed_form" => Some(&self.newton_closed_form.held_out),
            _ => None,
        }
    }
}

/// Our two-branch fit: the α ≤ 1 coefficients (powers of s⁻¹) and the α > 1 ones.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Ours {
    pub coefficients: Vec<f64>,
    pub coefficients_large: Vec<f64>,
    pub held_out: HeldOut,
    pub whole_range: WholeRange,
}

/// A method given by its coefficients.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Method {
    pub coefficients: Vec<f64>,
    pub held_out: HeldOut,
}

/// The paper's form with its coefficients refitted by Nelder–Mead.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Refit {
    pub coefficients: Vec<f64>,
    pub objective: f64,
    pub iterations: u64,
    pub held_out: HeldOut,
}

/// A lookup table of ln α at uniform s.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TableMethod {
    pub entries: usize,
    pub s0: f64,
    pub ds: f64,
    pub held_out: HeldOut,
}

/// Newton's method on the closed form (the reference's own error).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct NewtonMethod {
    pub held_out: HeldOut,
}

/// Where Eq 5 as printed breaks: its value at ‖b̄‖ = 1 and 2/3, the roots of its
/// numerator and its poles in (0, 1).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Eq5Audit {
    pub alpha_at_b_1: f64,
    pub alpha_at_b_2_3: f64,
    pub numerator_roots_in_0_1: Vec<f64>,
    pub poles_in_0_1: Vec<f64>,
}

/// Errors of `Ours` over the whole input range y ∈ [min normal, 1), beyond the fit domain.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WholeRange {
    /// Points tried (log-spaced in y for α ≤ 1 and in b = 1 − y for α > 1).
    pub points: usize,
    /// Smallest and largest exact α over the points.
    pub alpha_range: [f64; 2],
    /// Max relative error of the f64 form against Newton, and where (exact α).
    pub f64_max_rel: f64,
    pub f64_worst_alpha: f64,
    /// Max relative error of the f32 form (f32 coefficients and arithmetic) against
    /// Newton at the same f32 input, over inputs representable as normal f32.
    pub f32_max_rel: f64,
    pub f32_worst_alpha: f64,
    /// Max relative error restricted to α ∈ [1e-4, 1e2] (f64 form, f32 form).
    pub in_range_f64_max_rel: f64,
    pub in_range_f32_max_rel: f64,
    /// Whether every output was finite and ≥ 0 (including y = 0, y = 1 and NaN inputs).
    pub total: bool,
}

impl super::ResultFile for AlphaMe {
    const NAME: &'static str = super::names::MULTISCALE_ALPHA_ME;
}

//! results/fits/smith-lambda.json: the refitted Beckmann Λ(ν) (seed 001 §3.2) and its
//! held-out |ΔG1| beside Walter et al.'s two forms.

use crate::fit::spec::FitSpec;
use crate::microfacet::lambda_fit::Worst;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SmithLambda {
    pub spec: FitSpec,
    pub command: String,
    pub parameters: Parameters,
    pub iterations: usize,
    pub held_out: HeldOut,
    /// The worst |ΔG1| on the training ν.
    pub training: Worst,
    pub passed: bool,
    /// Where Walter et al.'s form departs from the exact Λ at its ends.
    pub limits: Limits,
}

/// The ends of the ν range, exact against Walter et al.'s printed form: the ν → 0
/// coefficient (exact 2√π), the root of Walter's numerator (past it his Λ is negative)
/// and the exact Λ his cut drops to 0.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Limits {
    /// 2√π: Λ ≈ 1/(2√π ν) as ν → 0.
    pub exact_b1: f64,
    /// Walter's printed b₁.
    pub walter_b1: f64,
    /// 1 − walter_b1/exact_b1.
    pub walter_b1_rel_miss: f64,
    /// The ν where Walter's numerator changes sign.
    pub walter_numerator_root: f64,
    /// Walter's cut, and the exact Λ there.
    pub walter_cut: f64,
    pub exact_lambda_at_cut: f64,
}

/// The six numbers of the rational form.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Parameters {
    pub a1: f64,
    pub a2: f64,
    pub b1: f64,
    pub b2: f64,
    pub b3: f64,
    pub nu_c: f64,
}

impl Parameters {
    /// In the order the fit and the generated code use: a1, a2, b1, b2, b3, ν_c.
    pub fn array(&self) -> [f64; 6] {
        [self.a1, self.a2, self.b1, self.b2, self.b3, self.nu_c]
    }
}

/// The worst |ΔG1| on held-out ν of each form.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct HeldOut {
    pub ours: Worst,
    pub walter_printed: Worst,
    pub walter_listing: Worst,
}

impl super::ResultFile for SmithLambda {
    const NAME: &'static str = super::names::SMITH_LAMBDA;
}

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

//! Accuracy presets shared by every engine and every later fit.

use serde::{Deserialize, Serialize};

/// `quick` for smoke runs and CI-sized tests, `default` for the main job, `precise` for
/// reference numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    Quick,
    Default,
    Precise,
}

impl Preset {
    /// Every preset, fastest first.
    pub const ALL: [Preset; 3] = [Preset::Quick, Preset::Default, Preset::Precise];
    /// Relative (and absolute) tolerance handed to adaptive quadrature.
    pub fn quad_tol(self) -> f64 {
        match self {
            Preset::Quick => 1e-7,
            Preset::Default => 1e-10,
            Preset::Precise => 1e-12,
        }
    }
    /// Evaluation budget for one adaptive quadrature.
    pub fn quad_max_evals(self) -> u64 {
        match self {
            Preset::Quick => 2_000_000,
            Preset::Default => 20_000_000,
            Preset::Precise => 200_000_000,
        }
    }
    /// Monte Carlo sample tuples.
    pub fn mc_samples(self) -> u64 {
        match self {
            Preset::Quick => 1 << 14,
            Preset::Default => 1 << 18,
            Preset::Precise => 1 << 22,
        }
    }
    /// (points per replicate ≤ 2^16, replicates) for RQMC.
    pub fn qmc(self) -> (u64, u32) {
        match self {
            Preset::Quick => (1 << 10, 8),
            Preset::Default => (1 << 14, 16),
            Preset::Precise => (1 << 16, 32),
        }
    }
    /// The preset named `s` (as [`Preset::name`] writes it).
    pub fn parse(s: &str) -> Option<Preset> {
        [Preset::Quick, Preset::Default, Preset::Precise]
            .into_iter()
            .find(|p| p.name() == s)
    }
    /// The preset a published result names (its `preset` field), or a typed error naming
    /// the file `what`.
    pub fn named(name: &str, what: &str) -> crate::error::Result<Preset> {
        Preset::parse(name).ok_or_else(|| {
            crate::error::Error::InvalidArgument(format!("{what}: unknown preset '{name}'"))
        })
    }

    pub fn name(self) -> &'static str {
        match self {
            Preset::Quick => "quick",
            Preset::Default => "default",
            Preset::Precise => "precise",
        }
    }
}

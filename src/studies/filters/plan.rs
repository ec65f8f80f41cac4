//! The footprint study's sizes per preset and the small shared pieces every step uses: view
//! directions, the two NDF kinds, per-case seeds.

use crate::integrate::Preset;
use crate::microfacet::NdfKind;
use nalgebra::Vector3;

type V3 = Vector3<f64>;

pub use crate::filters::plan::Plan;

/// fits/filters.toml as this build compiled it in: the plan of the commands that run the
/// study's measurements on a user's input (`prefilter --study`).
const SPEC: &str = include_str!("../../../fits/filters.toml");

/// The study's plan at `preset`, from the compiled-in spec.
pub fn builtin(p: Preset) -> crate::error::Result<Plan> {
    crate::fit::spec::FitSpec::compiled_params(SPEC, "fits/filters.toml", p)
}

pub(super) fn dir(theta_deg: f64, phi_deg: f64) -> V3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    V3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

pub(super) const KINDS: [NdfKind; 2] = [NdfKind::Ggx, NdfKind::Beckmann];

pub(super) fn kind_name(k: NdfKind) -> &'static str {
    match k {
        NdfKind::Ggx => "GGX",
        NdfKind::Beckmann => "Beckmann",
    }
}

pub(super) fn seed_of(base: u64, idx: usize) -> u64 {
    base ^ (idx as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

//! The footprint study's sizes per preset and the small shared pieces every step uses: view
//! directions, the two NDF kinds, per-case seeds.

use crate::integrate::Preset;
use crate::microfacet::NdfKind;
use nalgebra::Vector3;
use serde::Serialize;

type V3 = Vector3<f64>;

/// Sizes of the studies for a preset.
#[derive(Clone, Debug, Serialize)]
pub struct Plan {
    pub map_size: usize,
    pub levels: Vec<usize>,
    pub footprints_per_level: usize,
    pub alphas: Vec<f64>,
    pub views_deg: Vec<(f64, f64)>,
    pub samples: usize,
    /// (base α, κ in rad/px) pairs of the screen study (κ/α ≤ 8).
    pub screen_pairs: Vec<(f64, f64)>,
    pub anisotropy: Vec<f64>,
    pub screen_views_deg: Vec<f64>,
}

impl Plan {
    pub fn new(p: Preset) -> Plan {
        match p {
            Preset::Quick => Plan {
                map_size: 32,
                levels: vec![1, 2, 3],
                footprints_per_level: 2,
                alphas: vec![0.05],
                views_deg: vec![(0.0, 0.0), (60.0, 0.0)],
                samples: 256,
                screen_pairs: vec![(0.1, 0.03), (0.1, 0.3), (0.3, 0.8)],
                anisotropy: vec![1.0],
                screen_views_deg: vec![0.0, 60.0],
            },
            _ => Plan {
                map_size: if p == Preset::Precise { 256 } else { 128 },
                levels: vec![1, 2, 3, 4, 5],
                footprints_per_level: if p == Preset::Precise { 12 } else { 6 },
                alphas: vec![0.05, 0.25],
                views_deg: vec![(0.0, 0.0), (40.0, 0.0), (70.0, 0.0), (70.0, 90.0)],
                samples: if p == Preset::Precise { 4096 } else { 1024 },
                screen_pairs: vec![
                    (0.02, 0.01),
                    (0.02, 0.03),
                    (0.02, 0.1),
                    (0.1, 0.03),
                    (0.1, 0.1),
                    (0.1, 0.3),
                    (0.1, 0.6),
                    (0.3, 0.1),
                    (0.3, 0.3),
                    (0.3, 0.8),
                ],
                anisotropy: vec![1.0, 0.2],
                screen_views_deg: vec![0.0, 45.0, 75.0],
            },
        }
    }
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

pub(super) fn pct(m: f64, se: f64) -> String {
    crate::integrate::MeanSe { value: m, se }.pct_signed(1)
}

pub(super) fn seed_of(base: u64, idx: usize) -> u64 {
    base ^ (idx as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
}

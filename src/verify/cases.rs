//! The parameter sets the proofs run over. Extremes are first-class: α = 1e-4,
//! anisotropy ratio 100 (condition number 1e4 of A), rotated matrices, mean slopes up to
//! 10, directions to 89.99° from the normal.

use crate::integrate::Preset;
use crate::microfacet::{Microsurface, NdfKind, Roughness};
use nalgebra::{Vector2, Vector3};

/// A named surface.
pub struct Case {
    pub label: String,
    pub surface: Microsurface,
}

fn push(v: &mut Vec<Case>, label: String, s: Microsurface) {
    v.push(Case { label, surface: s });
}

/// Surfaces for NDF/Smith/furnace identities.
pub fn surfaces(preset: Preset) -> Vec<Case> {
    let mut v = Vec::new();
    let alphas: &[f64] = match preset {
        Preset::Quick => &[1e-4, 0.05, 1.0],
        _ => &[1e-4, 1e-3, 1e-2, 0.1, 0.3, 0.6, 1.0],
    };
    for kind in [NdfKind::Beckmann, NdfKind::Ggx] {
        let k = match kind {
            NdfKind::Beckmann => "Beckmann",
            NdfKind::Ggx => "GGX",
        };
        for &a in alphas {
            push(
                &mut v,
                format!("{k} α={a}"),
                Microsurface::new(kind, Roughness::iso(a).unwrap()),
            );
        }
        push(
            &mut v,
            format!("{k} αx=0.01 αy=1 (ratio 100)"),
            Microsurface::new(kind, Roughness::aniso(0.01, 1.0).unwrap()),
        );
        push(
            &mut v,
            format!("{k} αx=1e-4 αy=1e-2 (ratio 100)"),
            Microsurface::new(kind, Roughness::aniso(1e-4, 1e-2).unwrap()),
        );
        push(
            &mut v,
            format!("{k} matrix A: α=(0.01, 1) rotated 0.7 rad (cond 1e4)"),
            Microsurface::new(kind, Roughness::rotated(0.01, 1.0, 0.7).unwrap()),
        );
        if preset != Preset::Quick {
            push(
                &mut v,
                format!("{k} matrix A: α=(0.2, 0.5) rotated −1.1 rad"),
                Microsurface::new(kind, Roughness::rotated(0.2, 0.5, -1.1).unwrap()),
            );
        }
        let means: &[(f64, f64, f64)] = match preset {
            Preset::Quick => &[(0.5, -0.3, 0.3), (10.0, 0.0, 0.5)],
            _ => &[
                (0.5, -0.3, 0.3),
                (2.0, 1.0, 0.05),
                (10.0, 0.0, 0.5),
                (-3.0, 4.0, 1.0),
            ],
        };
        for &(mx, my, a) in means {
            push(
                &mut v,
                format!("{k} α={a} mean slope ({mx}, {my})"),
                Microsurface::new(kind, Roughness::iso(a).unwrap())
                    .with_mean(Vector2::new(mx, my))
                    .unwrap(),
            );
        }
    }
    v
}

/// Unit direction at polar angle θ (degrees) and azimuth φ (radians).
pub fn dir(theta_deg: f64, phi: f64) -> Vector3<f64> {
    let t = theta_deg.to_radians();
    Vector3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos())
}

/// Outgoing directions (θ in degrees, φ in radians).
pub fn directions(preset: Preset) -> Vec<(f64, f64)> {
    match preset {
        Preset::Quick => vec![(0.0, 0.0), (60.0, 0.4), (89.99, 2.2)],
        _ => vec![
            (0.0, 0.0),
            (30.0, 0.4),
            (60.0, 2.2),
            (80.0, -1.3),
            (89.0, 0.9),
            (89.9, 3.0),
            (89.99, -2.5),
        ],
    }
}

//! Lights in world space: point, two-sided quad, directional, an environment resolved
//! into a few directional lights (a Fibonacci set of the upper hemisphere), and a distant
//! environment as a sum of spherical Gaussians ([`crate::tensor::envsg::SgEnv`]).

use super::scene::LightSpec;
use crate::tensor::envsg::{Sg, SgEnv};
use nalgebra::Vector3;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

#[derive(Clone, Debug)]
pub enum Light {
    Point {
        pos: V3,
        intensity: f64,
    },
    Quad {
        center: V3,
        u: V3,
        v: V3,
        half: [f64; 2],
        radiance: f64,
        normal: V3,
        area: f64,
    },
    /// `dir` points toward the light.
    Directional {
        dir: V3,
        irradiance: f64,
    },
    /// Radiance from every direction: a sum of SGs in world axes.
    Sg(SgEnv),
}

/// Every light of a scene, environments expanded.
pub fn resolve(specs: &[LightSpec]) -> Vec<Light> {
    let mut out = Vec::new();
    for s in specs {
        match s {
            LightSpec::Point {
                position,
                intensity,
            } => out.push(Light::Point {
                pos: V3::from(*position),
                intensity: *intensity,
            }),
            LightSpec::Quad {
                center,
                u_axis,
                v_axis,
                half_size,
                radiance,
            } => {
                let (u, v) = (V3::from(*u_axis).normalize(), V3::from(*v_axis).normalize());
                out.push(Light::Quad {
                    center: V3::from(*center),
                    u,
                    v,
                    half: *half_size,
                    radiance: *radiance,
                    normal: u.cross(&v),
                    area: 4.0 * half_size[0] * half_size[1],
                })
            }
            LightSpec::Directional {
                direction,
                irradiance,
            } => out.push(Light::Directional {
                dir: V3::from(*direction).normalize(),
                irradiance: *irradiance,
            }),
            LightSpec::Environment {
                zenith,
                horizon,
                count,
            } => {
                let golden = PI * (3.0 - 5f64.sqrt());
                for k in 0..*count {
                    let z = 1.0 - (k as f64 + 0.5) / *count as f64;
                    let r = (1.0 - z * z).max(0.0).sqrt();
                    let phi = golden * k as f64;
                    let radiance = horizon + (zenith - horizon) * z;
                    out.push(Light::Directional {
                        dir: V3::new(r * phi.cos(), r * phi.sin(), z),
                        irradiance: radiance * 2.0 * PI / *count as f64,
                    });
                }
            }
            // the scene's check made every axis non-zero and finite, λ > 0 and A ≥ 0
            LightSpec::Sg { lobes } => out.push(Light::Sg(SgEnv {
                lobes: lobes
                    .iter()
                    .map(|g| {
                        let a = V3::from(g.axis).normalize();
                        Sg {
                            axis: [a.x, a.y, a.z],
                            lambda: g.lambda,
                            amp: g.amplitude,
                        }
                    })
                    .collect(),
            })),
        }
    }
    out
}

impl Light {
    /// The quad's four corners (counter-clockwise about its normal).
    pub fn corners(&self) -> Option<[V3; 4]> {
        match self {
            Light::Quad {
                center, u, v, half, ..
            } => Some([
                center - u * half[0] - v * half[1],
                center + u * half[0] - v * half[1],
                center + u * half[0] + v * half[1],
                center - u * half[0] + v * half[1],
            ]),
            _ => None,
        }
    }

    /// A uniform point on the quad from two uniforms.
    pub fn quad_point(&self, s: [f64; 2]) -> Option<V3> {
        match self {
            Light::Quad {
                center, u, v, half, ..
            } => Some(
                center + u * (half[0] * (2.0 * s[0] - 1.0)) + v * (half[1] * (2.0 * s[1] - 1.0)),
            ),
            _ => None,
        }
    }

    /// Where the ray p + t·d (t > 0) meets the quad, if it does.
    pub fn quad_hit(&self, p: &V3, d: &V3) -> Option<V3> {
        match self {
            Light::Quad {
                center,
                u,
                v,
                half,
                normal,
                ..
            } => {
                let dn = d.dot(normal);
                if dn.abs() < 1e-300 {
                    return None;
                }
                let t = (center - p).dot(normal) / dn;
                if !(t > 0.0 && t.is_finite()) {
                    return None;
                }
                let q = p + d * t - center;
                (q.dot(u).abs() <= half[0] && q.dot(v).abs() <= half[1]).then_some(p + d * t)
            }
            _ => None,
        }
    }
}

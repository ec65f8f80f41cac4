//! The camera (pinhole, optionally dollying) and the three surfaces (plane, sphere,
//! torus), each hit returned with its tangent frame, its map coordinates and their
//! derivatives: the pixel footprint on the map follows from ray differentials against the
//! tangent plane at the hit (Igehy 1999), the same quantity a GPU's derivatives give.

use super::scene::{CameraSpec, SurfaceKind, SurfaceSpec};
use crate::microfacet::lobe::Frame;
use nalgebra::Vector3;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// A pinhole camera for one frame.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub eye: V3,
    fwd: V3,
    right: V3,
    up: V3,
    tan_half: f64,
    pub width: usize,
    pub height: usize,
}

impl Camera {
    /// The camera of frame `k` (of `frames`) of `spec`'s path.
    pub fn at_frame(spec: &CameraSpec, k: usize) -> Camera {
        let p0 = V3::from(spec.position);
        let eye = match &spec.path {
            Some(p) if p.frames > 1 => {
                let t = k.min(p.frames - 1) as f64 / (p.frames - 1) as f64;
                p0 + (V3::from(p.to) - p0) * t
            }
            _ => p0,
        };
        let fwd = (V3::from(spec.look_at) - eye).normalize();
        let upw = V3::from(spec.up);
        let mut right = fwd.cross(&upw);
        if !(right.norm() > 1e-9) {
            right = fwd.cross(&V3::x());
            if !(right.norm() > 1e-9) {
                right = fwd.cross(&V3::y());
            }
        }
        let right = right.normalize();
        Camera {
            eye,
            fwd,
            right,
            up: right.cross(&fwd),
            tan_half: (0.5 * spec.fov_deg.to_radians()).tan(),
            width: spec.width,
            height: spec.height,
        }
    }

    /// Direction of the ray through image point (x, y) in pixels (y down, pixel centres at
    /// half-integers).
    pub fn dir(&self, x: f64, y: f64) -> V3 {
        let (w, h) = (self.width as f64, self.height as f64);
        let sx = (2.0 * x / w - 1.0) * self.tan_half * w / h;
        let sy = (1.0 - 2.0 * y / h) * self.tan_half;
        (self.fwd + self.right * sx + self.up * sy).normalize()
    }
}

/// A surface hit.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub p: V3,
    /// Tangent frame: t along ∂p/∂u, b along ∂p/∂v, n the outward geometric normal.
    pub frame: Frame,
    /// Map coordinates (1 = one repeat of the map).
    pub uv: [f64; 2],
    /// |∂p/∂u|, |∂p/∂v| (world length per unit of map coordinate).
    pub scale: [f64; 2],
}

/// The surface of a scene.
#[derive(Clone, Copy, Debug)]
pub struct Surface {
    kind: SurfaceKind,
    r: f64,
    tube: f64,
    repeats: [f64; 2],
}

impl Surface {
    pub fn new(s: &SurfaceSpec, scale: f64) -> Surface {
        Surface {
            kind: s.kind,
            r: s.radius,
            tube: s.minor_radius,
            repeats: [s.repeats[0] * scale, s.repeats[1] * scale],
        }
    }

    /// The first hit of the ray o + t·d (d unit), t > 0.
    pub fn intersect(&self, o: &V3, d: &V3) -> Option<Hit> {
        let t = match self.kind {
            SurfaceKind::Plane => {
                let t = -o.z / d.z;
                (t > 0.0 && t.is_finite()).then_some(t)?
            }
            SurfaceKind::Sphere => sphere_t(o, d, self.r)?,
            SurfaceKind::Torus => self.torus_t(o, d)?,
        };
        Some(self.hit_at(o + d * t))
    }

    /// The surface point with map coordinates uv (the inverse of the hits' uv).
    pub fn point_at(&self, uv: [f64; 2]) -> Hit {
        let [ru, rv] = self.repeats;
        let p = match self.kind {
            SurfaceKind::Plane => V3::new(uv[0] / ru, uv[1] / rv, 0.0),
            SurfaceKind::Sphere => {
                let (phi, theta) = (2.0 * PI * uv[0] / ru, PI * (1.0 - uv[1] / rv));
                V3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ) * self.r
            }
            SurfaceKind::Torus => {
                let (phi, psi) = (2.0 * PI * uv[0] / ru, 2.0 * PI * uv[1] / rv);
                let rho = self.r + self.tube * psi.cos();
                V3::new(rho * phi.cos(), rho * phi.sin(), self.tube * psi.sin())
            }
        };
        let mut h = self.hit_at(p);
        h.uv = uv;
        h
    }

    /// The periods of (u, v) in map coordinates (∞ where a coordinate does not wrap).
    pub fn periods(&self) -> [f64; 2] {
        match self.kind {
            SurfaceKind::Plane => [f64::INFINITY; 2],
            SurfaceKind::Sphere => [self.repeats[0], f64::INFINITY],
            SurfaceKind::Torus => self.repeats,
        }
    }

    fn hit_at(&self, p: V3) -> Hit {
        let [ru, rv] = self.repeats;
        match self.kind {
            SurfaceKind::Plane => Hit {
                p,
                frame: Frame {
                    t: V3::x(),
                    b: V3::y(),
                    n: V3::z(),
                },
                uv: [p.x * ru, p.y * rv],
                scale: [1.0 / ru, 1.0 / rv],
            },
            SurfaceKind::Sphere => {
                let n = p.normalize();
                let phi = n.y.atan2(n.x);
                let theta = n.z.clamp(-1.0, 1.0).acos();
                let st = theta.sin().max(1e-9);
                let t = V3::new(-phi.sin(), phi.cos(), 0.0);
                Hit {
                    p,
                    frame: Frame {
                        t,
                        b: n.cross(&t),
                        n,
                    },
                    uv: [phi / (2.0 * PI) * ru, (1.0 - theta / PI) * rv],
                    scale: [2.0 * PI * self.r * st / ru, PI * self.r / rv],
                }
            }
            SurfaceKind::Torus => {
                let phi = p.y.atan2(p.x);
                let rho = (p.x * p.x + p.y * p.y).sqrt();
                let psi = p.z.atan2(rho - self.r);
                let (cp, sp) = (phi.cos(), phi.sin());
                let n = V3::new(psi.cos() * cp, psi.cos() * sp, psi.sin());
                let t = V3::new(-sp, cp, 0.0);
                Hit {
                    p,
                    frame: Frame {
                        t,
                        b: n.cross(&t),
                        n,
                    },
                    uv: [phi / (2.0 * PI) * ru, psi / (2.0 * PI) * rv],
                    scale: [
                        2.0 * PI * (self.r + self.tube * psi.cos()).max(1e-9) / ru,
                        2.0 * PI * self.tube / rv,
                    ],
                }
            }
        }
    }

    /// Signed distance to the torus.
    fn torus_sdf(&self, p: &V3) -> f64 {
        let q = (p.x * p.x + p.y * p.y).sqrt() - self.r;
        (q * q + p.z * p.z).sqrt() - self.tube
    }

    /// Sphere tracing from the bounding sphere, then bisection on the bracketing step:
    /// deterministic and converged to 1e-12 of the scene's size.
    fn torus_t(&self, o: &V3, d: &V3) -> Option<f64> {
        let bound = self.r + self.tube;
        let b = o.dot(d);
        let c = o.norm_squared() - bound * bound;
        let disc = b * b - c;
        if disc < 0.0 {
            return None;
        }
        let (t0, t1) = (-b - disc.sqrt(), -b + disc.sqrt());
        if t1 <= 0.0 {
            return None;
        }
        let mut t = t0.max(0.0);
        let eps = 1e-9 * bound;
        for _ in 0..512 {
            let f = self.torus_sdf(&(o + d * t));
            if f < eps {
                // bracket [t − step, t] and bisect the sign change
                let (mut lo, mut hi) = ((t - 4.0 * eps).max(0.0), t);
                if self.torus_sdf(&(o + d * lo)) < 0.0 {
                    return Some(lo);
                }
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if self.torus_sdf(&(o + d * mid)) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return Some(hi);
            }
            t += f;
            if t > t1 {
                return None;
            }
        }
        None
    }
}

fn sphere_t(o: &V3, d: &V3, r: f64) -> Option<f64> {
    let b = o.dot(d);
    let c = o.norm_squared() - r * r;
    let disc = b * b - c;
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    // the numerically stable root pair
    let q = -b - s.copysign(b);
    let (ta, tb) = (q, c / q);
    let (t0, t1) = (ta.min(tb), ta.max(tb));
    if t0 > 0.0 {
        Some(t0)
    } else if t1 > 0.0 {
        Some(t1)
    } else {
        None
    }
}

/// The pixel footprint on the map at a hit: the map-coordinate derivatives (∂uv/∂x,
/// ∂uv/∂y) of one pixel step, from the neighbouring rays against the tangent plane.
pub fn footprint(cam: &Camera, hit: &Hit, x: f64, y: f64) -> [[f64; 2]; 2] {
    let n = hit.frame.n;
    let step = |dx: f64, dy: f64| -> [f64; 2] {
        let d = cam.dir(x + dx, y + dy);
        let denom = d.dot(&n);
        let t = (hit.p - cam.eye).dot(&n) / denom;
        if !(t.is_finite() && t > 0.0) {
            return [f64::INFINITY; 2];
        }
        let dp = cam.eye + d * t - hit.p;
        [
            dp.dot(&hit.frame.t) / hit.scale[0],
            dp.dot(&hit.frame.b) / hit.scale[1],
        ]
    };
    [step(1.0, 0.0), step(0.0, 1.0)]
}

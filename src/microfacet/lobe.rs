//! Geometry shared by every study that shades a surface: an orthonormal frame around a
//! normal and the cosine-weighted microfacet specular lobe seen in it (D·G2/(4 v_n),
//! F = 1; seed 003 Eq 14–15).

use super::Microsurface;
use nalgebra::Vector3;

type V3 = Vector3<f64>;

/// An orthonormal frame (t, b, n); `local` maps world → (x, y, z) = (·t, ·b, ·n).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub t: V3,
    pub b: V3,
    pub n: V3,
}

impl Frame {
    /// A frame around n whose tangent is the projection of the world x axis (smooth in n;
    /// falls back to y when n is parallel to x).
    pub fn around(n: V3) -> Frame {
        let n = n.normalize();
        let x = if n.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let t = (x - n * n.dot(&x)).normalize();
        Frame {
            t,
            b: n.cross(&t),
            n,
        }
    }
    pub fn local(&self, w: &V3) -> V3 {
        V3::new(w.dot(&self.t), w.dot(&self.b), w.dot(&self.n))
    }
    pub fn world(&self, w: &V3) -> V3 {
        self.t * w.x + self.b * w.y + self.n * w.z
    }
}

/// Cosine-weighted specular lobe of `s` (a centred or non-centred microsurface expressed
/// in `f`), for view v and light l in world space: D(h)G2(l, v, h)/(4 v_n). Zero when
/// either direction is below the geometric horizon (world z ≤ 0) or below the shading
/// frame.
pub fn lobe(s: &Microsurface, f: &Frame, v: &V3, l: &V3) -> f64 {
    if v.z <= 0.0 || l.z <= 0.0 {
        return 0.0;
    }
    let (vl, ll) = (f.local(v), f.local(l));
    let vn = s.projected_area(&vl);
    if vn <= 0.0 || s.projected_area(&ll) <= 0.0 {
        return 0.0;
    }
    let h = vl + ll;
    let hn = h.norm();
    if !(hn > 0.0) {
        return 0.0;
    }
    let h = h / hn;
    s.d(&h) * s.g2_correlated(&ll, &vl, &h) / (4.0 * vn)
}

/// [`lobe`] for one frame and one fixed view v: v in the frame, its projected area and
/// Λ(v) are computed once, since an integral over l evaluates the lobe many times. The
/// same operations in the same order as [`lobe`] with `Microsurface::g2_correlated`, so
/// the same bits.
#[derive(Clone, Copy, Debug)]
pub struct ViewedLobe {
    frame: Frame,
    v_above: bool,
    vl: V3,
    vn: f64,
    lambda_v: f64,
}

impl ViewedLobe {
    pub fn new(s: &Microsurface, f: &Frame, v: &V3) -> ViewedLobe {
        let vl = f.local(v);
        ViewedLobe {
            frame: *f,
            v_above: v.z > 0.0,
            vl,
            vn: s.projected_area(&vl),
            lambda_v: s.lambda(&vl),
        }
    }

    /// v in the lobe's frame, and Λ of it (what a visible-normal sampler of the same view
    /// needs, `VndfSampler::seen_with`).
    pub fn view(&self) -> (V3, f64) {
        (self.vl, self.lambda_v)
    }

    /// `lobe(s, f, v, l)` for the `s`, `f` and `v` given to [`ViewedLobe::new`].
    pub fn eval(&self, s: &Microsurface, l: &V3) -> f64 {
        if !self.v_above || l.z <= 0.0 {
            return 0.0;
        }
        let ll = self.frame.local(l);
        if self.vn <= 0.0 || s.projected_area(&ll) <= 0.0 {
            return 0.0;
        }
        let h = self.vl + ll;
        let hn = h.norm();
        if !(hn > 0.0) {
            return 0.0;
        }
        let h = h / hn;
        let g2 = if ll.dot(&h) <= 0.0 || self.vl.dot(&h) <= 0.0 {
            0.0
        } else {
            let sum = s.lambda(&ll) + self.lambda_v;
            if sum.is_infinite() {
                0.0
            } else {
                1.0 / (1.0 + sum)
            }
        };
        s.d(&h) * g2 / (4.0 * self.vn)
    }
}

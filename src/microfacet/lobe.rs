//! Geometry shared by every study that shades a surface: an orthonormal frame around a
//! normal and the cosine-weighted microfacet specular lobe seen in it (D·G2/(4 v_n),
//! F = 1; seed 003 Eq 14–15).

use super::surface::g2_from_lambdas;
use super::{g2_lanes, Microsurface};
use crate::lanes::{map, Dirs, Lanes, LANES};
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
            g2_from_lambdas(s.lambda(&ll), self.lambda_v)
        };
        s.d(&h) * g2 / (4.0 * self.vn)
    }

    /// The lobes of `g` (1 to [`LANES`] of them) one per lane, the last repeated in the
    /// lanes past them (whose values a caller ignores).
    pub fn lanes_of(g: &[ViewedLobe]) -> [&ViewedLobe; LANES] {
        std::array::from_fn(|i| &g[i.min(g.len().saturating_sub(1))])
    }

    /// [`Self::eval`] of lobe `g[i]` toward `l`'s lane i (one lobe may fill several
    /// lanes), step by step across the lanes (`crate::lanes`): the frames' maps and the
    /// half-vectors here, D and Λ(l) by `Microsurface::d_lanes` and `lambda_lanes`, every
    /// early return of `eval` a choice of 0 after the fact. The same operations in the
    /// same order, so each lane's bits are `eval`'s (`tests::lanes_are_eval`).
    pub fn eval_lanes(s: &Microsurface, g: [&ViewedLobe; LANES], l: &Dirs) -> Lanes {
        // Frame::local: (l·t, l·b, l·n)
        let ll = Dirs {
            x: dot_each(l, |i| g[i].frame.t),
            y: dot_each(l, |i| g[i].frame.b),
            z: dot_each(l, |i| g[i].frame.n),
        };
        let hs = Dirs {
            x: map(|i| g[i].vl.x + ll.x[i]),
            y: map(|i| g[i].vl.y + ll.y[i]),
            z: map(|i| g[i].vl.z + ll.z[i]),
        };
        let hn = hs.norm();
        let h = hs.over(&hn);
        let d = s.d_lanes(&h, s.d_norm());
        let lam = s.lambda_lanes(&ll);
        let lh = ll.dot(&h);
        let vh = map(|i| {
            let v = &g[i].vl;
            v.x * h.x[i] + v.y * h.y[i] + v.z * h.z[i]
        });
        let area = map(|i| s.projected_area(&ll.get(i)));
        let g2 = g2_lanes(&lh, &vh, &lam, &map(|i| g[i].lambda_v));
        map(|i| {
            let g = g[i];
            if !g.v_above || l.z[i] <= 0.0 || g.vn <= 0.0 || area[i] <= 0.0 || !(hn[i] > 0.0) {
                return 0.0;
            }
            d[i] * g2[i] / (4.0 * g.vn)
        })
    }
}

/// Lane i of `l` dotted with `e(i)`, as nalgebra's `dot`: (x x' + y y') + z z'.
#[inline(always)]
fn dot_each(l: &Dirs, e: impl Fn(usize) -> V3) -> Lanes {
    map(|i| {
        let e = e(i);
        l.x[i] * e.x + l.y[i] * e.y + l.z[i] * e.z
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::lanes::tests::direction;
    use crate::microfacet::Roughness;
    use rand::{Rng, SeedableRng};

    /// α: 1e-4, 1, or log-uniform between.
    pub(crate) fn alpha_of(case: usize, r: &mut impl Rng) -> f64 {
        match case % 6 {
            0 => 1e-4,
            1 => 1.0,
            _ => 10f64.powf(r.random_range(-4.0..0.0)),
        }
    }

    /// A surface for case `case`: isotropic or rotated anisotropic roughness (α from
    /// [`alpha_of`]), GGX, GGX with a mean slope (LEAN) or Beckmann.
    pub(crate) fn surface_of(case: usize, r: &mut impl Rng) -> Microsurface {
        let alpha = alpha_of(case, r);
        let rough = match case % 3 {
            0 => Roughness::iso(alpha),
            _ => Roughness::rotated(alpha, r.random_range(1e-4..1.0), r.random_range(-3.0..3.0)),
        }
        .unwrap();
        match case % 7 {
            0 => Microsurface::beckmann(rough),
            1 => Microsurface::ggx(rough)
                .with_mean(nalgebra::Vector2::new(
                    r.random_range(-1.0..1.0),
                    r.random_range(-1.0..1.0),
                ))
                .unwrap(),
            _ => Microsurface::ggx(rough),
        }
    }

    /// `ViewedLobe::eval_lanes` gives each lane `eval`'s bits, and `d_lanes` and
    /// `lambda_lanes` give `d_with`'s and `lambda`'s: 12 000 sets of four lobes (their own
    /// frames, tilted up to past the horizon, or one lobe in every lane) and four extreme
    /// directions (below, on and above the horizon, ±0, 1e-300, NaN, off the unit sphere)
    /// over every surface of [`surface_of`], views up to 89.99° and below the horizon.
    #[test]
    fn lanes_are_eval() {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(21);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for case in 0..12_000 {
            let s = surface_of(case, &mut r);
            let th = match case % 5 {
                0 => 89.99f64.to_radians(),
                1 => r.random_range(1.5707..1.8),
                _ => r.random_range(0.0..1.5707),
            };
            let ph = r.random_range(0.0..std::f64::consts::TAU);
            let v = V3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
            let lobes: Vec<ViewedLobe> = (0..LANES)
                .map(|_| {
                    let n = match r.random_range(0..4) {
                        0 => V3::z(),
                        1 => direction(&mut r),
                        _ => V3::new(r.random_range(-2.0..2.0), r.random_range(-2.0..2.0), 1.0),
                    };
                    ViewedLobe::new(&s, &Frame::around(n), &v)
                })
                .collect();
            let g = if case % 4 == 0 {
                [&lobes[0]; LANES]
            } else {
                ViewedLobe::lanes_of(&lobes)
            };
            let d: Vec<V3> = (0..LANES).map(|_| direction(&mut r)).collect();
            let l = Dirs::of(&d);
            let got = ViewedLobe::eval_lanes(&s, g, &l);
            let (dl, lam) = (s.d_lanes(&l, s.d_norm()), s.lambda_lanes(&l));
            for i in 0..LANES {
                let want = g[i].eval(&s, &d[i]);
                assert!(
                    same(got[i], want),
                    "case {case} lane {i}: {:?} {} vs {want}",
                    d[i],
                    got[i]
                );
                assert!(same(dl[i], s.d(&d[i])), "case {case} lane {i}: D");
                assert!(same(lam[i], s.lambda(&d[i])), "case {case} lane {i}: Λ");
            }
        }
    }
}

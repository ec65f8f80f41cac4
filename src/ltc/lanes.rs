//! Four samples at a time: the fitter's inner loop (`ltc::samples::metrics_on`) spends its
//! time in chains of divisions and square roots, one chain per sample (normalising the
//! LTC's image, the half-vector, Smith Λ, D, the LTC's Jacobian). Written one sample at a
//! time, each chain waits on its own latency; written step by step across four
//! independent samples, the four chains overlap.
//!
//! Every function here performs, lane by lane, exactly the IEEE operations of the scalar
//! form it names, in the same order (nalgebra's 3-vector dot and norm: (a + b) + c;
//! matrix times vector: (m₀₀x + m₀₁y) + m₀₂z per row), so each lane's bits are the
//! scalar form's: `tests::lanes_are_the_scalar_bits` checks them against it on random
//! and extreme inputs. Nothing is approximated and no sum is reordered.

use nalgebra::{Matrix2, Matrix3, Vector3};

type V3 = Vector3<f64>;

/// How many samples one call carries.
pub const LANES: usize = 4;

/// One number per lane.
pub type Lanes = [f64; LANES];

/// Four directions, one component per array.
#[derive(Clone, Copy, Debug, Default)]
pub struct Dirs {
    pub x: Lanes,
    pub y: Lanes,
    pub z: Lanes,
}

/// `f` applied lane by lane.
#[inline(always)]
pub fn map(f: impl Fn(usize) -> f64) -> Lanes {
    std::array::from_fn(f)
}

impl Dirs {
    /// The directions `d` (lanes past `d.len()` hold +z, whose results a caller ignores).
    pub fn of(d: &[V3]) -> Dirs {
        let at = |i: usize| d.get(i).copied().unwrap_or_else(V3::z);
        Dirs {
            x: map(|i| at(i).x),
            y: map(|i| at(i).y),
            z: map(|i| at(i).z),
        }
    }
    /// Lane `i` as a vector.
    pub fn get(&self, i: usize) -> V3 {
        V3::new(self.x[i], self.y[i], self.z[i])
    }
    /// M·d, each row (m₀x + m₁y) + m₂z as nalgebra's product computes it.
    #[inline(always)]
    pub fn times(&self, m: &Matrix3<f64>) -> Dirs {
        let row = |r: usize| {
            map(|i| m[(r, 0)] * self.x[i] + m[(r, 1)] * self.y[i] + m[(r, 2)] * self.z[i])
        };
        Dirs {
            x: row(0),
            y: row(1),
            z: row(2),
        }
    }
    /// ‖d‖ as nalgebra's `norm`: √((x² + y²) + z²).
    #[inline(always)]
    pub fn norm(&self) -> Lanes {
        map(|i| (self.x[i] * self.x[i] + self.y[i] * self.y[i] + self.z[i] * self.z[i]).sqrt())
    }
    /// d·e as nalgebra's `dot`: (x·x' + y·y') + z·z'.
    #[inline(always)]
    pub fn dot(&self, e: &Dirs) -> Lanes {
        map(|i| self.x[i] * e.x[i] + self.y[i] * e.y[i] + self.z[i] * e.z[i])
    }
    /// d/s, each component divided (nalgebra's `unscale`, so `normalize` with s = ‖d‖).
    #[inline(always)]
    pub fn over(&self, s: &Lanes) -> Dirs {
        Dirs {
            x: map(|i| self.x[i] / s[i]),
            y: map(|i| self.y[i] / s[i]),
            z: map(|i| self.z[i] / s[i]),
        }
    }
    /// d + v for one vector v (each component v + d, as nalgebra adds `v + l`).
    #[inline(always)]
    pub fn plus(&self, v: &V3) -> Dirs {
        Dirs {
            x: map(|i| v.x + self.x[i]),
            y: map(|i| v.y + self.y[i]),
            z: map(|i| v.z + self.z[i]),
        }
    }
}

/// uᵀ A u for the 2-vectors (x, y) of each lane, as `Roughness::quad` computes it with
/// nalgebra: A·u = (a₀₀x + a₀₁y, a₁₀x + a₁₁y), then the dot x·(Au)₀ + y·(Au)₁.
#[inline(always)]
pub fn quad2(a: &Matrix2<f64>, x: &Lanes, y: &Lanes) -> Lanes {
    map(|i| {
        let p = a[(0, 0)] * x[i] + a[(0, 1)] * y[i];
        let q = a[(1, 0)] * x[i] + a[(1, 1)] * y[i];
        x[i] * p + y[i] * q
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn wild(r: &mut impl Rng) -> f64 {
        match r.random_range(0..6) {
            0 => 0.0,
            1 => -0.0,
            2 => r.random_range(-1.0..1.0) * 1e-300,
            3 => r.random_range(-1.0..1.0) * 1e150,
            _ => r.random_range(-2.0..2.0),
        }
    }

    /// Every helper gives, lane by lane, the bits of the nalgebra operation it stands for,
    /// over 20 000 sets of four random vectors and matrices (zeros of both signs, 1e-300
    /// and 1e150 among them).
    #[test]
    fn helpers_are_nalgebra_bits() {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for _ in 0..20_000 {
            let d: Vec<V3> = (0..LANES)
                .map(|_| V3::new(wild(&mut r), wild(&mut r), wild(&mut r)))
                .collect();
            let e: Vec<V3> = (0..LANES)
                .map(|_| V3::new(wild(&mut r), wild(&mut r), wild(&mut r)))
                .collect();
            let m = Matrix3::from_fn(|_, _| wild(&mut r));
            let a = Matrix2::from_fn(|_, _| wild(&mut r));
            let (dd, ee) = (Dirs::of(&d), Dirs::of(&e));
            let (md, nd, de) = (dd.times(&m), dd.norm(), dd.dot(&ee));
            let (un, pl) = (dd.over(&nd), dd.plus(&e[0]));
            let q = quad2(&a, &dd.x, &dd.y);
            for i in 0..LANES {
                let mv = m * d[i];
                for c in 0..3 {
                    assert!(
                        same(md.get(i)[c], mv[c]),
                        "M·d {c}: {} vs {}",
                        md.get(i)[c],
                        mv[c]
                    );
                    assert!(same(un.get(i)[c], d[i].normalize()[c]));
                    assert!(same(pl.get(i)[c], (e[0] + d[i])[c]));
                }
                assert!(same(nd[i], d[i].norm()));
                assert!(same(de[i], d[i].dot(&e[i])));
                let u = nalgebra::Vector2::new(d[i].x, d[i].y);
                assert!(same(q[i], u.dot(&(a * u))));
            }
        }
    }

    fn direction(r: &mut impl Rng) -> V3 {
        match r.random_range(0..10) {
            0 => V3::new(wild(r), wild(r), wild(r)),
            1 => V3::new(r.random_range(-1.0..1.0), r.random_range(-1.0..1.0), 0.0),
            2 => V3::new(r.random_range(-1.0..1.0), 0.0, -0.0),
            3 => V3::new(0.0, 0.0, 1.0),
            4 => V3::new(1.0, 0.0, 1e-300),
            5 => V3::new(f64::NAN, 0.0, 1.0),
            _ => {
                let (z, p) = (
                    r.random_range(-0.2..1.0f64),
                    r.random_range(0.0..std::f64::consts::TAU),
                );
                let s = (1.0 - z * z).max(0.0).sqrt();
                V3::new(s * p.cos(), s * p.sin(), z)
            }
        }
    }

    /// The microfacet lobe (`FixedView`) and the LTC (`LtcDist`) in lanes give each lane
    /// the bits of their scalar forms: 12 000 sets of four directions (below, on and above
    /// the horizon, ±0, 1e-300, NaN, off the unit sphere) against isotropic GGX at α from
    /// 1e-4 to 1, rotated anisotropic GGX, GGX with a mean slope and Beckmann (the
    /// lane-by-lane path), views up to 89.99°, and random M.
    #[test]
    fn lobes_and_ltcs_are_the_scalar_bits() {
        use crate::ltc::target::FixedView;
        use crate::ltc::LtcDist;
        use crate::microfacet::{Microsurface, Roughness};
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for case in 0..12_000 {
            let alpha = match case % 6 {
                0 => 1e-4,
                1 => 1.0,
                _ => 10f64.powf(r.random_range(-4.0..0.0)),
            };
            let rough = match case % 3 {
                0 => Roughness::iso(alpha),
                _ => {
                    Roughness::rotated(alpha, r.random_range(1e-4..1.0), r.random_range(-3.0..3.0))
                }
            }
            .unwrap();
            let surface = match case % 7 {
                0 => Microsurface::beckmann(rough),
                // a non-centred (LEAN) slope distribution
                1 => Microsurface::ggx(rough)
                    .with_mean(nalgebra::Vector2::new(
                        r.random_range(-1.0..1.0),
                        r.random_range(-1.0..1.0),
                    ))
                    .unwrap(),
                _ => Microsurface::ggx(rough),
            };
            let th = if case % 5 == 0 {
                89.99f64.to_radians()
            } else {
                r.random_range(0.0..1.5707)
            };
            let view = FixedView::new(surface, V3::new(th.sin(), 0.0, th.cos()));
            let d: Vec<V3> = (0..LANES).map(|_| direction(&mut r)).collect();
            let (f, p) = view.eval_lanes(&Dirs::of(&d));
            for i in 0..LANES {
                let (f1, p1) = view.eval(&d[i]);
                assert!(
                    same(f[i], f1) && same(p[i], p1),
                    "case {case} lane {i}: {:?}",
                    d[i]
                );
            }
            let m = Matrix3::from_fn(|_, _| r.random_range(-2.0..2.0));
            let Ok(ltc) = LtcDist::new(m) else { continue };
            let (img, ok) = ltc.from_cosine_lanes(&Dirs::of(&d));
            let g = ltc.eval_lanes(&Dirs::of(&d));
            for i in 0..LANES {
                match ltc.from_cosine(&d[i]) {
                    Some(x) => {
                        assert!(ok[i]);
                        (0..3).for_each(|c| assert!(same(img.get(i)[c], x[c])));
                    }
                    None => assert!(!ok[i]),
                }
                assert!(
                    same(g[i], ltc.eval_reference(&d[i])),
                    "case {case} lane {i}"
                );
                assert!(same(ltc.eval(&d[i]), ltc.eval_reference(&d[i])));
            }
        }
    }
}

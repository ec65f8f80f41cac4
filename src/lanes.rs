//! Four samples at a time. The hot loops of the fits and of the held-out judge spend their
//! time in chains of divisions and square roots, one chain per sample (normalising the
//! LTC's image, the half-vector, Smith Λ, D, the LTC's Jacobian). Written one sample at a
//! time, each chain waits on its own latency; written step by step across four
//! independent samples (`ltc::samples::metrics_on`, the targets' `eval_lanes`,
//! `integrate::cubature::cubature_lanes`), the four chains overlap.
//!
//! Every helper here performs, lane by lane, exactly the IEEE operations of the nalgebra
//! form it names, in the same order (3-vector dot and norm: (a + b) + c; matrix times
//! vector: (m₀₀x + m₀₁y) + m₀₂z per row), so each lane's bits are the scalar form's:
//! `tests::helpers_are_nalgebra_bits` checks them on random and extreme inputs, and each
//! user checks its own lanes against its scalar form. Nothing is approximated and no sum
//! is reordered.

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

/// `f` at each of the `N` directions `d`, through `f`'s four lanes (the last call's lanes
/// past `d` hold +z, and their values are dropped): what a quadrature segment's nodes
/// take from an integrand written in lanes.
pub fn by_four<const N: usize>(d: &[V3; N], f: impl Fn(&Dirs) -> Lanes) -> [f64; N] {
    let mut out = [0.0; N];
    for (c, ds) in d.chunks(LANES).enumerate() {
        let r = f(&Dirs::of(ds));
        out[c * LANES..c * LANES + ds.len()].copy_from_slice(&r[..ds.len()]);
    }
    out
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
pub(crate) mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// A coordinate: ±0, ±1e-300-sized, ±1e150-sized or ordinary.
    pub(crate) fn wild(r: &mut impl Rng) -> f64 {
        match r.random_range(0..6) {
            0 => 0.0,
            1 => -0.0,
            2 => r.random_range(-1.0..1.0) * 1e-300,
            3 => r.random_range(-1.0..1.0) * 1e150,
            _ => r.random_range(-2.0..2.0),
        }
    }

    /// A direction for lane tests: arbitrary (`wild` components), on the horizon (+0 and
    /// −0), the pole, 1e-300 above the horizon, NaN, or unit and up to 0.2 below.
    pub(crate) fn direction(r: &mut impl Rng) -> V3 {
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
}

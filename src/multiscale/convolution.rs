//! Spherical convolution of two isotropic LTCs (seed 000 Eq 6):
//! c(m) = (γ_me ∗ γ_mi)(m) = ∫_{S²} γ_me(b) γ_mi(R_b⁻¹ m) db.
//!
//! Both lobes are isotropic about n, so γ_mi(R_b⁻¹ m) = g_mi(m·b) (its zonal profile,
//! independent of the twist of R_b) and c depends on θ_m only. Micro-normals rotated below
//! the horizon (m_z < 0) are kept in the unclipped quantities and counted as lost mass in
//! the clipped ones.

use crate::error::Result;
use crate::integrate::estimate::{ErrorKind, Estimate, Welford};
use crate::integrate::mc::Strategy;
use crate::integrate::quad::Tol;
use crate::integrate::sphere::{frame, integrate_sphere, integrate_sphere_lanes, SphereRule};
use crate::lanes::{map, Dirs, Lanes, LANES};
use crate::ltc::LtcDist;
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// Zonal profile g(cos θ) of the isotropic LTC: γ at polar angle θ.
pub fn zonal(d: &LtcDist, cos_t: f64) -> f64 {
    let c = cos_t.clamp(-1.0, 1.0);
    let s = (1.0 - c * c).max(0.0).sqrt();
    d.eval(&V3::new(s, 0.0, c))
}

/// The convolution of two isotropic LTCs.
pub struct Convolution {
    pub alpha_me: f64,
    pub alpha_mi: f64,
    me: LtcDist,
    mi: LtcDist,
}

/// Moments of the convolution, each with its error.
#[derive(Clone, Debug, Serialize)]
pub struct Moments {
    /// ∫_{S²} c (should be 1).
    pub mass_total: Estimate,
    /// ∫_{m_z<0} c: micro-normals rotated below the horizon.
    pub mass_below: Estimate,
    /// ∫_{S²} m_z c (unclipped mean resultant length).
    pub mrl_unclipped: Estimate,
    /// ∫_{m_z>0} m_z c / ∫_{m_z>0} c (clipped and renormalised).
    pub mrl_clipped: f64,
}

impl Convolution {
    pub fn new(alpha_me: f64, alpha_mi: f64) -> Result<Self> {
        Ok(Convolution {
            alpha_me,
            alpha_mi,
            me: LtcDist::isotropic(alpha_me)?,
            mi: LtcDist::isotropic(alpha_mi)?,
        })
    }

    /// The Eq 6 integrand γ_me(b)·g_mi(m·b) (zero where either lobe is below its horizon).
    fn integrand(&self, m: &V3, b: &V3) -> f64 {
        let c = m.dot(b);
        if b.z <= 0.0 || c <= 0.0 {
            return 0.0;
        }
        self.me.eval(b) * zonal(&self.mi, c)
    }

    /// [`Self::integrand`] at four b at a time (`crate::lanes`: both LTC densities step
    /// by step across the lanes, as `LtcDist::eval_lanes` computes them): each lane's
    /// bits are `integrand`'s (`tests::integrand_in_lanes_is_integrand`).
    fn integrand_lanes(&self, m: &V3, b: &Dirs) -> Lanes {
        let c = map(|i| m.x * b.x[i] + m.y * b.y[i] + m.z * b.z[i]);
        let me = self.me.eval_lanes(b);
        // zonal(mi, c): γ_mi at (sin θ, 0, cos θ) with cos θ = c clamped to [−1, 1]
        let cz = map(|i| c[i].clamp(-1.0, 1.0));
        let sz = map(|i| (1.0 - cz[i] * cz[i]).max(0.0).sqrt());
        let mi = self.mi.eval_lanes(&Dirs {
            x: sz,
            y: [0.0; LANES],
            z: cz,
        });
        map(|i| {
            if b.z[i] <= 0.0 || c[i] <= 0.0 {
                0.0
            } else {
                me[i] * mi[i]
            }
        })
    }

    /// c(θ_m) by adaptive sphere quadrature over b (kinks: b_z = 0 and m·b = 0).
    pub fn density(&self, theta_m: f64, tol: Tol) -> Estimate {
        let m = V3::new(theta_m.sin(), 0.0, theta_m.cos());
        let f = |b: &Dirs| self.integrand_lanes(&m, b);
        // pole at the narrower lobe's centre, scale its width
        let (pole, scale) = if self.alpha_mi <= self.alpha_me {
            (m, self.alpha_mi)
        } else {
            (V3::z(), self.alpha_me)
        };
        let rule = SphereRule::sphere(pole, scale.min(1.0))
            .with_kink(V3::z())
            .with_kink(m);
        integrate_sphere_lanes(&f, &rule, tol)
    }

    /// ∫ w(θ) c(θ) 2π sin θ dθ over [θ0, θ1] by adaptive GK, with geometric break points
    /// following the lobe; inner errors are propagated. `seen` holds the c(θ) already
    /// computed at this `tol` (by θ's bits): integrals of the same range with other
    /// weights start on the same nodes, and c(θ) is a pure function of θ, so a value taken
    /// from it is the one a fresh quadrature gives (and its evaluations are counted in
    /// each integral it serves: `evals` is what the figure rests on, not what was spent).
    fn radial(
        &self,
        w: &(dyn Fn(f64) -> f64 + Sync),
        t0: f64,
        t1: f64,
        tol: Tol,
        seen: &std::sync::Mutex<std::collections::HashMap<u64, Estimate>>,
    ) -> Estimate {
        let width = self.alpha_me.max(self.alpha_mi).min(1.0);
        let mut breaks = vec![t0, t1];
        let mut th = 0.25 * width;
        while th < t1 {
            if th > t0 {
                breaks.push(th);
            }
            th *= 2.0;
        }
        breaks.sort_by(|a, b| a.total_cmp(b));
        let inner = Tol::new(tol.abs * 0.1, tol.rel * 0.1, tol.max_evals / 20);
        let eval = |xs: &[f64; 15]| {
            let known = |t: f64| seen.lock().ok()?.get(&t.to_bits()).copied();
            let r: Vec<Estimate> = xs
                .par_iter()
                .map(|&t| {
                    known(t).unwrap_or_else(|| {
                        let e = self.density(t, inner);
                        if let Ok(mut m) = seen.lock() {
                            m.insert(t.to_bits(), e);
                        }
                        e
                    })
                })
                .collect();
            let mut v = [0.0; 15];
            let mut e = [0.0; 15];
            let mut n = 0;
            for (i, (est, &t)) in r.iter().zip(xs).enumerate() {
                let k = w(t) * 2.0 * PI * t.sin();
                v[i] = k * est.value;
                e[i] = (k * est.error).abs();
                n += est.evals;
            }
            (v, e, n)
        };
        crate::integrate::quad::adaptive_batched(&eval, &breaks, tol)
    }

    /// Moments by nested adaptive quadrature.
    pub fn moments_quad(&self, tol: Tol) -> Moments {
        let one = |_t: f64| 1.0;
        let cz = |t: f64| t.cos();
        // the mass and the mean resultant length of a half share its c(θ) nodes
        let seen = Default::default();
        let above = self.radial(&one, 0.0, PI / 2.0, tol, &seen);
        let below = self.radial(&one, PI / 2.0, PI, tol, &seen);
        let mrl_above = self.radial(&cz, 0.0, PI / 2.0, tol, &seen);
        let mrl_below = self.radial(&cz, PI / 2.0, PI, tol, &seen);
        let sum = |a: &Estimate, b: &Estimate| Estimate {
            value: a.value + b.value,
            error: a.error + b.error,
            evals: a.evals + b.evals,
            kind: ErrorKind::Quadrature,
            converged: a.converged && b.converged,
        };
        Moments {
            mass_total: sum(&above, &below),
            mass_below: below,
            mrl_unclipped: sum(&mrl_above, &mrl_below),
            mrl_clipped: mrl_above.value / above.value,
        }
    }

    /// c(θ_m) by Monte Carlo with MIS (balance heuristic) of the two lobes of the
    /// integrand γ_me(b)·g_mi(m·b): b ~ γ_me, and b ~ γ_mi rotated to m (the paper's
    /// estimator of Eq 6). Deterministic per seed at any thread count.
    pub fn density_mc(&self, theta_m: f64, n: u64, seed: u64) -> Estimate {
        let m = V3::new(theta_m.sin(), 0.0, theta_m.cos());
        let f = |b: &V3| self.integrand(&m, b);
        let around = Rotated {
            d: &self.mi,
            axis: m,
        };
        let strat: [&dyn Strategy<V3>; 2] = [&self.me, &around];
        crate::integrate::mc::mis(&f, &strat, n, seed)
    }

    /// Moments by Monte Carlo: b ~ γ_me, m′ ~ γ_mi, m = R_b m′ (the sampling the paper's MC
    /// uses); returns (mass below, unclipped MRL, clipped MRL) with standard errors.
    pub fn moments_mc(&self, n: u64, seed: u64) -> (Estimate, Estimate, Estimate) {
        let chunks = n.div_ceil(4096);
        let acc: Vec<(Welford, Welford, Welford, Welford)> = (0..chunks)
            .into_par_iter()
            .map(|k| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                rng.set_stream(k);
                let mut a = (
                    Welford::default(),
                    Welford::default(),
                    Welford::default(),
                    Welford::default(),
                );
                for _ in 0..4096.min(n - k * 4096) {
                    let b = self.me.sample([rng.random(), rng.random()]);
                    let mp = self.mi.sample([rng.random(), rng.random()]);
                    let (Some(b), Some(mp)) = (b, mp) else {
                        continue;
                    };
                    let (t1, t2) = frame(&b);
                    let m = t1 * mp.x + t2 * mp.y + b * mp.z;
                    a.0.push(if m.z < 0.0 { 1.0 } else { 0.0 });
                    a.1.push(m.z);
                    a.2.push(m.z.max(0.0));
                    a.3.push(if m.z >= 0.0 { 1.0 } else { 0.0 });
                }
                a
            })
            .collect();
        let t = acc.into_iter().fold(
            (
                Welford::default(),
                Welford::default(),
                Welford::default(),
                Welford::default(),
            ),
            |x, y| {
                (
                    x.0.merge(y.0),
                    x.1.merge(y.1),
                    x.2.merge(y.2),
                    x.3.merge(y.3),
                )
            },
        );
        let est = |w: &Welford| Estimate {
            value: w.mean,
            error: w.std_error(),
            evals: w.n,
            kind: ErrorKind::StandardError,
            converged: true,
        };
        // clipped MRL = E[m_z⁺]/P(m_z ≥ 0); first-order error propagation
        let (num, den) = (est(&t.2), est(&t.3));
        let clipped = Estimate {
            value: num.value / den.value,
            error: (num.error / den.value).hypot(num.value * den.error / (den.value * den.value)),
            evals: num.evals,
            kind: ErrorKind::StandardError,
            converged: true,
        };
        (est(&t.0), est(&t.1), clipped)
    }
}

/// An isotropic LTC rotated so that its pole is `axis` (any twist: the lobe is zonal).
struct Rotated<'a> {
    d: &'a LtcDist,
    axis: V3,
}

impl Strategy<V3> for Rotated<'_> {
    fn sample(&self, u: [f64; 2]) -> Option<V3> {
        let p = self.d.sample(u)?;
        let (t1, t2) = frame(&self.axis);
        Some(t1 * p.x + t2 * p.y + self.axis * p.z)
    }
    fn pdf(&self, b: &V3) -> f64 {
        zonal(self.d, self.axis.dot(b))
    }
}

/// ∫_cap γ_α(m) dm for the isotropic LTC (same cap parameterisation).
pub fn ltc_cap_integral(alpha: f64, theta_c: f64, r: f64, tol: Tol) -> Result<Estimate> {
    let d = LtcDist::isotropic(alpha)?;
    let axis = V3::new(theta_c.sin(), 0.0, theta_c.cos());
    let rule = SphereRule {
        pole: axis,
        scale: r,
        theta_max: r,
        phi_segments: 4,
        t_breaks: 0,
        stretch: None,
        kinks: Vec::new(),
        mirror_horizons: Vec::new(),
    };
    Ok(integrate_sphere(&|m: &V3| d.eval(m), &rule, tol))
}

/// c(θ) tabulated on Gauss–Legendre nodes per panel of [0, π] (panels split at geometric
/// breaks following the lobe and at π/2), with barycentric Lagrange interpolation inside
/// each panel — spectrally accurate for the smooth zonal density.
pub struct ZonalTable {
    panels: Vec<ZPanel>,
}

struct ZPanel {
    a: f64,
    b: f64,
    theta: Vec<f64>,
    weight: Vec<f64>,
    value: Vec<f64>,
    bary: Vec<f64>,
}

impl ZonalTable {
    /// (θ, quadrature weight, c(θ)) at every node.
    pub fn nodes(&self) -> impl Iterator<Item = (f64, f64, f64)> + '_ {
        self.panels
            .iter()
            .flat_map(|p| (0..p.theta.len()).map(move |i| (p.theta[i], p.weight[i], p.value[i])))
    }

    /// Interpolated c(θ).
    pub fn eval(&self, theta: f64) -> f64 {
        let t = theta.clamp(0.0, PI);
        let p = self
            .panels
            .iter()
            .find(|p| t >= p.a && t <= p.b)
            .unwrap_or_else(|| self.panels.last().expect("non-empty table"));
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..p.theta.len() {
            let d = t - p.theta[i];
            if d == 0.0 {
                return p.value[i];
            }
            let k = p.bary[i] / d;
            num += k * p.value[i];
            den += k;
        }
        num / den
    }
}

/// L2 distance² between the convolution and an isotropic LTC of roughness α over the
/// sphere: 2π ∫ (c(θ) − g_α(θ))² sin θ dθ on the table's Gauss–Legendre nodes.
pub fn l2_distance2(table: &ZonalTable, alpha: f64) -> f64 {
    let d = LtcDist::isotropic(alpha).expect("α > 0");
    table
        .nodes()
        .map(|(t, w, c)| {
            let g = zonal(&d, t.cos());
            w * (c - g) * (c - g) * 2.0 * PI * t.sin()
        })
        .sum()
}

/// Tabulate c(θ) (see [`ZonalTable`]).
pub fn density_table(conv: &Convolution, nodes_per_panel: usize, tol: Tol) -> ZonalTable {
    let width = conv.alpha_me.max(conv.alpha_mi).min(1.0);
    let mut breaks = vec![0.0, PI, PI / 2.0];
    let mut th = 0.25 * width;
    while th < PI {
        breaks.push(th);
        th *= 1.5;
    }
    breaks.sort_by(|a, b| a.total_cmp(b));
    breaks.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let (x, w) = crate::integrate::quad::gauss_legendre(nodes_per_panel);
    // barycentric weights of the GL nodes (on [-1, 1]; the affine map cancels)
    let bary: Vec<f64> = (0..x.len())
        .map(|j| {
            1.0 / (0..x.len())
                .filter(|&k| k != j)
                .map(|k| x[j] - x[k])
                .product::<f64>()
        })
        .collect();
    let panels = breaks
        .windows(2)
        .map(|p| {
            let (c, h) = (0.5 * (p[0] + p[1]), 0.5 * (p[1] - p[0]));
            let theta: Vec<f64> = x.iter().map(|xi| c + h * xi).collect();
            let value: Vec<f64> = theta
                .par_iter()
                .map(|&t| conv.density(t, tol).value)
                .collect();
            ZPanel {
                a: p[0],
                b: p[1],
                weight: w.iter().map(|wi| h * wi).collect(),
                theta,
                value,
                bary: bary.clone(),
            }
        })
        .collect();
    ZonalTable { panels }
}

/// A convex spherical polygon light (vertices in counter-clockwise order seen from the
/// origin, i.e. every edge normal v_i × v_(i+1) points inside).
#[derive(Clone, Debug, Serialize)]
pub struct Polygon {
    pub name: &'static str,
    pub vertices: Vec<[f64; 3]>,
}

impl Polygon {
    /// A spherical quad centred at polar angle θ, azimuth 0, with half-extents (h1, h2)
    /// along the polar and azimuthal tangents (gnomonic: vertices = normalize(c ± h1 e_θ ± h2 e_φ)).
    pub fn quad(name: &'static str, theta: f64, h1: f64, h2: f64) -> Polygon {
        let c = V3::new(theta.sin(), 0.0, theta.cos());
        let (e1, e2) = (
            V3::new(theta.cos(), 0.0, -theta.sin()),
            V3::new(0.0, 1.0, 0.0),
        );
        let v = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(a, b)| {
                let p = (c + e1 * (a * h1) + e2 * (b * h2)).normalize();
                [p.x, p.y, p.z]
            })
            .collect();
        Polygon { name, vertices: v }.oriented()
    }

    fn verts(&self) -> Vec<V3> {
        self.vertices
            .iter()
            .map(|v| V3::new(v[0], v[1], v[2]))
            .collect()
    }

    /// Reverse the order if the edge normals point away from the centroid.
    fn oriented(mut self) -> Polygon {
        let v = self.verts();
        let c: V3 = v.iter().sum();
        if v[0].cross(&v[1]).dot(&c) < 0.0 {
            self.vertices.reverse();
        }
        self
    }

    /// Inward edge normals.
    pub fn edge_normals(&self) -> Vec<V3> {
        let v = self.verts();
        (0..v.len())
            .map(|i| v[i].cross(&v[(i + 1) % v.len()]).normalize())
            .collect()
    }

    /// ∫_P f(m) dm by adaptive sphere quadrature around the centroid, the edges' great
    /// circles registered as kinks (the indicator's jumps fall on panel boundaries).
    pub fn integral(&self, f: &(dyn Fn(&V3) -> f64 + Sync), tol: Tol) -> Estimate {
        let v = self.verts();
        let c: V3 = v.iter().sum::<V3>().normalize();
        let reach = v
            .iter()
            .map(|p| p.dot(&c).clamp(-1.0, 1.0).acos())
            .fold(0.0, f64::max);
        let normals = self.edge_normals();
        let g = |m: &V3| {
            if normals.iter().all(|k| k.dot(m) >= 0.0) {
                f(m)
            } else {
                0.0
            }
        };
        let mut rule = SphereRule {
            theta_max: (reach * 1.01).min(PI),
            phi_segments: 4,
            t_breaks: 0,
            ..SphereRule::sphere(c, reach)
        };
        for &k in &normals {
            rule = rule.with_kink(k);
        }
        integrate_sphere(&g, &rule, tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `integrand_lanes` gives each lane `integrand`'s bits: 20 000 sets of four b (below,
    /// on and above the horizon, ±0, 1e-300, NaN, off the unit sphere) and random m, at
    /// α_me and α_mi from 1e-4 to 1. And the density through it is the density through
    /// the one-direction integrand, bit for bit (`integrate_sphere` against
    /// `integrate_sphere_lanes`).
    #[test]
    fn integrand_in_lanes_is_integrand() {
        use crate::lanes::tests::direction;
        let mut r = ChaCha8Rng::seed_from_u64(41);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        let alpha = |r: &mut ChaCha8Rng| match r.random_range(0..4) {
            0 => 1e-4,
            1 => 1.0,
            _ => 10f64.powf(r.random_range(-4.0..0.0)),
        };
        for case in 0..20_000 {
            let c = Convolution::new(alpha(&mut r), alpha(&mut r)).unwrap();
            let m = direction(&mut r);
            let d: Vec<V3> = (0..LANES).map(|_| direction(&mut r)).collect();
            let got = c.integrand_lanes(&m, &Dirs::of(&d));
            for i in 0..LANES {
                let want = c.integrand(&m, &d[i]);
                assert!(
                    same(got[i], want),
                    "case {case} lane {i}: {} vs {want}",
                    got[i]
                );
            }
        }
        let tol = Tol::new(1e-7, 1e-7, 400_000);
        for (me, mi, th) in [(0.3, 0.2, 0.4), (0.05, 0.5, 1.2), (1e-3, 1e-3, 1.5)] {
            let c = Convolution::new(me, mi).unwrap();
            let m = V3::new(f64::sin(th), 0.0, f64::cos(th));
            let rule = SphereRule::sphere(m, me.min(mi))
                .with_kink(V3::z())
                .with_kink(m);
            let one = integrate_sphere(&|b: &V3| c.integrand(&m, b), &rule, tol);
            let four = integrate_sphere_lanes(&|b: &Dirs| c.integrand_lanes(&m, b), &rule, tol);
            assert_eq!(one.value.to_bits(), four.value.to_bits());
            assert_eq!(one.error.to_bits(), four.error.to_bits());
            assert_eq!(one.evals, four.evals);
            assert!(one.value > 0.0);
        }
    }

    /// A radial integral that takes c(θ) from another's nodes is the integral it gives
    /// alone, bit for bit, and the two weights of a half do share nodes.
    #[test]
    fn shared_nodes_change_no_bit() {
        let c = Convolution::new(0.3, 0.2).unwrap();
        let tol = Tol::new(1e-6, 1e-6, 200_000);
        let cz = |t: f64| t.cos();
        let own = Default::default();
        let alone = c.radial(&cz, 0.0, PI / 2.0, tol, &own);
        let needed = own.lock().unwrap().len();
        let seen = Default::default();
        c.radial(&|_| 1.0, 0.0, PI / 2.0, tol, &seen);
        let filled = seen.lock().unwrap().len();
        assert!(filled > 0);
        let shared = c.radial(&cz, 0.0, PI / 2.0, tol, &seen);
        assert_eq!(alone.value.to_bits(), shared.value.to_bits());
        assert_eq!(alone.error.to_bits(), shared.error.to_bits());
        assert_eq!(alone.evals, shared.evals);
        // the second weight found some of its nodes computed already
        assert!(seen.lock().unwrap().len() - filled < needed);
    }
}

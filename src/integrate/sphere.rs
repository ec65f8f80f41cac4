//! Adaptive integration over the sphere (or a polar cap of it) around a chosen pole,
//! with a radial substitution that concentrates nodes where a peaked integrand lives.
//!
//! Parameterisation: ω = frame(pole)·(sin θ cos φ, sin θ sin φ, cos θ) with
//! θ(t) = (2θ_max/π)·atan(s·t/(1 − t)), t ∈ [0, 1]. Half of the nodes in t fall at
//! θ ≲ s, so s ≈ roughness makes α = 1e-4 lobes as easy as α = 1. dθ/dt =
//! (2θ_max/π)·s/((1 − t)² + s²t²) is bounded on [0, 1] (→ 1/s at t = 1).
//! The φ integral (periodic, split into `phi_segments` initial pieces) is nested inside
//! the t integral; both are G7–K15 adaptive and the inner errors are propagated into the
//! outer error estimate. The 15 inner integrals of an outer segment run in parallel
//! (rayon), written back by index, so the result is identical at any thread count.

use super::estimate::Estimate;
use super::quad::{adaptive_batched, NodeValues, Tol};
use crate::lanes::{by_four, Dirs, Lanes};
use nalgebra::Vector3;
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

/// Right-handed orthonormal basis (t1, t2) completing unit `n` (Duff et al. 2017).
pub fn frame(n: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let sign = 1.0_f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vector3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vector3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// How to lay the polar grid on the sphere.
#[derive(Clone, Debug)]
pub struct SphereRule {
    /// Unit vector around which θ is measured.
    pub pole: Vector3<f64>,
    /// Radial length scale s (radians, roughly): set it to the lobe width.
    pub scale: f64,
    /// π for the whole sphere, π/2 for the hemisphere around the pole.
    pub theta_max: f64,
    /// Initial φ segments (≥ 1); more helps strongly anisotropic lobes.
    pub phi_segments: usize,
    /// Extra initial t break points in (0, 1) (e.g. where the integrand has a kink).
    pub t_breaks: usize,
    /// Elongated lobes: (major-axis direction in the pole's tangent frame, axis ratio
    /// ≥ 1). At polar angle θ the azimuth is stretched by r(θ) = clamp(θ/scale, 1,
    /// ratio): directions ∝ r cos ψ·e_major + sin ψ·e_minor with dφ/dψ =
    /// r/(r² cos²ψ + sin²ψ), which turns a lobe of minor width `scale` into an O(1)-wide
    /// function of ψ at every radius (an elliptic stretch; nodes are not wasted on the
    /// empty sides of a needle-like lobe).
    pub stretch: Option<(nalgebra::Vector2<f64>, f64)>,
    /// Circles k·ω = c (unit k; c = 0 for great circles) across which the integrand has a
    /// kink or a jump (the horizon, ⟨o·m⟩ clamps, χ⁺ terms, the support edge h_z = 0 seen
    /// from ω_i). Their crossings with each polar circle become break points of the inner
    /// integral, and the polar angles where a polar circle touches them become break
    /// points of the outer one, so every GK panel sees a smooth integrand and its error
    /// estimate stays honest.
    pub kinks: Vec<(Vector3<f64>, f64)>,
    /// Views v whose mirror horizon bounds the integrand: for a half-vector integral
    /// about the pole z, the reflected direction l = 2(v·h)h − v reaches the horizon
    /// l_z = 0 where sin 2θ·(v_xy·(cos φ, sin φ)) = −v_z cos 2θ, a curve (not a circle)
    /// that the integrand of a cosine-weighted BRDF has a kink on. Its crossings with
    /// each polar circle become inner break points and its polar extent outer ones, as
    /// for `kinks`. Only for the pole z (the frame of `SphereRule::hemisphere` and of
    /// `from_covariance` about z).
    pub mirror_horizons: Vec<Vector3<f64>>,
}

impl SphereRule {
    pub fn hemisphere(scale: f64) -> Self {
        SphereRule {
            pole: Vector3::z(),
            scale,
            theta_max: PI / 2.0,
            phi_segments: 8,
            t_breaks: 4,
            stretch: None,
            kinks: Vec::new(),
            mirror_horizons: Vec::new(),
        }
    }
    pub fn sphere(pole: Vector3<f64>, scale: f64) -> Self {
        SphereRule {
            pole: pole.normalize(),
            scale,
            theta_max: PI,
            phi_segments: 8,
            t_breaks: 4,
            stretch: None,
            kinks: Vec::new(),
            mirror_horizons: Vec::new(),
        }
    }

    /// Layout for a lobe centred on `pole` whose angular covariance, in the basis
    /// `frame(pole)`, is ≈ `c` (2×2 SPD): scale = minor width, stretch along the major axis
    /// (the major width is capped at 1 rad: a linearised covariance means nothing beyond).
    pub fn from_covariance(pole: Vector3<f64>, c: nalgebra::Matrix2<f64>, theta_max: f64) -> Self {
        let (lo, hi, major) = crate::linalg::sym2_eigen(&c);
        let lmin = lo.max(1e-300);
        let lmax = hi.min(1.0).max(lmin);
        let ratio = (lmax / lmin).sqrt();
        SphereRule {
            pole: pole.normalize(),
            scale: lmin.sqrt().clamp(1e-9, 1.0),
            theta_max,
            phi_segments: 8,
            t_breaks: 4,
            stretch: (ratio > 1.5).then_some((major, ratio)),
            kinks: Vec::new(),
            mirror_horizons: Vec::new(),
        }
    }

    /// Add a kink along the great circle k·ω = 0.
    pub fn with_kink(self, k: Vector3<f64>) -> Self {
        self.with_circle(k, 0.0)
    }

    /// Add a kink along the circle k̂·ω = c.
    pub fn with_circle(mut self, k: Vector3<f64>, c: f64) -> Self {
        let n = k.norm();
        if n > 0.0 && n.is_finite() && c.abs() < 1.0 {
            self.kinks.push((k / n, c));
        }
        self
    }

    /// Add the mirror horizon of the view `v` (see `mirror_horizons`); ignored unless the
    /// pole is z and v is finite with v_z > 0.
    pub fn with_mirror_horizon(mut self, v: Vector3<f64>) -> Self {
        let z_pole = (self.pole.normalize() - Vector3::z()).norm() < 1e-15;
        debug_assert!(z_pole, "a mirror horizon needs the pole z");
        if z_pole && v.iter().all(|x| x.is_finite()) && v.z > 0.0 {
            self.mirror_horizons.push(v.normalize());
        }
        self
    }

    /// t of a polar angle θ (inverse of [`Self::theta`]).
    fn t_of(&self, th: f64) -> f64 {
        let c = 2.0 * self.theta_max / PI;
        let x = (th / c).tan();
        x / (self.scale + x)
    }

    /// Outer break points: polar angles where a polar circle touches a kink circle.
    fn kink_t_breaks(&self) -> Vec<f64> {
        let pole = self.pole.normalize();
        let mut v = Vec::new();
        for (k, c) in &self.kinks {
            // cos θ·(k·p) ± sin θ·|k_t| = c  ⇔  cos(θ ∓ γ) = c with γ = atan2(|k_t|, k·p)
            let kp = k.dot(&pole).clamp(-1.0, 1.0);
            let kt = (1.0 - kp * kp).max(0.0).sqrt();
            let g = kt.atan2(kp);
            let a = c.clamp(-1.0, 1.0).acos();
            for th in [g + a, g - a, -g + a, -g - a] {
                if th > 0.0 && th < self.theta_max {
                    let t = self.t_of(th);
                    if t > 0.0 && t < 1.0 {
                        v.push(t);
                    }
                }
            }
        }
        // a mirror horizon touches the polar circle θ where |v_xy| sin 2θ = ±v_z cos 2θ:
        // 2θ = π/2 ± γ, γ ∈ [0, π/2) the view's polar angle (the other roots lie outside
        // 0 < 2θ < π)
        for w in &self.mirror_horizons {
            let g = w.xy().norm().atan2(w.z);
            for two in [FRAC_PI_2 + g, FRAC_PI_2 - g] {
                let th = 0.5 * two;
                if th > 0.0 && th < self.theta_max {
                    let t = self.t_of(th);
                    if t > 0.0 && t < 1.0 {
                        v.push(t);
                    }
                }
            }
        }
        v
    }

    /// Inner break points (in ψ) where the polar circle at θ crosses a kink circle.
    fn kink_psi_breaks(&self, th: f64, t1: &Vector3<f64>, t2: &Vector3<f64>) -> Vec<f64> {
        let pole = self.pole.normalize();
        let (st, ct) = th.sin_cos();
        let mut v = Vec::new();
        let mut crossings = Vec::new();
        for (k, c0) in &self.kinks {
            let kp = k.dot(&pole);
            let (kx, ky) = (k.dot(t1), k.dot(t2));
            let kt = (kx * kx + ky * ky).sqrt();
            if kt == 0.0 || st == 0.0 {
                continue;
            }
            let c = (c0 - ct * kp) / (st * kt);
            if !(-1.0..=1.0).contains(&c) {
                continue;
            }
            let beta = ky.atan2(kx);
            let d = c.acos();
            crossings.extend([beta + d, beta - d]);
        }
        for w in &self.mirror_horizons {
            // the pole is z, so (t1, t2) = (x, y): v_xy·(cos φ, sin φ) = −v_z cot 2θ
            let (kx, ky) = (w.dot(t1), w.dot(t2));
            let kt = (kx * kx + ky * ky).sqrt();
            let s2 = (2.0 * th).sin();
            if kt == 0.0 || s2 == 0.0 {
                continue;
            }
            let c = -w.z * (2.0 * th).cos() / (s2 * kt);
            if !(-1.0..=1.0).contains(&c) {
                continue;
            }
            let (beta, d) = (ky.atan2(kx), c.acos());
            crossings.extend([beta + d, beta - d]);
        }
        for phi in crossings {
            let dir = nalgebra::Vector2::new(phi.cos(), phi.sin());
            let psi = match self.stretch {
                None => phi,
                Some((major, ratio)) => {
                    let r = (th / self.scale).clamp(1.0, ratio);
                    let minor = nalgebra::Vector2::new(-major.y, major.x);
                    (r * dir.dot(&minor)).atan2(dir.dot(&major))
                }
            };
            v.push(psi.rem_euclid(2.0 * PI));
        }
        v
    }

    /// Tangent direction and dφ/dψ at azimuth parameter ψ and polar angle θ.
    fn azimuth(&self, th: f64, psi: f64) -> (nalgebra::Vector2<f64>, f64) {
        // the inner rule's ψ nodes recur at every outer node: remembered (`trig`)
        let (sp, cp) = super::trig::sin_cos(psi);
        match self.stretch {
            None => (nalgebra::Vector2::new(cp, sp), 1.0),
            Some((major, ratio)) => {
                let r = (th / self.scale).clamp(1.0, ratio);
                let minor = nalgebra::Vector2::new(-major.y, major.x);
                let v = major * (r * cp) + minor * sp;
                let n2 = r * r * cp * cp + sp * sp;
                (v / n2.sqrt(), r / n2)
            }
        }
    }

    /// θ(t) and dθ/dt of the radial substitution.
    pub fn theta(&self, t: f64) -> (f64, f64) {
        let c = 2.0 * self.theta_max / PI;
        let s = self.scale;
        let om = 1.0 - t;
        let th = if om <= 0.0 {
            self.theta_max
        } else {
            c * (s * t / om).atan()
        };
        let dth = c * s / (om * om + s * s * t * t);
        (th, dth)
    }
}

impl SphereRule {
    /// The direction at (t, φ) and the measure factor sin θ·dθ/dt of the substitution.
    pub fn point(&self, t: f64, psi: f64) -> (Vector3<f64>, f64) {
        let pole = self.pole.normalize();
        let (t1, t2) = frame(&pole);
        let (th, dth) = self.theta(t);
        let (st, ct) = th.sin_cos();
        let (a, dphi) = self.azimuth(th, psi);
        (
            (t1 * (st * a.x) + t2 * (st * a.y) + pole * ct).normalize(),
            st * dth * dphi,
        )
    }
}

/// ∫ f(ω) dω over the region described by `rule`, to tolerance `tol`.
pub fn integrate_sphere<F: Fn(&Vector3<f64>) -> f64 + Sync>(
    f: &F,
    rule: &SphereRule,
    tol: Tol,
) -> Estimate {
    integrate_sphere_by(
        &|d: &[Vector3<f64>; 15]| std::array::from_fn(|k| f(&d[k])),
        rule,
        tol,
    )
}

/// [`integrate_sphere`] with f taking four directions at a time (`crate::lanes`): each
/// inner G7–K15 segment's 15 directions go through it in four calls (the last with three
/// live lanes). The same nodes and sums, so the same bits where f's lanes are f's values
/// (`tests::lanes_integrate_as_one_direction_at_a_time`).
pub fn integrate_sphere_lanes<F: Fn(&Dirs) -> Lanes + Sync>(
    f: &F,
    rule: &SphereRule,
    tol: Tol,
) -> Estimate {
    integrate_sphere_by(&|d: &[Vector3<f64>; 15]| by_four(d, f), rule, tol)
}

/// The sphere quadrature given `f15`, f at the 15 directions of one inner segment.
fn integrate_sphere_by<N: Fn(&[Vector3<f64>; 15]) -> [f64; 15] + Sync>(
    f15: &N,
    rule: &SphereRule,
    tol: Tol,
) -> Estimate {
    let pole = rule.pole.normalize();
    let (t1, t2) = frame(&pole);
    let nphi = rule.phi_segments.max(1);
    let phi_breaks: Vec<f64> = (0..=nphi)
        .map(|k| 2.0 * PI * k as f64 / nphi as f64)
        .collect();
    let nt = rule.t_breaks + 1;
    // geometric panels in θ (θ = 4^j·scale up to θ_max): heavy-tailed lobes (GGX) spread
    // their mass over every scale between the lobe width and the horizon, and the
    // adaptive rule converges much faster from panels that already follow that spread
    let mut extra = rule.kink_t_breaks();
    let mut th = 0.25 * rule.scale;
    while th < rule.theta_max {
        extra.push(rule.t_of(th));
        th *= 4.0;
    }
    let t_breaks = merge_breaks((0..=nt).map(|k| k as f64 / nt as f64).collect(), extra);
    let inner_tol = Tol::new(
        tol.abs * 0.05,
        tol.rel * 0.05,
        (tol.max_evals / 50).max(2000),
    );
    let inner = |t: f64| -> Estimate {
        let (th, dth) = rule.theta(t);
        let (st, ct) = th.sin_cos();
        let w = st * dth;
        if w == 0.0 || !w.is_finite() {
            return Estimate {
                value: 0.0,
                error: 0.0,
                evals: 0,
                kind: super::estimate::ErrorKind::Quadrature,
                converged: true,
            };
        }
        // G7–K15 in ψ (as `gk15_breaks`), f at a segment's 15 directions in one call
        let g = |psis: &[f64; 15]| -> NodeValues {
            let at: [(Vector3<f64>, f64); 15] = std::array::from_fn(|k| {
                let (a, dphi) = rule.azimuth(th, psis[k]);
                let dir = (t1 * (st * a.x) + t2 * (st * a.y) + pole * ct).normalize();
                (dir, dphi)
            });
            let fv = f15(&at.map(|(d, _)| d));
            (std::array::from_fn(|k| fv[k] * w * at[k].1), [0.0; 15], 15)
        };
        if rule.kinks.is_empty() && rule.mirror_horizons.is_empty() {
            adaptive_batched(&g, &phi_breaks, inner_tol)
        } else {
            let b = merge_breaks(phi_breaks.clone(), rule.kink_psi_breaks(th, &t1, &t2));
            adaptive_batched(&g, &b, inner_tol)
        }
    };
    let eval = |xs: &[f64; 15]| {
        let res: Vec<Estimate> = xs.par_iter().map(|&t| inner(t)).collect();
        let mut v = [0.0; 15];
        let mut e = [0.0; 15];
        let mut n = 0;
        for (i, r) in res.iter().enumerate() {
            v[i] = r.value;
            e[i] = r.error;
            n += r.evals;
        }
        (v, e, n)
    };
    adaptive_batched(&eval, &t_breaks, tol)
}

/// Sorted union of `base` (which spans the interval) and interior `extra` points, with
/// near-duplicates (closer than 1e-12) removed.
fn merge_breaks(mut base: Vec<f64>, extra: Vec<f64>) -> Vec<f64> {
    let (lo, hi) = (base[0], *base.last().expect("non-empty"));
    base.extend(extra.into_iter().filter(|x| *x > lo && *x < hi));
    base.sort_by(|a, b| a.total_cmp(b));
    base.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    base
}

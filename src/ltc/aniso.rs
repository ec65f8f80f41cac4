//! Anisotropic GGX as an LTC target, and the general LTC form it needs.
//!
//! The lobe: the cosine-weighted GGX BRDF (height-correlated Smith G2, F = 1) with
//! roughness α_x along a tangent at azimuth φ from T1 and α_y across it, in the view's
//! frame (T1 = the view projected on the tangent plane, T2 = N × T1, N): the frame every
//! engine builds for its LTC lookup. The view lies in the xz-plane; the lobe is no
//! longer symmetric about it, so M⁻¹ has no zero pattern to rely on.
//!
//! Production form (`Inv7`): the clamped cosine is invariant under rotations about z,
//! so M⁻¹ ~ R_z(ψ)·M⁻¹ and M⁻¹ ~ s·M⁻¹ (s > 0). ψ is chosen to zero the entry (0, 1)
//! (of the two such ψ, the one that leaves (1, 1) positive) and s to make (1, 1) = 1:
//! M⁻¹ ∝ [[a, 0, c], [e, 1, g], [b, h, d]] (rows), seven numbers. With e = g = h = 0 it
//! is the isotropic production form (a, b, c, d), so the isotropic table is the start
//! of every fit.
//!
//! Symmetries, used by the table's layout: a mirror y → −y maps φ to −φ ≡ π − φ (the
//! tangent is a line) and M⁻¹ to S·M⁻¹·S with S = diag(1, −1, 1) (e, g, h change sign);
//! swapping α_x and α_y is a quarter turn of the tangent: (α_x, α_y, φ) ≡ (α_y, α_x,
//! φ + π/2). So φ ∈ [0, π/2] covers every case, and (α_y, α_x, π/2 − φ) =
//! S·(α_x, α_y, φ)·S.

use super::fit::{FixedNodes, Nodes, TargetSamples};
use super::polish::FIXED_POLISH_SCALE;
use super::target::LtcTarget;
use super::LtcDist;
use crate::error::{Error, Result};
use crate::integrate::mc::Strategy;
use crate::microfacet::sampling::VndfSampler;
use crate::microfacet::{Microsurface, Roughness};
use nalgebra::{Matrix2, Matrix3, Vector3};

type V3 = Vector3<f64>;

/// The general production inverse: (a, b, c, d, e, g, h) with M⁻¹ ∝
/// [[a, 0, c], [e, 1, g], [b, h, d]].
pub type Inv7 = [f64; 7];

/// M⁻¹ of a production inverse.
pub fn inverse_of(p: &Inv7) -> Matrix3<f64> {
    Matrix3::new(p[0], 0.0, p[2], p[4], 1.0, p[5], p[1], p[6], p[3])
}

/// The production inverse of any invertible M⁻¹ (`None` where (1, 1) vanishes after
/// the rotation or an entry is not finite).
pub fn production_of(minv: &Matrix3<f64>) -> Option<Inv7> {
    // rows 0 and 1 rotated by ψ: r0' = c r0 − s r1, r1' = s r0 + c r1; r0'[1] = 0
    let (x, y) = (minv[(0, 1)], minv[(1, 1)]);
    let r = x.hypot(y);
    if !(r > 0.0 && r.is_finite()) {
        return None;
    }
    // c·x − s·y = 0 with s·x + c·y = r > 0: (s, c) = (x, y)/r
    let (s, c) = (x / r, y / r);
    let mut m = *minv;
    for j in 0..3 {
        let (a0, a1) = (minv[(0, j)], minv[(1, j)]);
        m[(0, j)] = c * a0 - s * a1;
        m[(1, j)] = s * a0 + c * a1;
    }
    let m = m / m[(1, 1)];
    let p = [
        m[(0, 0)],
        m[(2, 0)],
        m[(0, 2)],
        m[(2, 2)],
        m[(1, 0)],
        m[(1, 2)],
        m[(2, 1)],
    ];
    p.iter().all(|v| v.is_finite()).then_some(p)
}

/// The binary16 storage of a production inverse that keeps its lobe: every entry rounded
/// to nearest, then, where that makes det M⁻¹ ≤ 0 (a mirrored lobe) or flips b's sign, b
/// set to 0 and d raised by binary16 steps until the determinant is positive (at most
/// 64 steps; `ltc::storage::keep_lobe` does the same for the isotropic form).
pub fn half_keeping_lobe(p: &Inv7) -> Inv7 {
    let r = |x: f64| half::f16::from_f64(x).to_f64();
    let mut q = p.map(r);
    let ok = |q: &Inv7| inverse_of(q).determinant() > 0.0 && q[1] * p[1] >= 0.0;
    if ok(&q) {
        return q;
    }
    if q[1] * p[1] < 0.0 {
        q[1] = 0.0;
    }
    for _ in 0..64 {
        if ok(&q) {
            break;
        }
        let h = half::f16::from_f64(q[3]);
        let bits = if h.to_f64() >= 0.0 && h.to_bits() & 0x8000 == 0 {
            h.to_bits() + 1
        } else if h.to_bits() == 0x8000 {
            1
        } else {
            h.to_bits() - 1
        };
        q[3] = half::f16::from_bits(bits).to_f64();
    }
    q
}

/// The mirror y → −y of a production inverse (S·M⁻¹·S): e, g and h change sign.
pub fn mirror_y(p: &Inv7) -> Inv7 {
    [p[0], p[1], p[2], p[3], -p[4], -p[5], -p[6]]
}

/// The anisotropic GGX lobe of one cell.
pub struct AnisoGgxTarget {
    pub ax: f64,
    pub ay: f64,
    /// Azimuth of the α_x tangent from T1 (radians).
    pub phi: f64,
    pub v: V3,
    surface: Microsurface,
    vndf: VndfSampler,
    seen: super::target::FixedView,
}

impl AnisoGgxTarget {
    /// θ in radians (clamped to ≤ 89.99°), α_x, α_y > 0 (typed errors otherwise).
    pub fn new(ax: f64, ay: f64, theta: f64, phi: f64) -> Result<AnisoGgxTarget> {
        let th = theta.clamp(0.0, crate::ltc::hemisphere::THETA_MAX_DEG.to_radians());
        let v = V3::new(th.sin(), 0.0, th.cos());
        let surface = Microsurface::ggx(Roughness::rotated(ax, ay, phi)?);
        Ok(AnisoGgxTarget {
            ax,
            ay,
            phi,
            v,
            surface,
            vndf: VndfSampler::new(surface, v)?,
            seen: super::target::FixedView::new(surface, v),
        })
    }
}

impl LtcTarget for AnisoGgxTarget {
    fn view(&self) -> V3 {
        self.v
    }
    fn eval(&self, l: &V3) -> (f64, f64) {
        self.seen.eval(l)
    }
    fn eval_lanes(
        &self,
        l: &crate::lanes::Dirs,
        live: [bool; crate::lanes::LANES],
    ) -> [(f64, f64); crate::lanes::LANES] {
        let (f, p) = self.seen.eval_lanes(l);
        std::array::from_fn(|i| if live[i] { (f[i], p[i]) } else { (0.0, 0.0) })
    }
    fn sample(&self, u: [f64; 2]) -> Option<V3> {
        let m = self.vndf.sample(u)?;
        let l = m * (2.0 * self.v.dot(&m)) - self.v;
        (l.z > 0.0).then_some(l)
    }
    fn width(&self) -> f64 {
        (self.ax * self.ay).sqrt()
    }
    /// By nested adaptive sphere quadrature in half-vector space (as the isotropic
    /// target), the polar grid stretched along the roughness ellipse.
    fn albedo(&self, tol: f64) -> (f64, f64, f64) {
        use crate::integrate::sphere::SphereRule;
        let (s, c) = self.phi.sin_cos();
        let r = Matrix2::new(c, -s, s, c);
        let cov = r * Matrix2::new(self.ax * self.ax, 0.0, 0.0, self.ay * self.ay) * r.transpose();
        let rule = SphereRule::from_covariance(V3::z(), cov, std::f64::consts::FRAC_PI_2);
        super::target::microfacet_albedo(&self.surface, &self.v, &rule, tol)
    }
    /// Half-vectors from the projected NDF's LTC (the roughness ellipse turned by φ),
    /// reflected about the view.
    fn chart(&self) -> super::chart::Chart {
        let (s, c) = self.phi.sin_cos();
        let rot = Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        super::chart::Chart::half_vector(
            rot * Matrix3::from_diagonal(&V3::new(self.ax, self.ay, 1.0)),
        )
    }
}

/// The relative L2 of a production inverse with amplitude `norm` against a target on the
/// n×n set (offset `off`), ∞ where singular.
pub fn rel_l2<T: LtcTarget + ?Sized>(t: &T, p: &Inv7, norm: f64, n: usize, off: f64) -> f64 {
    rel_l2_on(t, &TargetSamples::new(t, n, off), p, norm)
}

/// [`rel_l2`] on the target's samples `s` drawn beforehand.
fn rel_l2_on<T: LtcTarget + ?Sized>(t: &T, s: &TargetSamples, p: &Inv7, norm: f64) -> f64 {
    ltc_of(p)
        .map(|l| super::fit::metrics_on(t, s, &l, norm).1)
        .filter(|x| x.is_finite())
        .unwrap_or(f64::INFINITY)
}

/// The parameters the optimiser moves, relative to a start p₀: a = a₀e^{q₀}, d = d₀e^{q₁},
/// b = d₀q₂, c = a₀q₃, e = q₄, g = a₀q₅, h = d₀q₆ (each moves on its own scale).
fn from_q(q: &[f64], p0: &Inv7) -> Inv7 {
    let (a0, d0) = (p0[0].abs().max(1e-300), p0[3].abs().max(1e-300));
    [
        a0 * q[0].clamp(-30.0, 30.0).exp(),
        d0 * q[2],
        a0 * q[3],
        d0 * q[1].clamp(-30.0, 30.0).exp(),
        q[4],
        a0 * q[5],
        d0 * q[6],
    ]
}

/// What a trial is measured on: the training set's moving samples (the LTC half drawn
/// from each trial) or nodes drawn once from the start (`FixedNodes`).
enum Trials<'a> {
    Moving(&'a TargetSamples),
    Fixed(&'a FixedNodes),
}

struct Objective<'a, T: ?Sized> {
    t: &'a T,
    p0: Inv7,
    norm: f64,
    train: Trials<'a>,
}

impl<T: LtcTarget + ?Sized> argmin::core::CostFunction for Objective<'_, T> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, q: &Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
        if q.iter().any(|x| !x.is_finite()) {
            return Ok(1e30);
        }
        let p = from_q(q, &self.p0);
        let v = match self.train {
            Trials::Moving(s) => rel_l2_on(self.t, s, &p, self.norm),
            Trials::Fixed(nodes) => ltc_of(&p)
                .map(|l| nodes.metrics(&l, self.norm).1)
                .filter(|x| x.is_finite())
                .unwrap_or(f64::INFINITY),
        };
        Ok(if v.is_finite() { v } else { 1e30 })
    }
}

/// The LTC of a production inverse (`None` where singular).
fn ltc_of(p: &Inv7) -> Option<LtcDist> {
    inverse_of(p)
        .try_inverse()
        .and_then(|m| LtcDist::new(m).ok())
}

/// How one anisotropic cell is fitted: stratified samples per axis and technique, the
/// Nelder–Mead cap, what the trials are measured on, and the training set's strata
/// offset (`ltc::samples::Sets::drawn`; the published tables' is `TRAIN_OFFSET`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Route {
    pub samples: usize,
    pub iters: u64,
    /// `Nodes::Moving`: each trial draws the LTC half of its samples (the reference);
    /// `Nodes::Fixed`: the trials are measured on nodes drawn once from the start,
    /// `ltc::polish::FIXED_POLISH_SCALE`× the samples per axis, and the cell is fitted
    /// again on moving samples where the result fails `ltc::polish::fixed_fit_holds`.
    /// The fit has one stage, so `Nodes::FixedAll` is `Nodes::Fixed`.
    pub nodes: Nodes,
    pub train: f64,
}

/// Fit one cell's production inverse by Nelder–Mead (argmin) on the relative L2 (n×n
/// stratified samples per technique, offset ½) from `start` (the isotropic table's entries
/// at √(α_x α_y), say), kept only if a separate validation set ((n + 7)², offset 0.37)
/// agrees; returns the inverse and the iterations. The reference route of
/// [`fit_cell_route`].
pub fn fit_cell<T: LtcTarget + ?Sized>(
    t: &T,
    start: &Inv7,
    norm: f64,
    n: usize,
    max_iters: u64,
) -> Result<(Inv7, u64)> {
    let route = Route {
        samples: n,
        iters: max_iters,
        nodes: Nodes::Moving,
        train: super::fit::TRAIN_OFFSET,
    };
    fit_cell_route(t, start, norm, route)
}

/// [`fit_cell`] by `route`: the same Nelder–Mead from `start` on the training set drawn at
/// `route.train`, its trials on moving samples or on fixed nodes, kept only where the
/// validation set's relative L2 (moving samples) is below the start's. A singular start
/// keeps moving samples.
pub fn fit_cell_route<T: LtcTarget + ?Sized>(
    t: &T,
    start: &Inv7,
    norm: f64,
    route: Route,
) -> Result<(Inv7, u64)> {
    let sets = super::fit::Sets::drawn(t, route.samples, route.train);
    let val = |p: &Inv7| rel_l2_on(t, &sets.val, p, norm);
    let moving = || nelder_mead(t, start, norm, Trials::Moving(&sets.train), route.iters);
    // the fixed route's result, with its validation figure, where it holds
    let fixed = match (route.nodes, ltc_of(start)) {
        (Nodes::Moving, _) | (_, None) => None,
        (Nodes::Fixed | Nodes::FixedAll, Some(from)) => {
            let wide = TargetSamples::new(t, FIXED_POLISH_SCALE * route.samples, route.train);
            let nodes = FixedNodes::new(t, &wide, &from);
            let (p, it) = nelder_mead(t, start, norm, Trials::Fixed(&nodes), route.iters)?;
            let at_p = val(&p);
            let holds = ltc_of(&p).is_some_and(|to| {
                super::polish::fixed_fit_holds(t, &sets.val, (&from, &to), norm, at_p)
            });
            Some((p, it, at_p, holds))
        }
    };
    let (p, iters, at_p) = match fixed {
        Some((p, it, at_p, true)) => (p, it, Some(at_p)),
        Some((_, it, _, false)) => {
            let (p, more) = moving()?;
            (p, it + more, None)
        }
        None => {
            let (p, it) = moving()?;
            (p, it, None)
        }
    };
    Ok(
        if p.iter().all(|x| x.is_finite()) && at_p.unwrap_or_else(|| val(&p)) < val(start) {
            (p, iters)
        } else {
            (*start, iters)
        },
    )
}

/// Nelder–Mead (argmin) from `start` on the trials' relative L2; the best parameters as a
/// production inverse and the iterations.
fn nelder_mead<T: LtcTarget + ?Sized>(
    t: &T,
    start: &Inv7,
    norm: f64,
    train: Trials<'_>,
    max_iters: u64,
) -> Result<(Inv7, u64)> {
    use argmin::core::{Executor, State};
    use argmin::solver::neldermead::NelderMead;
    let err = |e: argmin::core::Error| Error::InvalidArgument(format!("anisotropic LTC fit: {e}"));
    let (a0, d0) = (start[0].abs().max(1e-300), start[3].abs().max(1e-300));
    let q0 = vec![
        0.0,
        0.0,
        start[1] / d0,
        start[2] / a0,
        start[4],
        start[5] / a0,
        start[6] / d0,
    ];
    let mut simplex = vec![q0.clone()];
    for k in 0..7 {
        let mut q = q0.clone();
        q[k] += 0.05;
        simplex.push(q);
    }
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(1e-10)
        .map_err(err)?;
    let obj = Objective {
        t,
        p0: *start,
        norm,
        train,
    };
    let res = Executor::new(obj, solver)
        .configure(|s| s.max_iters(max_iters))
        .run()
        .map_err(err)?;
    let iters = res.state().get_iter();
    let q = res.state().get_best_param().cloned().unwrap_or(q0);
    Ok((from_q(&q, start), iters))
}

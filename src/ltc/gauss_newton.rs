//! A Levenberg–Marquardt fit of one LTC cell on fixed nodes: the fast route beside the
//! Nelder–Mead reference of [`super::fit`].
//!
//! The reference fitter's objective draws half of its samples from the LTC being fitted,
//! so every trial point sees a different sample set: the objective is a noisy black box
//! and Nelder–Mead needs ~200 iterations of 2·n² evaluations. Here the nodes are drawn
//! once — n×n stratified points from the target's own sampler and n×n from the *start*
//! LTC — with fixed balance weights w_k = 1/(p_start(l_k) + p_f(l_k)). The objective
//!
//!   E(p) = Σ_k w_k (f(l_k) − norm·D_p(l_k))² / Σ_k w_k f(l_k)²,
//!
//! the square of the relative L2 ‖f − norm·D_p‖/‖f‖ estimated on those nodes, is then a
//! smooth function of p = (ln m11, ln m22, m13/m11, φ) (the parameters of
//! [`super::fit::fit_cell`], `super::params`; D_p is the LTC density of seed 000 / Heitz et al. 2016 Eq 1
//! with M = [X Y Z]·[[m11, 0, m13], [0, m22, 0], [0, 0, 1]], Z turned by φ about Y), and
//! Levenberg–Marquardt on the residuals r_k = √w_k (f_k − norm·D_p(l_k)) converges in a
//! handful of iterations. The Jacobian is by forward differences (four more residual
//! sweeps per iteration; f is evaluated once per node). After the first convergence the
//! nodes are redrawn from the fitted LTC and the fit runs once more, so the final nodes
//! follow the final lobe.

use super::params::{matrix, params_to_m, turn};
use super::target::LtcTarget;
use super::LtcDist;
use crate::error::Result;
use crate::integrate::mc::Strategy;
use nalgebra::{Matrix4, Vector3, Vector4};

type V3 = Vector3<f64>;

/// The fixed nodes of one pass: direction, target value and balance weight (also the
/// nodes of a compact table's lobe fit, `ltc::compact_fit`).
pub(crate) struct Nodes {
    pub(crate) l: Vec<V3>,
    pub(crate) f: Vec<f64>,
    pub(crate) w: Vec<f64>,
    /// Σ w f²: the normaliser of the relative L2.
    pub(crate) f2: f64,
}

impl Nodes {
    /// n×n stratified points (offset ½) from the start LTC and from the target.
    pub(crate) fn draw<T: LtcTarget + ?Sized>(t: &T, start: &LtcDist, n: usize) -> Nodes {
        Nodes::balance(t, start, &[], n, 1.0)
    }

    /// n×n stratified points (offset ½, the same uniforms) from the start LTC, the target
    /// and each technique of `extra`, in that order, weighted 1/(scale·Σ p) with the sum
    /// of every technique's density (start, target, extra) at the point: with scale = n²
    /// the weighted sum over the nodes is the balance estimator of an integral.
    pub(crate) fn balance<T: LtcTarget + ?Sized>(
        t: &T,
        start: &LtcDist,
        extra: &[&dyn Strategy<V3>],
        n: usize,
        scale: f64,
    ) -> Nodes {
        let k = (2 + extra.len()) * n * n;
        let mut nodes = Nodes {
            l: Vec::with_capacity(k),
            f: Vec::with_capacity(k),
            w: Vec::with_capacity(k),
            f2: 0.0,
        };
        for i in 0..n {
            for j in 0..n {
                let u = [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
                let drawn = [start.sample(u), t.sample(u)]
                    .into_iter()
                    .chain(extra.iter().map(|s| s.sample(u)));
                for l in drawn.flatten() {
                    let (f, pb) = t.eval(&l);
                    let q = extra.iter().fold(start.eval(&l) + pb, |q, s| q + s.pdf(&l)) * scale;
                    if q > 0.0 && f.is_finite() && (1.0 / q).is_finite() {
                        nodes.l.push(l);
                        nodes.f.push(f);
                        nodes.w.push(1.0 / q);
                        nodes.f2 += f * f / q;
                    }
                }
            }
        }
        nodes
    }
}

/// The LTC of parameters p about the axis `z` (φ = p[3] turns it; clamped as the
/// reference fitter clamps it), or `None` where M is singular.
fn ltc_of(z: &V3, p: &[f64; 4]) -> Option<LtcDist> {
    if p.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let (m11, m22, m13) = params_to_m(p);
    LtcDist::new(matrix(m11, m22, m13, &turn(z, p[3].clamp(-0.5, 0.5)))).ok()
}

/// The residuals r_k = √w_k (f_k − norm·D_p(l_k)) / √(Σ w f²), so |r|² = E(p).
fn residuals(nodes: &Nodes, ltc: &LtcDist, norm: f64, out: &mut Vec<f64>) {
    out.clear();
    let s = 1.0 / nodes.f2.max(1e-300).sqrt();
    out.extend(
        nodes
            .l
            .iter()
            .zip(&nodes.f)
            .zip(&nodes.w)
            .map(|((l, f), w)| w.sqrt() * (f - norm * ltc.eval(l)) * s),
    );
}

fn cost(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum()
}

/// Levenberg–Marquardt from `p0` on the residuals `eval` writes (returning their squared
/// sum, ∞ where p is outside the model); the first `free` parameters move (3: φ held, 4:
/// all). The Jacobian is by forward differences, each step scaled to its parameter.
/// Returns the parameters, their cost and the iterations. Shared by the cell fit here
/// and the bilinear pass (`ltc::smooth`).
pub(crate) fn levenberg_marquardt(
    eval: impl Fn(&[f64; 4], &mut Vec<f64>) -> f64,
    p0: [f64; 4],
    free: usize,
    max_iters: usize,
) -> ([f64; 4], f64, usize) {
    let mut r = Vec::new();
    let mut p = p0;
    let mut c = eval(&p, &mut r);
    if !c.is_finite() {
        return (p0, c, 0);
    }
    let mut lambda = 1e-3;
    let mut rk = Vec::new();
    let mut jac: Vec<Vec<f64>> = vec![Vec::new(); free];
    let mut iters = 0;
    while iters < max_iters {
        iters += 1;
        // forward-difference Jacobian, step scaled to each parameter
        for (k, col) in jac.iter_mut().enumerate() {
            let h = 1e-6 * p[k].abs().max(1e-2);
            let mut q = p;
            q[k] += h;
            if eval(&q, &mut rk).is_finite() {
                col.clear();
                col.extend(rk.iter().zip(&r).map(|(a, b)| (a - b) / h));
            } else {
                col.clear();
                col.resize(r.len(), 0.0);
            }
        }
        let mut a = Matrix4::<f64>::identity();
        let mut g = Vector4::<f64>::zeros();
        for i in 0..free {
            g[i] = jac[i].iter().zip(&r).map(|(x, y)| x * y).sum();
            for j in 0..free {
                a[(i, j)] = jac[i].iter().zip(&jac[j]).map(|(x, y)| x * y).sum();
            }
        }
        // damp until a step lowers the cost (or the damping says the step is nil)
        let mut improved = false;
        while lambda < 1e12 {
            let mut m = a;
            for i in 0..free {
                m[(i, i)] = a[(i, i)] * (1.0 + lambda) + 1e-300;
            }
            let Some(d) = m.lu().solve(&(-g)) else {
                lambda *= 10.0;
                continue;
            };
            let mut q = p;
            for i in 0..free {
                q[i] += d[i];
            }
            let cq = eval(&q, &mut rk);
            if cq < c {
                let gain = (c - cq) / c.max(1e-300);
                p = q;
                c = cq;
                std::mem::swap(&mut r, &mut rk);
                lambda = (lambda / 3.0).max(1e-9);
                improved = gain > 1e-10;
                break;
            }
            lambda *= 4.0;
        }
        if !improved {
            break;
        }
    }
    (p, c, iters)
}

/// What one Levenberg–Marquardt cell fit returns.
#[derive(Clone, Copy, Debug)]
pub struct GnFit {
    /// (ln m11, ln m22, m13/m11, φ), as [`super::fit::fit_cell`] returns them.
    pub params: [f64; 4],
    /// The squared relative L2 on the final nodes.
    pub cost: f64,
    /// Levenberg–Marquardt iterations over both passes.
    pub iters: usize,
}

/// Fit one cell from `p0` = (ln m11, ln m22, m13/m11, φ) about the mean direction `z`
/// with amplitude `norm` (the albedo), on 2·n² fixed nodes per pass, two passes. At
/// normal incidence (the lobe symmetric about z) φ stays 0, and so does it where
/// `hold_turn` (at `p0`'s).
pub fn fit_cell_lm<T: LtcTarget + ?Sized>(
    t: &T,
    z: &V3,
    norm: f64,
    p0: &[f64; 4],
    n: usize,
    max_iters: usize,
    hold_turn: bool,
) -> Result<GnFit> {
    if n == 0 || !(norm.is_finite() && norm > 0.0) {
        return Err(crate::error::Error::InvalidArgument(format!(
            "LTC fit: {n}² nodes and amplitude {norm} (need n ≥ 1 and a finite, positive albedo)"
        )));
    }
    let symmetric = t.view().x.abs() <= 1e-12;
    let free = if symmetric || hold_turn { 3 } else { 4 };
    let mut p = *p0;
    if symmetric {
        p[3] = 0.0;
    }
    let mut total = 0;
    let mut c = f64::INFINITY;
    for _pass in 0..2 {
        let Some(start) = ltc_of(z, &p) else {
            return Err(crate::error::Error::InvalidArgument(
                "LTC fit: the start is singular".into(),
            ));
        };
        let nodes = Nodes::draw(t, &start, n);
        if !(nodes.f2 > 0.0 && nodes.f2.is_finite()) {
            return Err(crate::error::Error::InvalidArgument(
                "LTC fit: the target vanishes (or overflows) on every node".into(),
            ));
        }
        let eval = |p: &[f64; 4], r: &mut Vec<f64>| -> f64 {
            match ltc_of(z, p) {
                Some(ltc) => {
                    residuals(&nodes, &ltc, norm, r);
                    cost(r)
                }
                None => f64::INFINITY,
            }
        };
        let (q, cq, it) = levenberg_marquardt(eval, p, free, max_iters);
        total += it;
        p = q;
        c = cq;
    }
    Ok(GnFit {
        params: p,
        cost: c,
        iters: total,
    })
}

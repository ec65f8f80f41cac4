//! The fit objective of an LTC cell (`ltc::fit`): one metric of the LTC with parameters
//! p = (ln m11, ln m22, m13/m11[, φ]) against the target, on a cell's moving sample sets
//! or on fixed nodes, as argmin's cost function (and central-difference gradient).

use crate::ltc::params::{matrix, params_to_m, turn};
use crate::ltc::samples::{metrics_on, FixedNodes, Sets, TargetSamples};
use crate::ltc::target::LtcTarget;
use crate::ltc::LtcDist;
use nalgebra::Vector3;
use serde::Serialize;

type V3 = Vector3<f64>;

/// Which metric drives the fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Metric {
    Cubic,
    L2,
}

/// The LTC of parameters p = (ln m11, ln m22, m13/m11[, φ]) about the axis `z` turned by
/// φ (clamped to ±0.5, as the fit evaluates it); `None` where M is singular.
pub fn ltc_at(z: &V3, p: &[f64]) -> Option<LtcDist> {
    let (m11, m22, m13) = params_to_m(p);
    let z = if p.len() > 3 {
        turn(z, p[3].clamp(-0.5, 0.5))
    } else {
        *z
    };
    LtcDist::new(matrix(m11, m22, m13, &z)).ok()
}

/// The fit objective: one metric of the LTC with parameters p = (ln m11, ln m22,
/// m13/m11[, φ]) against the target, on the training set (offset 0.5, n×n) or the
/// validation set (offset 0.37, (n + 7)²). ∞ for non-finite parameters or a singular M.
pub(super) struct Objective<'a, T: ?Sized> {
    pub(super) t: &'a T,
    pub(super) z: V3,
    pub(super) norm: f64,
    /// The target's samples of the set (training or validation).
    pub(super) set: &'a TargetSamples,
    pub(super) metric: Metric,
    /// Fixed nodes in place of `set`'s moving ones (`FixedNodes`).
    pub(super) fixed: Option<&'a FixedNodes>,
}

impl<'a, T: LtcTarget + ?Sized> Objective<'a, T> {
    /// On the training or the validation set of `sets`; on the matching one of a stage's
    /// fixed `nodes` (training, validation) where given.
    pub(super) fn on(
        t: &'a T,
        z: V3,
        norm: f64,
        metric: Metric,
        sets: &'a Sets,
        nodes: Option<&'a (FixedNodes, FixedNodes)>,
        validation: bool,
    ) -> Self {
        Objective {
            t,
            z,
            norm,
            set: if validation { &sets.val } else { &sets.train },
            metric,
            fixed: nodes.map(|n| if validation { &n.1 } else { &n.0 }),
        }
    }

    pub(super) fn value(&self, p: &[f64]) -> f64 {
        if p.iter().any(|x| !x.is_finite()) {
            return f64::INFINITY;
        }
        match ltc_at(&self.z, p) {
            Some(ltc) => {
                let (c, l2) = match self.fixed {
                    Some(fx) => fx.metrics(&ltc, self.norm),
                    None => metrics_on(self.t, self.set, &ltc, self.norm),
                };
                if self.metric == Metric::Cubic {
                    c
                } else {
                    l2
                }
            }
            None => f64::INFINITY,
        }
    }
    /// The value the optimisers see: finite (1e30 stands in for ∞).
    pub(super) fn bounded(&self, p: &[f64]) -> f64 {
        let v = self.value(p);
        if v.is_finite() {
            v
        } else {
            1e30
        }
    }
}

impl<T: LtcTarget + ?Sized> argmin::core::CostFunction for Objective<'_, T> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
        Ok(self.bounded(p))
    }
}

impl<T: LtcTarget + ?Sized> argmin::core::Gradient for Objective<'_, T> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;
    /// Central differences, step 1e-5.
    fn gradient(&self, p: &Vec<f64>) -> std::result::Result<Vec<f64>, argmin::core::Error> {
        let h = 1e-5;
        Ok((0..p.len())
            .map(|k| {
                let (mut a, mut b) = (p.clone(), p.clone());
                a[k] += h;
                b[k] -= h;
                (self.bounded(&a) - self.bounded(&b)) / (2.0 * h)
            })
            .collect())
    }
}

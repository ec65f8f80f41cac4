//! A chart of the sphere in which a lobe is a smooth, broad function: a linearly
//! transformed upper hemisphere (directions, or half-vectors reflected about the view).
//! `ltc::lobe_error` integrates on them; `ltc::target` names each target's own.

use crate::lanes::{map, Dirs, Lanes, LANES};
use nalgebra::{Matrix3, Vector3};

type V3 = Vector3<f64>;

/// A linearly transformed hemisphere: ω (z ≥ 0) ↦ x = Mω/|Mω|, then, for a half-vector
/// chart, l = 2(v·x)x − v (the reflection of the view about x).
#[derive(Clone, Copy, Debug)]
pub struct Chart {
    pub m: Matrix3<f64>,
    pub half_vector: bool,
}

impl Chart {
    /// A chart of directions l = Mω/|Mω|.
    pub fn direction(m: Matrix3<f64>) -> Chart {
        Chart {
            m,
            half_vector: false,
        }
    }
    /// A chart of half-vectors h = Mω/|Mω|, mapped to l by reflecting the view.
    pub fn half_vector(m: Matrix3<f64>) -> Chart {
        Chart {
            m,
            half_vector: true,
        }
    }
    /// l at ω and the density ratio dl/dω (`None` where the chart does not reach a
    /// direction: a half-vector facing away from the view).
    pub(crate) fn map(&self, w: &V3, det: f64, v: &V3) -> Option<(V3, f64)> {
        let x = self.m * w;
        let n = x.norm();
        if !(n > 0.0 && n.is_finite()) {
            return None;
        }
        let x = x / n;
        let j = det / (n * n * n);
        if !self.half_vector {
            return Some((x, j));
        }
        let vx = v.dot(&x);
        if vx <= 0.0 {
            return None;
        }
        Some((x * (2.0 * vx) - v, j * 4.0 * vx))
    }

    /// [`Self::map`] of four ω (`lanes`, each lane with `map`'s bits): l, dl/dω and
    /// whether the chart reaches the lane (`map`'s `Some`).
    pub(crate) fn map_lanes(&self, w: &Dirs, det: f64, v: &V3) -> (Dirs, Lanes, [bool; LANES]) {
        let x = w.times(&self.m);
        let n = x.norm();
        let reach: [bool; LANES] = std::array::from_fn(|i| n[i] > 0.0 && n[i].is_finite());
        let x = x.over(&n);
        let j = map(|i| det / (n[i] * n[i] * n[i]));
        if !self.half_vector {
            return (x, j, reach);
        }
        let vx = map(|i| v.x * x.x[i] + v.y * x.y[i] + v.z * x.z[i]);
        let l = Dirs {
            x: map(|i| x.x[i] * (2.0 * vx[i]) - v.x),
            y: map(|i| x.y[i] * (2.0 * vx[i]) - v.y),
            z: map(|i| x.z[i] * (2.0 * vx[i]) - v.z),
        };
        let j = map(|i| j[i] * 4.0 * vx[i]);
        (l, j, std::array::from_fn(|i| reach[i] && !(vx[i] <= 0.0)))
    }
}

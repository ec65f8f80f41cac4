//! The held-out judge's integrand (`ltc::lobe_error`) at one node of its charts or at
//! four: where the node lands, the target's value there, every candidate's γ and the
//! balance weight of the node's chart. The four-node form evaluates the target and each
//! candidate four directions at a time (`lanes`), each lane with the one-node form's bits.

use crate::integrate::cubature::SinCosMemo;
use crate::lanes::{map, Dirs, Lanes, LANES};
use crate::ltc::chart::Chart;
use crate::ltc::target::LtcTarget;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::{FRAC_PI_2, PI};

type V3 = Vector3<f64>;

/// One LTC judged against a target: g = amp·γ_M. `chart`: whether its own lobe gets a
/// chart (give one to every candidate that can put its mass where the target has none;
/// near-copies of a charted candidate — the same table rounded — need none).
#[derive(Clone, Copy, Debug)]
pub struct Candidate {
    pub m: Matrix3<f64>,
    pub amp: f64,
    pub chart: bool,
}

/// An LTC prepared for evaluation: M⁻¹ and |det M⁻¹|.
pub(crate) struct Prepared {
    pub(crate) m: Matrix3<f64>,
    m_inv: Matrix3<f64>,
    det_inv: f64,
    amp: f64,
}

impl Prepared {
    pub(crate) fn new(c: &Candidate) -> Option<Prepared> {
        let m_inv = c.m.try_inverse()?;
        let det_inv = m_inv.determinant().abs();
        (det_inv.is_finite()
            && det_inv > 0.0
            && c.amp.is_finite()
            && c.m.iter().all(|x| x.is_finite()))
        .then_some(Prepared {
            m: c.m,
            m_inv,
            det_inv,
            amp: c.amp,
        })
    }
    /// γ_M(l) (seed 000 Eq 1).
    fn gamma(&self, l: &V3) -> f64 {
        let w = self.m_inv * l;
        let n = w.norm();
        if w.z <= 0.0 || n == 0.0 {
            0.0
        } else {
            w.z / n / PI * self.det_inv / (n * n * n)
        }
    }
    /// [`Self::gamma`] of four directions (`lanes`: each lane's bits are `gamma`'s).
    fn gamma_lanes(&self, l: &Dirs) -> Lanes {
        let w = l.times(&self.m_inv);
        let n = w.norm();
        map(|i| {
            if w.z[i] <= 0.0 || n[i] == 0.0 {
                0.0
            } else {
                w.z[i] / n[i] / PI * self.det_inv / (n[i] * n[i] * n[i])
            }
        })
    }
}

/// The target as the judge reads it: its value at a direction, and at four (each lane
/// with the bits of one; by default one at a time).
pub trait JudgedValue: Sync {
    fn value(&self, l: &V3) -> f64;
    fn values(&self, l: &Dirs, live: [bool; LANES]) -> Lanes {
        map(|i| if live[i] { self.value(&l.get(i)) } else { 0.0 })
    }
}

/// A target's value f(l) = `eval(l).0`, four at a time through its `eval_lanes`.
pub struct TargetValue<'a, T: ?Sized>(pub &'a T);

impl<T: LtcTarget + ?Sized> JudgedValue for TargetValue<'_, T> {
    fn value(&self, l: &V3) -> f64 {
        self.0.eval(l).0
    }
    fn values(&self, l: &Dirs, live: [bool; LANES]) -> Lanes {
        let e = self.0.eval_lanes(l, live);
        map(|i| e[i].0)
    }
}

/// Any function of the direction, one at a time.
pub struct FnValue<F>(pub F);

impl<F: Fn(&V3) -> f64 + Sync> JudgedValue for FnValue<F> {
    fn value(&self, l: &V3) -> f64 {
        (self.0)(l)
    }
}

/// The judge's integrand: at a node (s, φ) of the charts laid side by side, the direction
/// l of chart k = ⌊s⌋ and the balance weight of that chart; then ∫f², ∫f and, per live
/// candidate, ∫(f − g)² and ∫|f − g|.
pub(crate) struct Integrand<'a> {
    pub(crate) f: &'a dyn JudgedValue,
    pub(crate) albedo: f64,
    pub(crate) v: &'a V3,
    /// The target's chart, then each charted candidate's (index into `live`), each with
    /// its |det|.
    pub(crate) charts: Vec<(Chart, f64, Option<usize>)>,
    pub(crate) live: Vec<&'a Prepared>,
}

/// Where a node lands: l, its chart k, the chart's density ratio and sin θ of the node.
struct Place {
    l: V3,
    k: usize,
    j: f64,
    st: f64,
}

impl Integrand<'_> {
    fn place(&self, x: f64, phi: f64, memo: &mut (SinCosMemo, SinCosMemo)) -> Option<Place> {
        let k = (x.floor() as usize).min(self.charts.len() - 1);
        let s = x - k as f64;
        let (chart, det, _) = &self.charts[k];
        let th = s * FRAC_PI_2;
        let (st, ct) = memo.0.get(th);
        let (sp, cp) = memo.1.get(phi);
        let w = V3::new(st * cp, st * sp, ct);
        let (l, j) = chart.map(&w, *det, self.v)?;
        Some(Place { l, k, j, st })
    }
    /// [`Self::place`] of the first `live` of four nodes: where they share a chart (every
    /// node of a panel does) the chart maps the four at a time (`Chart::map_lanes`).
    fn places(
        &self,
        xs: &Lanes,
        ys: &Lanes,
        live: usize,
        memo: &mut (SinCosMemo, SinCosMemo),
    ) -> [Option<Place>; LANES] {
        let ks: [usize; LANES] =
            std::array::from_fn(|i| (xs[i].floor() as usize).min(self.charts.len() - 1));
        if ks[1..live].iter().any(|&k| k != ks[0]) {
            return std::array::from_fn(|i| {
                if i < live {
                    self.place(xs[i], ys[i], memo)
                } else {
                    None
                }
            });
        }
        let k = ks[0];
        let (chart, det, _) = &self.charts[k];
        let mut w = Dirs::default();
        let mut st = [0.0; LANES];
        for i in 0..live {
            let s = xs[i] - k as f64;
            let th = s * FRAC_PI_2;
            let (sti, ct) = memo.0.get(th);
            let (sp, cp) = memo.1.get(ys[i]);
            (w.x[i], w.y[i], w.z[i], st[i]) = (sti * cp, sti * sp, ct, sti);
        }
        let (l, j, reach) = chart.map_lanes(&w, *det, self.v);
        std::array::from_fn(|i| {
            (i < live && reach[i]).then(|| Place {
                l: l.get(i),
                k,
                j: j[i],
                st: st[i],
            })
        })
    }

    /// The components at a placed node with f(l) = `fv` and the live candidates' γ(l).
    fn write(&self, p: &Place, fv: f64, gs: &[f64], out: &mut impl FnMut(usize, f64)) {
        // the balance partition over the charts' densities
        let own = |c: &(Chart, f64, Option<usize>)| match c.2 {
            None => fv / self.albedo,
            Some(q) => gs[q],
        };
        let total: f64 = self.charts.iter().map(own).sum();
        if !(total > 0.0) {
            return;
        }
        let weight = own(&self.charts[p.k]) / total * p.j * p.st * FRAC_PI_2;
        out(0, fv * fv * weight);
        out(1, fv * weight);
        for (q, c) in self.live.iter().enumerate() {
            let d = fv - c.amp * gs[q];
            out(2 + 2 * q, d * d * weight);
            out(3 + 2 * q, d.abs() * weight);
        }
    }
    /// One node: the reference the four-node form is checked against.
    pub(crate) fn node(
        &self,
        x: f64,
        phi: f64,
        memo: &mut (SinCosMemo, SinCosMemo),
        out: &mut [f64],
    ) {
        let Some(p) = self.place(x, phi, memo) else {
            return;
        };
        let fv = self.f.value(&p.l);
        let gs: Vec<f64> = self.live.iter().map(|c| c.gamma(&p.l)).collect();
        self.write(&p, fv, &gs, &mut |c, x| out[c] = x);
    }
    /// Four nodes (the first `live`), each lane with the bits of [`Self::node`]: the target
    /// and every candidate evaluated four directions at a time.
    pub(crate) fn nodes(
        &self,
        xs: &Lanes,
        ys: &Lanes,
        live: usize,
        memo: &mut (SinCosMemo, SinCosMemo),
        out: &mut [Lanes],
    ) {
        let places = self.places(xs, ys, live, memo);
        let at: [V3; LANES] =
            std::array::from_fn(|i| places[i].as_ref().map_or_else(V3::z, |p| p.l));
        let dirs = Dirs::of(&at);
        let fv = self
            .f
            .values(&dirs, std::array::from_fn(|i| places[i].is_some()));
        // on the stack for up to 16 candidates (a table's judge has at most 6)
        let nc = self.live.len();
        let (mut gs_s, mut gs_h) = ([[0.0; LANES]; 16], Vec::new());
        let gs: &mut [Lanes] = if nc <= 16 {
            &mut gs_s[..nc]
        } else {
            gs_h.resize(nc, [0.0; LANES]);
            &mut gs_h
        };
        for (g, c) in gs.iter_mut().zip(&self.live) {
            *g = c.gamma_lanes(&dirs);
        }
        let (mut g_s, mut g_h) = ([0.0; 16], Vec::new());
        let g: &mut [f64] = if nc <= 16 {
            &mut g_s[..nc]
        } else {
            g_h.resize(nc, 0.0);
            &mut g_h
        };
        for (i, p) in places.iter().enumerate() {
            if let Some(p) = p {
                g.iter_mut().zip(gs.iter()).for_each(|(x, l)| *x = l[i]);
                self.write(p, fv[i], g, &mut |c, x| out[c][i] = x);
            }
        }
    }
}

//! The held-out error of an LTC against the lobe it stands for, as converged integrals
//! with their own error bars.
//!
//! For a target f (cosine-weighted BRDF, zero below the horizon) and a candidate
//! g = c·γ_M (an LTC density γ_M, seed 000 Eq 1, with amplitude c) the figures are
//!
//! - relative L2 = √(∫(f − g)² / ∫f²) over the whole sphere (an LTC's mass below the
//!   horizon is error: a shader clips it away);
//! - relative L1 = ∫|f − g| / ∫f.
//!
//! Both are ratios of four integrals, each computed by deterministic adaptive cubature
//! (`integrate::cubature`: K15 ⊗ K15 panels with the G7 ⊗ G7 rule on the same panels as
//! the coarse resolution, the estimate a multiple of their difference) until the interval
//! that the four integrals' errors put around each ratio is below `tol`. The error bar is
//! that interval's half-width: no sampling, so no ratio of noisy sums and no bias.
//! tests/lobe_error.rs checks figure and bar against an independent product rule.
//!
//! The sphere is covered by charts, each a linearly transformed upper hemisphere in
//! which one lobe is a smooth, broad function: the target's (`LtcTarget::chart`: for
//! microfacet lobes the projected NDF's LTC in half-vector space followed by the
//! reflection, where f becomes nearly a cosine at every roughness, α = 1e-5 included)
//! and each charted candidate's own (ω ↦ Mω/|Mω|, where γ_M is the clamped cosine ω_z/π
//! exactly). A partition of unity w_k = p_k/Σp (p = f̂ = f/∫f for the target's chart, γ_M
//! for a candidate's) splits every integrand between the charts — the balance heuristic
//! of MIS, with quadrature in place of sampling — so each chart integrates the part near
//! its own lobe and none has to resolve another's peak. The charts lie side by side
//! (s ∈ [k, k + 1) is chart k) in one adaptive cubature, and every candidate of a cell
//! (the table in f64, f32 and binary16, a shipped table…) is judged on the same panels:
//! f is evaluated once per node for all of them.

use crate::integrate::cubature::{
    cubature, cubature_lanes, SinCosMemo, SAFETY_KINKED, SAFETY_SMOOTH,
};
use crate::lanes::Lanes;
pub use crate::ltc::chart::Chart;
pub use crate::ltc::lobe_nodes::{Candidate, FnValue, JudgedValue, TargetValue};
use crate::ltc::lobe_nodes::{Integrand, Prepared};
use crate::ltc::target::LtcTarget;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

type V3 = Vector3<f64>;

// A held-out figure is a `Figure<Quad>`: the value and the half-width of the interval its
// integrals' errors allow.
use crate::integrate::{Figure, Quad};

/// The held-out error of one LTC against its target.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LobeError {
    /// ‖f − g‖₂ / ‖f‖₂.
    pub l2: Figure<Quad>,
    /// ∫|f − g| / ∫f.
    pub l1: Figure<Quad>,
    /// Integrand evaluations spent.
    pub evals: u64,
    /// Whether both error bars met the tolerance within the budget.
    pub converged: bool,
}

/// What the cubature must reach: the relative L2's error bar ≤ max(rel·value, abs), the
/// relative L1's ≤ max(rel_l1·value, abs).
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    pub rel: f64,
    /// The relative L1's own relative tolerance. |f − g| has kinks where f = g, so its
    /// integral converges far more slowly than the others': at the L2's tolerance it sets
    /// most of the work (the `ltc-judge-tolerance` study's L1 curve).
    pub rel_l1: f64,
    pub abs: f64,
    pub max_evals: u64,
}

impl Default for Tolerance {
    /// 5e-4 relative or 1e-8 absolute (a millionth of a percentage point: small enough
    /// that even a near-perfect cell is refined until its error estimate is reliable), at
    /// most 4·10⁶ evaluations.
    fn default() -> Self {
        Tolerance {
            rel: 5e-4,
            rel_l1: 5e-4,
            abs: 1e-8,
            max_evals: 4_000_000,
        }
    }
}

impl Tolerance {
    /// The default's absolute floor and budget with relative tolerance `rel`: what a
    /// table's spec sets (`held_out_rel`), chosen from the accuracy-against-work curve of
    /// the `ltc-judge-tolerance` study.
    pub fn relative(rel: f64) -> Tolerance {
        Tolerance {
            rel,
            rel_l1: rel,
            ..Tolerance::default()
        }
    }

    /// Relative tolerance `rel` for the relative L2 and `rel_l1` for the relative L1: what
    /// a table's spec sets (`held_out_rel`, `held_out_l1_rel`).
    pub fn figures(rel: f64, rel_l1: f64) -> Tolerance {
        Tolerance {
            rel,
            rel_l1,
            ..Tolerance::default()
        }
    }

    /// The tolerance as the reports state it.
    pub fn describe(&self) -> String {
        if self.rel_l1 == self.rel {
            format!(
                "tolerance {:e} relative or {:e} absolute",
                self.rel, self.abs
            )
        } else {
            format!(
                "tolerance {:e} relative for the relative L2 and {:e} for the relative L1, or {:e} absolute",
                self.rel, self.rel_l1, self.abs
            )
        }
    }

    /// The default's relative tolerance: what a spec written before `held_out_rel` judged
    /// to (the serde default of the readers of a published spec).
    pub fn default_relative() -> f64 {
        Tolerance::default().rel
    }

    /// The bounds a spec's `held_out_rel` must lie in: 1e-6 (the cubature's panels reach
    /// the f64 floor of the figures' integrals below it) to 0.1.
    pub fn check_relative(rel: f64) -> std::result::Result<(), String> {
        crate::fit::spec::within("held_out_rel", rel, 1e-6, 0.1)
    }

    /// The same bounds for a spec's `held_out_l1_rel`.
    pub fn check_relative_l1(rel: f64) -> std::result::Result<(), String> {
        crate::fit::spec::within("held_out_l1_rel", rel, 1e-6, 0.1)
    }
}

/// √(a/b) and c/d with the half-widths of the intervals [a ± ea]/[b ∓ eb] put around them.
fn ratios(
    a: f64,
    ea: f64,
    b: f64,
    eb: f64,
    c: f64,
    ec: f64,
    d: f64,
    ed: f64,
) -> (Figure<Quad>, Figure<Quad>) {
    let sq = |a: f64, b: f64| {
        if b > 0.0 {
            (a.max(0.0) / b).sqrt()
        } else {
            f64::INFINITY
        }
    };
    let l2 = sq(a, b);
    let (hi2, lo2) = (sq(a + ea, b - eb), sq(a - ea, b + eb));
    let l1 = if d > 0.0 { c / d } else { f64::INFINITY };
    let hi1 = if d - ed > 0.0 {
        (c + ec) / (d - ed)
    } else {
        f64::INFINITY
    };
    let lo1 = (c - ec).max(0.0) / (d + ed);
    (
        Figure::<Quad>::new(l2, (hi2 - l2).max(l2 - lo2)),
        Figure::<Quad>::new(l1, (hi1 - l1).max(l1 - lo1)),
    )
}

/// The held-out error of each candidate against the target `f` (cosine-weighted, seen
/// from `v`), whose integral is ≈ `albedo` (it only weighs the charts: the partition
/// sums to one whatever it is) and whose own chart is `chart`. `None` for a candidate
/// that is singular or not finite.
pub fn lobe_errors(
    f: &dyn JudgedValue,
    albedo: f64,
    v: &V3,
    chart: &Chart,
    candidates: &[Candidate],
    tol: Tolerance,
) -> Vec<Option<LobeError>> {
    judged(f, albedo, v, chart, candidates, tol, false)
}

/// [`lobe_errors`], its integrand four nodes at a time or (`one_at_a_time`, the reference
/// the four-node form is checked against) one: the same bits either way.
fn judged(
    f: &dyn JudgedValue,
    albedo: f64,
    v: &V3,
    chart: &Chart,
    candidates: &[Candidate],
    tol: Tolerance,
    one_at_a_time: bool,
) -> Vec<Option<LobeError>> {
    let prepared: Vec<Option<Prepared>> = candidates.iter().map(Prepared::new).collect();
    let live: Vec<(usize, &Prepared)> = prepared
        .iter()
        .enumerate()
        .filter_map(|(k, p)| p.as_ref().map(|p| (k, p)))
        .collect();
    if live.is_empty() || !(albedo > 0.0 && albedo.is_finite()) {
        return vec![None; candidates.len()];
    }
    // the charts: the target's, then each charted candidate's (index into `live`)
    let mut charts: Vec<(Chart, f64, Option<usize>)> =
        vec![(*chart, chart.m.determinant().abs(), None)];
    for (q, (k, p)) in live.iter().enumerate() {
        if candidates[*k].chart {
            charts.push((Chart::direction(p.m), p.m.determinant().abs(), Some(q)));
        }
    }
    let nc = live.len();
    // components: ∫f², ∫f, then per live candidate ∫(f − g)², ∫|f − g|
    let ncomp = 2 + 2 * nc;
    let integrand = Integrand {
        f,
        albedo,
        v,
        charts,
        live: live.iter().map(|(_, p)| *p).collect(),
    };
    let mut memo = (SinCosMemo::default(), SinCosMemo::default());
    let figures = |v: &[f64], e: &[f64], q: usize| {
        ratios(
            v[2 + 2 * q],
            e[2 + 2 * q],
            v[0],
            e[0],
            v[3 + 2 * q],
            e[3 + 2 * q],
            v[1],
            e[1],
        )
    };
    let sens = |v: &[f64]| {
        // ∂√(A/B)/∂(A, B) and ∂(C/D)/∂(C, D), each over the figure's own target
        let mut w = vec![0.0; ncomp];
        let b = v[0].abs().max(1e-300);
        let d = v[1].abs().max(1e-300);
        for q in 0..nc {
            let a = v[2 + 2 * q].max(1e-12 * b).max(1e-300);
            let c = v[3 + 2 * q].abs();
            let (l2, l1) = ((a / b).sqrt(), c / d);
            let t2 = (tol.rel * l2).max(tol.abs);
            let t1 = (tol.rel_l1 * l1).max(tol.abs);
            w[0] += 0.5 * l2 / b / t2;
            w[1] += l1 / d / t1;
            w[2 + 2 * q] = 0.5 / (a * b).sqrt() / t2;
            w[3 + 2 * q] = 1.0 / d / t1;
        }
        w
    };
    let done = |v: &[f64], e: &[f64]| {
        (0..nc).all(|q| {
            let (l2, l1) = figures(v, e, q);
            l2.error <= (tol.rel * l2.value).max(tol.abs)
                && l1.error <= (tol.rel_l1 * l1.value).max(tol.abs)
        })
    };
    // each chart starts as 4 × 8 panels (quarters of s × eighth turns): fewer let a
    // near-perfect cell's |f − g|, whose sign changes across the lobe, stop before its
    // error estimate can see them
    let xb: Vec<f64> = (0..=4 * integrand.charts.len())
        .map(|i| 0.25 * i as f64)
        .collect();
    let yb: Vec<f64> = (0..=8).map(|i| 0.25 * PI * i as f64).collect();
    // |f − g| has kinks where f = g; the others are smooth inside panels
    let safety: Vec<f64> = (0..ncomp)
        .map(|c| {
            if c >= 2 && c % 2 == 1 {
                SAFETY_KINKED
            } else {
                SAFETY_SMOOTH
            }
        })
        .collect();
    let r = if one_at_a_time {
        let scalar = |x: f64, y: f64, out: &mut [f64]| integrand.node(x, y, &mut memo, out);
        cubature(scalar, &safety, &xb, &yb, sens, done, tol.max_evals)
    } else {
        let lanes = |x: &Lanes, y: &Lanes, live: usize, out: &mut [Lanes]| {
            integrand.nodes(x, y, live, &mut memo, out)
        };
        cubature_lanes(lanes, &safety, &xb, &yb, sens, done, tol.max_evals)
    };

    let mut out = vec![None; candidates.len()];
    for (q, (k, _)) in live.iter().enumerate() {
        let (l2, l1) = figures(&r.value, &r.error, q);
        out[*k] = Some(LobeError {
            l2,
            l1,
            evals: r.evals,
            converged: r.converged,
        });
    }
    out
}

/// The held-out errors of LTCs given as tables store them — M⁻¹ (any scale) and an
/// amplitude — against a target whose integral is ≈ `albedo` (where that is not a
/// positive number, a 16² importance-sampled estimate stands in), in one cubature. A
/// candidate gets a chart of its own unless its M⁻¹ is within 10⁻³ (relative, after
/// normalising) of one that has one: the same table rounded to f32 or binary16 rides on
/// the charts of its f64 cells. `None` where an M⁻¹ is singular or not finite.
pub fn judge<T: LtcTarget + ?Sized>(
    t: &T,
    albedo: f64,
    inverses: &[(Matrix3<f64>, f64)],
    tol: Tolerance,
) -> Vec<Option<LobeError>> {
    // the albedo only weighs the target's chart: a rough one serves where none is given
    let albedo = if albedo > 0.0 && albedo.is_finite() {
        albedo
    } else {
        t.moments(16).0
    };
    let mut charted: Vec<Matrix3<f64>> = Vec::new();
    let candidates: Vec<Candidate> = inverses
        .iter()
        .map(|(m_inv, amp)| {
            let n = m_inv.norm();
            let unit = if n > 0.0 && n.is_finite() {
                m_inv / n
            } else {
                *m_inv
            };
            let chart = !charted.iter().any(|c| (c - unit).norm() < 1e-3);
            if chart {
                charted.push(unit);
            }
            Candidate {
                m: m_inv
                    .try_inverse()
                    .unwrap_or_else(|| Matrix3::from_element(f64::NAN)),
                amp: *amp,
                chart,
            }
        })
        .collect();
    lobe_errors(
        &TargetValue(t),
        albedo,
        &t.view(),
        &t.chart(),
        &candidates,
        tol,
    )
}

/// The mean and the largest of a set of held-out figures (one of l2, l1), each with its
/// error bar: the mean's is the mean of the bars (deterministic errors can add up; no
/// cancellation is assumed), the largest's is that figure's own.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Spread {
    pub count: usize,
    pub mean: Figure<Quad>,
    pub max: Figure<Quad>,
    /// Index (in the order given) of the largest.
    pub argmax: usize,
}

/// How one set of held-out figures moved against a reference set, cell by cell: the mean
/// change (its bar the mean of the summed bars: both figures' errors may add) and the
/// largest change in magnitude with its own bar.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Change {
    pub count: usize,
    pub mean: Figure<Quad>,
    pub largest: Figure<Quad>,
    /// Index (in the order given) of the largest; `None` when nothing changed.
    pub argmax: Option<usize>,
    /// Changes larger than the `big` given, in magnitude.
    pub big: usize,
}

impl Change {
    /// Over the (reference, changed) pairs given (`None` entries are left out).
    pub fn of(
        pairs: impl Iterator<Item = Option<(Figure<Quad>, Figure<Quad>)>>,
        big: f64,
    ) -> Change {
        let (mut n, mut sum, mut bars, mut nbig) = (0usize, 0.0, 0.0, 0usize);
        let (mut largest, mut argmax) = (Figure::<Quad>::new(0.0, 0.0), None);
        for (k, p) in pairs.enumerate() {
            let Some((a, b)) = p else { continue };
            let (d, bar) = (b.value - a.value, a.error + b.error);
            n += 1;
            sum += d;
            bars += bar;
            if d.abs() > largest.value.abs() {
                (largest, argmax) = (Figure::new(d, bar), Some(k));
            }
            if d.abs() > big {
                nbig += 1;
            }
        }
        let m = n.max(1) as f64;
        Change {
            count: n,
            mean: Figure::new(sum / m, bars / m),
            largest,
            argmax,
            big: nbig,
        }
    }
}

impl Spread {
    /// Over the figures given (`None` entries are left out).
    pub fn of<'a>(figures: impl Iterator<Item = Option<&'a Figure<Quad>>>) -> Spread {
        let (mut n, mut sv, mut se) = (0usize, 0.0, 0.0);
        let mut max = Figure::<Quad>::new(f64::NAN, f64::NAN);
        let mut argmax = 0;
        for (k, b) in figures.enumerate() {
            let Some(b) = b else { continue };
            n += 1;
            sv += b.value;
            se += b.error;
            if !(b.value <= max.value) {
                max = *b;
                argmax = k;
            }
        }
        let m = n.max(1) as f64;
        Spread {
            count: n,
            mean: Figure::<Quad>::new(
                if n > 0 { sv / m } else { f64::NAN },
                if n > 0 { se / m } else { f64::NAN },
            ),
            max,
            argmax,
        }
    }
}

/// The held-out error of one LTC, amp·γ_M, against the target (see [`lobe_errors`]).
pub fn lobe_error(
    f: &dyn JudgedValue,
    albedo: f64,
    v: &V3,
    chart: &Chart,
    m: &Matrix3<f64>,
    amp: f64,
    tol: Tolerance,
) -> LobeError {
    lobe_errors(
        f,
        albedo,
        v,
        chart,
        &[Candidate {
            m: *m,
            amp,
            chart: true,
        }],
        tol,
    )[0]
    .unwrap_or(LobeError {
        l2: Figure::<Quad>::new(f64::INFINITY, f64::INFINITY),
        l1: Figure::<Quad>::new(f64::INFINITY, f64::INFINITY),
        evals: 0,
        converged: false,
    })
}

/// The held-out error (`ltc::lobe_error`: relative L2 and L1 as converged integrals with
/// their error bars) of a cell in each precision it is stored in; `None` where that
/// precision's matrix is singular.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Held {
    pub f64: Option<LobeError>,
    pub f32: Option<LobeError>,
    /// Every entry rounded to the nearest binary16.
    pub f16_nearest: Option<LobeError>,
    /// The binary16 storage chosen by `ltc::storage` (what every f16 file holds).
    pub f16: Option<LobeError>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ltc::aniso::AnisoGgxTarget;
    use crate::ltc::diffuse::{BurleyRoughness, BurleyTarget};
    use crate::ltc::sheen::{CharlieTarget, SheenVisibility};
    use crate::ltc::target::GgxTarget;
    use rand::{Rng, SeedableRng};

    /// The judge with its integrand four nodes at a time gives every figure, bar,
    /// evaluation count and convergence flag of the one-node reference, bit for bit: 96
    /// random cells of every fitted target (α down to 1e-4, θ up to 89.99°), each with
    /// four candidates as a table's judge sees them (a matrix near the lobe, its copy
    /// rounded to f32, the clamped cosine, one far off the lobe), at the tables'
    /// tolerances and a looser one.
    #[test]
    fn four_nodes_at_a_time_are_the_one_node_bits() {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        for case in 0..96 {
            let alpha = match case % 6 {
                0 => 1e-4,
                1 => 1.0,
                _ => 10f64.powf(r.random_range(-3.0..0.0)),
            };
            let th = if case % 5 == 0 {
                89.99f64.to_radians()
            } else {
                r.random_range(0.0..1.5)
            };
            let t: Box<dyn LtcTarget> = match case % 4 {
                0 => Box::new(GgxTarget::new(alpha, th).unwrap()),
                1 => Box::new(
                    AnisoGgxTarget::new(alpha, r.random_range(1e-3..1.0), th, 0.4).unwrap(),
                ),
                2 => Box::new(
                    CharlieTarget::new(alpha.max(0.01), th, SheenVisibility::EstevezKulla).unwrap(),
                ),
                _ => Box::new(BurleyTarget::new(alpha, th, BurleyRoughness::Paper).unwrap()),
            };
            let a = alpha.max(0.02);
            let near = Matrix3::new(
                a,
                0.0,
                r.random_range(-0.3..0.3),
                0.0,
                a,
                0.0,
                0.0,
                0.0,
                1.0,
            );
            let f32s = near.map(|x| x as f32 as f64);
            let far = Matrix3::new(0.5, 0.1, 0.4, 0.0, 2.0, 0.0, -0.3, 0.0, 1.0);
            let candidates: Vec<Candidate> = [
                (near, true),
                (f32s, false),
                (Matrix3::identity(), true),
                (far, true),
            ]
            .iter()
            .map(|&(m, chart)| Candidate {
                m,
                amp: r.random_range(0.3..1.1),
                chart,
            })
            .collect();
            let tol = if case % 2 == 0 {
                Tolerance::figures(2e-3, 1e-2)
            } else {
                Tolerance::relative(2e-2)
            };
            let albedo = t.moments(8).0;
            let f = TargetValue(t.as_ref());
            let (v, chart) = (t.view(), t.chart());
            let lanes = judged(&f, albedo, &v, &chart, &candidates, tol, false);
            let one = judged(&f, albedo, &v, &chart, &candidates, tol, true);
            let bits = |e: &Option<LobeError>| {
                e.map(|e| {
                    [
                        e.l2.value,
                        e.l2.error,
                        e.l1.value,
                        e.l1.error,
                        e.evals as f64,
                    ]
                    .map(f64::to_bits)
                })
            };
            for (x, y) in lanes.iter().zip(&one) {
                assert_eq!(bits(x), bits(y), "case {case}");
                assert_eq!(x.map(|e| e.converged), y.map(|e| e.converged));
            }
            assert!(
                lanes.iter().all(|e| e.is_some()),
                "case {case}: every candidate judged"
            );
        }
    }
}

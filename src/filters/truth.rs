//! Ground truth for the filters: the footprint-averaged specular lobe under
//! seed 004 Hypothesis 1 — Eq 11, ρ_A(l, v) = Σ_x ŵ(x) ρ_x(l, v)(n_x·l) — with each
//! texel's BRDF the microfacet lobe around its own normal n_x (D·G2/(4 n_x·v), the
//! cosine n_x·l cancelled; F = 1). Filters are compared with it over all light
//! directions by importance-sampled Monte Carlo (every number with its standard error).

use crate::error::Result;
use crate::integrate::mc::Strategy;
use crate::microfacet::sampling::VndfSampler;
use crate::microfacet::{Microsurface, NdfKind, Roughness};
use nalgebra::{Matrix2, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

type V3 = Vector3<f64>;

use crate::lanes::{Dirs, LANES};
use crate::microfacet::lobe::ViewedLobe;
pub use crate::microfacet::lobe::{lobe, Frame};

/// A footprint: normals with weights summing to 1.
#[derive(Clone, Debug)]
pub struct Footprint {
    pub normals: Vec<V3>,
    pub weights: Vec<f64>,
}

impl Footprint {
    pub fn uniform(normals: Vec<V3>) -> Footprint {
        let w = 1.0 / normals.len() as f64;
        Footprint {
            weights: vec![w; normals.len()],
            normals,
        }
    }
    /// Unnormalised mean normal.
    pub fn mean(&self) -> V3 {
        self.normals
            .iter()
            .zip(&self.weights)
            .fold(V3::zeros(), |a, (n, w)| a + n * *w)
    }
}

/// The exact footprint-averaged lobe with base roughness α (isotropic).
pub struct Truth {
    surface: Microsurface,
    frames: Vec<Frame>,
    weights: Vec<f64>,
    alpha: f64,
}

impl Truth {
    pub fn new(kind: NdfKind, alpha: f64, fp: &Footprint) -> Result<Truth> {
        Ok(Truth {
            surface: Microsurface::new(kind, Roughness::iso(alpha)?),
            frames: fp.normals.iter().map(|n| Frame::around(*n)).collect(),
            weights: fp.weights.clone(),
            alpha,
        })
    }
    pub fn value(&self, v: &V3, l: &V3) -> f64 {
        self.frames
            .iter()
            .zip(&self.weights)
            .map(|(f, w)| w * lobe(&self.surface, f, v, l))
            .sum()
    }

    /// The truth seen from `v`, each texel's lobe with the view prepared once
    /// (`ViewedLobe`: Λ(v) and v in the texel's frame), for many light directions.
    pub fn viewed(&self, v: &V3) -> ViewedTruth<'_> {
        ViewedTruth {
            truth: self,
            lobes: self
                .frames
                .iter()
                .map(|f| ViewedLobe::new(&self.surface, f, v))
                .collect(),
        }
    }
}

/// [`Truth`] from one view: [`ViewedTruth::value`] is `Truth::value` bit for bit (the
/// same terms, summed in the same order).
pub struct ViewedTruth<'a> {
    truth: &'a Truth,
    lobes: Vec<ViewedLobe>,
}

impl ViewedTruth<'_> {
    pub fn value(&self, l: &V3) -> f64 {
        // four texels' lobes at a time (their chains overlap), summed in order
        let ls = Dirs::of(&[*l; LANES]);
        let s = &self.truth.surface;
        self.lobes
            .chunks(LANES)
            .zip(self.truth.weights.chunks(LANES))
            .flat_map(|(g, w)| {
                let e = ViewedLobe::eval_lanes(s, ViewedLobe::lanes_of(g), &ls);
                (0..g.len()).map(move |i| w[i] * e[i])
            })
            .sum()
    }

    /// The one-lobe-at-a-time form of [`Self::value`] (its reference).
    pub fn value_reference(&self, l: &V3) -> f64 {
        self.lobes
            .iter()
            .zip(&self.truth.weights)
            .map(|(g, w)| w * g.eval(&self.truth.surface, l))
            .sum()
    }
}

/// A filtered lobe to compare: its value for (v, l) and an isotropic GGX proposal
/// (normal, α) used to sample where it lives.
pub struct Candidate<'a> {
    pub name: String,
    pub value: Box<dyn Fn(&V3, &V3) -> f64 + Sync + 'a>,
    pub proposal: (V3, f64),
}

impl<'a> Candidate<'a> {
    /// An isotropic lobe of roughness α around the unit normal n.
    pub fn iso(name: &str, kind: NdfKind, n: V3, alpha: f64) -> Result<Candidate<'a>> {
        let s = Microsurface::new(kind, Roughness::iso(alpha)?);
        let f = Frame::around(n);
        Ok(Candidate {
            name: name.into(),
            value: Box::new(move |v, l| lobe(&s, &f, v, l)),
            proposal: (f.n, alpha),
        })
    }
    /// A microsurface (any A, any mean slope) in the frame f.
    pub fn surface(name: &str, s: Microsurface, f: Frame) -> Candidate<'a> {
        let (lo, hi) = s.rough.eigenvalues();
        let _ = lo;
        Candidate {
            name: name.into(),
            value: Box::new(move |v, l| lobe(&s, &f, v, l)),
            proposal: (f.world(&s.mean_normal()), hi.sqrt()),
        }
    }
}

/// A ratio with its standard error.
pub use crate::integrate::Figure;

/// One candidate against the truth for one (footprint, view).
#[derive(Clone, Debug, Serialize)]
pub struct CaseResult {
    /// ∫f_k / ∫f_truth − 1 over light directions.
    pub energy: Figure,
    /// ‖f_k − f_truth‖₂ / ‖f_truth‖₂ over light directions.
    pub l2: Figure,
    /// max f_k / max f_truth − 1, maxima over the sampled light directions and the
    /// mirror directions of the mean normal, ≤ 64 texel normals and the lobe's own normal
    /// (a search, so no standard error; both maxima are lower bounds).
    pub peak: f64,
}

/// Proposal: a mixture of GGX VNDF lobes (truth normals with their weights, candidates)
/// plus a cosine hemisphere, all in world space.
struct Mixture {
    /// Per lobe: its frame, sampler and surface, the view in its frame, and the view's
    /// masking G1(v), which every density evaluation needs and the view fixes.
    comps: Vec<(Frame, VndfSampler, Microsurface, V3, f64)>,
    cum: Vec<f64>,
    probs: Vec<f64>,
    w_cos: f64,
}

impl Mixture {
    fn new(parts: &[(V3, f64, f64)], v: &V3, w_cos: f64) -> Result<Mixture> {
        let mut comps = Vec::new();
        let mut probs = Vec::new();
        for &(n, a, w) in parts {
            let f = Frame::around(n);
            let vl = f.local(v);
            if vl.z <= 1e-9 || w <= 0.0 {
                continue;
            }
            let s = Microsurface::ggx(Roughness::iso(a.clamp(1e-4, 4.0))?);
            let sampler = VndfSampler::new(s, vl)?;
            comps.push((f, sampler, s, vl, s.g1_dir(&vl)));
            probs.push(w);
        }
        let tot: f64 = probs.iter().sum();
        let scale = if tot > 0.0 { (1.0 - w_cos) / tot } else { 0.0 };
        let w_cos = if tot > 0.0 { w_cos } else { 1.0 };
        let mut acc = 0.0;
        let mut cum = Vec::with_capacity(probs.len());
        for p in probs.iter_mut() {
            *p *= scale;
            acc += *p;
            cum.push(acc);
        }
        Ok(Mixture {
            comps,
            cum,
            probs,
            w_cos,
        })
    }
    fn sample(&self, v: &V3, u: [f64; 3]) -> Option<V3> {
        let total = 1.0 - self.w_cos;
        if u[0] < total {
            let i = self
                .cum
                .partition_point(|&c| c <= u[0])
                .min(self.comps.len() - 1);
            let (f, sampler, ..) = &self.comps[i];
            let m = sampler.sample([u[1], u[2]])?;
            let h = f.world(&m);
            let l = h * (2.0 * v.dot(&h)) - v;
            Some(l)
        } else {
            let r = u[1].sqrt();
            let phi = 2.0 * std::f64::consts::PI * u[2];
            Some(V3::new(
                r * phi.cos(),
                r * phi.sin(),
                (1.0 - u[1]).max(0.0).sqrt(),
            ))
        }
    }
    fn pdf(&self, v: &V3, l: &V3) -> f64 {
        let mut p = if l.z > 0.0 {
            self.w_cos * l.z / std::f64::consts::PI
        } else {
            0.0
        };
        let h = v + l;
        let hn = h.norm();
        if !(hn > 0.0) {
            return p;
        }
        let h = h / hn;
        let vh = v.dot(&h);
        if vh <= 0.0 {
            return p;
        }
        for ((f, _, s, vl, g1_v), w) in self.comps.iter().zip(&self.probs) {
            let hl = f.local(&h);
            if hl.z <= 0.0 {
                continue;
            }
            // VNDF pdf of h, times the reflection Jacobian 1/(4 v·h)
            p += w * g1_v * s.d(&hl) / (4.0 * vl.z);
        }
        p
    }
}

/// Ratio A/B of two sample means with the delta-method standard error.
fn ratio(a: &[f64], b: &[f64]) -> (f64, f64) {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    if !(mb > 0.0) {
        return (f64::NAN, f64::NAN);
    }
    let r = ma / mb;
    let var = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - r * y).powi(2))
        .sum::<f64>()
        / (n - 1.0).max(1.0);
    (r, (var / n).sqrt() / mb)
}

/// Light directions drawn for one (footprint, view) with their mixture density and the
/// truth there; reused to measure any number of candidates (and to fit constants).
pub struct CaseSamples {
    pub v: V3,
    ls: Vec<Option<V3>>,
    q: Vec<f64>,
    t: Vec<f64>,
    /// Directions where the lobes peak: mirror directions of the mean normal and of up to
    /// 64 texel normals (evenly spread); the truth's maximum over these and the samples.
    peak_dirs: Vec<V3>,
    t_peak: f64,
}

/// Draw `n` light directions from a defensive mixture of the truth's texel lobes (45 %),
/// the given proposals (45 %) and a cosine hemisphere (10 %); seeded, bit-identical.
pub fn draw(
    truth: &Truth,
    v: &V3,
    proposals: &[(V3, f64)],
    n: usize,
    seed: u64,
) -> Result<CaseSamples> {
    let a_prop = truth.alpha.max(2e-3);
    let mut parts: Vec<(V3, f64, f64)> = truth
        .frames
        .iter()
        .zip(&truth.weights)
        .map(|(f, w)| (f.n, a_prop, 0.45 * w))
        .collect();
    for p in proposals {
        parts.push((p.0, p.1.max(2e-3), 0.45 / proposals.len() as f64));
    }
    let mix = Mixture::new(&parts, v, 0.1)?;
    let seen = truth.viewed(v);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut ls, mut q, mut t) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for _ in 0..n {
        let u = [
            rng.random::<f64>(),
            rng.random::<f64>(),
            rng.random::<f64>(),
        ];
        match mix.sample(v, u) {
            Some(l) if l.z > 0.0 => {
                let p = mix.pdf(v, &l);
                ls.push(Some(l));
                q.push(if p > 0.0 { p } else { 1.0 });
                t.push(seen.value(&l));
            }
            _ => {
                ls.push(None);
                q.push(1.0);
                t.push(0.0);
            }
        }
    }
    let nbar = truth
        .frames
        .iter()
        .zip(&truth.weights)
        .fold(V3::zeros(), |a, (f, w)| a + f.n * *w);
    let nbar = if nbar.norm() > 0.0 {
        nbar.normalize()
    } else {
        V3::z()
    };
    let mirror = |n: &V3| n * (2.0 * v.dot(n)) - v;
    let step = truth.frames.len().div_ceil(64).max(1);
    let mut peak_dirs = vec![mirror(&nbar)];
    peak_dirs.extend(truth.frames.iter().step_by(step).map(|f| mirror(&f.n)));
    let t_peak = peak_dirs
        .iter()
        .map(|l| seen.value(l))
        .chain(t.iter().copied())
        .fold(0.0, f64::max);
    Ok(CaseSamples {
        v: *v,
        ls,
        q,
        t,
        peak_dirs,
        t_peak,
    })
}

impl CaseSamples {
    /// ∫ f_truth over light directions (estimate, s.e.).
    pub fn truth_energy(&self) -> Figure {
        let x: Vec<f64> = self.t.iter().zip(&self.q).map(|(t, q)| t / q).collect();
        Figure::mean_of(&x)
    }

    /// Measure one candidate lobe f(v, l) against the truth; `normal` is the lobe's own
    /// normal (its mirror direction joins the peak search).
    pub fn measure(&self, f: &dyn Fn(&V3, &V3) -> f64, normal: &V3) -> CaseResult {
        let v = &self.v;
        let n = self.ls.len();
        let mut fmax = 0.0f64;
        let (mut a, mut b, mut c, mut d) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for i in 0..n {
            let fk = self.ls[i].map_or(0.0, |l| f(v, &l));
            fmax = fmax.max(fk);
            let (t, q) = (self.t[i], self.q[i]);
            a.push(fk / q);
            b.push(t / q);
            c.push((fk - t).powi(2) / q);
            d.push(t * t / q);
        }
        let (e, es) = ratio(&a, &b);
        let (l2, l2s) = ratio(&c, &d);
        let l2r = l2.max(0.0).sqrt();
        let own = normal * (2.0 * v.dot(normal)) - v;
        for l in self.peak_dirs.iter().chain(std::iter::once(&own)) {
            fmax = fmax.max(f(v, l));
        }
        CaseResult {
            energy: Figure::with_se(e - 1.0, es),
            l2: Figure::with_se(
                l2r,
                if l2r > 0.0 {
                    l2s / (2.0 * l2r)
                } else {
                    l2s.sqrt()
                },
            ),
            peak: if self.t_peak > 0.0 {
                fmax / self.t_peak - 1.0
            } else {
                f64::NAN
            },
        }
    }
}

/// Compare every candidate with the truth for view v (world, z > 0) with `n` samples.
pub fn compare(
    truth: &Truth,
    v: &V3,
    cands: &[Candidate],
    n: usize,
    seed: u64,
) -> Result<Vec<CaseResult>> {
    let props: Vec<(V3, f64)> = cands.iter().map(|c| c.proposal).collect();
    let s = draw(truth, v, &props, n, seed)?;
    Ok(cands
        .iter()
        .map(|c| s.measure(&*c.value, &c.proposal.0))
        .collect())
}

/// A roughness matrix from (xx, yy, xy), as a typed error when not SPD.
pub fn matrix(a: [f64; 3]) -> Result<Roughness> {
    Roughness::matrix(Matrix2::new(a[0], a[2], a[2], a[1]))
}

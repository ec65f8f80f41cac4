//! Lobe mixtures fitted by expectation–maximisation, and their MIP-mapping by aligned
//! lobes (seed 004 §3.2.2):
//!
//! - [`SlopeMixture`]: Tan et al.'s isotropic Gaussian lobes in slope space (Eq 21), a
//!   direct spanning-set method (§7.4.1). EM runs on the texels' slopes; each component's
//!   variance then gains the base lobe's α²/2, so the mixture is the footprint's μNDF.
//!   4 parameters per lobe (a, mean slope, second moment), less one for Σa = 1.
//! - [`VmfMixture`]: Han et al.'s von Mises–Fisher lobes of the macroscopic NDF p_A
//!   (Eq 22), a convolution spanning-set method (§7.4.2): spherical EM (Banerjee et al.
//!   2005) on the texel normals; the lobes are convolved with the base lobe in
//!   [`super::sh::VmfConvolved`]. Same parameter count.
//!
//! EM's pitfalls, each handled and tested: a component that loses all its points is
//! re-seeded at the worst-explained texel (and dropped when every texel is explained
//! exactly, e.g. fewer distinct normals than lobes); a variance is floored at
//! [`VAR_FLOOR`] (a cluster of identical slopes); κ is capped at [`KAPPA_MAX`] and every
//! vMF density is evaluated in logs (log C(κ) = ln κ − ln 2π − κ − ln(1 − e^{−2κ}), so
//! that neither sinh κ nor e^κ overflows).
//!
//! Alignment ([`align`]): a parent's lobes come from its four children by matching each
//! child's lobes to the first child's (the permutation with the smallest total angle
//! between matched means, all K! tried) and averaging the interpolable quantities: a_k,
//! a_k μ_k and a_k(σ_k² + ‖μ_k‖²) for slope Gaussians (the best Gaussian of the matched
//! pair, proofs/gaussian-moment-matching.md), a_k and a_k(coth κ_k − 1/κ_k)μ_k for vMF
//! lobes (proofs/vmf-mixture-moments.md). At a sharp edge the matched lobes can be far
//! apart — alignment is impossible — and the average then is one wide lobe between them;
//! such merges are counted ([`Merged::misaligned`]) so the study can report what they
//! cost.

use crate::error::{Error, Result};
use nalgebra::{Vector2, Vector3};
use std::f64::consts::PI;

type V3 = Vector3<f64>;
type V2 = Vector2<f64>;

/// Smallest per-axis slope variance of a component before the base lobe is added.
pub const VAR_FLOOR: f64 = 1e-14;
/// Largest vMF concentration (about 0.0001° of spread).
pub const KAPPA_MAX: f64 = 1e8;
const ITERS: usize = 200;
const TOL: f64 = 1e-10;

/// What EM did (for the pitfall counts of the report).
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct EmLog {
    pub iterations: usize,
    pub reseeded: usize,
    pub dropped: usize,
    pub floored: usize,
    pub kappa_capped: usize,
}

/// Deterministic farthest-point initial centres: the heaviest point first, then the point
/// whose weighted distance to the chosen centres is largest.
fn farthest_points(
    n: usize,
    w: &[f64],
    dist: &dyn Fn(usize, usize) -> f64,
    k: usize,
) -> Vec<usize> {
    let mut first = 0;
    for i in 0..n {
        if w[i] > w[first] {
            first = i;
        }
    }
    let mut c = vec![first];
    let mut d: Vec<f64> = (0..n).map(|i| dist(i, first)).collect();
    while c.len() < k.min(n) {
        let (mut bi, mut bv) = (0, -1.0);
        for i in 0..n {
            if w[i] * d[i] > bv {
                bv = w[i] * d[i];
                bi = i;
            }
        }
        if bv <= 0.0 {
            break;
        }
        c.push(bi);
        for i in 0..n {
            d[i] = d[i].min(dist(i, bi));
        }
    }
    c
}

/// Responsibilities from per-component log densities (log-sum-exp); returns the
/// weighted log-likelihood.
fn responsibilities(logp: &[Vec<f64>], w: &[f64], r: &mut [Vec<f64>]) -> f64 {
    let mut ll = 0.0;
    for i in 0..w.len() {
        let m = logp.iter().map(|l| l[i]).fold(f64::NEG_INFINITY, f64::max);
        if !m.is_finite() {
            for rk in r.iter_mut() {
                rk[i] = 1.0 / logp.len() as f64;
            }
            continue;
        }
        // each e^(l − m) once: kept in r, summed in the components' order, then divided
        let mut s = 0.0;
        for (rk, l) in r.iter_mut().zip(logp) {
            rk[i] = (l[i] - m).exp();
            s += rk[i];
        }
        for rk in r.iter_mut().take(logp.len()) {
            rk[i] /= s;
        }
        ll += w[i] * (m + s.ln());
    }
    ll
}

/// One mixture family's pieces for [`run_em`].
struct Em<'a, C> {
    /// ln(a_k p_k(x_i)).
    log_density: &'a dyn Fn(&C, usize) -> f64,
    /// The M step for one component from its responsibilities and their weighted sum.
    m_step: &'a dyn Fn(&[f64], f64, &C, &mut EmLog) -> C,
    /// A component re-seeded at point i, or `None` when a component already sits there.
    reseed: &'a dyn Fn(usize, &[C]) -> Option<C>,
    weight: &'a dyn Fn(&C) -> f64,
    set_weight: &'a dyn Fn(&mut C, f64),
}

/// EM to convergence (relative log-likelihood change ≤ 1e-10, ≤ 200 iterations): an empty
/// component is re-seeded at the worst-explained point (or dropped when that point is
/// taken), the weights renormalised after every M step.
fn run_em<C: Copy>(n: usize, w: &[f64], comps: &mut Vec<C>, log: &mut EmLog, em: &Em<C>) {
    let mut r = vec![vec![0.0; n]; comps.len()];
    let mut prev = f64::NEG_INFINITY;
    for it in 0..ITERS {
        log.iterations = it + 1;
        let logp: Vec<Vec<f64>> = comps
            .iter()
            .map(|c| (0..n).map(|i| (em.log_density)(c, i)).collect())
            .collect();
        let ll = responsibilities(&logp, w, &mut r);
        let mut changed = false;
        for k in 0..comps.len() {
            let nk: f64 = (0..n).map(|i| w[i] * r[k][i]).sum();
            if nk >= 1e-12 {
                comps[k] = (em.m_step)(&r[k], nk, &comps[k], log);
                continue;
            }
            let best = |i: usize| logp.iter().map(|l| l[i]).fold(f64::NEG_INFINITY, f64::max);
            let worst = (0..n)
                .min_by(|&a, &b| best(a).total_cmp(&best(b)))
                .unwrap_or(0);
            match (em.reseed)(worst, comps) {
                Some(c) => {
                    comps[k] = c;
                    log.reseeded += 1;
                    changed = true;
                }
                None => {
                    (em.set_weight)(&mut comps[k], 0.0);
                    log.dropped += 1;
                }
            }
        }
        comps.retain(|c| (em.weight)(c) > 0.0);
        r.truncate(comps.len());
        let s: f64 = comps.iter().map(|c| (em.weight)(c)).sum();
        for c in comps.iter_mut() {
            let v = (em.weight)(c) / s;
            (em.set_weight)(c, v);
        }
        if !changed && (ll - prev).abs() <= TOL * ll.abs().max(1.0) {
            break;
        }
        prev = ll;
    }
}

/// One isotropic Gaussian lobe of slopes: weight, mean slope, per-axis variance.
#[derive(Clone, Copy, Debug)]
pub struct SlopeLobe {
    pub weight: f64,
    pub mean: V2,
    pub var: f64,
}

/// Tan et al.'s mixture (Eq 21) in the geometric tangent plane.
#[derive(Clone, Debug)]
pub struct SlopeMixture {
    /// The lobes of the texels' slopes (without the base lobe).
    pub comps: Vec<SlopeLobe>,
    /// The base lobe's per-axis slope variance α²/2, added when evaluated.
    pub base_var: f64,
    pub log: EmLog,
}

fn slope_of(n: &V3) -> V2 {
    let z = n.z.max(1e-12);
    V2::new(-n.x / z, -n.y / z)
}

impl SlopeMixture {
    /// EM with `k` lobes on the slopes of `normals` (weights summing to 1).
    pub fn fit(normals: &[V3], w: &[f64], k: usize, alpha: f64) -> Result<SlopeMixture> {
        if k == 0 || normals.is_empty() || normals.len() != w.len() {
            return Err(Error::InvalidArgument(
                "slope EM: empty input or k = 0".into(),
            ));
        }
        let x: Vec<V2> = normals.iter().map(slope_of).collect();
        let n = x.len();
        let centres = farthest_points(n, w, &|i, j| (x[i] - x[j]).norm_squared(), k);
        let mut log = EmLog {
            dropped: k - centres.len(),
            ..EmLog::default()
        };
        let total_var = {
            let m = x.iter().zip(w).fold(V2::zeros(), |a, (p, wi)| a + p * *wi);
            x.iter()
                .zip(w)
                .map(|(p, wi)| wi * (p - m).norm_squared())
                .sum::<f64>()
                * 0.5
        };
        let mut comps: Vec<SlopeLobe> = centres
            .iter()
            .map(|&c| SlopeLobe {
                weight: 1.0 / centres.len() as f64,
                mean: x[c],
                var: (total_var / centres.len() as f64).max(VAR_FLOOR),
            })
            .collect();
        run_em(
            n,
            w,
            &mut comps,
            &mut log,
            &Em {
                log_density: &|c: &SlopeLobe, i| {
                    c.weight.max(1e-300).ln()
                        - (2.0 * PI * c.var).ln()
                        - (x[i] - c.mean).norm_squared() / (2.0 * c.var)
                },
                m_step: &|r: &[f64], nk, _c: &SlopeLobe, log: &mut EmLog| {
                    let mean = (0..n).fold(V2::zeros(), |a, i| a + x[i] * (w[i] * r[i])) / nk;
                    let var = (0..n)
                        .map(|i| w[i] * r[i] * (x[i] - mean).norm_squared())
                        .sum::<f64>()
                        / (2.0 * nk);
                    if var < VAR_FLOOR {
                        log.floored += 1;
                    }
                    SlopeLobe {
                        weight: nk,
                        mean,
                        var: var.max(VAR_FLOOR),
                    }
                },
                reseed: &|i, comps: &[SlopeLobe]| {
                    let taken = comps.iter().any(|c| (c.mean - x[i]).norm() < 1e-12);
                    (!taken).then(|| SlopeLobe {
                        weight: 1e-3,
                        mean: x[i],
                        var: total_var.max(VAR_FLOOR),
                    })
                },
                weight: &|c: &SlopeLobe| c.weight,
                set_weight: &|c: &mut SlopeLobe, v| c.weight = v,
            },
        );
        Ok(SlopeMixture {
            comps,
            base_var: 0.5 * alpha * alpha,
            log,
        })
    }
}

impl super::NormalPdf for SlopeMixture {
    fn pdf(&self, h: &V3) -> f64 {
        if !(h.z > 0.0) {
            return 0.0;
        }
        let x = V2::new(-h.x / h.z, -h.y / h.z);
        let j = 1.0 / (h.z * h.z * h.z);
        self.comps
            .iter()
            .map(|c| {
                let v = c.var + self.base_var;
                c.weight * (-(x - c.mean).norm_squared() / (2.0 * v)).exp() / (2.0 * PI * v)
            })
            .sum::<f64>()
            * j
    }
}

/// One vMF lobe.
#[derive(Clone, Copy, Debug)]
pub struct VmfLobe {
    pub weight: f64,
    pub mu: V3,
    pub kappa: f64,
}

/// ln of the vMF normaliser κ/(4π sinh κ), stable for every κ ≥ 0.
pub fn vmf_log_norm(kappa: f64) -> f64 {
    if kappa < 1e-6 {
        return -(4.0 * PI).ln();
    }
    kappa.ln() - (2.0 * PI).ln() - kappa - (-(-2.0 * kappa).exp_m1()).ln()
}

/// The mean resultant length A(κ) = coth κ − 1/κ: its series κ/3 − κ³/45 + 2κ⁵/945 −
/// κ⁷/4725 below κ = 0.1 (the next term is below 1e-12 of A there), coth by expm1 above.
pub fn langevin(kappa: f64) -> f64 {
    if kappa < 0.1 {
        let k2 = kappa * kappa;
        return kappa * (1.0 / 3.0 - k2 * (1.0 / 45.0 - k2 * (2.0 / 945.0 - k2 / 4725.0)));
    }
    let e = (-2.0 * kappa).exp();
    (1.0 + e) / (-(-2.0 * kappa).exp_m1()) - 1.0 / kappa
}

/// κ with A(κ) = r: Banerjee et al.'s start (3r − r³)/(1 − r²), then Newton on A
/// (A′ = 1 − A² − 2A/κ); capped at [`KAPPA_MAX`].
pub fn inverse_langevin(r: f64) -> f64 {
    let r = r.clamp(0.0, 1.0);
    if r < 1e-9 {
        return 0.0;
    }
    if 1.0 - r < 1.0 / KAPPA_MAX {
        return KAPPA_MAX;
    }
    let mut k = (r * (3.0 - r * r) / ((1.0 - r) * (1.0 + r))).min(KAPPA_MAX);
    for _ in 0..20 {
        let a = langevin(k);
        let d = 1.0 - a * a - 2.0 * a / k;
        if !(d > 0.0) {
            break;
        }
        let step = (a - r) / d;
        let kn = (k - step).clamp(k / 10.0, k * 10.0);
        if (kn - k).abs() <= 1e-14 * k {
            k = kn;
            break;
        }
        k = kn;
    }
    k.min(KAPPA_MAX)
}

/// Han et al.'s vMF mixture of the macroscopic NDF (Eq 22).
#[derive(Clone, Debug)]
pub struct VmfMixture {
    pub comps: Vec<VmfLobe>,
    pub log: EmLog,
}

impl VmfMixture {
    /// Spherical EM with `k` lobes on unit `normals` (weights summing to 1).
    pub fn fit(normals: &[V3], w: &[f64], k: usize) -> Result<VmfMixture> {
        if k == 0 || normals.is_empty() || normals.len() != w.len() {
            return Err(Error::InvalidArgument(
                "vMF EM: empty input or k = 0".into(),
            ));
        }
        let n = normals.len();
        let centres = farthest_points(n, w, &|i, j| 1.0 - normals[i].dot(&normals[j]), k);
        let mut log = EmLog {
            dropped: k - centres.len(),
            ..EmLog::default()
        };
        let mbar = normals
            .iter()
            .zip(w)
            .fold(V3::zeros(), |a, (p, wi)| a + p * *wi);
        let k0 = inverse_langevin(mbar.norm()).max(1.0);
        let mut comps: Vec<VmfLobe> = centres
            .iter()
            .map(|&c| VmfLobe {
                weight: 1.0 / centres.len() as f64,
                mu: normals[c],
                kappa: k0,
            })
            .collect();
        run_em(
            n,
            w,
            &mut comps,
            &mut log,
            &Em {
                // ln C(κ) holds −κ, so ln C + κ μ·η = … − κ(1 − μ·η) stays bounded
                log_density: &|c: &VmfLobe, i| {
                    c.weight.max(1e-300).ln()
                        + vmf_log_norm(c.kappa)
                        + c.kappa * normals[i].dot(&c.mu)
                },
                m_step: &|r: &[f64], nk, c: &VmfLobe, log: &mut EmLog| {
                    let s = (0..n).fold(V3::zeros(), |a, i| a + normals[i] * (w[i] * r[i]));
                    let kappa = inverse_langevin((s.norm() / nk).min(1.0));
                    if kappa >= KAPPA_MAX {
                        log.kappa_capped += 1;
                    }
                    let mu = if s.norm() > 0.0 { s.normalize() } else { c.mu };
                    VmfLobe {
                        weight: nk,
                        mu,
                        kappa,
                    }
                },
                reseed: &|i, comps: &[VmfLobe]| {
                    let taken = comps.iter().any(|c| (c.mu - normals[i]).norm() < 1e-12);
                    (!taken).then(|| VmfLobe {
                        weight: 1e-3,
                        mu: normals[i],
                        kappa: k0,
                    })
                },
                weight: &|c: &VmfLobe| c.weight,
                set_weight: &|c: &mut VmfLobe, v| c.weight = v,
            },
        );
        Ok(VmfMixture { comps, log })
    }

    /// The density Σ a_k C(κ_k) e^{κ_k μ_k·η} of the macroscopic NDF (in logs).
    pub fn density(&self, h: &V3) -> f64 {
        self.comps
            .iter()
            .map(|c| c.weight * (vmf_log_norm(c.kappa) + c.kappa * c.mu.dot(h)).exp())
            .sum()
    }
}

/// A parent's lobes from its children, with the count of matched pairs that could not be
/// aligned.
#[derive(Clone, Debug)]
pub struct Merged<T> {
    pub lobes: Vec<T>,
    pub misaligned: usize,
    pub pairs: usize,
}

/// Every permutation of 0..k (k ≤ 6).
fn permutations(k: usize) -> Vec<Vec<usize>> {
    if k <= 1 {
        return vec![(0..k).collect()];
    }
    let mut out = Vec::new();
    for p in permutations(k - 1) {
        for pos in 0..k {
            let mut q = p.clone();
            q.insert(pos, k - 1);
            out.push(q);
        }
    }
    out
}

/// For each child after the first, the permutation of its lobes matching child 0's lobes
/// that minimises Σ cost(ref_k, child_π(k)); children with a different lobe count are
/// padded by repeating their heaviest lobe with weight 0.
pub fn align<T: Copy>(
    children: &[Vec<T>],
    cost: &dyn Fn(&T, &T) -> f64,
    zero: &dyn Fn(&T) -> T,
) -> Vec<Vec<T>> {
    let k = children.iter().map(|c| c.len()).max().unwrap_or(0);
    let pad = |c: &Vec<T>| {
        let mut c = c.clone();
        while c.len() < k {
            let z = zero(&c[0]);
            c.push(z);
        }
        c
    };
    let reference = pad(&children[0]);
    let perms = permutations(k);
    let mut out = vec![reference.clone()];
    for ch in &children[1..] {
        let ch = pad(ch);
        let best = perms
            .iter()
            .min_by(|a, b| {
                let ca: f64 = a
                    .iter()
                    .enumerate()
                    .map(|(i, &j)| cost(&reference[i], &ch[j]))
                    .sum();
                let cb: f64 = b
                    .iter()
                    .enumerate()
                    .map(|(i, &j)| cost(&reference[i], &ch[j]))
                    .sum();
                ca.total_cmp(&cb)
            })
            .cloned()
            .unwrap_or_else(|| (0..k).collect());
        out.push(best.iter().map(|&j| ch[j]).collect());
    }
    out
}

/// The angular width of a slope lobe, for the alignment test.
fn slope_width(l: &SlopeLobe, base_var: f64) -> f64 {
    (2.0 * (l.var + base_var)).sqrt()
}

/// Tan et al.'s MIP-map step: the parent mixture from four equally weighted children.
/// A matched pair is misaligned when its means are farther apart than twice the sum of
/// the lobes' widths.
pub fn merge_slopes(children: &[SlopeMixture]) -> Merged<SlopeLobe> {
    let base = children[0].base_var;
    let lists: Vec<Vec<SlopeLobe>> = children.iter().map(|c| c.comps.clone()).collect();
    let aligned = align(&lists, &|a, b| (a.mean - b.mean).norm_squared(), &|a| {
        SlopeLobe { weight: 0.0, ..*a }
    });
    let k = aligned[0].len();
    let nc = children.len() as f64;
    let (mut misaligned, mut pairs) = (0, 0);
    let mut lobes = Vec::with_capacity(k);
    for i in 0..k {
        let (mut a, mut am, mut am2) = (0.0, V2::zeros(), 0.0);
        for ch in &aligned {
            let l = ch[i];
            a += l.weight / nc;
            am += l.mean * (l.weight / nc);
            am2 += (2.0 * l.var + l.mean.norm_squared()) * (l.weight / nc);
        }
        for ch in &aligned[1..] {
            let (r, l) = (aligned[0][i], ch[i]);
            if r.weight > 0.0 && l.weight > 0.0 {
                pairs += 1;
                if (r.mean - l.mean).norm() > 2.0 * (slope_width(&r, base) + slope_width(&l, base))
                {
                    misaligned += 1;
                }
            }
        }
        if a > 0.0 {
            let mean = am / a;
            let var = ((am2 / a - mean.norm_squared()) * 0.5).max(VAR_FLOOR);
            lobes.push(SlopeLobe {
                weight: a,
                mean,
                var,
            });
        }
    }
    Merged {
        lobes,
        misaligned,
        pairs,
    }
}

/// Han et al.'s MIP-map step for vMF lobes: a_k and r_k = a_k A(κ_k) μ_k averaged, then
/// μ = r/‖r‖ and κ = A⁻¹(‖r‖/a). Misaligned as for slopes, with the angular width
/// 1/√κ + the base lobe's α.
pub fn merge_vmf(children: &[VmfMixture], alpha: f64) -> Merged<VmfLobe> {
    let lists: Vec<Vec<VmfLobe>> = children.iter().map(|c| c.comps.clone()).collect();
    let aligned = align(&lists, &|a, b| 1.0 - a.mu.dot(&b.mu), &|a| VmfLobe {
        weight: 0.0,
        ..*a
    });
    let k = aligned[0].len();
    let nc = children.len() as f64;
    let width = |l: &VmfLobe| 1.0 / l.kappa.max(1e-12).sqrt() + alpha;
    let (mut misaligned, mut pairs) = (0, 0);
    let mut lobes = Vec::with_capacity(k);
    for i in 0..k {
        let (mut a, mut r) = (0.0, V3::zeros());
        for ch in &aligned {
            let l = ch[i];
            a += l.weight / nc;
            r += l.mu * (l.weight * langevin(l.kappa) / nc);
        }
        for ch in &aligned[1..] {
            let (p, l) = (aligned[0][i], ch[i]);
            if p.weight > 0.0 && l.weight > 0.0 {
                pairs += 1;
                let ang = p.mu.dot(&l.mu).clamp(-1.0, 1.0).acos();
                if ang > 2.0 * (width(&p) + width(&l)) {
                    misaligned += 1;
                }
            }
        }
        if a > 0.0 && r.norm() > 0.0 {
            lobes.push(VmfLobe {
                weight: a,
                mu: r.normalize(),
                kappa: inverse_langevin(r.norm() / a),
            });
        }
    }
    Merged {
        lobes,
        misaligned,
        pairs,
    }
}

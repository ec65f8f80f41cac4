//! A compact LTC table (`ltc::compact`) fitted by the lobe error a shader sees, not by the
//! distance to the table's entries.
//!
//! The shader reads the rebuilt table bilinearly: at (r, t) between texels it uses
//! e = Σ_q w_q E(texel_q), the four corners' entries weighted bilinearly, where each
//! entry E is the channel's series at the texel centre through its transform. The lobe
//! it shades with is norm·D_e, D_e the LTC density of the production inverse
//! M⁻¹ = [[e₀, 0, e₂], [0, 1, 0], [e₁, 0, e₃]] (seed 000 / Heitz et al. 2016 Eq 1):
//!
//!   D_e(l) = |det M⁻¹|·x_z / (π |x|⁴),   x = M⁻¹ l  (0 where x_z ≤ 0).
//!
//! The objective is the mean over training places of the squared relative L2 over the
//! sphere, ‖f − norm·D_e‖² / ‖f‖² = 1 − (2·norm·∫f·D_e − norm²·∫D_e²)/∫f² (as the judge
//! `ltc::lobe_error` measures it: lobe mass below the horizon is error). ∫f² and ∫f·D_e
//! are estimated on 3·n² fixed balance nodes drawn from the target's sampler, the start
//! lobe and the clamped cosine ([`draw`]); ∫D_e² on the lobe's own n² samples, mapped
//! from fixed cosine points ([`self_overlap`]), so the estimate moves with the lobe and
//! mass the nodes miss still counts.
//! The five lobe channels' coefficients (a, b, c, d, norm: 5·p² unknowns) move together
//! by Levenberg–Marquardt: the residuals' derivatives with respect to a place's five
//! entries are analytic (below; the Hessian is JᵀJ of the node residuals
//! √w_k(f_k − norm·D_k), the gradient exact), and the chain to the coefficients is linear
//! (∂e_c/∂C_c,kl = Σ_q w_q·E′_c(q)·T_k(x_q)·T_l(y_q), E′ = 1 for a raw channel, E for a
//! log one), so the normal equations are assembled place by place from 5×5 blocks. After
//! each pass the nodes are redrawn from the fitted lobes. The fresnel channel is not part
//! of the lobe and keeps its start.
//!
//! Training places are every texel centre (where a table's own cells are fitted) and one
//! point per table square at a low-discrepancy offset inside it (the R₂ sequence), so
//! the reading between texels is fitted where no judged square centre lies.
//! Assembly runs in a fixed number of place blocks summed in order: the same bits at any
//! thread count. The fit is in f64 on the series' values; binary16 storage is applied by
//! `Compact::rebuild` afterwards, and the study judges that.

use super::compact::{vandermonde, Compact};
use super::gauss_newton::Nodes;
use super::target::LtcTarget;
use super::LtcDist;
use crate::error::{Error, Result};
use crate::integrate::mc::{CosineHemisphere, Strategy};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use rayon::prelude::*;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// The lobe channels (a, b, c, d, norm) a lobe fit moves.
const LOBE: usize = 5;
/// The smallest relative L2 a place's weight divides by.
const WEIGHT_FLOOR: f64 = 0.02;
/// Place blocks the normal equations are summed over (fixed: thread-count independent).
const BLOCKS: usize = 16;

/// How a lobe fit runs.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LobeFit {
    /// n: 3·n² nodes per training place.
    pub nodes: usize,
    /// Levenberg–Marquardt iterations per pass at most.
    pub iterations: usize,
    /// Node draws (the first from the start series, each next from the last fit).
    pub passes: usize,
}

/// What a lobe fit did: per pass the mean relative L2 over the training places on that
/// pass's nodes, at its start and end, and the iterations taken.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Trace {
    pub places: usize,
    pub nodes_per_place: usize,
    pub passes: Vec<[f64; 2]>,
    pub iterations: usize,
}

/// The LTC density of production entries `e` = (a, b, c, d) at `l` and its derivatives
/// with respect to the four entries (the module doc's D_e).
pub fn density_grad(e: &[f64; 4], l: &V3) -> (f64, [f64; 4]) {
    let x1 = e[0] * l.x + e[2] * l.z;
    let x3 = e[1] * l.x + e[3] * l.z;
    if x3 <= 0.0 {
        return (0.0, [0.0; 4]);
    }
    let q = x1 * x1 + l.y * l.y + x3 * x3;
    let det = e[0] * e[3] - e[2] * e[1];
    let (s, ad) = (det.signum(), det.abs());
    let k = 1.0 / (PI * q * q);
    let d = ad * x3 * k;
    let h = 4.0 * d / q;
    (
        d,
        [
            s * e[3] * x3 * k - h * x1 * l.x,
            -s * e[2] * x3 * k + ad * l.x * k - h * x3 * l.x,
            -s * e[1] * x3 * k - h * x1 * l.z,
            s * e[0] * x3 * k + ad * l.z * k - h * x3 * l.z,
        ],
    )
}

/// A training place: the four texels read there (index i + n·j) with their bilinear
/// weights, and its nodes.
struct Place {
    corner: [usize; 4],
    w: [f64; 4],
    nodes: Nodes,
    /// The place's weight in the objective (1/its relative L2 at the pass's start).
    weight: f64,
}

/// The fractional part of the R₂ sequence's k-th point (offset ½).
fn r2(k: usize) -> (f64, f64) {
    const G: f64 = 1.324_717_957_244_746; // the plastic number
    let (a1, a2) = (1.0 / G, 1.0 / (G * G));
    ((0.5 + a1 * k as f64).fract(), (0.5 + a2 * k as f64).fract())
}

/// The series' lobe channels at the texel centres: per texel the five entries and their
/// derivatives with respect to the series value (`Transform::slope`).
fn texels(c: &Compact, theta: &DVector<f64>, a: &DMatrix<f64>) -> Vec<([f64; LOBE], [f64; LOBE])> {
    let (n, p) = (a.nrows(), c.p);
    let mut out = vec![([0.0; LOBE], [0.0; LOBE]); n * n];
    for ch in 0..LOBE {
        let cm = DMatrix::from_fn(p, p, |k, l| theta[ch * p * p + k + p * l]);
        let s = a * cm * a.transpose();
        for j in 0..n {
            for i in 0..n {
                let v = s[(i, j)];
                let o = &mut out[i + n * j];
                let r = i as f64 / (n - 1) as f64;
                let alpha = (r * r).max(c.alpha_min);
                let tr = c.channels[ch].transform;
                o.0[ch] = tr.inverse(v, alpha);
                o.1[ch] = tr.slope(v, alpha);
            }
        }
    }
    out
}

/// The entries read at a place.
fn entries_at(pl: &Place, tex: &[([f64; LOBE], [f64; LOBE])]) -> [f64; LOBE] {
    std::array::from_fn(|ch| (0..4).map(|q| pl.w[q] * tex[pl.corner[q]].0[ch]).sum())
}

/// ∫D_e² over the sphere and its derivatives in (a, b, c, d), estimated on the lobe's own
/// samples: l = Mx/|Mx| for the clamped-cosine points x of `xs`, where
/// D_e(l) = (x_z/π)·|v|³/det², v = adj(M⁻¹)·x = (d x₁ − c x₃, det·x₂, a x₃ − b x₁) and
/// det = ad − cb. The points are fixed, so the estimate is a smooth function of e.
pub fn self_overlap(e: &[f64; 4], xs: &[V3]) -> (f64, [f64; 4]) {
    let det = e[0] * e[3] - e[2] * e[1];
    if xs.is_empty() || det == 0.0 || !det.is_finite() {
        return (f64::INFINITY, [0.0; 4]);
    }
    let ddet = [e[3], -e[2], -e[1], e[0]];
    let (mut s, mut g) = (0.0, [0.0; 4]);
    for x in xs {
        let v = V3::new(e[3] * x.x - e[2] * x.z, det * x.y, e[0] * x.z - e[1] * x.x);
        let vv = v.norm_squared();
        let sx = x.z / PI * vv * vv.sqrt() / (det * det);
        // ∂v/∂e_i
        let dv = [
            V3::new(0.0, e[3] * x.y, x.z),
            V3::new(0.0, -e[2] * x.y, -x.x),
            V3::new(-x.z, -e[1] * x.y, 0.0),
            V3::new(x.x, e[0] * x.y, 0.0),
        ];
        s += sx;
        for i in 0..4 {
            g[i] += sx * (3.0 * v.dot(&dv[i]) / vv - 2.0 * ddet[i] / det);
        }
    }
    let k = 1.0 / xs.len() as f64;
    (s * k, g.map(|v| v * k))
}

/// A place's squared relative L2, (∫f² − 2·norm·∫f·D + norm²·∫D²)/∫f²: ∫f² and ∫f·D on
/// its nodes, ∫D² on the lobe's own samples ([`self_overlap`]), so lobe mass the nodes
/// miss (a spike, mass below the horizon) still counts in full. ∞ where not finite.
fn place_cost(pl: &Place, e: &[f64; LOBE], xs: &[V3]) -> f64 {
    let m = [e[0], e[1], e[2], e[3]];
    let mut x = 0.0;
    for ((l, f), w) in pl.nodes.l.iter().zip(&pl.nodes.f).zip(&pl.nodes.w) {
        x += w * f * density_grad(&m, l).0;
    }
    let (s2, _) = self_overlap(&m, xs);
    let c = 1.0 + (e[4] * e[4] * s2 - 2.0 * e[4] * x) / pl.nodes.f2;
    if c.is_finite() {
        c
    } else {
        f64::INFINITY
    }
}

/// The weighted mean of the places' costs (the objective), or with `weighted` false the
/// mean of their relative L2s, √cost (what the trace reports).
fn cost(places: &[Place], tex: &[([f64; LOBE], [f64; LOBE])], xs: &[V3], weighted: bool) -> f64 {
    let parts: Vec<f64> = places
        .par_chunks(places.len().div_ceil(BLOCKS).max(1))
        .map(|b| {
            b.iter()
                .map(|pl| {
                    let c = place_cost(pl, &entries_at(pl, tex), xs);
                    if weighted {
                        pl.weight * c
                    } else {
                        c.max(0.0).sqrt()
                    }
                })
                .sum()
        })
        .collect();
    parts.iter().sum::<f64>() / places.len() as f64
}

/// The Gauss–Newton system of the mean cost over the 5·p² lobe coefficients: JᵀJ of the
/// node residuals r_k = √(w_k/∫f²)(f_k − norm·D_k) (which stand in for the curvature of
/// ∫(f − g)²) and half the exact gradient of [`place_cost`].
fn assemble(
    places: &[Place],
    tex: &[([f64; LOBE], [f64; LOBE])],
    xs: &[V3],
    a: &DMatrix<f64>,
    p: usize,
) -> (DMatrix<f64>, DVector<f64>) {
    let n = a.nrows();
    let pp = p * p;
    let dim = LOBE * pp;
    let parts: Vec<(Vec<f64>, Vec<f64>)> = places
        .par_chunks(places.len().div_ceil(BLOCKS).max(1))
        .map(|block| {
            // row-major, upper blocks only (x ≤ y)
            let mut h = vec![0.0; dim * dim];
            let mut g = vec![0.0; dim];
            let mut phi = vec![0.0; dim];
            for pl in block {
                let e = entries_at(pl, tex);
                let m = [e[0], e[1], e[2], e[3]];
                // JᵀJ of the node residuals; ½∇ of the cost in the entries
                let mut gg = [[0.0; LOBE]; LOBE];
                let mut gr = [0.0; LOBE];
                let inv_f2 = 1.0 / pl.nodes.f2;
                let nm = e[4];
                for ((l, f), w) in pl.nodes.l.iter().zip(&pl.nodes.f).zip(&pl.nodes.w) {
                    let (d, dd) = density_grad(&m, l);
                    let sw = (w * inv_f2).sqrt();
                    let jr = [
                        -sw * nm * dd[0],
                        -sw * nm * dd[1],
                        -sw * nm * dd[2],
                        -sw * nm * dd[3],
                        -sw * d,
                    ];
                    let wf = w * inv_f2 * f;
                    for x in 0..4 {
                        gr[x] -= wf * nm * dd[x];
                    }
                    gr[4] -= wf * d;
                    for x in 0..LOBE {
                        for y in x..LOBE {
                            gg[x][y] += jr[x] * jr[y];
                        }
                    }
                }
                let (s2, ds2) = self_overlap(&m, xs);
                for x in 0..4 {
                    gr[x] += 0.5 * nm * nm * ds2[x] * inv_f2;
                }
                gr[4] += nm * s2 * inv_f2;
                let wt = pl.weight;
                gr.iter_mut().for_each(|v| *v *= wt);
                gg.iter_mut().flatten().for_each(|v| *v *= wt);
                // the chain to the coefficients: φ_c = Σ_q w_q E′_c(q) T(x_q) ⊗ T(y_q)
                phi.iter_mut().for_each(|v| *v = 0.0);
                for ch in 0..LOBE {
                    let f = &mut phi[ch * pp..(ch + 1) * pp];
                    for q in 0..4 {
                        let (i, j) = (pl.corner[q] % n, pl.corner[q] / n);
                        let s = pl.w[q] * tex[pl.corner[q]].1[ch];
                        if s == 0.0 {
                            continue;
                        }
                        for l in 0..p {
                            let sl = s * a[(j, l)];
                            for k in 0..p {
                                f[k + p * l] += sl * a[(i, k)];
                            }
                        }
                    }
                }
                for x in 0..LOBE {
                    let fx = &phi[x * pp..(x + 1) * pp];
                    for (u, &fu) in fx.iter().enumerate() {
                        g[x * pp + u] += gr[x] * fu;
                    }
                    for y in x..LOBE {
                        let gxy = gg[x][y];
                        let fy = &phi[y * pp..(y + 1) * pp];
                        for (u, &fu) in fx.iter().enumerate() {
                            let s = gxy * fu;
                            if s == 0.0 {
                                continue;
                            }
                            let row = &mut h[(x * pp + u) * dim + y * pp..][..pp];
                            for (hv, &fv) in row.iter_mut().zip(fy) {
                                *hv += s * fv;
                            }
                        }
                    }
                }
            }
            (h, g)
        })
        .collect();
    let mut hs = vec![0.0; dim * dim];
    let mut g = DVector::<f64>::zeros(dim);
    for (hb, gb) in parts {
        hs.iter_mut().zip(&hb).for_each(|(a, b)| *a += b);
        g.iter_mut().zip(&gb).for_each(|(a, b)| *a += b);
    }
    // the blocks at and above the diagonal were summed (x ≤ y); the diagonal blocks are
    // whole, the blocks below are the mirror of those above
    let h = DMatrix::from_fn(dim, dim, |r, c| {
        if r / pp <= c / pp {
            hs[r * dim + c]
        } else {
            hs[c * dim + r]
        }
    });
    let s = 1.0 / places.len() as f64;
    (h * s, g * s)
}

/// The start lobe at a place (the entries read there), for drawing its nodes; the
/// clamped cosine where the entries are singular.
fn start_lobe(e: &[f64; LOBE]) -> LtcDist {
    let inv = Matrix3::new(e[0], 0.0, e[2], 0.0, 1.0, 0.0, e[1], 0.0, e[3]);
    inv.try_inverse()
        .and_then(|m| LtcDist::new(m).ok())
        .unwrap_or_else(|| LtcDist::new(Matrix3::identity()).expect("the identity is a valid LTC"))
}

/// 3·n² balance nodes at a place: n×n stratified samples (offset ½) each from the target,
/// the start lobe and the clamped cosine, weighted 1/(n²(p_target + p_start + p_cosine)): Σ w·h
/// over them estimates ∫h. The
/// cosine third is defensive: a trial lobe that moves mass where neither the target nor
/// the start puts any is still seen there, so the fit cannot hide error between nodes.
fn draw<T: LtcTarget + ?Sized>(t: &T, start: &LtcDist, n: usize) -> Nodes {
    Nodes::balance(t, start, &[&CosineHemisphere], n, (n * n) as f64)
}

/// The training places at grid positions `pos` ((x, y) ∈ [0, n − 1]²), each with its
/// nodes drawn from its target and from the lobe `tex` gives there.
fn places_at<T: LtcTarget>(
    pos: &[(f64, f64)],
    tex: &[([f64; LOBE], [f64; LOBE])],
    n: usize,
    alpha_min: f64,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    nodes: usize,
) -> Result<Vec<Place>> {
    pos.par_iter()
        .map(|&(x, y)| {
            let (r, t) = (x / (n - 1) as f64, y / (n - 1) as f64);
            // the square read there (the last texel row reads its square at weight 1)
            let (i, j) = ((x as usize).min(n - 2), (y as usize).min(n - 2));
            let (u, v) = (x - i as f64, y - j as f64);
            let lobe = target((r * r).max(alpha_min), (1.0 - t * t).clamp(0.0, 1.0).acos())?;
            let corner = [
                i + n * j,
                i + 1 + n * j,
                i + n * (j + 1),
                i + 1 + n * (j + 1),
            ];
            let w = [(1.0 - u) * (1.0 - v), u * (1.0 - v), (1.0 - u) * v, u * v];
            let mut pl = Place {
                corner,
                w,
                nodes: Nodes {
                    l: Vec::new(),
                    f: Vec::new(),
                    w: Vec::new(),
                    f2: 1.0,
                },
                weight: 1.0,
            };
            let e = entries_at(&pl, tex);
            pl.nodes = draw(&lobe, &start_lobe(&e), nodes);
            Ok(pl)
        })
        .collect()
}

/// Refine `start` (a compact form of an n×n table) by the lobe error after bilinear
/// reading of its rebuilt texels, against `target(α, θ)` at α = max(r², `alpha_min`),
/// θ = acos(1 − t²). Returns the refined form (the fresnel channel as `start`'s) and what
/// the fit did. A typed error for a side below 2, a zero node count or pass count, or a
/// target that cannot be built.
pub fn refine<T: LtcTarget>(
    start: &Compact,
    n: usize,
    alpha_min: f64,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    plan: LobeFit,
    label: &str,
) -> Result<(Compact, Trace)> {
    start.check()?;
    if !(alpha_min > 0.0 && alpha_min < 1.0) {
        return Err(Error::InvalidArgument(format!(
            "compact LTC lobe fit: the grid's α floor {alpha_min} is not in (0, 1)"
        )));
    }
    if !(2..=crate::ltc::table::MAX_SIDE).contains(&n) || plan.nodes == 0 || plan.passes == 0 {
        return Err(Error::InvalidArgument(format!(
            "compact LTC lobe fit: side {n} (2..={}), {} nodes, {} passes (both ≥ 1)",
            crate::ltc::table::MAX_SIDE,
            plan.nodes,
            plan.passes
        )));
    }
    let p = start.p;
    let pp = p * p;
    let a = vandermonde(n, p);
    let mut theta = DVector::from_iterator(
        LOBE * pp,
        start.channels[..LOBE]
            .iter()
            .flat_map(|s| s.coeffs.iter().copied()),
    );
    // grid positions (x, y) ∈ [0, n − 1]²: one R₂ point inside every square, then every
    // texel centre (where a table's own cells are fitted)
    let squares: Vec<(f64, f64)> = (0..(n - 1) * (n - 1))
        .map(|k| {
            let (u, v) = r2(k);
            ((k % (n - 1)) as f64 + u, (k / (n - 1)) as f64 + v)
        })
        .chain((0..n * n).map(|k| ((k % n) as f64, (k / n) as f64)))
        .collect();
    let bar = crate::progress::Progress::new(
        format!("{label}: lobe fit p = {p}"),
        (plan.passes * plan.iterations) as u64,
    );
    // the clamped-cosine points every lobe's own samples are mapped from
    let xs: Vec<V3> = (0..plan.nodes * plan.nodes)
        .filter_map(|k| {
            let (i, j) = (k % plan.nodes, k / plan.nodes);
            CosineHemisphere.sample([
                (i as f64 + 0.5) / plan.nodes as f64,
                (j as f64 + 0.5) / plan.nodes as f64,
            ])
        })
        .collect();
    let mut trace = Trace {
        places: squares.len(),
        nodes_per_place: 3 * plan.nodes * plan.nodes,
        passes: Vec::new(),
        iterations: 0,
    };
    for _pass in 0..plan.passes {
        let mut tex = texels(start, &theta, &a);
        let places = places_at(&squares, &tex, n, alpha_min, target, plan.nodes)?;
        // places whose target vanishes on every node carry no error to fit
        let places: Vec<Place> = places
            .into_iter()
            .filter(|pl| pl.nodes.f2 > 0.0 && pl.nodes.f2.is_finite())
            .collect();
        if places.is_empty() {
            return Err(Error::InvalidArgument(
                "compact LTC lobe fit: the target vanishes at every training place".into(),
            ));
        }
        // weights 1/relative L2 (at most 1/WEIGHT_FLOOR): the objective then follows the
        // mean relative L2, not its square, so the few places no LTC fits do not set the
        // coefficients for all the others
        let mut places = places;
        for pl in places.iter_mut() {
            let e = place_cost(pl, &entries_at(pl, &tex), &xs).max(0.0).sqrt();
            pl.weight = 1.0 / e.max(WEIGHT_FLOOR);
        }
        let mut c = cost(&places, &tex, &xs, true);
        let c0 = cost(&places, &tex, &xs, false);
        let mut lambda = 1e-3;
        for _ in 0..plan.iterations {
            trace.iterations += 1;
            bar.inc(1);
            let (h, g) = assemble(&places, &tex, &xs, &a, p);
            let mut improved = false;
            while lambda < 1e12 {
                let mut m = h.clone();
                let top = (0..m.nrows()).map(|k| h[(k, k)]).fold(0.0, f64::max);
                for k in 0..m.nrows() {
                    m[(k, k)] = h[(k, k)] * (1.0 + lambda) + 1e-14 * top;
                }
                let Some(ch) = m.cholesky() else {
                    lambda *= 10.0;
                    continue;
                };
                let trial = &theta - ch.solve(&g);
                let trial_tex = texels(start, &trial, &a);
                let ct = cost(&places, &trial_tex, &xs, true);
                if ct < c {
                    let gain = (c - ct) / c.max(1e-300);
                    theta = trial;
                    tex = trial_tex;
                    c = ct;
                    lambda = (lambda / 3.0).max(1e-9);
                    improved = gain > 1e-7;
                    break;
                }
                lambda *= 4.0;
            }
            if !improved {
                break;
            }
        }
        trace.passes.push([c0, cost(&places, &tex, &xs, false)]);
    }
    bar.finish();
    let mut out = start.clone();
    for ch in 0..LOBE {
        out.channels[ch].coeffs = theta.as_slice()[ch * pp..(ch + 1) * pp].to_vec();
    }
    out.check()?;
    Ok((out, trace))
}

//! The two studies of the footprint-filter work (seed 004 Eq 11): mip-map filters on normal maps, and screen-space
//! kernels on synthetic derivative fields (curved surfaces seen at varying distance,
//! where the footprint's normal distribution is known exactly).

use super::footprint::Stats;
use super::registry::{screen_index, MapRule, ScreenRule, MAP, SCREEN};
use super::rules;
use super::truth::{matrix, Candidate, Footprint, Frame};
use crate::error::Result;
use crate::microfacet::{Microsurface, NdfKind};
use crate::multiscale::mrl::{alpha_from_one_minus, mrl_pair};
use nalgebra::{Vector2, Vector3};

type V3 = Vector3<f64>;

/// α′ of every isotropic map filter (f64 references), indexed like [`MAP`] (LEAN is
/// anisotropic: NaN here).
pub fn map_alphas(alpha: f64, r: f64) -> Result<[f64; 12]> {
    let y = 1.0 - r * mrl_pair(alpha).0;
    let moment = alpha_from_one_minus(y.max(1e-300))?;
    Ok(MAP.map(|f| f.rule.alpha(alpha, r, || moment).unwrap_or(f64::NAN)))
}

/// The map-filter candidates for one footprint's statistics.
pub fn map_candidates<'a>(kind: NdfKind, alpha: f64, s: &Stats) -> Result<Vec<Candidate<'a>>> {
    let mu = V3::from(s.mean_normal);
    let r = mu.norm().min(1.0);
    let nbar = mu / mu.norm();
    let alphas = map_alphas(alpha, r)?;
    let mut out = Vec::new();
    for (f, a) in MAP.iter().zip(alphas) {
        if f.rule == MapRule::Lean {
            let a = rules::lean(alpha, s.covariance());
            let surf = Microsurface::new(kind, matrix(a)?).with_mean(s.mean_slope())?;
            out.push(Candidate::surface(f.label, surf, Frame::around(V3::z())));
        } else {
            out.push(Candidate::iso(f.label, kind, nbar, a.max(1e-4))?);
        }
    }
    Ok(out)
}

/// A synthetic curved surface seen by a pixel: the normal at screen offset p (pixels)
/// is normalize(z + R_ψ diag(κ_u, κ_v) p) — tangent components linear in p, as for a
/// sphere or cylinder whose curvature × distance gives κ radians per pixel.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Field {
    pub kappa_u: f64,
    pub kappa_v: f64,
    pub psi: f64,
}

impl Field {
    pub fn normal(&self, x: f64, y: f64) -> V3 {
        let (c, s) = (self.psi.cos(), self.psi.sin());
        let (a, b) = (self.kappa_u * x, self.kappa_v * y);
        V3::new(c * a - s * b, s * a + c * b, 1.0).normalize()
    }
}

/// The pixel's reconstruction footprint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum PixelFilter {
    /// Gaussian with per-axis variance 0.25 px² (the kernels' own σ², seed 003 Eq 2).
    Gaussian,
    /// The 1×1 pixel box (variance 1/12 px²).
    Box,
}

/// The truth footprint of a pixel, for base roughness α: a tensor midpoint rule with
/// uniform node spacing (Gaussian: ±4σ, weights ∝ the density; box: the pixel) and
/// n = clamp(8 + ⌈8·spread/α⌉, 8, 64) nodes per axis, so that neighbouring nodes' normals
/// differ by less than about α/2 and the sum of per-node lobes resolves the continuous
/// average (tests/filters.rs checks n against 2n). κ/α is kept ≤ 8 by the plan.
pub fn pixel_footprint(f: &Field, pf: PixelFilter, alpha: f64) -> Footprint {
    let kmax = f.kappa_u.abs().max(f.kappa_v.abs());
    let half = match pf {
        PixelFilter::Gaussian => 2.0, // 4σ with σ = 0.5 px
        PixelFilter::Box => 0.5,
    };
    let n = (8.0 + (8.0 * kmax * half / alpha).ceil()).clamp(8.0, 64.0) as usize;
    let h = 2.0 * half / n as f64;
    let nodes: Vec<f64> = (0..n).map(|i| -half + (i as f64 + 0.5) * h).collect();
    let w1: Vec<f64> = match pf {
        PixelFilter::Gaussian => nodes.iter().map(|x| (-2.0 * x * x).exp()).collect(),
        PixelFilter::Box => vec![1.0; n],
    };
    let s1: f64 = w1.iter().sum();
    let mut ns = Vec::with_capacity(n * n);
    let mut ws = Vec::with_capacity(n * n);
    for (i, x) in nodes.iter().enumerate() {
        for (j, y) in nodes.iter().enumerate() {
            ns.push(f.normal(*x, *y));
            ws.push(w1[i] * w1[j] / (s1 * s1));
        }
    }
    Footprint {
        normals: ns,
        weights: ws,
    }
}

/// Quad derivatives as a GPU computes them for the even pixel at the origin:
/// ddx = value(1, 0) − value(0, 0), ddy = value(0, 1) − value(0, 0).
fn quad_d<T: Copy + std::ops::Sub<Output = T>>(g: &dyn Fn(f64, f64) -> T) -> (T, T) {
    let c = g(0.0, 0.0);
    (g(1.0, 0.0) - c, g(0.0, 1.0) - c)
}

fn arr3(v: V3) -> [f64; 3] {
    [v.x, v.y, v.z]
}
fn arr2(v: Vector2<f64>) -> [f64; 2] {
    [v.x, v.y]
}

/// Isotropic α′ of every kernel for a field, indexed like [`SCREEN`] (the forward
/// kernels are anisotropic and per light: NaN here).
pub fn screen_alphas(alpha: f64, f: &Field) -> [f64; 12] {
    let (du, dv) = quad_d(&|x, y| f.normal(x, y));
    let (du, dv) = (arr3(du), arr3(dv));
    // projected-disk derivatives in the centre's tangent frame (centre normal = z)
    let c = Frame::around(f.normal(0.0, 0.0));
    let (pu, pv) = quad_d(&|x, y| {
        let n = c.local(&f.normal(x, y));
        Vector2::new(n.x, n.y)
    });
    // Listing 3 as intended: project the quad's normals in the frame of the quad average
    let avg = (f.normal(0.0, 0.0) + f.normal(1.0, 0.0) + f.normal(0.0, 1.0) + f.normal(1.0, 1.0))
        .normalize();
    let qf = Frame::around(avg);
    let (su, sv) = quad_d(&|x, y| {
        let n = qf.local(&f.normal(x, y));
        Vector2::new(n.x / n.z.abs(), n.y / n.z.abs())
    });
    SCREEN.map(|k| {
        (k.rule.alpha_from_normals(alpha, du, dv))
            .or_else(|| match k.rule {
                ScreenRule::Eigen { .. } => k.rule.alpha_from_2d(alpha, arr2(pu), arr2(pv)),
                _ => k.rule.alpha_from_2d(alpha, arr2(su), arr2(sv)),
            })
            .unwrap_or(f64::NAN)
    })
}

/// Forward kernels: the roughness matrix for light l (the half-vector's derivatives in
/// each pixel's own tangent frame; slope space when `slope`, projected disk otherwise).
pub fn forward_a(alpha: f64, f: &Field, v: &V3, l: &V3, slope: bool) -> [f64; 3] {
    let h = (v + l).normalize();
    let (du, dv) = quad_d(&|x, y| {
        let hl = Frame::around(f.normal(x, y)).local(&h);
        if slope {
            Vector2::new(-hl.x / hl.z, -hl.y / hl.z)
        } else {
            Vector2::new(hl.x, hl.y)
        }
    });
    rules::forward_matrix(alpha, arr2(du), arr2(dv), 0.25)
}

/// The screen-space candidates for one field.
pub fn screen_candidates<'a>(
    kind: NdfKind,
    alpha: f64,
    f: &'a Field,
) -> Result<Vec<Candidate<'a>>> {
    let n0 = f.normal(0.0, 0.0);
    let alphas = screen_alphas(alpha, f);
    let frame = Frame::around(n0);
    // the forward kernels draw their samples around the exact eigenvalue kernel's lobe
    let prop_alpha = alphas[screen_index("eigen-eq10")];
    let mut out = Vec::new();
    for (k, a) in SCREEN.iter().zip(alphas) {
        let ScreenRule::Forward { slope } = k.rule else {
            out.push(Candidate::iso(k.label, kind, n0, a.max(1e-4))?);
            continue;
        };
        out.push(Candidate {
            name: k.label.into(),
            value: Box::new(move |v: &V3, l: &V3| {
                if v.z <= 0.0 || l.z <= 0.0 {
                    return 0.0;
                }
                let a = forward_a(alpha, f, v, l, slope);
                // A = α²I + PSD is SPD whenever the derivatives are finite
                match matrix(a) {
                    Ok(r) => super::truth::lobe(&Microsurface::new(kind, r), &frame, v, l),
                    Err(_) => 0.0,
                }
            }),
            proposal: (n0, prop_alpha),
        });
    }
    Ok(out)
}

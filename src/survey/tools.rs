//! The generic tools of seed 004 §7: a map used non-linearly is pre-filtered through new
//! parameters K that average linearly (Eq 40, [`prefilter`]); the parameters characterise
//! either the average function f_A itself (direct) or the distribution p_A of the map's
//! values, which is then convolved with f (Eq 41–42, convolution). Three ways to choose K:
//!
//! | tool | direct | convolution |
//! |---|---|---|
//! | moments (§7.2, [`moments`], [`moment_match`]) | Olano & North (Eq 17), Olano & Baker / LEAN (Eq 19), Schilling, SGGX | Toksvig, the vMF rules (mean normal only) |
//! | basis (§7.3, [`basis_coefficients`]) | — (Legendre horizon maps, Fourier shadow maps: not normals) | Han et al.'s spherical harmonics |
//! | spanning set (§7.4) | Fournier's Blinn–Phong sums (Eq 20), Tan et al.'s Gaussians (Eq 21) | Han et al.'s vMF lobes (Eq 22) |
//!
//! [`TOOLS`] is that table as data; the survey report prints it.

use nalgebra::{Matrix2, SMatrix, SVector, Vector2, Vector3};

type V3 = Vector3<f64>;

/// A generic tool of §7.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Tool {
    Moments,
    Basis,
    SpanningSet,
}

/// Which function the parameters characterise (§7.1.1–7.1.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Method {
    /// The average function f_A (here the μNDF).
    Direct,
    /// The distribution p_A of the map's values (the macroscopic NDF), then a convolution.
    Convolution,
}

/// Every representation of the survey study with its tool and method.
pub const TOOLS: [(&str, Tool, Method); 11] = [
    ("Toksvig / vMF rules", Tool::Moments, Method::Convolution),
    ("Schilling", Tool::Moments, Method::Direct),
    ("Olano & North", Tool::Moments, Method::Direct),
    ("SGGX (Neyret)", Tool::Moments, Method::Direct),
    ("Olano & Baker", Tool::Moments, Method::Direct),
    ("LEAN", Tool::Moments, Method::Direct),
    ("Fournier", Tool::SpanningSet, Method::Direct),
    ("Tan et al.", Tool::SpanningSet, Method::Direct),
    ("Han et al. SH", Tool::Basis, Method::Convolution),
    ("Han et al. vMF", Tool::SpanningSet, Method::Convolution),
    ("exact q_A", Tool::Basis, Method::Direct),
];

/// Eq 40: K_A = Σ ŵ_x K_x, the linear pre-filter (a MIP level, a bilinear tap) of
/// per-texel parameter vectors.
pub fn prefilter(params: &[Vec<f64>], w: &[f64]) -> Vec<f64> {
    let n = params.first().map_or(0, |p| p.len());
    let mut out = vec![0.0; n];
    for (p, wi) in params.iter().zip(w) {
        for (o, x) in out.iter_mut().zip(p) {
            *o += wi * x;
        }
    }
    out
}

/// §7.2: the weighted first and second moments (E[y], E[yyᵀ]) of points y ∈ ℝᴺ.
pub fn moments<const N: usize>(
    points: &[SVector<f64, N>],
    w: &[f64],
) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
    let mut m1 = SVector::<f64, N>::zeros();
    let mut m2 = SMatrix::<f64, N, N>::zeros();
    for (p, wi) in points.iter().zip(w) {
        m1 += p * *wi;
        m2 += p * p.transpose() * *wi;
    }
    (m1, m2)
}

/// The best Gaussian of a mixture Σ w_i N(μ_i, Σ_i) (Σ w_i = 1) in the maximum-likelihood
/// (cross-entropy) sense: mean Σ w_i μ_i, second moment Σ w_i (Σ_i + μ_i μ_iᵀ)
/// (proofs/gaussian-moment-matching.md). Returns (mean, covariance).
pub fn moment_match(comps: &[(f64, Vector2<f64>, Matrix2<f64>)]) -> (Vector2<f64>, Matrix2<f64>) {
    let mut m = Vector2::zeros();
    let mut s = Matrix2::zeros();
    for (w, mu, c) in comps {
        m += mu * *w;
        s += (c + mu * mu.transpose()) * *w;
    }
    (m, s - m * m.transpose())
}

/// The cross-entropy −E_p[ln N(y; m, C)] of a 2D Gaussian mixture p against one Gaussian,
/// in closed form per component: ½ Σ w_i (ln|2πC| + tr(C⁻¹Σ_i) + (μ_i − m)ᵀC⁻¹(μ_i − m)).
/// `None` when C is not positive definite.
pub fn cross_entropy(
    comps: &[(f64, Vector2<f64>, Matrix2<f64>)],
    m: &Vector2<f64>,
    c: &Matrix2<f64>,
) -> Option<f64> {
    let det = c.determinant();
    if !(det > 0.0) || !(c[(0, 0)] > 0.0) {
        return None;
    }
    let inv = c.try_inverse()?;
    let ln_det = (2.0 * std::f64::consts::PI).powi(2).ln() + det.ln();
    Some(
        comps
            .iter()
            .map(|(w, mu, s)| {
                let d = mu - m;
                0.5 * w * (ln_det + (inv * s).trace() + d.dot(&(inv * d)))
            })
            .sum(),
    )
}

/// §7.3: the coefficients of the distribution Σ ŵ δ(η − n_x) in a basis B_k, Σ ŵ B_k(n_x)
/// (`basis` writes B_0..B_{n−1} at a direction).
pub fn basis_coefficients(
    basis: &dyn Fn(&V3, &mut [f64]),
    n: usize,
    points: &[V3],
    w: &[f64],
) -> Vec<f64> {
    let mut out = vec![0.0; n];
    let mut b = vec![0.0; n];
    for (p, wi) in points.iter().zip(w) {
        basis(p, &mut b);
        for (o, x) in out.iter_mut().zip(&b) {
            *o += wi * x;
        }
    }
    out
}

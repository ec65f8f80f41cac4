//! Closed-form eigen-decomposition of symmetric 2×2 matrices.
//!
//! Used instead of `nalgebra::SymmetricEigen` for 2×2: in this build, nalgebra 0.35's
//! iterative solver returned λ_max = 1.618·trace(Σ) for a nearly rank-one PSD matrix in an
//! optimisation-dependent way (reproduced in `verify`, vanished when a print was added);
//! the closed form below has no iteration and no such failure mode.

use nalgebra::{Matrix2, Vector2};

/// Eigenvalues (ascending) and the unit eigenvector of the larger one of the symmetric
/// matrix [[p, b], [b, q]]. The smaller eigenvalue is formed as det/λ_max when both have
/// the same sign, avoiding cancellation for nearly singular matrices.
pub fn sym2_eigen(m: &Matrix2<f64>) -> (f64, f64, Vector2<f64>) {
    let (p, q) = (m[(0, 0)], m[(1, 1)]);
    let b = 0.5 * (m[(0, 1)] + m[(1, 0)]);
    let mean = 0.5 * (p + q);
    let d = 0.5 * (p - q);
    let r = d.hypot(b);
    let hi = mean + r;
    let det = p * q - b * b;
    let lo = if hi != 0.0 && det > 0.0 {
        det / hi
    } else {
        mean - r
    };
    // eigenvector of hi: (b, hi − p) or (hi − q, b), whichever is better conditioned
    let v1 = Vector2::new(b, hi - p);
    let v2 = Vector2::new(hi - q, b);
    let v = if v1.norm_squared() >= v2.norm_squared() {
        v1
    } else {
        v2
    };
    let n = v.norm();
    let v = if n > 0.0 {
        v / n
    } else {
        Vector2::new(1.0, 0.0)
    };
    (lo, hi, v)
}

//! The parameters of an LTC cell fit and the matrix they stand for: p = (ln m11, ln m22,
//! m13/m11, φ), M = [X Y Z]·[[m11, 0, m13], [0, m22, 0], [0, 0, 1]] with Z the frame axis
//! turned by φ about Y (seed 000's LTC, Heitz et al. 2016 §4's parameterisation with the
//! production form's fourth degree of freedom). Shared by the Nelder–Mead reference
//! (`fit`) and the Levenberg–Marquardt route (`gauss_newton`); and the production form a
//! table stores, M⁻¹ normalised by its middle element, to and from them.

use crate::error::{Error, Result};
use nalgebra::{Matrix3, Vector3};

type V3 = Vector3<f64>;

/// M from the parameters and the frame.
pub fn matrix(m11: f64, m22: f64, m13: f64, z: &V3) -> Matrix3<f64> {
    let y = V3::y();
    let x = y.cross(z).normalize();
    let b = Matrix3::from_columns(&[x, y, *z]);
    b * Matrix3::new(m11, 0.0, m13, 0.0, m22, 0.0, 0.0, 0.0, 1.0)
}

/// (m11, m22, m13) from the fit parameters (ln m11, ln m22, m13/m11), clamped to a finite box.
pub fn params_to_m(p: &[f64]) -> (f64, f64, f64) {
    let m11 = p[0].clamp(-30.0, 5.0).exp();
    let m22 = p[1].clamp(-30.0, 5.0).exp();
    (m11, m22, p[2].clamp(-1e3, 1e3) * m11)
}

/// The frame axis `z` (in the xz-plane) turned by φ about Y.
pub fn turn(z: &V3, phi: f64) -> V3 {
    let (s, c) = phi.sin_cos();
    V3::new(z.x * c + z.z * s, 0.0, -z.x * s + z.z * c)
}

/// (a, b, c, d) of M⁻¹ normalised by its middle element (typed error if singular).
pub fn production_inverse(m: &Matrix3<f64>) -> Result<[f64; 4]> {
    let inv = m
        .try_inverse()
        .ok_or_else(|| Error::InvalidArgument("LTC matrix is singular".into()))?;
    let s = inv[(1, 1)];
    if !(s.is_finite() && s != 0.0) {
        return Err(Error::InvalidArgument(
            "LTC inverse has a zero middle element".into(),
        ));
    }
    let n = inv / s;
    Ok([n[(0, 0)], n[(2, 0)], n[(0, 2)], n[(2, 2)]])
}

/// The fit parameters of a production-form cell: (m11, m22, m13, φ) with the frame axis
/// `turn(zm, φ)`, i.e. the inverse of `production_inverse(matrix(m11, m22, m13, turn(zm, φ)))`.
/// M's xz-block is s·Q·[[m11, m13], [0, 1]] with Q the frame rotation and s = 1/m22 (the
/// production form has M_yy = 1): a QR factorisation. `None` where M is singular or the
/// factor's sign would flip the lobe below the horizon.
pub fn params_from_production(p: &[f64; 4], zm: &V3) -> Option<(f64, f64, f64, f64)> {
    // M⁻¹'s xz-block [[a, c], [b, d]] and its inverse A = M's xz-block
    let (a, b, c, d) = (p[0], p[1], p[2], p[3]);
    let det = a * d - b * c;
    if !(det.is_finite() && det != 0.0) {
        return None;
    }
    let m = [[d / det, -c / det], [-b / det, a / det]];
    // Gram–Schmidt on A's columns: q1 = (Z_z, −Z_x), q2 = (Z_x, Z_z)
    let col1 = [m[0][0], m[1][0]];
    let col2 = [m[0][1], m[1][1]];
    let u00 = (col1[0] * col1[0] + col1[1] * col1[1]).sqrt();
    if !(u00 > 0.0) {
        return None;
    }
    let q1 = [col1[0] / u00, col1[1] / u00];
    let q2 = [-q1[1], q1[0]];
    let u01 = q1[0] * col2[0] + q1[1] * col2[1];
    let s = q2[0] * col2[0] + q2[1] * col2[1];
    if !(s > 0.0) {
        return None;
    }
    let (zx, zz) = (q2[0], q2[1]);
    let phi = zx.atan2(zz) - zm.x.atan2(zm.z);
    Some((u00 / s, 1.0 / s, u01 / s, phi))
}

/// Rebuild M⁻¹ from the production form.
pub fn inverse_from_production(p: &[f64; 4]) -> Matrix3<f64> {
    Matrix3::new(p[0], 0.0, p[2], 0.0, 1.0, 0.0, p[1], 0.0, p[3])
}

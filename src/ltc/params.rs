//! The parameters of an LTC cell fit and the matrix they stand for: p = (ln m11, ln m22,
//! m13/m11, φ), M = [X Y Z]·[[m11, 0, m13], [0, m22, 0], [0, 0, 1]] with Z the frame axis
//! turned by φ about Y (seed 000's LTC, Heitz et al. 2016 §4's parameterisation with the
//! production form's fourth degree of freedom). Shared by the Nelder–Mead reference
//! (`fit`) and the Levenberg–Marquardt route (`gauss_newton`).

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

//! f32 shading forms of D, Λ, G1, G2 for centred surfaces, tested against the f64
//! reference ([`super::surface`]) in tests/shading_f32.rs with these stated bounds
//! (relative, inputs exactly representable in f32, reference built from the f32
//! parameters by [`Rough32::reference`]; k = 16·ε·√cond(A) for rotated anisotropic A
//! (ε = 2^-24), 0 otherwise — the minor-axis coordinate of a direction lying along the
//! major axis is a cancelling sum):
//! - GGX D and Λ: ≤ 2e-6 + k (2e-6 ≈ 16 ulp).
//! - Beckmann D: ≤ (1e-6 + k)·(4 + x) where x = w/m_z² is the exponent (exp amplifies the
//!   relative error of its argument by x).
//! - Beckmann Λ: ≤ (2e-5 + k)·(1 + ν²) + absolute 1e-30 (erfcf plus the cancellation of
//!   two nearly equal terms, replaced by an asymptotic series for ν ≥ 6).
//! - G1, G2: ≤ 1e-5 absolute.
//!
//! Cancellation: nothing here forms 1 − cos²θ. D uses m_xyᵀA⁻¹m_xy + m_z² directly
//! (|n×h|² rather than 1 − (n·h)², which is useless in f32 when α = 1e-4), and Λ uses
//! o_xyᵀ A o_xy / o_z².

use super::roughness::Roughness;

/// A roughness matrix prepared for f32 shading, in eigen form A = R·diag(α1², α2²)·Rᵀ.
/// Quadratic forms are then sums of two non-negative squares, xᵀA⁻¹x = (e1·x)²/α1² +
/// (e2·x)²/α2², with no cancellation whatever the conditioning of A (the entry form
/// A⁻¹11·x² + 2A⁻¹12·xy + A⁻¹22·y² loses ~log10(cond A) digits in f32).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rough32 {
    /// Unit major axis (cos φ, sin φ).
    pub c: f32,
    pub s: f32,
    /// α1², α2² along (c, s) and (−s, c).
    pub a1: f32,
    pub a2: f32,
    /// 1/α1², 1/α2².
    pub i1: f32,
    pub i2: f32,
    /// 1/(π√det A)
    pub norm: f32,
}

impl From<&Roughness> for Rough32 {
    fn from(r: &Roughness) -> Self {
        let (lo, hi, v) = crate::linalg::sym2_eigen(r.a());
        Rough32 {
            c: v.x as f32,
            s: v.y as f32,
            a1: hi as f32,
            a2: lo as f32,
            i1: (1.0 / hi) as f32,
            i2: (1.0 / lo) as f32,
            norm: (1.0 / (std::f64::consts::PI * r.sqrt_det())) as f32,
        }
    }
}

impl Rough32 {
    /// The f64 roughness this f32 form represents: A′ = R′·diag(α1², α2²)·R′ᵀ built from
    /// the f32-rounded parameters (R′ = [[c, −s], [s, c]] is a rotation scaled by
    /// c² + s² = 1 ± 1e-7). At high anisotropy the f32 rotation itself moves the lobe, so
    /// arithmetic error is measured against A′, not against the matrix that was rounded.
    pub fn reference(&self) -> crate::error::Result<Roughness> {
        let (c, s) = (self.c as f64, self.s as f64);
        let r = nalgebra::Matrix2::new(c, -s, s, c);
        let d = nalgebra::Matrix2::new(self.a1 as f64, 0.0, 0.0, self.a2 as f64);
        let mut a = r * d * r.transpose();
        let off = 0.5 * (a[(0, 1)] + a[(1, 0)]);
        a[(0, 1)] = off;
        a[(1, 0)] = off;
        Roughness::matrix(a)
    }
}

#[inline]
fn axes(r: &Rough32, x: f32, y: f32) -> (f32, f32) {
    (r.c * x + r.s * y, -r.s * x + r.c * y)
}

#[inline]
fn quad_inv(r: &Rough32, x: f32, y: f32) -> f32 {
    let (u, v) = axes(r, x, y);
    u * u * r.i1 + v * v * r.i2
}

#[inline]
fn quad(r: &Rough32, x: f32, y: f32) -> f32 {
    let (u, v) = axes(r, x, y);
    u * u * r.a1 + v * v * r.a2
}

/// GGX D(m) in f32 (seed 003 Eq 17).
pub fn d_ggx(r: &Rough32, m: [f32; 3]) -> f32 {
    if !(m[2] > 0.0) {
        return 0.0;
    }
    let s = quad_inv(r, m[0], m[1]) + m[2] * m[2];
    r.norm / (s * s)
}

/// Beckmann D(m) in f32 (seed 001 Eq 2 with Gaussian P22).
pub fn d_beckmann(r: &Rough32, m: [f32; 3]) -> f32 {
    if !(m[2] > 0.0) {
        return 0.0;
    }
    let z2 = m[2] * m[2];
    let e = (-quad_inv(r, m[0], m[1]) / z2).exp();
    if e == 0.0 {
        return 0.0;
    }
    r.norm * e / (z2 * z2)
}

/// 1/ν² = o_xyᵀAo_xy/o_z² (∞ for o_z ≤ 0).
#[inline]
fn inv_nu2(r: &Rough32, o: [f32; 3]) -> f32 {
    if !(o[2] > 0.0) {
        return f32::INFINITY;
    }
    quad(r, o[0], o[1]) / (o[2] * o[2])
}

/// GGX Λ(o) in f32 (seed 003 Eq 18), cancellation-free form.
pub fn lambda_ggx(r: &Rough32, o: [f32; 3]) -> f32 {
    let k = inv_nu2(r, o);
    if k.is_infinite() {
        return f32::INFINITY;
    }
    k / (2.0 * (1.0 + (1.0 + k).sqrt()))
}

/// Beckmann Λ(o) in f32 (exact formula; asymptotic series for ν ≥ 6).
pub fn lambda_beckmann(r: &Rough32, o: [f32; 3]) -> f32 {
    let k = inv_nu2(r, o);
    if k.is_infinite() {
        return f32::INFINITY;
    }
    if k == 0.0 {
        return 0.0;
    }
    let nu = 1.0 / k.sqrt();
    let inv_sqrt_pi = 0.564_189_6_f32;
    if nu >= 6.0 {
        // 8 terms of the asymptotic series; truncation < 5e-8 relative at ν = 6
        let x = 0.5 * k; // 1/(2ν²)
        let s = x
            * (1.0
                - 3.0
                    * x
                    * (1.0
                        - 5.0
                            * x
                            * (1.0
                                - 7.0
                                    * x
                                    * (1.0
                                        - 9.0
                                            * x
                                            * (1.0
                                                - 11.0
                                                    * x
                                                    * (1.0 - 13.0 * x * (1.0 - 15.0 * x)))))));
        return (-nu * nu).exp() * inv_sqrt_pi / (2.0 * nu) * s;
    }
    0.5 * ((-nu * nu).exp() * inv_sqrt_pi / nu - libm::erfcf(nu))
}

/// Smith G1(o) = 1/(1 + Λ(o)) given Λ.
#[inline]
pub fn g1_from_lambda(l: f32) -> f32 {
    if l.is_infinite() {
        0.0
    } else {
        1.0 / (1.0 + l)
    }
}

/// Height-correlated G2 = 1/(1 + Λ(i) + Λ(o)) given the two Λ (χ⁺ terms by the caller).
#[inline]
pub fn g2_from_lambdas(li: f32, lo: f32) -> f32 {
    let s = li + lo;
    if s.is_infinite() {
        0.0
    } else {
        1.0 / (1.0 + s)
    }
}

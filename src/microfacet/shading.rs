//! f32 shading forms of D, Λ, G1, G2 for centred surfaces, tested against the f64
//! reference ([`super::surface`]) in tests/shading_f32.rs with these stated bounds
//! (relative, for inputs exactly representable in f32):
//! - GGX D and Λ: ≤ 2e-6 (≈ 16 ulp).
//! - Beckmann D: ≤ 1e-6·(4 + x) where x = w/m_z² is the exponent (exp amplifies the
//!   relative error of its argument by x).
//! - Beckmann Λ: ≤ 2e-5·(1 + ν²) + absolute 1e-30 (erfcf plus the cancellation of two
//!   nearly equal terms, replaced by an asymptotic series for ν ≥ 6).
//! - G1, G2: ≤ 1e-5.
//!
//! Cancellation: nothing here forms 1 − cos²θ. D uses m_xyᵀA⁻¹m_xy + m_z² directly
//! (|n×h|² rather than 1 − (n·h)², which is useless in f32 when α = 1e-4), and Λ uses
//! o_xyᵀ A o_xy / o_z².

use super::roughness::Roughness;

/// A roughness matrix prepared for f32 shading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rough32 {
    pub a11: f32,
    pub a12: f32,
    pub a22: f32,
    pub i11: f32,
    pub i12: f32,
    pub i22: f32,
    /// 1/(π√det A)
    pub norm: f32,
}

impl From<&Roughness> for Rough32 {
    fn from(r: &Roughness) -> Self {
        let a = r.a();
        let i = r.inv();
        Rough32 {
            a11: a[(0, 0)] as f32,
            a12: a[(0, 1)] as f32,
            a22: a[(1, 1)] as f32,
            i11: i[(0, 0)] as f32,
            i12: i[(0, 1)] as f32,
            i22: i[(1, 1)] as f32,
            norm: (1.0 / (std::f64::consts::PI * r.sqrt_det())) as f32,
        }
    }
}

#[inline]
fn quad_inv(r: &Rough32, x: f32, y: f32) -> f32 {
    r.i11 * x * x + 2.0 * r.i12 * x * y + r.i22 * y * y
}

#[inline]
fn quad(r: &Rough32, x: f32, y: f32) -> f32 {
    r.a11 * x * x + 2.0 * r.a12 * x * y + r.a22 * y * y
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
                                            * (1.0 - 11.0 * x * (1.0 - 13.0 * x * (1.0 - 15.0 * x)))))));
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

//! AVX2 + FMA backend: the arithmetic of the generated scalar functions, 8 lanes at a
//! time. Each function processes the largest multiple of 8 and returns where it stopped;
//! the caller finishes the tail with the scalar twin.

use super::batch::{DeferredIn, LeadrIn, LtcQuadIn, SpecularIn};
use crate::generated::shading as g;
use std::arch::x86_64::*;

#[inline(always)]
unsafe fn ld(s: &[f32], i: usize) -> __m256 {
    _mm256_loadu_ps(s.as_ptr().add(i))
}

#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn ggx_specular(inp: &SpecularIn, out: &mut [f32]) -> usize {
    // the fused form of the generated `ggx_specular`, same operation order
    let n = out.len() / 8 * 8;
    let zero = _mm256_setzero_ps();
    let two_pi = _mm256_set1_ps(2.0 * g::PI);
    let mut i = 0;
    while i < n {
        let (lx, ly, lz) = (ld(inp.l[0], i), ld(inp.l[1], i), ld(inp.l[2], i));
        let (vx, vy, vz) = (ld(inp.v[0], i), ld(inp.v[1], i), ld(inp.v[2], i));
        let a = ld(inp.alpha, i);
        let a2 = _mm256_mul_ps(a, a);
        let ux = _mm256_add_ps(lx, vx);
        let uy = _mm256_add_ps(ly, vy);
        let uz = _mm256_add_ps(lz, vz);
        let uxy = _mm256_add_ps(_mm256_mul_ps(ux, ux), _mm256_mul_ps(uy, uy));
        let hh = _mm256_add_ps(uxy, _mm256_mul_ps(uz, uz));
        let k = _mm256_add_ps(uxy, _mm256_mul_ps(_mm256_mul_ps(a2, uz), uz));
        let lxy = _mm256_add_ps(_mm256_mul_ps(lx, lx), _mm256_mul_ps(ly, ly));
        let vxy = _mm256_add_ps(_mm256_mul_ps(vx, vx), _mm256_mul_ps(vy, vy));
        let ql = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(lz, lz), _mm256_mul_ps(a2, lxy)));
        let qv = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(vz, vz), _mm256_mul_ps(a2, vxy)));
        let num = _mm256_mul_ps(_mm256_mul_ps(_mm256_mul_ps(a2, hh), hh), lz);
        let den = _mm256_mul_ps(
            _mm256_mul_ps(_mm256_mul_ps(two_pi, k), k),
            _mm256_add_ps(_mm256_mul_ps(ql, vz), _mm256_mul_ps(qv, lz)),
        );
        let f = _mm256_div_ps(num, den);
        let ok = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(lz, zero),
            _mm256_cmp_ps::<_CMP_GT_OQ>(vz, zero),
        );
        _mm256_storeu_ps(out.as_mut_ptr().add(i), _mm256_blendv_ps(zero, f, ok));
        i += 8;
    }
    n
}

#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn deferred(inp: &DeferredIn, sigma2: f32, delta: f32, out: &mut [f32]) -> usize {
    let n = out.len() / 8 * 8;
    let one = _mm256_set1_ps(1.0);
    let two_s2 = _mm256_set1_ps(2.0 * sigma2);
    let dl = _mm256_set1_ps(delta);
    let mut i = 0;
    while i < n {
        let a = ld(inp.alpha, i);
        let (ux, uy, uz) = (ld(inp.du[0], i), ld(inp.du[1], i), ld(inp.du[2], i));
        let (wx, wy, wz) = (ld(inp.dv[0], i), ld(inp.dv[1], i), ld(inp.dv[2], i));
        // same association as the scalar form: ((((ux² + uy²) + uz²) + wx²) + wy²) + wz²
        let mut n2 = _mm256_mul_ps(ux, ux);
        n2 = _mm256_add_ps(n2, _mm256_mul_ps(uy, uy));
        n2 = _mm256_add_ps(n2, _mm256_mul_ps(uz, uz));
        n2 = _mm256_add_ps(n2, _mm256_mul_ps(wx, wx));
        n2 = _mm256_add_ps(n2, _mm256_mul_ps(wy, wy));
        n2 = _mm256_add_ps(n2, _mm256_mul_ps(wz, wz));
        let kern = _mm256_min_ps(_mm256_mul_ps(two_s2, n2), dl);
        let r = _mm256_sqrt_ps(_mm256_min_ps(_mm256_add_ps(_mm256_mul_ps(a, a), kern), one));
        _mm256_storeu_ps(out.as_mut_ptr().add(i), r);
        i += 8;
    }
    n
}

/// Natural log for x > 0 (normal floats): x = m·2^e with m ∈ [√½, √2), ln m = 2 atanh z,
/// z = (m − 1)/(m + 1), |z| ≤ 0.172, series to z⁹ (truncation < 4e-10).
#[inline(always)]
unsafe fn ln(x: __m256) -> __m256 {
    let bits = _mm256_castps_si256(x);
    let mut e = _mm256_sub_epi32(_mm256_srli_epi32::<23>(bits), _mm256_set1_epi32(127));
    let mbits = _mm256_or_si256(
        _mm256_and_si256(bits, _mm256_set1_epi32(0x007f_ffff)),
        _mm256_set1_epi32(0x3f80_0000),
    );
    let mut m = _mm256_castsi256_ps(mbits);
    let big = _mm256_cmp_ps::<_CMP_GT_OQ>(m, _mm256_set1_ps(std::f32::consts::SQRT_2));
    m = _mm256_blendv_ps(m, _mm256_mul_ps(m, _mm256_set1_ps(0.5)), big);
    e = _mm256_add_epi32(
        e,
        _mm256_and_si256(_mm256_castps_si256(big), _mm256_set1_epi32(1)),
    );
    let one = _mm256_set1_ps(1.0);
    let z = _mm256_div_ps(_mm256_sub_ps(m, one), _mm256_add_ps(m, one));
    let z2 = _mm256_mul_ps(z, z);
    let mut p = _mm256_set1_ps(1.0 / 9.0);
    p = _mm256_fmadd_ps(p, z2, _mm256_set1_ps(1.0 / 7.0));
    p = _mm256_fmadd_ps(p, z2, _mm256_set1_ps(1.0 / 5.0));
    p = _mm256_fmadd_ps(p, z2, _mm256_set1_ps(1.0 / 3.0));
    p = _mm256_fmadd_ps(p, z2, one);
    let lnm = _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(2.0), z), p);
    _mm256_fmadd_ps(
        _mm256_cvtepi32_ps(e),
        _mm256_set1_ps(std::f32::consts::LN_2),
        lnm,
    )
}

#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn multiscale(y_me: &[f32], y_mi: &[f32], out: &mut [f32]) -> usize {
    let n = out.len() / 8 * 8;
    let one = _mm256_set1_ps(1.0);
    let half = _mm256_set1_ps(0.5);
    let tiny = _mm256_set1_ps(f32::MIN_POSITIVE);
    let third = _mm256_set1_ps(1.0 / 3.0);
    let (c, d) = (super::batch::ALPHA_ME_C, super::batch::ALPHA_ME_D);
    let mut i = 0;
    while i < n {
        let a = ld(y_me, i);
        let b = ld(y_mi, i);
        let y = _mm256_sub_ps(_mm256_add_ps(a, b), _mm256_mul_ps(a, b));
        // ρ = (1 − y_me)(1 − y_mi), as the generated code
        let rho = _mm256_mul_ps(_mm256_sub_ps(one, a), _mm256_sub_ps(one, b));
        // clamp(y, m, 1) as the generated code (max/min take the second operand on NaN)
        let y = _mm256_min_ps(_mm256_max_ps(y, tiny), one);
        // α ≤ 1 branch
        let s = _mm256_sub_ps(_mm256_setzero_ps(), ln(y));
        let x = _mm256_div_ps(one, s);
        let mut p = _mm256_set1_ps(c[6]);
        for k in (0..6).rev() {
            p = _mm256_fmadd_ps(x, p, _mm256_set1_ps(c[k]));
        }
        p = _mm256_mul_ps(x, p);
        let r = _mm256_add_ps(
            _mm256_add_ps(
                _mm256_fmadd_ps(half, s, _mm256_set1_ps(-0.653_426_4)),
                _mm256_mul_ps(half, ln(s)),
            ),
            p,
        );
        let small = _mm256_sqrt_ps(_mm256_div_ps(y, r));
        // α > 1 branch: (π/2)(1 + g(b))/b, b = clamp(ρ, m, 1)
        let bb = _mm256_min_ps(_mm256_max_ps(rho, tiny), one);
        let mut q = _mm256_set1_ps(d[7]);
        for k in (0..7).rev() {
            q = _mm256_fmadd_ps(bb, q, _mm256_set1_ps(d[k]));
        }
        q = _mm256_fmadd_ps(bb, q, one);
        let large = _mm256_div_ps(
            _mm256_mul_ps(_mm256_set1_ps(std::f32::consts::FRAC_PI_2), q),
            bb,
        );
        let big = _mm256_cmp_ps::<_CMP_GT_OQ>(y, third);
        _mm256_storeu_ps(out.as_mut_ptr().add(i), _mm256_blendv_ps(small, large, big));
        i += 8;
    }
    n
}

/// θ/(2π sin θ) of an edge, the generated `ltc_edge_factor` 8 lanes wide.
#[inline(always)]
unsafe fn edge_factor(x: __m256) -> __m256 {
    let y = _mm256_andnot_ps(_mm256_set1_ps(-0.0), x);
    let a = _mm256_add_ps(
        _mm256_set1_ps(0.8543985),
        _mm256_mul_ps(
            _mm256_add_ps(
                _mm256_set1_ps(0.4965155),
                _mm256_mul_ps(_mm256_set1_ps(0.0145206), y),
            ),
            y,
        ),
    );
    let b = _mm256_add_ps(
        _mm256_set1_ps(3.417594),
        _mm256_mul_ps(_mm256_add_ps(_mm256_set1_ps(4.1616724), y), y),
    );
    let v = _mm256_div_ps(a, b);
    let one = _mm256_set1_ps(1.0);
    let neg = _mm256_sub_ps(
        _mm256_div_ps(
            _mm256_set1_ps(0.5),
            _mm256_sqrt_ps(_mm256_max_ps(
                _mm256_sub_ps(one, _mm256_mul_ps(x, x)),
                _mm256_set1_ps(0.0000001),
            )),
        ),
        v,
    );
    _mm256_blendv_ps(neg, v, _mm256_cmp_ps::<_CMP_GT_OQ>(x, _mm256_setzero_ps()))
}

#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn ltc_quad(inp: &LtcQuadIn, out: &mut [f32]) -> usize {
    let n = out.len() / 8 * 8;
    let one = _mm256_set1_ps(1.0);
    let mut i = 0;
    while i < n {
        let (a, b, c, d) = (
            ld(inp.m[0], i),
            ld(inp.m[1], i),
            ld(inp.m[2], i),
            ld(inp.m[3], i),
        );
        let mut u = [[_mm256_setzero_ps(); 3]; 4];
        for (k, uk) in u.iter_mut().enumerate() {
            let (px, py, pz) = (
                ld(inp.p[3 * k], i),
                ld(inp.p[3 * k + 1], i),
                ld(inp.p[3 * k + 2], i),
            );
            let qx = _mm256_add_ps(_mm256_mul_ps(a, px), _mm256_mul_ps(c, pz));
            let qz = _mm256_add_ps(_mm256_mul_ps(b, px), _mm256_mul_ps(d, pz));
            let nn = _mm256_add_ps(
                _mm256_add_ps(_mm256_mul_ps(qx, qx), _mm256_mul_ps(py, py)),
                _mm256_mul_ps(qz, qz),
            );
            let inv = _mm256_div_ps(one, _mm256_sqrt_ps(nn));
            *uk = [
                _mm256_mul_ps(qx, inv),
                _mm256_mul_ps(py, inv),
                _mm256_mul_ps(qz, inv),
            ];
        }
        let mut e = [_mm256_setzero_ps(); 4];
        for (k, ek) in e.iter_mut().enumerate() {
            let (p, q) = (u[k], u[(k + 1) % 4]);
            let x = _mm256_add_ps(
                _mm256_add_ps(_mm256_mul_ps(p[0], q[0]), _mm256_mul_ps(p[1], q[1])),
                _mm256_mul_ps(p[2], q[2]),
            );
            *ek = edge_factor(x);
        }
        let cross = |p: &[__m256; 3], q: &[__m256; 3], comp: usize| -> __m256 {
            let (j, k) = ((comp + 1) % 3, (comp + 2) % 3);
            _mm256_sub_ps(_mm256_mul_ps(p[j], q[k]), _mm256_mul_ps(p[k], q[j]))
        };
        let mut f = [_mm256_setzero_ps(); 3];
        for (comp, fc) in f.iter_mut().enumerate() {
            // same association as the scalar form: ((t0 + t1) + t2) + t3
            let mut acc = _mm256_mul_ps(e[0], cross(&u[0], &u[1], comp));
            for k in 1..4 {
                acc = _mm256_add_ps(
                    acc,
                    _mm256_mul_ps(e[k], cross(&u[k], &u[(k + 1) % 4], comp)),
                );
            }
            *fc = acc;
        }
        let len = _mm256_sqrt_ps(_mm256_add_ps(
            _mm256_add_ps(_mm256_mul_ps(f[0], f[0]), _mm256_mul_ps(f[1], f[1])),
            _mm256_mul_ps(f[2], f[2]),
        ));
        let fz = _mm256_andnot_ps(_mm256_set1_ps(-0.0), f[2]);
        let r = _mm256_div_ps(
            _mm256_add_ps(_mm256_mul_ps(len, len), fz),
            _mm256_add_ps(len, one),
        );
        _mm256_storeu_ps(
            out.as_mut_ptr().add(i),
            _mm256_min_ps(_mm256_max_ps(r, _mm256_setzero_ps()), one),
        );
        i += 8;
    }
    n
}

/// e^x for x ≤ 88 (clamped below at −87): Cody–Waite reduction x = n ln 2 + r, |r| ≤ ½ ln 2,
/// degree-7 Taylor polynomial (truncation < 2e-9 relative), 2^n by exponent bits.
#[inline(always)]
pub(super) unsafe fn exp(x: __m256) -> __m256 {
    let x = _mm256_min_ps(
        _mm256_max_ps(x, _mm256_set1_ps(-87.0)),
        _mm256_set1_ps(88.0),
    );
    let n = _mm256_round_ps::<{ _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC }>(_mm256_mul_ps(
        x,
        _mm256_set1_ps(std::f32::consts::LOG2_E),
    ));
    let r = _mm256_fnmadd_ps(n, _mm256_set1_ps(0.693_145_75), x);
    let r = _mm256_fnmadd_ps(n, _mm256_set1_ps(1.428_606_8e-6), r);
    let mut p = _mm256_set1_ps(1.0 / 5040.0);
    for c in [
        1.0 / 720.0,
        1.0 / 120.0,
        1.0 / 24.0,
        1.0 / 6.0,
        0.5,
        1.0,
        1.0,
    ] {
        p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(c));
    }
    let bits = _mm256_slli_epi32::<23>(_mm256_add_epi32(
        _mm256_cvtps_epi32(n),
        _mm256_set1_epi32(127),
    ));
    _mm256_mul_ps(p, _mm256_castsi256_ps(bits))
}

#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn leadr5(inp: &LeadrIn, out: &mut [f32]) -> usize {
    let n = out.len() / 8 * 8;
    let zero = _mm256_setzero_ps();
    let one = _mm256_set1_ps(1.0);
    let two = _mm256_set1_ps(2.0);
    let h = g::LEADR_SPACING_N5;
    let w = [
        g::LEADR_W2,
        g::LEADR_W1,
        g::LEADR_W0,
        g::LEADR_W1,
        g::LEADR_W2,
    ];
    let mut i = 0;
    while i < n {
        let (x0, y0, sx, sy, rxy) = (
            ld(inp.s[0], i),
            ld(inp.s[1], i),
            ld(inp.s[2], i),
            ld(inp.s[3], i),
            ld(inp.s[4], i),
        );
        let (vx, vy, vz) = (ld(inp.v[0], i), ld(inp.v[1], i), ld(inp.v[2], i));
        let sr = _mm256_sqrt_ps(_mm256_max_ps(
            _mm256_sub_ps(one, _mm256_mul_ps(rxy, rxy)),
            zero,
        ));
        let (mut num, mut den) = (zero, zero);
        for a in 0..5 {
            for b in 0..5 {
                let pa = _mm256_set1_ps((a as f32 - 2.0) * h);
                let pb = _mm256_set1_ps((b as f32 - 2.0) * h);
                let nx = _mm256_add_ps(x0, _mm256_mul_ps(pa, sx));
                let ny = _mm256_add_ps(
                    y0,
                    _mm256_mul_ps(
                        _mm256_add_ps(_mm256_mul_ps(pa, rxy), _mm256_mul_ps(pb, sr)),
                        sy,
                    ),
                );
                let inv = _mm256_div_ps(
                    one,
                    _mm256_sqrt_ps(_mm256_add_ps(
                        _mm256_add_ps(_mm256_mul_ps(nx, nx), _mm256_mul_ps(ny, ny)),
                        one,
                    )),
                );
                let d = _mm256_mul_ps(
                    _mm256_add_ps(
                        _mm256_sub_ps(
                            _mm256_sub_ps(zero, _mm256_mul_ps(nx, vx)),
                            _mm256_mul_ps(ny, vy),
                        ),
                        vz,
                    ),
                    inv,
                );
                let wt = _mm256_set1_ps(w[a] * w[b]);
                let area = _mm256_div_ps(_mm256_mul_ps(wt, _mm256_max_ps(d, zero)), inv);
                // reflect and shade
                let td = _mm256_mul_ps(two, d);
                let rx = _mm256_sub_ps(
                    _mm256_mul_ps(td, _mm256_mul_ps(_mm256_sub_ps(zero, nx), inv)),
                    vx,
                );
                let ry = _mm256_sub_ps(
                    _mm256_mul_ps(td, _mm256_mul_ps(_mm256_sub_ps(zero, ny), inv)),
                    vy,
                );
                let rz = _mm256_sub_ps(_mm256_mul_ps(td, inv), vz);
                let c = _mm256_mul_ps(
                    _mm256_add_ps(
                        _mm256_add_ps(
                            _mm256_mul_ps(_mm256_set1_ps(0.5), rx),
                            _mm256_mul_ps(_mm256_set1_ps(0.2), ry),
                        ),
                        _mm256_mul_ps(_mm256_set1_ps(0.8), rz),
                    ),
                    _mm256_set1_ps(1.0369517),
                );
                let e = exp(_mm256_max_ps(
                    _mm256_mul_ps(_mm256_set1_ps(50.0), _mm256_sub_ps(c, one)),
                    _mm256_set1_ps(-87.0),
                ));
                let l = _mm256_add_ps(
                    _mm256_add_ps(_mm256_set1_ps(0.5), _mm256_mul_ps(_mm256_set1_ps(0.5), rz)),
                    _mm256_mul_ps(_mm256_set1_ps(10.0), e),
                );
                num = _mm256_add_ps(num, _mm256_mul_ps(area, l));
                den = _mm256_add_ps(den, area);
            }
        }
        let r = _mm256_div_ps(num, den);
        let ok = _mm256_cmp_ps::<_CMP_GT_OQ>(den, zero);
        _mm256_storeu_ps(out.as_mut_ptr().add(i), _mm256_blendv_ps(zero, r, ok));
        i += 8;
    }
    n
}

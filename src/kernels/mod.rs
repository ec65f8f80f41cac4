//! Batched f32 shading kernels over structure-of-arrays inputs, with an
//! AVX2+FMA backend chosen at run time and the scalar generated twins as fallback.
//!
//! Kernels: (a) GGX point-light specular with height-correlated Smith G2
//! ([`ggx_specular`]), (b) the deferred specular-AA roughness update of seed 003 Eq 13
//! ([`deferred_roughness`]), (c) the multi-scale α, y_me, y_mi → α through the α_me fit
//! ([`multiscale_alpha`]). The scalar backend calls `crate::generated::shading` (the
//! same source text as the WGSL); the AVX2 backend (`avx2.rs`) re-implements the same
//! arithmetic 8 lanes at a time. Agreement (tests/kernels.rs): SIMD vs scalar ≤ 16 ulp
//! relative for (a), ≤ 2 ulp for (b) and ≤ 512 ulp for (c) (its fitted Horner sum is
//! ill-conditioned near α = 1 and its logarithm is a series); both vs the f64 references
//! within the bounds of tests/codegen.rs.

mod accuracy;
#[cfg(target_arch = "x86_64")]
mod avx2;
mod inputs;

pub use accuracy::{accuracy, ltc_quad_conditioning, ltc_quad_f64};
pub use inputs::{bench_inputs, BenchInputs};

use crate::error::{Error, Result};
use crate::generated::shading as g;

/// The generated α_me coefficients as arrays (α ≤ 1 branch in 1/s, α > 1 branch in ‖b̄‖),
/// for code that evaluates the same form lane-wise or in a loop.
pub const ALPHA_ME_C: [f32; 7] = [
    g::ALPHA_ME_C1,
    g::ALPHA_ME_C2,
    g::ALPHA_ME_C3,
    g::ALPHA_ME_C4,
    g::ALPHA_ME_C5,
    g::ALPHA_ME_C6,
    g::ALPHA_ME_C7,
];
pub const ALPHA_ME_D: [f32; 8] = [
    g::ALPHA_ME_D1,
    g::ALPHA_ME_D2,
    g::ALPHA_ME_D3,
    g::ALPHA_ME_D4,
    g::ALPHA_ME_D5,
    g::ALPHA_ME_D6,
    g::ALPHA_ME_D7,
    g::ALPHA_ME_D8,
];

/// Which implementation runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Backend {
    /// One pixel per (non-inlined) call: no auto-vectorisation — the one-pixel-at-a-time
    /// baseline of a shader-style loop.
    PerPixel,
    /// The scalar twins in a plain loop (LLVM may auto-vectorise it with SSE2).
    Scalar,
    /// AVX2 + FMA, 8 lanes (x86_64 only; detected at run time).
    Avx2,
}

impl Backend {
    /// The fastest backend this CPU supports.
    pub fn best() -> Backend {
        if Backend::Avx2.available() {
            Backend::Avx2
        } else {
            Backend::Scalar
        }
    }
    pub fn available(self) -> bool {
        match self {
            Backend::PerPixel | Backend::Scalar => true,
            #[cfg(target_arch = "x86_64")]
            Backend::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(not(target_arch = "x86_64"))]
            Backend::Avx2 => false,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Backend::PerPixel => "per-pixel",
            Backend::Scalar => "scalar",
            Backend::Avx2 => "avx2",
        }
    }
}

fn check(backend: Backend, lens: &[usize], out: usize) -> Result<()> {
    if lens.iter().any(|&l| l != out) {
        return Err(Error::InvalidArgument(format!(
            "kernel inputs have lengths {lens:?}, output {out}: all must be equal"
        )));
    }
    if !backend.available() {
        return Err(Error::InvalidArgument(format!(
            "backend {} is not available on this CPU",
            backend.name()
        )));
    }
    Ok(())
}

#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn one_specular(lx: f32, ly: f32, lz: f32, vx: f32, vy: f32, vz: f32, a: f32) -> f32 {
    g::ggx_specular(lx, ly, lz, vx, vy, vz, a)
}
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn one_deferred(
    a: f32,
    ux: f32,
    uy: f32,
    uz: f32,
    wx: f32,
    wy: f32,
    wz: f32,
    s2: f32,
    d: f32,
) -> f32 {
    g::filter_deferred(a, ux, uy, uz, wx, wy, wz, s2, d)
}
#[inline(never)]
fn one_multiscale(a: f32, b: f32) -> f32 {
    g::multiscale_alpha(a, b)
}

/// Inputs of the GGX specular kernel: tangent-space unit light and view directions and α.
pub struct SpecularIn<'a> {
    pub l: [&'a [f32]; 3],
    pub v: [&'a [f32]; 3],
    pub alpha: &'a [f32],
}

/// (a) out[i] = D·G2/(4 v_z) for pixel i (F = 1; 0 below either horizon).
pub fn ggx_specular(backend: Backend, inp: &SpecularIn, out: &mut [f32]) -> Result<()> {
    let lens = [
        inp.l[0].len(),
        inp.l[1].len(),
        inp.l[2].len(),
        inp.v[0].len(),
        inp.v[1].len(),
        inp.v[2].len(),
        inp.alpha.len(),
    ];
    check(backend, &lens, out.len())?;
    let mut start = 0;
    #[cfg(target_arch = "x86_64")]
    if backend == Backend::Avx2 {
        // SAFETY: avx2 and fma were detected at run time in `check`.
        start = unsafe { avx2::ggx_specular(inp, out) };
    }
    if backend == Backend::PerPixel {
        for i in 0..out.len() {
            out[i] = one_specular(
                inp.l[0][i],
                inp.l[1][i],
                inp.l[2][i],
                inp.v[0][i],
                inp.v[1][i],
                inp.v[2][i],
                inp.alpha[i],
            );
        }
        return Ok(());
    }
    for i in start..out.len() {
        out[i] = g::ggx_specular(
            inp.l[0][i],
            inp.l[1][i],
            inp.l[2][i],
            inp.v[0][i],
            inp.v[1][i],
            inp.v[2][i],
            inp.alpha[i],
        );
    }
    Ok(())
}

/// Inputs of the deferred roughness update: α and the screen derivatives of the normal.
pub struct DeferredIn<'a> {
    pub alpha: &'a [f32],
    pub du: [&'a [f32]; 3],
    pub dv: [&'a [f32]; 3],
}

/// (b) out[i] = √min(1, α² + min(2σ²(‖Δn_u‖² + ‖Δn_v‖²), δ)) (seed 003 Eq 13).
pub fn deferred_roughness(
    backend: Backend,
    inp: &DeferredIn,
    sigma2: f32,
    delta: f32,
    out: &mut [f32],
) -> Result<()> {
    let lens = [
        inp.alpha.len(),
        inp.du[0].len(),
        inp.du[1].len(),
        inp.du[2].len(),
        inp.dv[0].len(),
        inp.dv[1].len(),
        inp.dv[2].len(),
    ];
    check(backend, &lens, out.len())?;
    let mut start = 0;
    #[cfg(target_arch = "x86_64")]
    if backend == Backend::Avx2 {
        // SAFETY: avx2 and fma were detected at run time in `check`.
        start = unsafe { avx2::deferred(inp, sigma2, delta, out) };
    }
    if backend == Backend::PerPixel {
        for i in 0..out.len() {
            out[i] = one_deferred(
                inp.alpha[i],
                inp.du[0][i],
                inp.du[1][i],
                inp.du[2][i],
                inp.dv[0][i],
                inp.dv[1][i],
                inp.dv[2][i],
                sigma2,
                delta,
            );
        }
        return Ok(());
    }
    for i in start..out.len() {
        out[i] = g::filter_deferred(
            inp.alpha[i],
            inp.du[0][i],
            inp.du[1][i],
            inp.du[2][i],
            inp.dv[0][i],
            inp.dv[1][i],
            inp.dv[2][i],
            sigma2,
            delta,
        );
    }
    Ok(())
}

/// (c) out[i] = α of the multi-scale lobe from y_me = 1 − ‖μ‖ (mip) and y_mi = 1 − ρ(α_mi)
/// (generated `multiscale_alpha`; inputs in (0, 1)).
pub fn multiscale_alpha(
    backend: Backend,
    y_me: &[f32],
    y_mi: &[f32],
    out: &mut [f32],
) -> Result<()> {
    check(backend, &[y_me.len(), y_mi.len()], out.len())?;
    let mut start = 0;
    #[cfg(target_arch = "x86_64")]
    if backend == Backend::Avx2 {
        // SAFETY: avx2 and fma were detected at run time in `check`.
        start = unsafe { avx2::multiscale(y_me, y_mi, out) };
    }
    if backend == Backend::PerPixel {
        for i in 0..out.len() {
            out[i] = one_multiscale(y_me[i], y_mi[i]);
        }
        return Ok(());
    }
    for i in start..out.len() {
        out[i] = g::multiscale_alpha(y_me[i], y_mi[i]);
    }
    Ok(())
}

/// Inputs of the LTC quad-light kernel: the table's production M⁻¹ (a, b, c, d) per pixel
/// and the quad's 4 vertices in the pixel's shading frame (12 columns p0x, p0y, p0z, …).
pub struct LtcQuadIn<'a> {
    pub m: [&'a [f32]; 4],
    pub p: [&'a [f32]; 12],
}

#[inline(never)]
fn one_ltc(inp: &LtcQuadIn, i: usize) -> f32 {
    let p = |k: usize| inp.p[k][i];
    g::ltc_quad(
        inp.m[0][i],
        inp.m[1][i],
        inp.m[2][i],
        inp.m[3][i],
        p(0),
        p(1),
        p(2),
        p(3),
        p(4),
        p(5),
        p(6),
        p(7),
        p(8),
        p(9),
        p(10),
        p(11),
    )
}

/// (d) out[i] = the LTC integral of the quad (generated `ltc_quad`; multiply by the
/// table's norm for the shading).
pub fn ltc_quad(backend: Backend, inp: &LtcQuadIn, out: &mut [f32]) -> Result<()> {
    let lens: Vec<usize> = inp.m.iter().chain(inp.p.iter()).map(|c| c.len()).collect();
    check(backend, &lens, out.len())?;
    if backend == Backend::PerPixel {
        for (i, o) in out.iter_mut().enumerate() {
            *o = one_ltc(inp, i);
        }
        return Ok(());
    }
    let mut start = 0;
    #[cfg(target_arch = "x86_64")]
    if backend == Backend::Avx2 {
        // SAFETY: avx2 and fma were detected at run time in `check`.
        start = unsafe { avx2::ltc_quad(inp, out) };
    }
    for i in start..out.len() {
        let p = |k: usize| inp.p[k][i];
        out[i] = g::ltc_quad(
            inp.m[0][i],
            inp.m[1][i],
            inp.m[2][i],
            inp.m[3][i],
            p(0),
            p(1),
            p(2),
            p(3),
            p(4),
            p(5),
            p(6),
            p(7),
            p(8),
            p(9),
            p(10),
            p(11),
        );
    }
    Ok(())
}

/// Inputs of the LEADR 5×5 kernel: slope statistics (x0, y0, sx, sy, rxy) and the view.
pub struct LeadrIn<'a> {
    pub s: [&'a [f32]; 5],
    pub v: [&'a [f32]; 3],
}

#[inline(never)]
fn one_leadr(inp: &LeadrIn, i: usize) -> f32 {
    g::leadr5_env(
        inp.s[0][i],
        inp.s[1][i],
        inp.s[2][i],
        inp.s[3][i],
        inp.s[4][i],
        inp.v[0][i],
        inp.v[1][i],
        inp.v[2][i],
    )
}

/// (e) out[i] = the LEADR 5×5 grid estimate of rough specular under the analytic test
/// environment (generated `leadr5_env`, fitted spacing).
pub fn leadr5(backend: Backend, inp: &LeadrIn, out: &mut [f32]) -> Result<()> {
    let lens: Vec<usize> = inp.s.iter().chain(inp.v.iter()).map(|c| c.len()).collect();
    check(backend, &lens, out.len())?;
    if backend == Backend::PerPixel {
        for (i, o) in out.iter_mut().enumerate() {
            *o = one_leadr(inp, i);
        }
        return Ok(());
    }
    let mut start = 0;
    #[cfg(target_arch = "x86_64")]
    if backend == Backend::Avx2 {
        // SAFETY: avx2 and fma were detected at run time in `check`.
        start = unsafe { avx2::leadr5(inp, out) };
    }
    for i in start..out.len() {
        out[i] = g::leadr5_env(
            inp.s[0][i],
            inp.s[1][i],
            inp.s[2][i],
            inp.s[3][i],
            inp.s[4][i],
            inp.v[0][i],
            inp.v[1][i],
            inp.v[2][i],
        );
    }
    Ok(())
}

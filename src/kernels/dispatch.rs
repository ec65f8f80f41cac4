//! Each kernel once: the backend chosen at run time (AVX2+FMA or the scalar twin), the
//! lengths checked, the batch run.

#[cfg(target_arch = "x86_64")]
use super::avx2;
use super::batch::*;
use crate::error::{Error, Result};
use crate::generated::shading as g;

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

pub(super) fn check(backend: Backend, lens: &[usize], out: usize) -> Result<()> {
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
pub(super) fn one_specular(lx: f32, ly: f32, lz: f32, vx: f32, vy: f32, vz: f32, a: f32) -> f32 {
    g::ggx_specular(lx, ly, lz, vx, vy, vz, a)
}

#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn one_deferred(
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
pub(super) fn one_multiscale(a: f32, b: f32) -> f32 {
    g::multiscale_alpha(a, b)
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

#[inline(never)]
pub(super) fn one_ltc(inp: &LtcQuadIn, i: usize) -> f32 {
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

#[inline(never)]
pub(super) fn one_leadr(inp: &LeadrIn, i: usize) -> f32 {
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

//! Batched f32 shading kernels over structure-of-arrays inputs (issue 7 §4), with an
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

#[cfg(target_arch = "x86_64")]
mod avx2;

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

/// Deterministic benchmark / accuracy inputs: 15 columns of `n` pixels — l (3), v (3),
/// α (log-uniform in [1e-3, 1]), Δn_u (3), Δn_v (3), y_me, y_mi (of α log-uniform in
/// [1e-3, 1]). Directions are unit and above the horizon.
pub struct BenchInputs {
    pub cols: Vec<Vec<f32>>,
}

pub fn bench_inputs(n: usize) -> BenchInputs {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut cols = vec![Vec::with_capacity(n); 15];
    let dir = |rng: &mut rand_chacha::ChaCha8Rng| {
        let t = rng.random::<f64>() * 1.5;
        let p = rng.random::<f64>() * std::f64::consts::TAU;
        [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()]
    };
    for _ in 0..n {
        let l = dir(&mut rng);
        let v = dir(&mut rng);
        for k in 0..3 {
            cols[k].push(l[k] as f32);
            cols[3 + k].push(v[k] as f32);
        }
        cols[6].push(10f64.powf(-3.0 * rng.random::<f64>()) as f32);
        for k in 0..6 {
            cols[7 + k].push(((rng.random::<f64>() - 0.5) * 0.4) as f32);
        }
        let y = |rng: &mut rand_chacha::ChaCha8Rng| {
            crate::multiscale::mrl::mrl_pair(10f64.powf(-3.0 * rng.random::<f64>())).1 as f32
        };
        cols[13].push(y(&mut rng));
        cols[14].push(y(&mut rng));
    }
    BenchInputs { cols }
}

/// Measured accuracy of a kernel on `n` benchmark inputs: (max relative error vs the f64
/// reference, max ulp vs the scalar twin) for the given backend.
pub fn accuracy(kernel: &str, backend: Backend, n: usize) -> Result<(f64, f64)> {
    let d = bench_inputs(n);
    let c = &d.cols;
    let mut out = vec![0.0f32; n];
    let mut sc = vec![0.0f32; n];
    let reference: Vec<f64> = match kernel {
        "kernel-ggx-specular" => {
            let inp = SpecularIn {
                l: [&c[0], &c[1], &c[2]],
                v: [&c[3], &c[4], &c[5]],
                alpha: &c[6],
            };
            ggx_specular(backend, &inp, &mut out)?;
            ggx_specular(Backend::Scalar, &inp, &mut sc)?;
            let fr = crate::filters::truth::Frame::around(nalgebra::Vector3::z());
            (0..n)
                .map(|i| {
                    let s = crate::microfacet::Microsurface::ggx(
                        crate::microfacet::Roughness::iso(c[6][i] as f64)?,
                    );
                    let v3 = |a: usize| {
                        nalgebra::Vector3::new(
                            c[a][i] as f64,
                            c[a + 1][i] as f64,
                            c[a + 2][i] as f64,
                        )
                    };
                    Ok(crate::filters::truth::lobe(&s, &fr, &v3(3), &v3(0)))
                })
                .collect::<Result<_>>()?
        }
        "kernel-deferred" => {
            let inp = DeferredIn {
                alpha: &c[6],
                du: [&c[7], &c[8], &c[9]],
                dv: [&c[10], &c[11], &c[12]],
            };
            deferred_roughness(backend, &inp, 0.25, 0.18, &mut out)?;
            deferred_roughness(Backend::Scalar, &inp, 0.25, 0.18, &mut sc)?;
            (0..n)
                .map(|i| {
                    let f = |k: usize| c[k][i] as f64;
                    crate::filters::rules::deferred(
                        f(6),
                        [f(7), f(8), f(9)],
                        [f(10), f(11), f(12)],
                        0.25,
                        0.18,
                    )
                })
                .collect()
        }
        "kernel-multiscale" => {
            multiscale_alpha(backend, &c[13], &c[14], &mut out)?;
            multiscale_alpha(Backend::Scalar, &c[13], &c[14], &mut sc)?;
            (0..n)
                .map(|i| {
                    let (a, b) = (c[13][i] as f64, c[14][i] as f64);
                    crate::multiscale::mrl::alpha_from_one_minus(a + b - a * b)
                })
                .collect::<Result<_>>()?
        }
        _ => return Err(Error::InvalidArgument(format!("unknown kernel '{kernel}'"))),
    };
    let mut worst = (0.0f64, 0.0f64);
    for i in 0..n {
        let r = reference[i];
        if r > 1e-30 && (kernel != "kernel-multiscale" || r <= 1.0) {
            worst.0 = worst.0.max(((out[i] as f64) - r).abs() / r);
        }
        if sc[i] != 0.0 {
            worst.1 = worst
                .1
                .max(((out[i] - sc[i]) / sc[i]).abs() as f64 / f32::EPSILON as f64);
        }
    }
    Ok(worst)
}

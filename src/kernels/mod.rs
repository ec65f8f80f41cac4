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

/// Deterministic benchmark / accuracy inputs: 31 columns of `n` pixels — l (3), v (3),
/// α (log-uniform in [1e-3, 1]), Δn_u (3), Δn_v (3), y_me, y_mi (of α log-uniform in
/// [1e-3, 1]), then an LTC M⁻¹ (a, b, c, d) (15–18) and a quad light's 12 vertex
/// coordinates (19–30) above the horizon. Directions are unit and above the horizon.
pub struct BenchInputs {
    pub cols: Vec<Vec<f32>>,
}

pub fn bench_inputs(n: usize) -> BenchInputs {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut cols = vec![Vec::with_capacity(n); 39];
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
        // an LTC inverse like the table's: a, d > 0, b ≤ 0, c ≥ 0
        let al = 10f64.powf(-2.0 * rng.random::<f64>());
        cols[15].push((1.0 / al) as f32 * 0.5);
        cols[16].push(-(rng.random::<f64>() * 0.2 / al) as f32);
        cols[17].push((rng.random::<f64>() * 0.5) as f32);
        cols[18].push(1.0);
        // a quad: centre above the horizon, random size and orientation
        let cx = (rng.random::<f64>() - 0.5) * 2.0;
        let cy = (rng.random::<f64>() - 0.5) * 2.0;
        let cz = 0.5 + rng.random::<f64>();
        let (hu, hw) = (
            0.1 + rng.random::<f64>() * 0.5,
            0.1 + rng.random::<f64>() * 0.5,
        );
        let corners = [(-hu, -hw), (hu, -hw), (hu, hw), (-hu, hw)];
        for (k, (du, dw)) in corners.iter().enumerate() {
            cols[19 + 3 * k].push((cx + du) as f32);
            cols[20 + 3 * k].push((cy + dw) as f32);
            cols[21 + 3 * k].push(cz as f32);
        }
        // LEADR slope statistics (31–35) and a view (36–38)
        cols[31].push(((rng.random::<f64>() - 0.5) * 0.6) as f32);
        cols[32].push(((rng.random::<f64>() - 0.5) * 0.6) as f32);
        cols[33].push((0.05 + 0.45 * rng.random::<f64>()) as f32);
        cols[34].push((0.05 + 0.45 * rng.random::<f64>()) as f32);
        cols[35].push(((rng.random::<f64>() - 0.5) * 1.2) as f32);
        let vv = dir(&mut rng);
        for k in 0..3 {
            cols[36 + k].push(vv[k] as f32);
        }
    }
    BenchInputs { cols }
}

/// Measured accuracy of a kernel on `n` benchmark inputs: (max relative error vs the f64
/// reference — absolute for the LTC quad, whose values are form factors in [0, 1] — and max ulp vs the scalar
/// twin) for the given backend.
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
        "kernel-ltc-quad" => {
            let inp = LtcQuadIn {
                m: [&c[15], &c[16], &c[17], &c[18]],
                p: std::array::from_fn(|k| c[19 + k].as_slice()),
            };
            ltc_quad(backend, &inp, &mut out)?;
            ltc_quad(Backend::Scalar, &inp, &mut sc)?;
            // reference: the same vector form factor and sphere horizon in f64 with the
            // exact θ/sin θ (the approximation's own error is measured in results/ltc.md)
            (0..n)
                .map(|i| {
                    let f = |k: usize| c[k][i] as f64;
                    Ok(ltc_quad_f64(
                        [f(15), f(16), f(17), f(18)],
                        std::array::from_fn(|k| f(19 + k)),
                    ))
                })
                .collect::<Result<_>>()?
        }
        "kernel-leadr" => {
            let inp = LeadrIn {
                s: [&c[31], &c[32], &c[33], &c[34], &c[35]],
                v: [&c[36], &c[37], &c[38]],
            };
            leadr5(backend, &inp, &mut out)?;
            leadr5(Backend::Scalar, &inp, &mut sc)?;
            // the reference grid uses the spacing the kernel was compiled with
            let h = g::LEADR_SPACING_N5 as f64;
            let grid = crate::leadr::Grid::riemann(5, h);
            let sun = nalgebra::Vector3::new(0.5, 0.2, 0.8).normalize();
            let env = |v: nalgebra::Vector3<f64>| {
                move |nn: &nalgebra::Vector3<f64>| {
                    let r = nn * (2.0 * nn.dot(&v)) - v;
                    0.5 + 0.5 * r.z + 10.0 * (50.0 * (r.dot(&sun) - 1.0)).exp()
                }
            };
            (0..n)
                .map(|i| {
                    let f = |k: usize| c[k][i] as f64;
                    let s = crate::leadr::Slopes {
                        x0: f(31),
                        y0: f(32),
                        sx: f(33),
                        sy: f(34),
                        rxy: f(35),
                    };
                    let v = nalgebra::Vector3::new(f(36), f(37), f(38));
                    let r = crate::leadr::grid_estimate(&grid, &s, &v, &env(v), None);
                    Ok(if r.is_finite() { r } else { 0.0 })
                })
                .collect::<Result<_>>()?
        }
        _ => return Err(Error::InvalidArgument(format!("unknown kernel '{kernel}'"))),
    };
    let mut worst = (0.0f64, 0.0f64);
    for i in 0..n {
        let r = reference[i];
        // the LTC integral (a form factor in [0, 1]) is measured absolutely: its f32 edge
        // sum cancels for far, faint quads, so its error is ≈ ε·Σ|edge terms|, not ε·value
        let scale = if kernel == "kernel-ltc-quad" { 1.0 } else { r };
        if r > 1e-30 && (kernel != "kernel-multiscale" || r <= 1.0) {
            worst.0 = worst.0.max(((out[i] as f64) - r).abs() / scale);
        }
        if sc[i] != 0.0 {
            worst.1 = worst
                .1
                .max(((out[i] - sc[i]) / sc[i]).abs() as f64 / f32::EPSILON as f64);
        }
    }
    Ok(worst)
}

/// f64 reference of the generated `ltc_quad` with the exact θ/sin θ: the vector form
/// factor of M⁻¹P and the clipped-sphere horizon (|F|² + |F_z|)/(|F| + 1) clamped to [0, 1].
pub fn ltc_quad_f64(m: [f64; 4], p: [f64; 12]) -> f64 {
    use nalgebra::Vector3;
    let u: Vec<Vector3<f64>> = (0..4)
        .map(|k| {
            let (x, y, z) = (p[3 * k], p[3 * k + 1], p[3 * k + 2]);
            Vector3::new(m[0] * x + m[2] * z, y, m[1] * x + m[3] * z).normalize()
        })
        .collect();
    let mut f = Vector3::zeros();
    for k in 0..4 {
        let (a, b) = (u[k], u[(k + 1) % 4]);
        let cr = a.cross(&b);
        let s = cr.norm();
        if s > 0.0 {
            f += cr * (s.atan2(a.dot(&b)) / s / (2.0 * std::f64::consts::PI));
        }
    }
    let len = f.norm();
    ((len * len + f.z.abs()) / (len + 1.0)).clamp(0.0, 1.0)
}

/// The smallest 1 − x² over the quad's edges after M⁻¹ (x = cos of the angle between
/// consecutive transformed vertices): near 0 an edge maps to nearly antipodal directions,
/// where the edge integral is ill-conditioned (f32 inputs) and the shipped rational's
/// 1e-7 clamp bites.
pub fn ltc_quad_conditioning(m: [f64; 4], p: [f64; 12]) -> f64 {
    use nalgebra::Vector3;
    let u: Vec<Vector3<f64>> = (0..4)
        .map(|k| {
            let (x, y, z) = (p[3 * k], p[3 * k + 1], p[3 * k + 2]);
            Vector3::new(m[0] * x + m[2] * z, y, m[1] * x + m[3] * z).normalize()
        })
        .collect();
    (0..4)
        .map(|k| 1.0 - u[k].dot(&u[(k + 1) % 4]).powi(2))
        .fold(f64::INFINITY, f64::min)
}

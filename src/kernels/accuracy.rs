//! Measured accuracy of each kernel: against its f64 reference and, in ulp, against the
//! scalar twin, on the benchmark inputs. The f64 references of the LTC quad kernel and
//! its conditioning live here too.

use super::batch::*;
use super::dispatch::*;
use super::inputs::bench_inputs;
use crate::error::{Error, Result};
use crate::generated::shading as g;

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
            let fr = crate::microfacet::lobe::Frame::around(nalgebra::Vector3::z());
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
                    Ok(crate::microfacet::lobe::lobe(&s, &fr, &v3(3), &v3(0)))
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
            // exact θ/sin θ (the approximation's own error is measured in results/ltc-ggx.md)
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

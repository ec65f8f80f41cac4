//! SIMD kernels: AVX2 vs scalar within a stated ulp bound, both vs the f64
//! reference, extremes included; bad input gives a typed error. On a CPU without
//! AVX2+FMA the SIMD comparisons are skipped with a message (the scalar checks run).

mod common;

use nalgebra::Vector3;
use ndfbench::kernels::{self, Backend, DeferredIn, SpecularIn};
use ndfbench::microfacet::{Microsurface, Roughness};
use proptest::prelude::*;

const EPS: f64 = f32::EPSILON as f64;

fn rel(a: f32, b: f64) -> f64 {
    if b == 0.0 {
        (a as f64).abs()
    } else {
        ((a as f64) - b).abs() / b.abs()
    }
}

fn simd() -> bool {
    let ok = Backend::Avx2.available();
    if !ok {
        eprintln!("skipping SIMD comparison: this CPU has no AVX2+FMA");
    }
    ok
}

fn dir(t: f64, p: f64) -> [f32; 3] {
    [
        (t.sin() * p.cos()) as f32,
        (t.sin() * p.sin()) as f32,
        t.cos() as f32,
    ]
}

proptest! {
    #![proptest_config(common::config(10_000))] // was 64

    /// (a) SIMD vs scalar ≤ 16 ulp relative (FMA vs separate rounding; 11 ulp measured over
    /// 65 536 random pixels); both vs the f64 lobe ≤ 1e-5 relative.
    #[test]
    fn specular_kernel(
        px in prop::collection::vec((prop_oneof![Just(1e-4f64), 1e-4f64..1.0], 0.0f64..1.5706, 0.0f64..std::f64::consts::TAU, 0.0f64..1.5706, 0.0f64..std::f64::consts::TAU), 1..40)
    ) {
        let n = px.len();
        let mut c: Vec<Vec<f32>> = vec![Vec::with_capacity(n); 7];
        for &(a, tl, pl, tv, pv) in &px {
            let (l, v) = (dir(tl, pl), dir(tv, pv));
            for k in 0..3 {
                c[k].push(l[k]);
                c[3 + k].push(v[k]);
            }
            c[6].push(a as f32);
        }
        let inp = SpecularIn { l: [&c[0], &c[1], &c[2]], v: [&c[3], &c[4], &c[5]], alpha: &c[6] };
        let mut s = vec![0.0; n];
        kernels::ggx_specular(Backend::Scalar, &inp, &mut s).unwrap();
        for i in 0..n {
            let ms = Microsurface::ggx(Roughness::iso(c[6][i] as f64).unwrap());
            let l = Vector3::new(c[0][i] as f64, c[1][i] as f64, c[2][i] as f64);
            let v = Vector3::new(c[3][i] as f64, c[4][i] as f64, c[5][i] as f64);
            let f = ndfbench::filters::truth::Frame::around(Vector3::z());
            let want = ndfbench::filters::truth::lobe(&ms, &f, &v, &l);
            if want > 1e-30 {
                prop_assert!(rel(s[i], want) < 1e-5, "scalar {} vs f64 {want}", s[i]);
            }
        }
        if simd() {
            let mut w = vec![0.0; n];
            kernels::ggx_specular(Backend::Avx2, &inp, &mut w).unwrap();
            for i in 0..n {
                prop_assert!(rel(w[i], s[i] as f64) <= 16.0 * EPS, "lane {i}: avx2 {} vs scalar {}", w[i], s[i]);
            }
        }
    }

    /// (b) SIMD vs scalar: identical association, ≤ 2 ulp.
    #[test]
    fn deferred_kernel(
        px in prop::collection::vec((1e-4f32..1.0, prop::array::uniform6(-2.0f32..2.0)), 1..40)
    ) {
        let n = px.len();
        let alpha: Vec<f32> = px.iter().map(|p| p.0).collect();
        let d: Vec<Vec<f32>> = (0..6).map(|k| px.iter().map(|p| p.1[k]).collect()).collect();
        let inp = DeferredIn { alpha: &alpha, du: [&d[0], &d[1], &d[2]], dv: [&d[3], &d[4], &d[5]] };
        let mut s = vec![0.0; n];
        kernels::deferred_roughness(Backend::Scalar, &inp, 0.25, 0.18, &mut s).unwrap();
        for i in 0..n {
            let want = ndfbench::filters::rules::deferred(
                alpha[i] as f64,
                [d[0][i] as f64, d[1][i] as f64, d[2][i] as f64],
                [d[3][i] as f64, d[4][i] as f64, d[5][i] as f64],
                0.25,
                0.18,
            );
            prop_assert!(rel(s[i], want) < 1e-6);
        }
        if simd() {
            let mut w = vec![0.0; n];
            kernels::deferred_roughness(Backend::Avx2, &inp, 0.25, 0.18, &mut w).unwrap();
            for i in 0..n {
                prop_assert!(rel(w[i], s[i] as f64) <= 2.0 * EPS, "avx2 {} vs scalar {}", w[i], s[i]);
            }
        }
    }

    /// (c) SIMD vs scalar ≤ 512 ulp (6e-5 relative; 253 ulp measured over 65 536 random
    /// pixels): the α_me fit's Horner sum in 1/s has alternating coefficients up to 109 that
    /// cancel to ≈ 0.4 near α = 1 (condition ≈ 10³), so FMA-vs-separate rounding and the
    /// series logarithm are amplified; both stay within 3e-4 of Newton on the closed form
    /// (the fit's own held-out error is 1.6e-4), now over α_mi, α_me ∈ [1e-4, 1e2] (both branches).
    #[test]
    fn multiscale_kernel(
        px in prop::collection::vec((-4.0f64..2.0, -4.0f64..2.0), 1..40)
    ) {
        let n = px.len();
        let mut ym = Vec::new();
        let mut yi = Vec::new();
        let mut want = Vec::new();
        for &(la, lb) in &px {
            let (ami, ame) = (10f64.powf(la), 10f64.powf(lb));
            yi.push(ndfbench::multiscale::mrl::mrl_pair(ami).1 as f32);
            ym.push(ndfbench::multiscale::mrl::mrl_pair(ame).1 as f32);
            want.push(ndfbench::multiscale::overall::alpha_moment(ami, ame).unwrap());
        }
        let mut s = vec![0.0; n];
        kernels::multiscale_alpha(Backend::Scalar, &ym, &yi, &mut s).unwrap();
        // both branches of the total fit, α_mi and α_me over [1e-4, 1e2] (overall α to ~6e3)
        for i in 0..n {
            prop_assert!(rel(s[i], want[i]) < 3e-4, "scalar {} vs {}", s[i], want[i]);
        }
        if simd() {
            let mut w = vec![0.0; n];
            kernels::multiscale_alpha(Backend::Avx2, &ym, &yi, &mut w).unwrap();
            for i in 0..n {
                prop_assert!(rel(w[i], s[i] as f64) <= 512.0 * EPS, "avx2 {} vs scalar {}", w[i], s[i]);
            }
        }
    }
}

#[test]
fn mismatched_lengths_are_a_typed_error() {
    let a = [0.1f32; 9];
    let b = [0.1f32; 8];
    let mut out = [0.0f32; 9];
    let e = kernels::multiscale_alpha(Backend::Scalar, &a, &b, &mut out).unwrap_err();
    assert!(e.to_string().contains("lengths"), "{e}");
}

#[test]
fn ltc_quad_kernel() {
    // (d): SIMD vs scalar ≤ 2 ulp (same operation order, no FMA); scalar vs the f64 form
    // with the exact θ/sin θ within 2e-5 absolute (form factors in [0, 1]; the f32 edge sum
    // cancels for far, faint quads, so a relative bound would not hold there, and the shipped
    // rational θ/sin θ clamps 1 − x² at 1e-7, which M⁻¹'s stretch makes reachable: edges
    // mapped to nearly antipodal directions; 5.0e-6 measured on 4096 inputs)
    let (err, _) = kernels::accuracy("kernel-ltc-quad", Backend::Scalar, 4096).unwrap();
    assert!(err < 2e-5, "scalar vs f64: {err}");
    if simd() {
        let (err, ulp) = kernels::accuracy("kernel-ltc-quad", Backend::Avx2, 4096).unwrap();
        assert!(err < 2e-5 && ulp <= 2.0, "avx2: {err}, {ulp} ulp");
    }
    let (e, u) = kernels::accuracy("kernel-ltc-quad", Backend::PerPixel, 512).unwrap();
    assert!(e < 2e-5 && u == 0.0);
}

#[test]
fn leadr_kernel() {
    // (e): scalar twin vs the f64 grid estimate with the same fitted spacing ≤ 3e-5
    // relative (1.0e-5 measured on 2^16 inputs: f32 rounding of 25 terms, the sun lobe's
    // exp amplifying its argument's error by 50); AVX2 vs scalar ≤ 8 ulp (its exp is a
    // polynomial, 2 ulp measured)
    let (err, _) = kernels::accuracy("kernel-leadr", Backend::Scalar, 4096).unwrap();
    assert!(err < 3e-5, "scalar vs f64: {err}");
    if simd() {
        let (err, ulp) = kernels::accuracy("kernel-leadr", Backend::Avx2, 4096).unwrap();
        assert!(err < 3e-5 && ulp <= 8.0, "avx2: {err}, {ulp} ulp");
    }
}

proptest! {
    #![proptest_config(common::config(10_000))] // was 48

    /// (d) at the extremes: LTC inverses of α down to 1e-4 (a up to 5e3), skew, quads from
    /// overhead to grazing and straddling the horizon. Always finite and in [0, 1]; AVX2 vs
    /// scalar ≤ 2ε·max(|v|, 1) absolute; scalar vs the f64 form ≤ 2e-5 + 4e-6·π/√c absolute,
    /// c = min over edges of 1 − x² after M⁻¹ (the rational's relative error ≈ 1.4e-6 times
    /// θ/sin θ ≈ π/√c near antipodal edges), wherever c ≥ 1e-4. The constant is measured:
    /// the worst error/(π/√c) over 200 000 random cases was 1.8e-6, and 2.4e-6 in the
    /// regression case kept in kernels.proptest-regressions (α = 1e-4, c = 1.2e-4); the
    /// earlier 2e-6, set from 48 cases, was too tight. Below that the edge integral
    /// is ill-conditioned for f32 inputs (a 3.7e-3 error at c = 3.7e-6 was found) and, under
    /// 1e-7, the shipped rational clamps; only the range [0, 1] is asserted there.
    #[test]
    fn ltc_quad_extremes(
        px in prop::collection::vec((
            prop_oneof![Just(1e-4f64), 1e-4f64..1.0], -1.0f64..0.0, 0.0f64..1.0,
            -2.0f64..2.0, -2.0f64..2.0, prop_oneof![Just(1e-3f64), 1e-3f64..2.0, Just(-0.2f64)], 0.01f64..1.0, 0.01f64..1.0,
        ), 1..24)
    ) {
        let n = px.len();
        let mut cols: Vec<Vec<f32>> = vec![Vec::with_capacity(n); 16];
        for &(al, sk, cc, cx, cy, cz, hu, hw) in &px {
            for (k, v) in [0.5 / al, sk / al, cc, 1.0].iter().enumerate() {
                cols[k].push(*v as f32);
            }
            let corners = [(-hu, -hw), (hu, -hw), (hu, hw), (-hu, hw)];
            for (k, (du, dw)) in corners.iter().enumerate() {
                cols[4 + 3 * k].push((cx + du) as f32);
                cols[5 + 3 * k].push((cy + dw) as f32);
                cols[6 + 3 * k].push((cz + 0.5 * du) as f32);
            }
        }
        let inp = kernels::LtcQuadIn { m: [&cols[0], &cols[1], &cols[2], &cols[3]], p: std::array::from_fn(|k| cols[4 + k].as_slice()) };
        let mut s = vec![0.0; n];
        kernels::ltc_quad(Backend::Scalar, &inp, &mut s).unwrap();
        for i in 0..n {
            let f = |k: usize| cols[k][i] as f64;
            let r = kernels::ltc_quad_f64([f(0), f(1), f(2), f(3)], std::array::from_fn(|k| f(4 + k)));
            prop_assert!(s[i].is_finite() && (0.0..=1.0).contains(&s[i]));
            let cond = kernels::ltc_quad_conditioning([f(0), f(1), f(2), f(3)], std::array::from_fn(|k| f(4 + k)));
            if cond >= 1e-4 {
                let bound = 2e-5 + 4e-6 * std::f64::consts::PI / cond.sqrt();
                prop_assert!(((s[i] as f64) - r).abs() < bound, "scalar {} vs f64 {r} (cond {cond:e}, bound {bound:e})", s[i]);
            }
        }
        if simd() {
            let mut w = vec![0.0; n];
            kernels::ltc_quad(Backend::Avx2, &inp, &mut w).unwrap();
            for i in 0..n {
                prop_assert!(((w[i] - s[i]).abs() as f64) <= 2.0 * EPS * (s[i].abs() as f64).max(1.0), "avx2 {} vs scalar {}", w[i], s[i]);
            }
        }
    }

    /// (e) at the extremes: slope deviations down to 1e-4, correlation to ±0.999, mean
    /// slopes to ±3, views to 89.9°. Scalar vs the f64 grid ≤ 1e-4 relative; AVX2 vs scalar
    /// ≤ 8 ulp relative.
    #[test]
    fn leadr_extremes(
        px in prop::collection::vec((
            -3.0f64..3.0, -3.0f64..3.0, prop_oneof![Just(1e-4f64), 1e-4f64..0.6], prop_oneof![Just(1e-4f64), 1e-4f64..0.6],
            prop_oneof![Just(0.999f64), Just(-0.999f64), -0.99f64..0.99], 0.0f64..1.569, 0.0f64..std::f64::consts::TAU,
        ), 1..24)
    ) {
        let n = px.len();
        let mut cols: Vec<Vec<f32>> = vec![Vec::with_capacity(n); 8];
        for &(x0, y0, sx, sy, r, t, p) in &px {
            for (k, v) in [x0, y0, sx, sy, r, t.sin() * p.cos(), t.sin() * p.sin(), t.cos()].iter().enumerate() {
                cols[k].push(*v as f32);
            }
        }
        let inp = kernels::LeadrIn { s: [&cols[0], &cols[1], &cols[2], &cols[3], &cols[4]], v: [&cols[5], &cols[6], &cols[7]] };
        let mut s = vec![0.0; n];
        kernels::leadr5(Backend::Scalar, &inp, &mut s).unwrap();
        let h = ndfbench::generated::shading::LEADR_SPACING_N5 as f64;
        let grid = ndfbench::leadr::Grid::riemann(5, h);
        let sun = Vector3::new(0.5, 0.2, 0.8).normalize();
        for i in 0..n {
            let f = |k: usize| cols[k][i] as f64;
            let sl = ndfbench::leadr::Slopes { x0: f(0), y0: f(1), sx: f(2), sy: f(3), rxy: f(4) };
            let v = Vector3::new(f(5), f(6), f(7));
            let env = |nn: &Vector3<f64>| {
                let r = nn * (2.0 * nn.dot(&v)) - v;
                0.5 + 0.5 * r.z + 10.0 * (50.0 * (r.dot(&sun) - 1.0)).exp()
            };
            let want = ndfbench::leadr::grid_estimate(&grid, &sl, &v, &env, None);
            prop_assert!(s[i].is_finite());
            if want.is_finite() {
                prop_assert!(rel(s[i], want) < 1e-4, "scalar {} vs f64 {want}", s[i]);
            } else {
                prop_assert!(s[i] == 0.0, "all nodes face away: {}", s[i]);
            }
        }
        if simd() {
            let mut w = vec![0.0; n];
            kernels::leadr5(Backend::Avx2, &inp, &mut w).unwrap();
            for i in 0..n {
                prop_assert!(rel(w[i], s[i] as f64) <= 8.0 * EPS || (s[i] == 0.0 && w[i] == 0.0), "avx2 {} vs scalar {}", w[i], s[i]);
            }
        }
    }
}

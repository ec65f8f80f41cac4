//! Generated code: committed files are fresh, every WGSL module validates
//! with naga, and every Rust twin agrees with its f64 reference within a stated bound.

mod common;

use nalgebra::{Matrix2, Vector3};
use ndfbench::codegen;
use ndfbench::filters::rules as r;
use ndfbench::generated::shading as g;
use ndfbench::microfacet::{Microsurface, Roughness};
use proptest::prelude::*;
use std::path::Path;

type V3 = Vector3<f64>;

#[test]
fn committed_generated_files_are_fresh() {
    let files = codegen::render_all(Path::new("results"), true).expect("fit results present");
    // the function modules, the two LTC table modules and the two LTC lookups (any
    // table; anisotropic), each in three forms (plain, naga_oil, WESL), and the two Rust
    // files
    // … and the compact GGX table's WGSL library and compute rebuild, ES module, three.js
    // drop-in and Rust; and the texture-free sheen forms' WGSL, GLSL, three.js recipes
    // (WebGL and WebGPU) and Rust
    assert_eq!(files.len(), 3 * (codegen::MODULES.len() + 4) + 2 + 5 + 5);
    for (rel, text) in files {
        let path = if rel.starts_with("wgsl/")
            || rel.starts_with("glsl/")
            || rel.starts_with("shaders/")
            || rel.starts_with("textures/")
        {
            Path::new("results").join(&rel)
        } else {
            Path::new(&rel).to_path_buf()
        };
        let committed =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            committed == text,
            "{} is stale with respect to results/fits/*.json: run `{}`",
            path.display(),
            codegen::COMMAND
        );
        assert!(committed.lines().next().unwrap().contains(codegen::COMMAND));
    }
}

#[test]
fn every_wgsl_module_validates_with_naga() {
    let mut n = 0;
    for (file, _, names) in codegen::MODULES {
        let path = Path::new("results/wgsl").join(file);
        let src = std::fs::read_to_string(&path).unwrap();
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
        for name in names {
            assert!(
                module.functions.iter().any(|(_, f)| f.name.as_deref()
                    == Some(codegen::namespace::wgsl_name(name).as_str())),
                "{file} lacks {name}"
            );
        }
        n += 1;
    }
    assert_eq!(n, codegen::MODULES.len());
}

/// The LTC table modules validate, and their data equal the fitted table read
/// independently from results/fits/ltc-ggx.json: f32 to the bit, binary16 within half an
/// f16 ulp (decoded here by `half`, as `unpack2x16float` decodes it on a GPU).
#[test]
fn ltc_table_data_validate_and_match_the_fit() {
    for file in ["ltc_table.wgsl", "ltc_table_f16.wgsl"] {
        let path = Path::new("results/wgsl").join(file);
        let src = std::fs::read_to_string(&path).unwrap();
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&src)));
        // `unpack2x16float` is core WGSL; naga validates it only with the
        // SHADER_FLOAT16_IN_FLOAT32 capability (a downlevel flag in wgpu)
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default()
                | naga::valid::Capabilities::SHADER_FLOAT16_IN_FLOAT32,
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
        assert!(module
            .functions
            .iter()
            .any(|(_, f)| f.name.as_deref() == Some("ndfb_ltc_table_texel")));
    }
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("results/fits/ltc-ggx.json").unwrap())
            .unwrap();
    let table = v["table"].as_array().unwrap();
    use ndfbench::generated::ltc_table as lt;
    assert_eq!(table.len(), lt::LTC_TABLE_N);
    let n = lt::LTC_TABLE_N;
    for (j, col) in table.iter().enumerate() {
        for (i, c) in col.as_array().unwrap().iter().enumerate() {
            let k = i + n * j;
            let x: Vec<f64> = (0..6).map(|q| c[q].as_f64().unwrap()).collect();
            for q in 0..4 {
                assert_eq!(lt::LTC_1[k][q], x[q] as f32, "cell ({i}, {j})");
            }
            assert_eq!(lt::LTC_2[k], [x[4] as f32, x[5] as f32]);
            let unpack = |u: u32| {
                [
                    half::f16::from_bits(u as u16).to_f64(),
                    half::f16::from_bits((u >> 16) as u16).to_f64(),
                ]
            };
            let h = [unpack(lt::LTC_1_F16[k][0]), unpack(lt::LTC_1_F16[k][1])];
            let got = [h[0][0], h[0][1], h[1][0], h[1][1]];
            // the stored binary16 table (`table_f16`) exactly
            let stored = &v["table_f16"][j][i];
            for q in 0..4 {
                assert_eq!(
                    got[q],
                    stored[q].as_f64().unwrap(),
                    "f16 cell ({i}, {j})[{q}]"
                );
            }
            assert_eq!(
                unpack(lt::LTC_2_F16[k][0]),
                [stored[4].as_f64().unwrap(), stored[5].as_f64().unwrap()]
            );
            // round to nearest, and whether that keeps the lobe (det M⁻¹ = ad − bc > 0, b
            // of the f64 entry's sign); where it does not, the storage moves b toward 0 and d
            // up until it does (up to 64 binary16 steps) before its ±4-step search
            let near: Vec<f64> = x[..4]
                .iter()
                .map(|&y| half::f16::from_f64(y).to_f64())
                .collect();
            let keeps = |e: &[f64]| e[0] * e[3] - e[1] * e[2] > 0.0 && e[1] * x[1] >= 0.0;
            let steps = if keeps(&near) { 4.5 } else { 68.5 };
            assert!(keeps(&got), "f16 cell ({i}, {j}) mirrors its lobe: {got:?}");
            for q in 0..4 {
                // one binary16 step: relative 2⁻¹⁰ for normals, 2⁻²⁴ absolute below
                let tol = steps * (x[q].abs() * 2f64.powi(-10)).max(2f64.powi(-24));
                assert!(
                    (got[q] - x[q]).abs() <= tol,
                    "f16 cell ({i}, {j})[{q}]: {} vs {}",
                    got[q],
                    x[q]
                );
            }
        }
    }
}

#[test]
fn broken_wgsl_is_rejected_by_the_validator_used_above() {
    // the check above can fail: a type error is caught
    let src = "fn f(x: f32) -> f32 { return x + true; }";
    let bad = naga::front::wgsl::parse_str(src).map(|m| {
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&m)
        .is_ok()
    });
    assert!(!matches!(bad, Ok(true)));
}

fn unit(theta: f64, phi: f64) -> [f32; 3] {
    [
        (theta.sin() * phi.cos()) as f32,
        (theta.sin() * phi.sin()) as f32,
        theta.cos() as f32,
    ]
}
fn v64(a: [f32; 3]) -> V3 {
    V3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}
fn rel(a: f32, b: f64) -> f64 {
    ((a as f64) - b).abs() / b.abs().max(1e-300)
}

/// results/generated-range.md is what the compiled twins give now, and every generated
/// fitted function meets its stated bound over the whole input range, with no non-finite
/// output (the references are the f64 closed forms and rules, independent of the twins).
#[test]
fn generated_functions_meet_their_bounds_over_the_whole_range() {
    let audits = codegen::audit::run();
    let md = codegen::audit::markdown(&audits, codegen::COMMAND);
    let committed = std::fs::read_to_string("results/generated-range.md").unwrap_or_default();
    assert!(
        committed == md,
        "results/generated-range.md is stale: run `{}`",
        codegen::COMMAND
    );
    for a in &audits {
        assert_eq!(a.non_finite, 0, "{}: non-finite outputs", a.function);
        // (whole range, domain) bounds stated in the functions' docs
        let (whole, dom) = match a.function {
            "alpha_me" => (2e-4, 2e-4),
            "multiscale_alpha" => (3e-4, 3e-4),
            "beckmann_lambda" => (1e-4, 1e-4),
            "ggx_lambda" => (1e-6, 1e-6),
            "ltc_edge_factor" => (f64::INFINITY, 3e-5),
            _ => (1e-6, 1e-6),
        };
        assert!(
            a.max_error <= whole,
            "{}: {:e} over the whole range",
            a.function,
            a.max_error
        );
        assert!(
            a.in_domain_max_error.unwrap_or(0.0) <= dom,
            "{}: {:?} in its domain",
            a.function,
            a.in_domain_max_error
        );
    }
}

proptest! {
    #![proptest_config(common::config(10_000))] // was 500

    /// Every f32 input, NaN and ±∞ included: the table coordinates land on the table, the
    /// filters' square-root sum is finite and correct, and GGX Λ is finite for o_z > 0.
    #[test]
    fn generated_forms_are_total_over_f32(x in any::<f32>(), y in any::<f32>(), z in 1e-38f32..1.0) {
        let n = g::LTC_LUT_SIZE;
        for c in [g::ltc_lut_u(x), g::ltc_lut_v(x)] {
            prop_assert!(c >= 0.5 / n - 1e-7 && c <= (n - 0.5) / n + 1e-7, "{x}: {c}");
        }
        if x.is_finite() && y.is_finite() {
            let (a, k) = (x.abs(), y.abs());
            let got = g::filter_sqrt_sum(a, k) as f64;
            let want = (a as f64).hypot((k as f64).sqrt());
            prop_assert!(got.is_finite() && (got - want).abs() <= 4e-7 * want, "{a}, {k}: {got} vs {want}");
            // any unit direction above the surface, any finite α
            let (ox, oz) = ((1.0 - z * z).max(0.0).sqrt(), z);
            let l = g::ggx_lambda(ox, 0.0, oz, a);
            prop_assert!(!l.is_nan() && l >= 0.0, "α {a}, oz {oz}: {l}");
        }
    }

    /// GGX D (iso, aniso, matrix) and Λ: ≤ 2e-6 relative (≈ 16 ulp) plus, for the
    /// matrix form, 16·ε·cond(A) (the adjugate quadratic form cancels).
    #[test]
    fn ggx_twins_match_f64(
        alpha in prop_oneof![Just(1e-4f64), 1e-4f64..1.0],
        aniso in 1.0f64..30.0,
        off in -0.9f64..0.9,
        theta in 0.0f64..1.5706,
        phi in 0.0f64..std::f64::consts::TAU,
    ) {
        let a = alpha as f32;
        let h = unit(theta, phi);
        let s = Microsurface::ggx(Roughness::iso(a as f64).unwrap());
        let d64 = s.d(&v64(h));
        prop_assert!(rel(g::ggx_d(h[0], h[1], h[2], a), d64) < 2e-6);
        let ay = (alpha * aniso).min(1.0) as f32;
        let sa = Microsurface::ggx(Roughness::aniso(a as f64, ay as f64).unwrap());
        prop_assert!(rel(g::ggx_d_aniso(h[0], h[1], h[2], a, ay), sa.d(&v64(h))) < 2e-6);
        // matrix: a12 = off·√(a11 a22), exactly representable parameters
        let (a11, a22) = (a * a, ay * ay);
        let a12 = (off as f32) * (a11 * a22).sqrt();
        let m = Roughness::matrix(Matrix2::new(a11 as f64, a12 as f64, a12 as f64, a22 as f64)).unwrap();
        let (lo, hi) = m.eigenvalues();
        let cond = hi / lo;
        let sm = Microsurface::ggx(m);
        let got = g::ggx_d_matrix(h[0], h[1], h[2], a11, a12, a22);
        prop_assert!(rel(got, sm.d(&v64(h))) < 2e-6 + 16.0 * f32::EPSILON as f64 * cond,
            "matrix D: {} vs {} (cond {cond})", got, sm.d(&v64(h)));
        if h[2] > 0.0 && theta > 1e-3 {
            prop_assert!(rel(g::ggx_lambda(h[0], h[1], h[2], a), s.lambda(&v64(h))) < 2e-6);
        }
    }

    /// Point-light GGX specular vs the f64 lobe of the filters' truth: ≤ 1e-5 relative.
    #[test]
    fn ggx_specular_twin_matches_f64(
        alpha in prop_oneof![Just(1e-3f64), 1e-3f64..1.0],
        tl in 0.0f64..1.55, pl in 0.0f64..std::f64::consts::TAU,
        tv in 0.0f64..1.55, pv in 0.0f64..std::f64::consts::TAU,
    ) {
        let a = alpha as f32;
        let (l, v) = (unit(tl, pl), unit(tv, pv));
        let s = Microsurface::ggx(Roughness::iso(a as f64).unwrap());
        let f = ndfbench::filters::truth::Frame::around(V3::z());
        let want = ndfbench::filters::truth::lobe(&s, &f, &v64(v), &v64(l));
        let got = g::ggx_specular(l[0], l[1], l[2], v[0], v[1], v[2], a);
        if want > 1e-30 {
            prop_assert!(rel(got, want) < 1e-5, "{got} vs {want}");
        } else {
            prop_assert!(got.abs() < 1e-20);
        }
    }

    /// Beckmann: D ≤ 1e-6·(4 + x) relative (x = tan²θ/α², exp's amplification); G1 from
    /// the refitted Λ within 5e-5 of the exact (fit 2.3e-5 + f32).
    #[test]
    fn beckmann_twins_match_f64(
        alpha in 1e-3f64..1.0,
        theta in 0.0f64..1.5706,
        phi in 0.0f64..std::f64::consts::TAU,
    ) {
        let a = alpha as f32;
        let h = unit(theta, phi);
        let s = Microsurface::beckmann(Roughness::iso(a as f64).unwrap());
        let d64 = s.d(&v64(h));
        let hz = h[2] as f64;
        let x = ((h[0] as f64).powi(2) + (h[1] as f64).powi(2)) / (hz * hz * (a as f64).powi(2));
        if d64 > 1e-30 {
            prop_assert!(rel(g::beckmann_d(h[0], h[1], h[2], a), d64) < 1e-6 * (4.0 + x));
        }
        if h[2] > 0.0 && theta > 1e-3 {
            let exact = 1.0 / (1.0 + s.lambda(&v64(h)));
            let ours = 1.0 / (1.0 + g::beckmann_lambda(h[0], h[1], h[2], a) as f64);
            prop_assert!((ours - exact).abs() < 5e-5, "G1 {ours} vs {exact}");
        }
    }

    /// Filters: the generated forms equal the f64 rules within 1e-6 relative.
    #[test]
    fn filter_twins_match_rules(
        alpha in 1e-4f32..1.0,
        m in 0.5f32..1.0,
        d in prop::array::uniform6(-0.5f32..0.5),
    ) {
        let (a, mm) = (alpha as f64, m as f64);
        let d64 = d.map(|x| x as f64);
        prop_assert!(rel(g::filter_vmf(alpha, m, 2.0), r::vmf(a, mm, 2.0)) < 1e-6);
        prop_assert!(rel(g::filter_toksvig(alpha, m, 2.0), r::toksvig_alpha2(a, mm, 2.0)) < 1e-6);
        prop_assert!(rel(
            g::filter_deferred(alpha, d[0], d[1], d[2], d[3], d[4], d[5], 0.25, 0.18),
            r::deferred(a, [d64[0], d64[1], d64[2]], [d64[3], d64[4], d64[5]], 0.25, 0.18)
        ) < 1e-6);
        prop_assert!(rel(
            g::filter_eq10(alpha, d[0], d[1], d[3], d[4], 0.25, 0.18),
            r::eigen_eq10(a, [d64[0], d64[1]], [d64[3], d64[4]], 0.25, 0.18)
        ) < 1e-6);
        if alpha < 0.99 {
            prop_assert!(rel(
                g::filter_projected(alpha, d[0], d[1], d[2], d[3], d[4], d[5], 0.1, 0.04),
                r::projected_space(a, [d64[0], d64[1], d64[2]], [d64[3], d64[4], d64[5]], 0.1, 0.04)
            ) < 1e-6 * (1.0 + 1.0 / (1.0 - a * a)));
        }
    }

    /// α_me and the multi-scale α over every f32 input y ∈ [m, 1] (m the smallest normal
    /// f32): within 2e-4 relative of Newton on the closed form at the same f32 input (the
    /// fit's held-out error is 1.6e-4 on α ∈ [1e-4, 1e2]; beyond, both branches follow
    /// their exact asymptotes). Inputs are drawn log-uniform in y (α ≤ 1) and in
    /// b = 1 − y (α > 1), so both ends are sampled as densely as the middle.
    #[test]
    fn multiscale_twins_match_newton(l in -37.9f64..0.0, large in any::<bool>(), lb in -4.0f64..2.0) {
        let y32 = if large {
            1.0 - (10f64.powf(l) * (2.0 / 3.0)) as f32 // b ∈ [1.2e-38, 2/3)
        } else {
            (10f64.powf(l) / 3.0) as f32 // y ∈ [1.2e-38, 1/3]
        };
        let y32 = y32.max(f32::MIN_POSITIVE);
        let (y, b) = (y32 as f64, 1.0 - y32 as f64);
        if b > 0.0 {
            let want = ndfbench::multiscale::mrl::alpha_from_pair(b, y).unwrap();
            let got = g::alpha_me(y32);
            prop_assert!(got.is_finite() && rel(got, want) < 2e-4, "y {y32:e}: {got} vs {want}");
        }
        // overall α for (α_mi, α_me): ρ = ρ_me ρ_mi, α_me over [1e-4, 1e2]
        let ame = 10f64.powf(lb);
        let alpha = ndfbench::multiscale::mrl::alpha_from_pair(b.max(1e-300), y).unwrap_or(1.0).clamp(1e-4, 1e2);
        let want = ndfbench::multiscale::overall::alpha_moment(alpha, ame).unwrap();
        let y_me = ndfbench::multiscale::mrl::mrl_pair(ame).1 as f32;
        let y_mi = ndfbench::multiscale::mrl::mrl_pair(alpha).1 as f32;
        let got = g::multiscale_alpha(y_me, y_mi);
        // the f32 inputs carry ε/2 each; near y = 1 that is ε/(2b) relative in α
        let yy = ndfbench::multiscale::mrl::mrl_pair(want).1;
        let input = f32::EPSILON as f64 * (1.0 + yy / (1.0 - yy).max(1e-30));
        prop_assert!(got.is_finite() && rel(got, want) < 3e-4 + input, "({alpha}, {ame}): {got} vs {want}");
    }

    /// Nonsense inputs (NaN, ±∞, negative, above 1) give a finite α ≥ 0.
    #[test]
    fn alpha_me_is_total(y in any::<f32>()) {
        let v = g::alpha_me(y);
        prop_assert!(v.is_finite() && v >= 0.0, "y {y}: {v}");
    }
}

//! `eval filter`: α′ of one footprint filter, f64 reference and f32 shading form.

use super::args::*;
use crate::error::{Error, Result};
use crate::microfacet::Roughness;
use nalgebra::Matrix2;
use serde_json::json;

/// `eval filter`: α′ of one footprint filter, f64 reference and f32 shading form.
pub(super) fn filter_eval(
    a: &EvalArgs,
    fits: &std::path::Path,
) -> Result<(f64, serde_json::Value)> {
    use crate::filters::rules as r;
    let f = a
        .filter
        .ok_or_else(|| Error::InvalidArgument("filter needs --filter NAME".into()))?;
    let al = a
        .alpha
        .ok_or_else(|| Error::InvalidArgument("filter needs --alpha".into()))?;
    if !(al.is_finite() && al > 0.0) {
        return Err(Error::InvalidRoughness(al));
    }
    let b = || -> Result<f64> {
        let b = a.b.ok_or_else(|| {
            Error::InvalidArgument(format!(
                "filter {f:?} needs --b (|μ| of the mip-mapped normal)"
            ))
        })?;
        if !(b > 0.0 && b <= 1.0) {
            return Err(Error::InvalidArgument(format!(
                "--b must lie in (0, 1], got {b:e}"
            )));
        }
        Ok(b)
    };
    let v3 = |s: &Option<String>, n: &str| -> Result<[f64; 3]> {
        let s = s
            .as_ref()
            .ok_or_else(|| Error::InvalidArgument(format!("filter {f:?} needs --{n}")))?;
        let v = parse_list(s, 3, n)?;
        Ok([v[0], v[1], v[2]])
    };
    let v2 = |s: &Option<String>, n: &str| -> Result<[f64; 2]> {
        let s = s
            .as_ref()
            .ok_or_else(|| Error::InvalidArgument(format!("filter {f:?} needs --{n}")))?;
        let v = parse_list(s, 2, n)?;
        Ok([v[0], v[1]])
    };
    let c32 = |x: [f64; 3]| x.map(|y| y as f32);
    let d32 = |x: [f64; 2]| x.map(|y| y as f32);
    let lmax = |m: [f64; 3]| crate::linalg::sym2_eigen(&Matrix2::new(m[0], m[2], m[2], m[1])).1;
    let a32 = al as f32;
    // a rule evaluated twice from one argument list: f64 reference and f32 shading form
    // (the literal constants infer to either precision)
    macro_rules! both {
        ($f:path; $x64:expr, $x32:expr; $($c:expr),*) => {
            ($f(al, $x64, $($c),*), $f(a32, $x32, $($c),*), json!({}))
        };
        ($f:path; $x64:expr, $y64:expr, $x32:expr, $y32:expr; $($c:expr),*) => {
            ($f(al, $x64, $y64, $($c),*), $f(a32, $x32, $y32, $($c),*), json!({}))
        };
    }
    let (v64, v32, extra): (f64, f32, serde_json::Value) = match f {
        FilterName::ToksvigBp => {
            let bv = b()?;
            (
                r::toksvig_bp(al, bv),
                r::toksvig_bp(a32, bv as f32),
                json!({}),
            )
        }
        FilterName::Toksvig => both!(r::toksvig_alpha2; b()?, b()? as f32; 2.0),
        FilterName::ToksvigHalf => both!(r::toksvig_alpha2; b()?, b()? as f32; 1.0),
        FilterName::Vmf2 => both!(r::vmf; b()?, b()? as f32; 2.0),
        FilterName::Vmf1 => both!(r::vmf; b()?, b()? as f32; 1.0),
        FilterName::VmfHalf => both!(r::vmf; b()?, b()? as f32; 0.5),
        FilterName::Seed000Paper => {
            let bv = b()?;
            (
                r::seed000_paper(al, bv),
                r::seed000_paper(a32, bv as f32),
                json!({}),
            )
        }
        FilterName::Seed000Moment => {
            let rho = crate::multiscale::mrl::mrl_pair(al).0;
            let y = 1.0 - b()? * rho;
            let exact = crate::multiscale::mrl::alpha_from_one_minus(y)?;
            let coeffs = ours_coefficients(fits)?;
            let (s32, l32) = coeffs.to_f32();
            (
                exact,
                r::seed000_moment_fit(b()? as f32, rho as f32, &s32, &l32),
                json!({"rho_base": rho, "fit": "results/fits/multiscale-alpha-me.json (ours)"}),
            )
        }
        FilterName::Lean => {
            let c = v3(&a.cov, "cov")?;
            let m = r::lean(al, c);
            Roughness::matrix(Matrix2::new(m[0], m[2], m[2], m[1]))?;
            let m32 = r::lean(a32, c32(c));
            (
                lmax(m).sqrt(),
                lmax(m32.map(|x| x as f64)).sqrt() as f32,
                json!({"matrix_xx_yy_xy": m}),
            )
        }
        FilterName::Deferred
        | FilterName::DeferredUnclamped
        | FilterName::Filament
        | FilterName::Unity
        | FilterName::UnityProjected
        | FilterName::Godot => {
            let (u, v) = (v3(&a.dn_u, "dn-u")?, v3(&a.dn_v, "dn-v")?);
            let (u3, w3) = (c32(u), c32(v));
            match f {
                FilterName::Deferred => both!(r::deferred; u, v, u3, w3; 0.25, 0.18),
                // 1e30 for "no clamp": the saturation at α′ = 1 acts long before it
                FilterName::DeferredUnclamped => both!(r::deferred; u, v, u3, w3; 0.25, 1e30),
                FilterName::Filament => both!(r::deferred; u, v, u3, w3; 0.15, 0.04),
                FilterName::Unity => both!(r::deferred; u, v, u3, w3; 0.1, 0.04),
                FilterName::UnityProjected => both!(r::projected_space; u, v, u3, w3; 0.1, 0.04),
                _ => both!(r::deferred_on_alpha; u, v, u3, w3; 0.25, 0.18),
            }
        }
        FilterName::Eigen | FilterName::KaplanyanRect | FilterName::Forward => {
            let (u, v) = (v2(&a.du, "du")?, v2(&a.dv, "dv")?);
            let (u2, w2) = (d32(u), d32(v));
            match f {
                FilterName::Eigen => both!(r::eigen_eq10; u, v, u2, w2; 0.25, 0.18),
                FilterName::KaplanyanRect => both!(r::kaplanyan_rect; u, v, u2, w2; 0.25, 0.18),
                _ => {
                    let m = r::forward_matrix(al, u, v, 0.25);
                    let m32 = r::forward_matrix(a32, u2, w2, 0.25);
                    (
                        lmax(m).sqrt(),
                        lmax(m32.map(|x| x as f64)).sqrt() as f32,
                        json!({"matrix_xx_yy_xy": m}),
                    )
                }
            }
        }
    };
    filter_result(a, f, al, (v64, v32, extra))
}

/// The `Ours` α_me coefficients, refitted from fits/multiscale-alpha-me.toml exactly as
/// `regen` does (deterministic linear least squares, < 1 ms).
fn ours_coefficients(fits: &std::path::Path) -> Result<crate::multiscale::alpha_me::OursFit> {
    let spec = crate::fit::spec::load_dir(fits)?
        .into_iter()
        .find(|s| s.name == "multiscale-alpha-me")
        .ok_or_else(|| {
            Error::InvalidArgument(format!(
                "no multiscale-alpha-me spec in '{}'",
                fits.display()
            ))
        })?;
    let train = crate::multiscale::alpha_me::training_alphas(
        spec.training.points,
        spec.domain.alpha_min,
        spec.domain.alpha_max,
    );
    crate::multiscale::alpha_me::fit_ours(spec.terms, spec.terms_large, &train)
}

/// The JSON of one filter evaluation: the f64 value, and the f32 shading form where every
/// input is an f32 (otherwise why it is absent).
fn filter_result(
    a: &EvalArgs,
    f: FilterName,
    al: f64,
    (v64, v32, extra): (f64, f32, serde_json::Value),
) -> Result<(f64, serde_json::Value)> {
    if !v64.is_finite() {
        return Err(Error::InvalidArgument(format!(
            "filter {f:?} is not finite for these inputs"
        )));
    }
    // the f32 shading form is reported only where every input is an f32 (no overflow to ∞
    // and no non-zero input flushed to 0); otherwise the JSON says why it is absent
    let inputs: Vec<f64> = [Some(al), a.b]
        .into_iter()
        .flatten()
        .chain(
            [&a.cov, &a.dn_u, &a.dn_v, &a.du, &a.dv]
                .into_iter()
                .flatten()
                .flat_map(|s| parse_list(s, s.split(',').count(), "input").unwrap_or_default()),
        )
        .collect();
    let representable = inputs
        .iter()
        .all(|&x| (x as f32).is_finite() && (x == 0.0 || x as f32 != 0.0));
    /// What `eval filter` prints besides the value.
    #[derive(serde::Serialize)]
    struct Out {
        filter: String,
        alpha_in: f64,
        detail: serde_json::Value,
        report: &'static str,
        #[serde(skip_serializing_if = "Option::is_none")]
        f32_note: Option<&'static str>,
        #[serde(skip_serializing_if = "Option::is_none")]
        f32: Option<f32>,
        #[serde(skip_serializing_if = "Option::is_none")]
        f32_rel_diff: Option<f64>,
    }
    let mut out = Out {
        filter: format!("{f:?}"),
        alpha_in: al,
        detail: extra,
        report: "results/filters.md",
        f32_note: None,
        f32: None,
        f32_rel_diff: None,
    };
    if !representable {
        out.f32_note = Some("an input is outside the f32 range (|x| > 3.4e38 or a non-zero |x| < 1.4e-45): the shading form cannot receive it");
    } else if v32.is_finite() {
        out.f32 = Some(v32);
        out.f32_rel_diff = Some((v32 as f64 - v64) / v64);
    } else {
        return Err(Error::InvalidArgument(format!(
            "the f32 shading form of filter {f:?} is not finite for these inputs (f64: {v64:e})"
        )));
    }
    Ok((v64, serde_json::to_value(out).unwrap_or_default()))
}

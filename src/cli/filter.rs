//! `eval filter`: α′ of one footprint filter, f64 reference and f32 shading form.

use super::args::*;
use crate::error::{Error, Result};
use crate::filters::registry::{Filter, MapRule, Rule, ScreenRule};
use crate::filters::rules;
use crate::microfacet::Roughness;
use nalgebra::Matrix2;
use serde_json::json;

/// `eval filter`: α′ of one footprint filter of the registry
/// ([`crate::filters::registry`]), f64 reference and f32 shading form. A refitted filter
/// reads its constant from `results`/fits/filters.json.
pub(super) fn filter_eval(
    a: &EvalArgs,
    fits: &std::path::Path,
    results: &std::path::Path,
) -> Result<(f64, serde_json::Value)> {
    let key = a
        .filter
        .as_deref()
        .ok_or_else(|| Error::InvalidArgument("filter needs --filter NAME".into()))?;
    let f = Filter::get(key, "--filter")?;
    let al = a
        .alpha
        .ok_or_else(|| Error::InvalidArgument("filter needs --alpha".into()))?;
    if !(al.is_finite() && al > 0.0) {
        return Err(Error::InvalidRoughness(al));
    }
    let (rule, constant) = match f.family() {
        Some(family) => {
            let v: crate::results::filters::Filters = crate::results::require(results)?;
            let c = v.fitted(family, "GGX").map(|x| x.constant);
            (f.rule_with(|_| c)?, c)
        }
        None => (f.rule(), None),
    };
    let b = || -> Result<f64> {
        let b = a.b.ok_or_else(|| {
            Error::InvalidArgument(format!(
                "filter {key} needs --b (|μ| of the mip-mapped normal)"
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
            .ok_or_else(|| Error::InvalidArgument(format!("filter {key} needs --{n}")))?;
        let v = parse_list(s, 3, n)?;
        Ok([v[0], v[1], v[2]])
    };
    let v2 = |s: &Option<String>, n: &str| -> Result<[f64; 2]> {
        let s = s
            .as_ref()
            .ok_or_else(|| Error::InvalidArgument(format!("filter {key} needs --{n}")))?;
        let v = parse_list(s, 2, n)?;
        Ok([v[0], v[1]])
    };
    let lmax = |m: [f64; 3]| crate::linalg::sym2_eigen(&Matrix2::new(m[0], m[2], m[2], m[1])).1;
    let a32 = al as f32;
    // every rule is one generic function: f64 reference and f32 shading form
    let (v64, v32, extra): (f64, f32, serde_json::Value) = match rule {
        Rule::Map(MapRule::Lean) => {
            let c = v3(&a.cov, "cov")?;
            let m = rules::lean(al, c);
            Roughness::matrix(Matrix2::new(m[0], m[2], m[2], m[1]))?;
            let m32 = rules::lean(a32, c.map(|y| y as f32));
            (
                lmax(m).sqrt(),
                lmax(m32.map(|x| x as f64)).sqrt() as f32,
                json!({"matrix_xx_yy_xy": m}),
            )
        }
        Rule::Map(MapRule::Moment) => {
            let rho = crate::multiscale::mrl::mrl_pair(al).0;
            let y = 1.0 - b()? * rho;
            let exact = crate::multiscale::mrl::alpha_from_one_minus(y)?;
            let coeffs = ours_coefficients(fits)?;
            let (s32, l32) = coeffs.to_f32();
            (
                exact,
                rules::seed000_moment_fit(b()? as f32, rho as f32, &s32, &l32),
                json!({"rho_base": rho, "fit": "results/fits/multiscale-alpha-me.json (ours)"}),
            )
        }
        Rule::Map(r) => {
            let bv = b()?;
            // the moment rule and LEAN are handled above: no moment is needed here
            (
                r.alpha(al, bv, || f64::NAN).unwrap_or(f64::NAN),
                r.alpha(a32, bv as f32, || f32::NAN).unwrap_or(f32::NAN),
                json!({}),
            )
        }
        Rule::Screen(ScreenRule::None) => (al, a32, json!({})),
        Rule::Screen(
            r @ (ScreenRule::Deferred { .. }
            | ScreenRule::DeferredOnAlpha { .. }
            | ScreenRule::ProjectedSpace { .. }),
        ) => {
            let (u, v) = (v3(&a.dn_u, "dn-u")?, v3(&a.dn_v, "dn-v")?);
            let f32s = |x: [f64; 3]| x.map(|y| y as f32);
            (
                r.alpha_from_normals(al, u, v).unwrap_or(f64::NAN),
                r.alpha_from_normals(a32, f32s(u), f32s(v))
                    .unwrap_or(f32::NAN),
                json!({}),
            )
        }
        Rule::Screen(r @ (ScreenRule::Eigen { .. } | ScreenRule::KaplanyanRect { .. })) => {
            let (u, v) = (v2(&a.du, "du")?, v2(&a.dv, "dv")?);
            let f32s = |x: [f64; 2]| x.map(|y| y as f32);
            (
                r.alpha_from_2d(al, u, v).unwrap_or(f64::NAN),
                r.alpha_from_2d(a32, f32s(u), f32s(v)).unwrap_or(f32::NAN),
                json!({}),
            )
        }
        Rule::Screen(ScreenRule::Forward { .. }) => {
            let (u, v) = (v2(&a.du, "du")?, v2(&a.dv, "dv")?);
            let f32s = |x: [f64; 2]| x.map(|y| y as f32);
            let m = rules::forward_matrix(al, u, v, 0.25);
            let m32 = rules::forward_matrix(a32, f32s(u), f32s(v), 0.25);
            (
                lmax(m).sqrt(),
                lmax(m32.map(|x| x as f64)).sqrt() as f32,
                json!({"matrix_xx_yy_xy": m}),
            )
        }
    };
    filter_result(a, (f, constant), al, (v64, v32, extra))
}

/// The `Ours` α_me coefficients, refitted from fits/multiscale-alpha-me.toml exactly as
/// `regen` does (deterministic linear least squares, < 1 ms).
fn ours_coefficients(fits: &std::path::Path) -> Result<crate::multiscale::alpha_me::OursFit> {
    crate::studies::multiscale_alpha_me::params_in(fits)?.fit()
}

/// The JSON of one filter evaluation: the f64 value, and the f32 shading form where every
/// input is an f32 (otherwise why it is absent).
fn filter_result(
    a: &EvalArgs,
    (f, constant): (Filter, Option<f64>),
    al: f64,
    (v64, v32, extra): (f64, f32, serde_json::Value),
) -> Result<(f64, serde_json::Value)> {
    if !v64.is_finite() {
        return Err(Error::InvalidArgument(format!(
            "filter {} is not finite for these inputs",
            f.key()
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
        label: String,
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
        filter: f.key().into(),
        label: f.label_with(constant),
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
            "the f32 shading form of filter {} is not finite for these inputs (f64: {v64:e})",
            f.key()
        )));
    }
    Ok((v64, serde_json::to_value(out).unwrap_or_default()))
}

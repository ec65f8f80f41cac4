//! `eval` of the model quantities: the microsurface, the Jacobians, ‖b̄‖, α_me and the
//! overall α.

use super::args::*;
use crate::error::{Error, Result};
use crate::jacobian::{DirMap, HalfToSlope, HalfVector, NormalToSlope, ProjectedDisk, Reflection};
use crate::microfacet::sampling::VndfSampler;
use crate::microfacet::Roughness;
use nalgebra::Vector2;
use serde_json::json;

/// ‖b̄‖ of the isotropic LTC (closed form).
pub(super) fn mrl(a: &EvalArgs) -> Result<(f64, serde_json::Value)> {
    let al = a
        .alpha
        .ok_or_else(|| Error::InvalidArgument("mrl needs --alpha".into()))?;
    if !(al.is_finite() && al > 0.0) {
        return Err(Error::InvalidRoughness(al));
    }
    let (b, y) = crate::multiscale::mrl::mrl_pair(al);
    Ok((
        b,
        json!({"one_minus_b": y, "form": "closed form, proofs/mrl-closed-form.md"}),
    ))
}

/// The overall α of γ_me ∗ γ_mi under every metric.
pub(super) fn overall_alpha(a: &EvalArgs) -> Result<(f64, serde_json::Value)> {
    let get = |v: Option<f64>, n: &str| -> Result<f64> {
        let v = v.ok_or_else(|| Error::InvalidArgument(format!("overall-alpha needs --{n}")))?;
        // the supported roughness range, as for every surface
        Roughness::iso(v)?;
        Ok(v)
    };
    let (mi, me) = (get(a.alpha_mi, "alpha-mi")?, get(a.alpha_me, "alpha-me")?);
    let e = crate::multiscale::overall::evaluate_pair(mi, me)?;
    /// What `eval overall-alpha` prints besides the value.
    #[derive(serde::Serialize)]
    struct Out<'a, C: serde::Serialize> {
        value_is: &'static str,
        moment_unclipped: f64,
        paper_eq7: f64,
        note: &'a str,
        report: &'static str,
        #[serde(flatten)]
        fit: Option<FitPart<C>>,
        #[serde(skip_serializing_if = "Option::is_none")]
        limit_every_metric: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        limit_rel_error: Option<f64>,
    }
    #[derive(serde::Serialize)]
    struct FitPart<C: serde::Serialize> {
        moment_clipped: f64,
        l2: f64,
        caps: C,
        cap_quadrature_rel_error: f64,
    }
    let (limit, limit_err) = match (e.limit, e.limit_rel_error) {
        (Some(l), Some(err)) => (Some(l), Some(err)),
        _ => (None, None),
    };
    let m = Out {
        value_is: "moment-unclipped (closed form); the other metrics follow where evaluated",
        moment_unclipped: e.moment_unclipped,
        paper_eq7: crate::multiscale::overall::eq7(mi, me),
        note: &e.note,
        report: "results/multiscale-convolution.md",
        fit: e.fit.as_ref().map(|f| FitPart {
            moment_clipped: f.moment_clipped,
            l2: f.l2,
            caps: &f.caps,
            cap_quadrature_rel_error: f.cap_quad_rel_error,
        }),
        limit_every_metric: limit,
        limit_rel_error: limit_err,
    };
    Ok((
        e.moment_unclipped,
        serde_json::to_value(m).unwrap_or_default(),
    ))
}

/// α_me(‖b̄‖) by the chosen method, with its held-out error.
pub(super) fn alpha_me(a: &EvalArgs, fits: &std::path::Path) -> Result<(f64, serde_json::Value)> {
    let (b, y) = match (a.b, a.one_minus_b) {
        (Some(b), None) => (b, 1.0 - b),
        (None, Some(y)) => (1.0 - y, y),
        _ => {
            return Err(Error::InvalidArgument(
                "alpha-me needs exactly one of --b, --one-minus-b".into(),
            ))
        }
    };
    // either may round to 1 when the other is tiny; neither may be 0
    if !(y > 0.0 && y <= 1.0 && b > 0.0 && b <= 1.0) {
        return Err(Error::InvalidArgument(match a.b {
            Some(b) => format!("--b (‖b̄‖) must lie in (0, 1), got {b:e}"),
            None => format!("--one-minus-b must lie in (0, 1), got {y:e}"),
        }));
    }
    let spec = || crate::studies::multiscale_alpha_me::params_in(fits);
    use crate::multiscale::alpha_me::{held_out, held_out_alphas, paper_method, Table};
    let method: Box<dyn Fn(f64, f64) -> f64> = match a.method {
        AlphaMethod::Paper => Box::new(paper_method),
        AlphaMethod::Newton => {
            Box::new(|b, y| crate::multiscale::mrl::alpha_from_pair(b, y).unwrap_or(f64::NAN))
        }
        AlphaMethod::Ours => {
            let c = spec()?.fit()?;
            Box::new(move |_b, y| c.eval(y))
        }
        AlphaMethod::Table => {
            let s = spec()?;
            let t = Table::build(s.table_entries, s.alpha_min, s.alpha_max);
            Box::new(move |_b, y| t.eval(y))
        }
    };
    let v = method(b, y);
    // the method's measured error on the spec's held-out points (or the default domain)
    let (lo, hi, n) = spec()
        .map(|s| (s.alpha_min, s.alpha_max, s.held_out_points))
        .unwrap_or((1e-3, 1.0, 2000));
    let h = held_out(&held_out_alphas(n, lo, hi), &|b, y| method(b, y));
    // inside the fit domain is a property of the input: y between y(α_min) and
    // y(α_max) (1 − ‖b̄‖ increases with α)
    let (y_at_lo, y_at_hi) = (
        crate::multiscale::mrl::mrl_pair(lo).1,
        crate::multiscale::mrl::mrl_pair(hi).1,
    );
    Ok((
        v,
        json!({"method": format!("{:?}", a.method), "held_out": h, "held_out_domain_alpha": [lo, hi], "held_out_domain_one_minus_b": [y_at_lo, y_at_hi], "inside_domain": y >= y_at_lo && y <= y_at_hi}),
    ))
}

/// The Jacobian determinant of a direction map.
pub(super) fn jacobian(a: &EvalArgs) -> Result<(f64, serde_json::Value)> {
    let w = vec3(&a.w, "w")?;
    let map: Box<dyn DirMap> = match a
        .map
        .ok_or_else(|| Error::InvalidArgument("jacobian needs --map".into()))?
    {
        MapName::NormalToSlope => Box::new(NormalToSlope),
        MapName::SlopeParallel => Box::new(HalfToSlope),
        MapName::ProjectedDisk => Box::new(ProjectedDisk),
        MapName::Reflection => Box::new(Reflection {
            o: vec3(&a.o, "o")?,
        }),
        MapName::HalfVector => Box::new(HalfVector {
            o: vec3(&a.o, "o")?,
        }),
    };
    if matches!(a.map, Some(MapName::NormalToSlope | MapName::SlopeParallel)) && !(w.z > 0.0) {
        return Err(Error::BelowHorizon { what: "w", z: w.z });
    }
    if matches!(a.map, Some(MapName::HalfVector)) {
        // ω_i = −ω_o has no half-vector (w + o = 0)
        let o = vec3(&a.o, "o")?;
        if (w + o).norm() <= 1e-12 {
            return Err(Error::DegenerateDirection {
                what: "w + o (the half-vector of w = −o)",
            });
        }
    }
    Ok((map.det(&w), json!({"map": map.name()})))
}

/// A quantity of the microsurface (D, P22, Λ, ν, G1, G2, VNDF pdf).
pub(super) fn surface_quantity(a: &EvalArgs) -> Result<(f64, serde_json::Value)> {
    let s = surface(a)?;
    let v = match a.quantity {
        Quantity::D => s.d(&vec3(&a.m, "m")?),
        Quantity::P22 => {
            let sl = parse_list(
                a.slope
                    .as_deref()
                    .ok_or_else(|| Error::InvalidArgument("p22 needs --slope".into()))?,
                2,
                "slope",
            )?;
            s.p22(&Vector2::new(sl[0], sl[1]))
        }
        Quantity::Lambda => s.lambda(&vec3(&a.o, "o")?),
        Quantity::Nu => s.nu(&vec3(&a.o, "o")?),
        Quantity::G1 => s.g1(&vec3(&a.o, "o")?, &vec3(&a.m, "m")?),
        Quantity::G2Correlated => {
            s.g2_correlated(&vec3(&a.i, "i")?, &vec3(&a.o, "o")?, &vec3(&a.m, "m")?)
        }
        Quantity::G2Separable => {
            s.g2_separable(&vec3(&a.i, "i")?, &vec3(&a.o, "o")?, &vec3(&a.m, "m")?)
        }
        Quantity::VndfPdf => VndfSampler::new(s, vec3(&a.o, "o")?)?.pdf_exact(&vec3(&a.m, "m")?),
        Quantity::Jacobian
        | Quantity::Mrl
        | Quantity::AlphaMe
        | Quantity::OverallAlpha
        | Quantity::Filter => {
            unreachable!("handled above")
        }
    };
    Ok((
        v,
        json!({"ndf": format!("{:?}", s.kind), "roughness_matrix": [s.rough.a()[(0,0)], s.rough.a()[(0,1)], s.rough.a()[(1,1)]], "mean_slope": [s.mean.x, s.mean.y], "lambda": format!("{:?}", s.lambda_kind)}),
    ))
}

//! `eval`: evaluate one model quantity from the command line, JSON out. The argument
//! types and the dispatch live here; the quantities in [`quantities`], the footprint
//! filters in [`filter`]; the `prefilter` arguments in [`prefilter`].

mod args;
pub mod batch;
pub mod command;
mod filter;
pub mod prefilter;
mod quantities;

use filter::filter_eval;
use quantities::{alpha_me, jacobian, mrl, overall_alpha, surface_quantity};

pub use args::{parse_list, surface, AlphaMethod, EvalArgs, LambdaArg, MapName, NdfArg, Quantity};

use crate::error::{Error, Result};
use serde_json::json;

/// Evaluate and return pretty JSON. Closed forms carry no statistical error; the JSON
/// says so and points to the measured agreement in results/proofs.md.
pub fn eval(a: &EvalArgs, fits: &std::path::Path, results: &std::path::Path) -> Result<String> {
    let (value, extra) = match a.quantity {
        Quantity::Filter => filter_eval(a, fits, results)?,
        Quantity::Mrl => mrl(a)?,
        Quantity::OverallAlpha => overall_alpha(a)?,
        Quantity::AlphaMe => alpha_me(a, fits)?,
        Quantity::Jacobian => jacobian(a)?,
        _ => surface_quantity(a)?,
    };
    let fitted = a.quantity == Quantity::AlphaMe && a.method != AlphaMethod::Newton;
    let (method, note) = if a.quantity == Quantity::Filter {
        ("closed form, f64 reference (model.f32 is the shading form)", "exact up to rounding; the filter's error against the footprint-averaged BRDF is measured in results/filters.md")
    } else if a.quantity == Quantity::OverallAlpha {
        ("moment: Newton on the closed form; clipped/L2/caps: nested adaptive quadrature of Eq 6 + Brent", "moment: round trip ≤ 1e-13; quadrature metrics: see model.cap_quadrature_rel_error and results/proofs.md (mrl-product)")
    } else if fitted {
        (
            "fitted approximation",
            "see model.held_out: max/RMS relative error in α on held-out points",
        )
    } else if a.quantity == Quantity::AlphaMe {
        (
            "Newton on the closed form",
            "round-trip relative error ≤ 1e-13 (results/proofs.md, mrl-closed-form)",
        )
    } else {
        ("closed form, f64", "closed form in f64, exact up to rounding; its agreement with quadrature/MC is measured in results/proofs.md")
    };
    if value.is_nan() {
        return Err(Error::InvalidArgument(format!(
            "{:?} is not defined for these inputs (the evaluation gave NaN)",
            a.quantity
        )));
    }
    let out = json!({
        "quantity": format!("{:?}", a.quantity),
        // JSON has no infinity: a documented infinite value (Λ = ∞ below the mean surface,
        // ν = ±∞ along the normal) is reported as null + flag + sign
        "value": if value.is_finite() { json!(value) } else { json!(null) },
        "infinite": value.is_infinite(),
        "sign": if value < 0.0 { -1 } else { 1 },
        "method": method,
        "error": null,
        "error_note": note,
        "model": extra,
    });
    Ok(serde_json::to_string_pretty(&out).expect("json"))
}

//! `eval`: evaluate one model quantity from the command line, JSON out.

use crate::error::{Error, Result};
use crate::jacobian::{DirMap, HalfToSlope, HalfVector, NormalToSlope, ProjectedDisk, Reflection};
use crate::microfacet::sampling::VndfSampler;
use crate::microfacet::{unit, LambdaKind, Microsurface, NdfKind, Roughness};
use nalgebra::{Matrix2, Vector2, Vector3};
use serde_json::json;

/// Quantities `eval` knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Quantity {
    /// NDF D(m) (needs --m)
    D,
    /// slope density P22 (needs --slope)
    P22,
    /// Smith Λ(o) (needs --o)
    Lambda,
    /// normalised slope ν(o) (needs --o)
    Nu,
    /// G1(o, m) (needs --o, --m)
    G1,
    /// height-correlated G2(i, o, m) (needs --i, --o, --m)
    G2Correlated,
    /// separable G2(i, o, m)
    G2Separable,
    /// GGX visible-normal pdf D_o(m) (needs --o, --m)
    VndfPdf,
    /// closed-form Jacobian determinant of --map at --w (reflection/half-vector need --o)
    Jacobian,
    /// mean resultant length ‖b̄‖ of the isotropic LTC (needs --alpha; seed 000 Eq 4)
    Mrl,
    /// α_me from ‖b̄‖ (needs --b or --one-minus-b; --method paper|ours|table|newton)
    AlphaMe,
    /// overall α of γ_me ∗ γ_mi fitted by one LTC under every metric (needs --alpha-mi,
    /// --alpha-me; ~1 s: quadrature of seed 000 Eq 6)
    OverallAlpha,
}

/// Ways to get α_me from ‖b̄‖.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum AlphaMethod {
    /// seed 000 Eq 5 as printed
    Paper,
    /// our limit-respecting fit (fits/multiscale-alpha-me.toml)
    Ours,
    /// lookup table of the same spec
    Table,
    /// Newton on the closed form (reference)
    Newton,
}

/// Direction maps for `eval jacobian`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MapName {
    NormalToSlope,
    Reflection,
    HalfVector,
    SlopeParallel,
    ProjectedDisk,
}

/// Arguments of `eval`. Vectors are comma-separated, e.g. `--o 0.3,0,0.95` (normalised).
#[derive(Clone, Debug, clap::Args)]
pub struct EvalArgs {
    #[arg(value_enum)]
    pub quantity: Quantity,
    #[arg(long, value_enum, default_value = "ggx")]
    pub ndf: NdfArg,
    /// isotropic roughness α
    #[arg(long)]
    pub alpha: Option<f64>,
    /// anisotropic roughness αx,αy
    #[arg(long)]
    pub alpha_xy: Option<String>,
    /// general roughness matrix a11,a12,a22 (must be SPD)
    #[arg(long)]
    pub matrix: Option<String>,
    /// mean slope x,y
    #[arg(long)]
    pub mean: Option<String>,
    #[arg(long, value_enum, default_value = "exact")]
    pub lambda: LambdaArg,
    #[arg(long)]
    pub o: Option<String>,
    #[arg(long)]
    pub i: Option<String>,
    #[arg(long)]
    pub m: Option<String>,
    #[arg(long)]
    pub slope: Option<String>,
    #[arg(long, value_enum)]
    pub map: Option<MapName>,
    #[arg(long)]
    pub w: Option<String>,
    /// mean resultant length ‖b̄‖ ∈ (0, 1)
    #[arg(long)]
    pub b: Option<f64>,
    /// 1 − ‖b̄‖ (more precise than --b as ‖b̄‖ → 1)
    #[arg(long)]
    pub one_minus_b: Option<f64>,
    #[arg(long, value_enum, default_value = "newton")]
    pub method: AlphaMethod,
    /// micro-scale roughness α_mi
    #[arg(long)]
    pub alpha_mi: Option<f64>,
    /// meso-scale roughness α_me
    #[arg(long)]
    pub alpha_me: Option<f64>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum NdfArg {
    Ggx,
    Beckmann,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum LambdaArg {
    Exact,
    WalterPrinted,
    WalterListing,
}

/// Parse "a,b,c" into exactly `n` finite numbers.
pub fn parse_list(s: &str, n: usize, what: &str) -> Result<Vec<f64>> {
    let v: std::result::Result<Vec<f64>, _> =
        s.split(',').map(|x| x.trim().parse::<f64>()).collect();
    let v = v.map_err(|e| Error::InvalidArgument(format!("--{what} '{s}': {e}")))?;
    if v.len() != n {
        return Err(Error::InvalidArgument(format!(
            "--{what} needs {n} comma-separated numbers, got {}",
            v.len()
        )));
    }
    if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
        return Err(Error::NonFinite {
            what: "eval argument",
            value: *bad,
        });
    }
    Ok(v)
}

fn vec3(s: &Option<String>, what: &'static str) -> Result<Vector3<f64>> {
    let s = s
        .as_ref()
        .ok_or_else(|| Error::InvalidArgument(format!("this quantity needs --{what}")))?;
    let v = parse_list(s, 3, what)?;
    unit(Vector3::new(v[0], v[1], v[2]), what)
}

/// Build the surface described by the arguments.
pub fn surface(a: &EvalArgs) -> Result<Microsurface> {
    let rough = match (&a.alpha, &a.alpha_xy, &a.matrix) {
        (Some(al), None, None) => Roughness::iso(*al)?,
        (None, Some(xy), None) => {
            let v = parse_list(xy, 2, "alpha-xy")?;
            Roughness::aniso(v[0], v[1])?
        }
        (None, None, Some(m)) => {
            let v = parse_list(m, 3, "matrix")?;
            Roughness::matrix(Matrix2::new(v[0], v[1], v[1], v[2]))?
        }
        (None, None, None) => {
            return Err(Error::InvalidArgument(
                "give one of --alpha, --alpha-xy, --matrix".into(),
            ))
        }
        _ => {
            return Err(Error::InvalidArgument(
                "--alpha, --alpha-xy and --matrix are mutually exclusive".into(),
            ))
        }
    };
    let kind = match a.ndf {
        NdfArg::Ggx => NdfKind::Ggx,
        NdfArg::Beckmann => NdfKind::Beckmann,
    };
    let mut s = Microsurface::new(kind, rough);
    if let Some(m) = &a.mean {
        let v = parse_list(m, 2, "mean")?;
        s = s.with_mean(Vector2::new(v[0], v[1]))?;
    }
    let lk = match a.lambda {
        LambdaArg::Exact => LambdaKind::Exact,
        LambdaArg::WalterPrinted => LambdaKind::WalterPrinted,
        LambdaArg::WalterListing => LambdaKind::WalterListing,
    };
    s.with_lambda(lk)
}

/// Evaluate and return pretty JSON. Closed forms carry no statistical error; the JSON
/// says so and points to the measured agreement in results/proofs.md.
pub fn eval(a: &EvalArgs, fits: &std::path::Path) -> Result<String> {
    let (value, extra) = match a.quantity {
        Quantity::Mrl => {
            let al = a
                .alpha
                .ok_or_else(|| Error::InvalidArgument("mrl needs --alpha".into()))?;
            if !(al.is_finite() && al > 0.0) {
                return Err(Error::InvalidRoughness(al));
            }
            let (b, y) = crate::multiscale::mrl::mrl_pair(al);
            (
                b,
                json!({"one_minus_b": y, "form": "closed form, proofs/mrl-closed-form.md"}),
            )
        }
        Quantity::OverallAlpha => {
            let get = |v: Option<f64>, n: &str| -> Result<f64> {
                let v =
                    v.ok_or_else(|| Error::InvalidArgument(format!("overall-alpha needs --{n}")))?;
                if !(v.is_finite() && v > 0.0) {
                    return Err(Error::InvalidRoughness(v));
                }
                Ok(v)
            };
            let (mi, me) = (get(a.alpha_mi, "alpha-mi")?, get(a.alpha_me, "alpha-me")?);
            let f = crate::multiscale::overall::fit_pair(mi, me)?;
            (
                f.moment_unclipped,
                json!({
                    "value_is": "moment-unclipped (closed form); the other metrics follow",
                    "moment_unclipped": f.moment_unclipped,
                    "moment_clipped": f.moment_clipped,
                    "l2": f.l2,
                    "caps": f.caps,
                    "cap_quadrature_rel_error": f.cap_quad_rel_error,
                    "paper_eq7": crate::multiscale::overall::eq7(mi, me),
                    "report": "results/multiscale-convolution.md",
                }),
            )
        }
        Quantity::AlphaMe => {
            let (b, y) = match (a.b, a.one_minus_b) {
                (Some(b), None) => (b, 1.0 - b),
                (None, Some(y)) => (1.0 - y, y),
                _ => {
                    return Err(Error::InvalidArgument(
                        "alpha-me needs exactly one of --b, --one-minus-b".into(),
                    ))
                }
            };
            if !(y > 0.0 && y < 1.0) {
                return Err(Error::InvalidArgument(format!(
                    "‖b̄‖ must lie in (0, 1), got {b}"
                )));
            }
            let spec = || -> Result<crate::fit::spec::FitSpec> {
                crate::fit::spec::load_dir(fits)?
                    .into_iter()
                    .find(|s| s.name == "multiscale-alpha-me")
                    .ok_or_else(|| {
                        Error::InvalidArgument(format!(
                            "no multiscale-alpha-me spec in '{}'",
                            fits.display()
                        ))
                    })
            };
            use crate::multiscale::alpha_me::{
                fit_ours, held_out, held_out_alphas, ours_eval, paper_method, training_alphas,
                Table,
            };
            let method: Box<dyn Fn(f64, f64) -> f64> = match a.method {
                AlphaMethod::Paper => Box::new(paper_method),
                AlphaMethod::Newton => Box::new(|_b, y| {
                    crate::multiscale::mrl::alpha_from_one_minus(y).unwrap_or(f64::NAN)
                }),
                AlphaMethod::Ours => {
                    let s = spec()?;
                    let c = fit_ours(
                        s.terms,
                        &training_alphas(s.training.points, s.domain.alpha_min, s.domain.alpha_max),
                    )?;
                    Box::new(move |_b, y| ours_eval(&c, y))
                }
                AlphaMethod::Table => {
                    let s = spec()?;
                    let t = Table::build(s.table_entries, s.domain.alpha_min, s.domain.alpha_max);
                    Box::new(move |_b, y| t.eval(y))
                }
            };
            let v = method(b, y);
            // the method's measured error on the spec's held-out points (or the default domain)
            let (lo, hi, n) = spec()
                .map(|s| (s.domain.alpha_min, s.domain.alpha_max, s.held_out.points))
                .unwrap_or((1e-3, 1.0, 2000));
            let h = held_out(&held_out_alphas(n, lo, hi), &|b, y| method(b, y));
            (
                v,
                json!({"method": format!("{:?}", a.method), "held_out": h, "held_out_domain_alpha": [lo, hi], "inside_domain": v >= lo && v <= hi}),
            )
        }
        Quantity::Jacobian => {
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
            if matches!(a.map, Some(MapName::NormalToSlope | MapName::SlopeParallel))
                && !(w.z > 0.0)
            {
                return Err(Error::BelowHorizon { what: "w", z: w.z });
            }
            (map.det(&w), json!({"map": map.name()}))
        }
        q => {
            let s = surface(a)?;
            let v = match q {
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
                Quantity::VndfPdf => {
                    VndfSampler::new(s, vec3(&a.o, "o")?)?.pdf_exact(&vec3(&a.m, "m")?)
                }
                Quantity::Jacobian | Quantity::Mrl | Quantity::AlphaMe | Quantity::OverallAlpha => {
                    unreachable!("handled above")
                }
            };
            (
                v,
                json!({"ndf": format!("{:?}", s.kind), "roughness_matrix": [s.rough.a()[(0,0)], s.rough.a()[(0,1)], s.rough.a()[(1,1)]], "mean_slope": [s.mean.x, s.mean.y], "lambda": format!("{:?}", s.lambda_kind)}),
            )
        }
    };
    let fitted = a.quantity == Quantity::AlphaMe && a.method != AlphaMethod::Newton;
    let (method, note) = if a.quantity == Quantity::OverallAlpha {
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
    let out = json!({
        "quantity": format!("{:?}", a.quantity),
        // JSON has no infinity: Λ = ∞ below the mean surface is reported as null + flag
        "value": if value.is_finite() { json!(value) } else { json!(null) },
        "infinite": value.is_infinite(),
        "method": method,
        "error": null,
        "error_note": note,
        "model": extra,
    });
    Ok(serde_json::to_string_pretty(&out).expect("json"))
}

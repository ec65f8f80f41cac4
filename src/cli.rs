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
    /// a footprint roughness filter α′ (needs --filter, --alpha and the filter's inputs:
    /// --b |μ| for mean-normal filters, --cov for LEAN, --dn-u/--dn-v for deferred
    /// kernels, --du/--dv 2D derivatives for eigen/rect/forward); f64 and f32 forms
    Filter,
}

/// Filters for `eval filter` (results/filters.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FilterName {
    /// Toksvig, Blinn–Phong form (--b)
    ToksvigBp,
    /// α′² = α² + 2σ², σ² = (1 − |μ|)/|μ| (--b)
    Toksvig,
    /// α′² = α² + σ² (--b)
    ToksvigHalf,
    /// α′² = α² + 2/κ (--b)
    Vmf2,
    /// α′² = α² + 1/κ (--b)
    Vmf1,
    /// α′² = α² + 1/(2κ) (--b)
    VmfHalf,
    /// LEAN A = α²I + 2Σ (--cov xx,yy,xy); value = √λ_max(A)
    Lean,
    /// seed 000 Eq 5 + Eq 7 (--b)
    Seed000Paper,
    /// ρ⁻¹(|μ|ρ(α)) by Newton (f64) and the fitted form (f32) (--b)
    Seed000Moment,
    /// seed 003 Eq 13, σ² 0.25, δ 0.18 (--dn-u, --dn-v)
    Deferred,
    /// Eq 13 without the clamp
    DeferredUnclamped,
    /// Filament 0.15 / 0.04
    Filament,
    /// Unity HDRP 0.1 / 0.04
    Unity,
    /// Unity projected space 0.1 / 0.04
    UnityProjected,
    /// Godot 0.25 / 0.18 added to α
    Godot,
    /// seed 003 Eq 10 (--du, --dv: projected-disk derivatives)
    Eigen,
    /// Kaplanyan rectangular kernel, Listing 3 (--du, --dv: slope derivatives)
    KaplanyanRect,
    /// forward matrix A = α²I + 2Σ (Eq 3 with Eq 2 or 7 derivatives --du, --dv); value = √λ_max(A)
    Forward,
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
    /// which footprint filter (`eval filter`)
    #[arg(long, value_enum)]
    pub filter: Option<FilterName>,
    /// slope covariance xx,yy,xy (LEAN)
    #[arg(long)]
    pub cov: Option<String>,
    /// screen derivative of the normal along x (3 numbers)
    #[arg(long)]
    pub dn_u: Option<String>,
    /// screen derivative of the normal along y (3 numbers)
    #[arg(long)]
    pub dn_v: Option<String>,
    /// 2D derivative along x (projected disk or slope space, 2 numbers)
    #[arg(long)]
    pub du: Option<String>,
    /// 2D derivative along y (2 numbers)
    #[arg(long)]
    pub dv: Option<String>,
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
        Quantity::Filter => filter_eval(a, fits)?,
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
                // the supported roughness range, as for every surface
                Roughness::iso(v)?;
                Ok(v)
            };
            let (mi, me) = (get(a.alpha_mi, "alpha-mi")?, get(a.alpha_me, "alpha-me")?);
            let e = crate::multiscale::overall::evaluate_pair(mi, me)?;
            let mut m = json!({
                "value_is": "moment-unclipped (closed form); the other metrics follow where evaluated",
                "moment_unclipped": e.moment_unclipped,
                "paper_eq7": crate::multiscale::overall::eq7(mi, me),
                "note": e.note,
                "report": "results/multiscale-convolution.md",
            });
            if let Some(f) = &e.fit {
                m["moment_clipped"] = json!(f.moment_clipped);
                m["l2"] = json!(f.l2);
                m["caps"] = json!(f.caps);
                m["cap_quadrature_rel_error"] = json!(f.cap_quad_rel_error);
            }
            if let (Some(l), Some(err)) = (e.limit, e.limit_rel_error) {
                m["limit_every_metric"] = json!(l);
                m["limit_rel_error"] = json!(err);
            }
            (e.moment_unclipped, m)
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
            // either may round to 1 when the other is tiny; neither may be 0
            if !(y > 0.0 && y <= 1.0 && b > 0.0 && b <= 1.0) {
                return Err(Error::InvalidArgument(match a.b {
                    Some(b) => format!("--b (‖b̄‖) must lie in (0, 1), got {b:e}"),
                    None => format!("--one-minus-b must lie in (0, 1), got {y:e}"),
                }));
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
                fit_ours, held_out, held_out_alphas, paper_method, training_alphas, Table,
            };
            let method: Box<dyn Fn(f64, f64) -> f64> = match a.method {
                AlphaMethod::Paper => Box::new(paper_method),
                AlphaMethod::Newton => Box::new(|b, y| {
                    crate::multiscale::mrl::alpha_from_pair(b, y).unwrap_or(f64::NAN)
                }),
                AlphaMethod::Ours => {
                    let s = spec()?;
                    let c = fit_ours(
                        s.terms,
                        s.terms_large,
                        &training_alphas(s.training.points, s.domain.alpha_min, s.domain.alpha_max),
                    )?;
                    Box::new(move |_b, y| c.eval(y))
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
            // inside the fit domain is a property of the input: y between y(α_min) and
            // y(α_max) (1 − ‖b̄‖ increases with α)
            let (y_at_lo, y_at_hi) = (
                crate::multiscale::mrl::mrl_pair(lo).1,
                crate::multiscale::mrl::mrl_pair(hi).1,
            );
            (
                v,
                json!({"method": format!("{:?}", a.method), "held_out": h, "held_out_domain_alpha": [lo, hi], "held_out_domain_one_minus_b": [y_at_lo, y_at_hi], "inside_domain": y >= y_at_lo && y <= y_at_hi}),
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
            if matches!(a.map, Some(MapName::HalfVector)) {
                // ω_i = −ω_o has no half-vector (w + o = 0)
                let o = vec3(&a.o, "o")?;
                if (w + o).norm() <= 1e-12 {
                    return Err(Error::DegenerateDirection {
                        what: "w + o (the half-vector of w = −o)",
                    });
                }
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
                Quantity::Jacobian
                | Quantity::Mrl
                | Quantity::AlphaMe
                | Quantity::OverallAlpha
                | Quantity::Filter => {
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

/// `eval filter`: α′ of one footprint filter, f64 reference and f32 shading form.
fn filter_eval(a: &EvalArgs, fits: &std::path::Path) -> Result<(f64, serde_json::Value)> {
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
    let mut out = json!({"filter": format!("{f:?}"), "alpha_in": al, "detail": extra, "report": "results/filters.md"});
    if !representable {
        out["f32_note"] = json!("an input is outside the f32 range (|x| > 3.4e38 or a non-zero |x| < 1.4e-45): the shading form cannot receive it");
    } else if v32.is_finite() {
        out["f32"] = json!(v32);
        out["f32_rel_diff"] = json!((v32 as f64 - v64) / v64);
    } else {
        return Err(Error::InvalidArgument(format!(
            "the f32 shading form of filter {f:?} is not finite for these inputs (f64: {v64:e})"
        )));
    }
    Ok((v64, out))
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

//! The arguments of `eval`: the quantities, filters and maps it knows, and the surface they
//! describe (parsed and checked once, here).

use crate::error::{Error, Result};
use crate::microfacet::{unit, LambdaKind, Microsurface, NdfKind, Roughness};
use nalgebra::{Matrix2, Vector2, Vector3};

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

/// The keys `eval filter --filter` accepts: every filter of the registry
/// ([`crate::filters::registry`]), each with its label as help.
pub fn filter_keys() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(
        crate::filters::registry::Filter::all()
            .map(|f| clap::builder::PossibleValue::new(f.key()).help(f.label())),
    )
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
    /// which footprint filter (`eval filter`): a key of results/filters.md's filters;
    /// map filters need --b (LEAN --cov), the deferred kernels --dn-u/--dn-v, Eq 10,
    /// the rect and the forward kernels --du/--dv; refitted ones read
    /// results/fits/filters.json
    #[arg(long, value_parser = filter_keys())]
    pub filter: Option<String>,
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

pub(super) fn vec3(s: &Option<String>, what: &'static str) -> Result<Vector3<f64>> {
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

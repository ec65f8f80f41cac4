//! Whole-range audit of the generated fitted functions: each f32 twin (the compiled copy of
//! src/generated/shading.rs, the same text as the WGSL) evaluated over every input its
//! shader can receive — not only its fit's domain — against its f64 reference, with
//! non-finite outputs counted. Written to results/generated-range.md by `regen`.
//!
//! Grids are deterministic (log-spaced in the quantity that spans decades, plus the special
//! values 0, 1, NaN, ±∞ where the type allows them), so the report is reproducible.

use crate::filters::rules;
use crate::generated::shading as g;
use crate::microfacet::lambda;
use crate::multiscale::mrl::{alpha_from_pair, mrl_pair};
use serde::Serialize;

/// One function's audit.
#[derive(Clone, Debug, Serialize)]
pub struct Audit {
    pub function: &'static str,
    /// The inputs swept, in words.
    pub inputs: String,
    /// The error measure.
    pub metric: &'static str,
    pub points: usize,
    /// Worst error over the whole sweep, and where.
    pub max_error: f64,
    pub worst_at: String,
    /// Worst error restricted to the fit's or the study's domain (None: same sweep).
    pub in_domain_max_error: Option<f64>,
    pub domain: String,
    /// Outputs that were NaN or ±∞ where the reference is finite.
    pub non_finite: usize,
}

fn logspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| (lo.ln() + (hi.ln() - lo.ln()) * i as f64 / (n - 1) as f64).exp())
        .collect()
}

struct Acc {
    max: f64,
    at: String,
    dom: f64,
    n: usize,
    bad: usize,
}

impl Acc {
    fn new() -> Acc {
        Acc {
            max: 0.0,
            at: String::new(),
            dom: 0.0,
            n: 0,
            bad: 0,
        }
    }
    fn add(&mut self, got: f64, want: f64, err: f64, inside: bool, at: impl Fn() -> String) {
        self.n += 1;
        if want.is_finite() && !got.is_finite() {
            self.bad += 1;
            return;
        }
        let e = if err.is_nan() { f64::INFINITY } else { err };
        if e > self.max {
            self.max = e;
            self.at = at();
        }
        if inside {
            self.dom = self.dom.max(e);
        }
    }
}

fn rel(got: f64, want: f64) -> f64 {
    if got == want {
        0.0
    } else {
        ((got - want) / want).abs()
    }
}

/// Relative error, or absolute where the reference is below 1e-15: squares of f32
/// inputs below ~1e-19 underflow, and a roughness of 1e-30 is 0 to any shader.
fn rel_or_abs(got: f64, want: f64) -> f64 {
    (got - want).abs() / want.abs().max(1e-15)
}

/// Audit every generated fitted function (and the generated forms they rely on).
pub fn run() -> Vec<Audit> {
    vec![
        alpha_me(),
        multiscale(),
        beckmann_lambda(),
        ggx_lambda(),
        vmf_fitted(),
        toksvig(),
        deferred_fitted(),
        lut_coords(),
        edge_factor(),
    ]
}

fn alpha_me() -> Audit {
    let mut a = Acc::new();
    let (lo, hi) = (mrl_pair(1e-4).1, mrl_pair(1e2).1);
    let mut ys: Vec<f32> = logspace(f32::MIN_POSITIVE as f64, 1.0 / 3.0, 600)
        .into_iter()
        .map(|y| y as f32)
        .collect();
    ys.extend(
        logspace(f32::MIN_POSITIVE as f64, 2.0 / 3.0, 600)
            .into_iter()
            .map(|b| 1.0 - b as f32),
    );
    for y in ys {
        let (yy, b) = (y as f64, 1.0 - y as f64);
        if !(b > 0.0 && yy > 0.0) {
            continue;
        }
        let want = alpha_from_pair(b, yy).unwrap_or(f64::NAN);
        let got = g::alpha_me(y) as f64;
        a.add(got, want, rel(got, want), yy >= lo && yy <= hi, || {
            format!("y = {y:e} (α = {want:.3e})")
        });
    }
    for y in [
        0.0f32,
        1.0,
        -1.0,
        2.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
    ] {
        a.n += 1;
        if !g::alpha_me(y).is_finite() {
            a.bad += 1;
        }
    }
    Audit {
        function: "alpha_me",
        inputs: "y = 1 − ‖b̄‖ from the smallest normal f32 to 1/3 and ‖b̄‖ from it to 2/3 (log-spaced), plus 0, 1, NaN, ±∞, −1, 2".into(),
        metric: "relative error in α against Newton on the closed form at the same f32 input",
        points: a.n,
        max_error: a.max,
        worst_at: a.at,
        in_domain_max_error: Some(a.dom),
        domain: "α ∈ [1e-4, 1e2] (the fit's)".into(),
        non_finite: a.bad,
    }
}

fn multiscale() -> Audit {
    let mut a = Acc::new();
    let alphas = logspace(1e-6, 1e4, 60);
    for &am in &alphas {
        for &ai in &alphas {
            let (bm, ym) = mrl_pair(am);
            let (bi, yi) = mrl_pair(ai);
            let (ym32, yi32) = (ym as f32, yi as f32);
            // the reference at the f32 inputs, without cancellation in either of the pair
            let (ym, yi) = (ym32 as f64, yi32 as f64);
            let (bm, bi) = (
                if ym > 0.5 { 1.0 - ym } else { bm },
                if yi > 0.5 { 1.0 - yi } else { bi },
            );
            let want = alpha_from_pair(bm * bi, ym + yi - ym * yi).unwrap_or(f64::NAN);
            let got = g::multiscale_alpha(ym32, yi32) as f64;
            let inside = (1e-4..=1e2).contains(&want);
            a.add(got, want, rel(got, want), inside, || {
                format!("α_me = {am:.2e}, α_mi = {ai:.2e}")
            });
        }
    }
    Audit {
        function: "multiscale_alpha",
        inputs: "y_me = 1 − ρ(α_me), y_mi = 1 − ρ(α_mi) as f32 for α_me, α_mi log-spaced over [1e-6, 1e4] (60 × 60)".into(),
        metric: "relative error in α against Newton on ρ = ρ_me·ρ_mi at the same f32 inputs",
        points: a.n,
        max_error: a.max,
        worst_at: a.at,
        in_domain_max_error: Some(a.dom),
        domain: "overall α ∈ [1e-4, 1e2]".into(),
        non_finite: a.bad,
    }
}

/// ν → (ox, 0, oz) with α = 1: a unit direction of normalised slope ν, as f32.
fn dir_of_nu(nu: f64) -> (f32, f32) {
    let n = (1.0 + nu * nu).sqrt();
    ((1.0 / n) as f32, (nu / n) as f32)
}

fn lambda_audit(
    function: &'static str,
    f: &dyn Fn(f32, f32) -> f32,
    exact: &dyn Fn(f64) -> f64,
    domain: (f64, f64),
) -> Audit {
    let mut a = Acc::new();
    for nu in logspace(1e-30, 1e30, 1200) {
        let (ox, oz) = dir_of_nu(nu);
        if ox == 0.0 || oz == 0.0 {
            continue;
        }
        let nu32 = oz as f64 / ox as f64;
        let want = exact(nu32);
        let got = f(ox, oz) as f64;
        // G1 = 1/(1 + Λ): what the shader multiplies by
        let g1 = |l: f64| {
            if l.is_infinite() {
                0.0
            } else {
                1.0 / (1.0 + l)
            }
        };
        a.add(
            got,
            want,
            (g1(got) - g1(want)).abs(),
            nu32 >= domain.0 && nu32 <= domain.1,
            || format!("ν = {nu32:.3e}"),
        );
    }
    Audit {
        function,
        inputs: "unit directions with ν = o_z/(α‖o_xy‖) log-spaced over [1e-30, 1e30] (α = 1; any α maps to the same ν)".into(),
        metric: "abs(ΔG1) = abs(1/(1 + Λ) − 1/(1 + Λ_exact))",
        points: a.n,
        max_error: a.max,
        worst_at: a.at,
        in_domain_max_error: Some(a.dom),
        domain: format!("ν ∈ [{:e}, {:e}]", domain.0, domain.1),
        non_finite: a.bad,
    }
}

fn beckmann_lambda() -> Audit {
    lambda_audit(
        "beckmann_lambda",
        &|ox, oz| g::beckmann_lambda(ox, 0.0, oz, 1.0),
        &lambda::beckmann,
        (1e-3, 10.0),
    )
}

fn ggx_lambda() -> Audit {
    lambda_audit(
        "ggx_lambda",
        &|ox, oz| g::ggx_lambda(ox, 0.0, oz, 1.0),
        &lambda::ggx,
        (1e-3, 1e3),
    )
}

/// α from 0 and log-spaced to 1e30; r = ‖μ‖ log-spaced near 0 and near 1.
fn alpha_r_grid() -> (Vec<f32>, Vec<f32>) {
    let mut al: Vec<f32> = vec![0.0];
    al.extend(logspace(1e-30, 1e30, 61).into_iter().map(|x| x as f32));
    let mut rs: Vec<f32> = logspace(f32::MIN_POSITIVE as f64, 1.0, 60)
        .into_iter()
        .map(|x| x as f32)
        .collect();
    rs.extend(
        logspace(1e-7, 0.5, 30)
            .into_iter()
            .map(|e| (1.0 - e) as f32),
    );
    rs.push(1.0);
    (al, rs)
}

fn filter_audit(
    function: &'static str,
    f: &dyn Fn(f32, f32) -> f32,
    reference: &dyn Fn(f64, f64) -> f64,
) -> Audit {
    let mut a = Acc::new();
    let (al, rs) = alpha_r_grid();
    for &x in &al {
        for &r in &rs {
            let want = reference(x as f64, r as f64);
            let got = f(x, r) as f64;
            let inside = (1e-4..=1.0).contains(&(x as f64)) && r >= 0.01;
            a.add(got, want, rel_or_abs(got, want), inside, || {
                format!("α = {x:e}, r = {r:e}")
            });
        }
    }
    for r in [0.0f32, -1.0, 2.0, f32::NAN] {
        a.n += 1;
        if !f(0.5, r).is_finite() {
            a.bad += 1;
        }
    }
    Audit {
        function,
        inputs: "α ∈ {0} ∪ [1e-30, 1e30], r = ‖μ‖ from the smallest normal f32 to 1 (log-spaced, and 1 − r from 1e-7), plus r = 0, −1, 2, NaN".into(),
        metric: "relative error against the f64 rule at the same f32 inputs (absolute below 1e-15)",
        points: a.n,
        max_error: a.max,
        worst_at: a.at,
        in_domain_max_error: Some(a.dom),
        domain: "α ∈ [1e-4, 1], r ≥ 0.01".into(),
        non_finite: a.bad,
    }
}

fn vmf_fitted() -> Audit {
    let c = g::FILTER_VMF_C_GGX as f64;
    filter_audit(
        "filter_vmf_fitted",
        &|x, r| g::filter_vmf_fitted(x, r),
        &|x, r| rules::vmf(x, r, c),
    )
}

fn toksvig() -> Audit {
    filter_audit(
        "filter_toksvig (c = 2)",
        &|x, r| g::filter_toksvig(x, r, 2.0),
        &|x, r| rules::toksvig_alpha2(x, r, 2.0),
    )
}

fn deferred_fitted() -> Audit {
    let mut a = Acc::new();
    let s2 = g::FILTER_EQ13_SIGMA2_GAUSSIAN_PIXEL;
    let mut al: Vec<f32> = vec![0.0];
    al.extend(logspace(1e-30, 1e30, 31).into_iter().map(|x| x as f32));
    let mut ds: Vec<f32> = vec![0.0];
    ds.extend(logspace(1e-30, 1e30, 31).into_iter().map(|x| x as f32));
    for &x in &al {
        for &d in &ds {
            let (u, v) = ([d, 0.5 * d, -d], [0.25 * d, d, 0.0]);
            let want = rules::deferred(
                x as f64,
                u.map(|t| t as f64),
                v.map(|t| t as f64),
                s2 as f64,
                g::FILTER_DELTA_MAX as f64,
            );
            let got = g::filter_deferred_fitted(x, u[0], u[1], u[2], v[0], v[1], v[2]) as f64;
            let inside = (1e-4..=1.0).contains(&(x as f64)) && d <= 10.0;
            a.add(got, want, rel_or_abs(got, want), inside, || {
                format!("α = {x:e}, ‖Δn‖ ≈ {d:e}")
            });
        }
    }
    Audit {
        function: "filter_deferred_fitted",
        inputs: "α ∈ {0} ∪ [1e-30, 1e30], normal derivatives ∈ {0} ∪ [1e-30, 1e30] (squares overflow f32 above ~1e19)".into(),
        metric: "relative error against the f64 rule (seed 003 Eq 13) at the same f32 inputs (absolute below 1e-15)",
        points: a.n,
        max_error: a.max,
        worst_at: a.at,
        in_domain_max_error: Some(a.dom),
        domain: "α ∈ [1e-4, 1], ‖Δn‖ ≤ 10".into(),
        non_finite: a.bad,
    }
}

fn lut_coords() -> Audit {
    let mut a = Acc::new();
    let n = g::LTC_LUT_SIZE as f64;
    let (lo, hi) = (0.5 / n, (n - 0.5) / n);
    let mut xs: Vec<f32> = (0..=2000).map(|i| i as f32 / 2000.0).collect();
    xs.extend([
        -1.0,
        -1e30,
        2.0,
        1e30,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::MIN_POSITIVE,
        1e-45,
    ]);
    for &x in &xs {
        let inside = (0.0..=1.0).contains(&x);
        let xc = (x as f64).clamp(0.0, 1.0);
        for (got, want) in [
            (g::ltc_lut_u(x) as f64, (xc.sqrt() * (n - 1.0) + 0.5) / n),
            (
                g::ltc_lut_v(x) as f64,
                ((1.0 - xc).sqrt() * (n - 1.0) + 0.5) / n,
            ),
        ] {
            // outside [0, 1] (and NaN) the coordinate must still land on the table
            let err = if (lo - 1e-7..=hi + 1e-7).contains(&got) {
                if inside {
                    (got - want).abs()
                } else {
                    0.0
                }
            } else {
                f64::INFINITY
            };
            a.add(got, want.max(lo), err, inside, || format!("input {x:e}"));
        }
    }
    Audit {
        function: "ltc_lut_u / ltc_lut_v",
        inputs: "α or cos θ on a 2001-point grid of [0, 1], plus −1, ±1e30, 2, NaN, ±∞ and subnormals".into(),
        metric: "absolute error of the texture coordinate on [0, 1]; outside it, ∞ unless the coordinate lies on the table [½/n, (n − ½)/n]",
        points: a.n,
        max_error: a.max,
        worst_at: a.at,
        in_domain_max_error: Some(a.dom),
        domain: "inputs in [0, 1]".into(),
        non_finite: a.bad,
    }
}

fn edge_factor() -> Audit {
    let mut a = Acc::new();
    for i in 0..=20_000 {
        let x = (-1.0 + 2.0 * i as f64 / 20_000.0) as f32;
        let xd = x as f64;
        let s2 = (1.0 - xd * xd).max(0.0);
        let want = if s2 == 0.0 {
            if xd > 0.0 {
                0.5 / std::f64::consts::PI
            } else {
                f64::INFINITY
            }
        } else {
            xd.acos() / (2.0 * std::f64::consts::PI * s2.sqrt())
        };
        let got = g::ltc_edge_factor(x) as f64;
        if !want.is_finite() {
            a.n += 1;
            if !got.is_finite() {
                a.bad += 1;
            }
            continue;
        }
        a.add(got, want, rel(got, want), s2 >= 1e-7, || {
            format!("x = {x:e}")
        });
    }
    Audit {
        function: "ltc_edge_factor",
        inputs: "x = cos θ on a 20 001-point grid of [−1, 1]".into(),
        metric: "relative error against acos(x)/(2π√(1 − x²)) (the exact value diverges at x = −1; the shader clamps 1 − x² at 1e-7)",
        points: a.n,
        max_error: a.max,
        worst_at: a.at,
        in_domain_max_error: Some(a.dom),
        domain: "1 − x² ≥ 1e-7".into(),
        non_finite: a.bad,
    }
}

/// The markdown report.
pub fn markdown(audits: &[Audit], command: &str) -> String {
    let mut md = format!(
        "{}# Generated functions over their whole input range\n\n\
Each generated f32 function (the Rust twin, the same text as results/wgsl/) evaluated over every input its shader can \
receive — not only its fit's domain — against its f64 reference at the same f32 inputs. \"non-finite\" counts NaN or ±∞ \
outputs where the reference is finite (and, for nonsense inputs such as NaN, any non-finite output). Domains: the fit's or \
the study's.\n\n",
        super::text::header("<!--", command, "src/codegen/audit.rs")
    );
    let mut t = crate::report::table::Table::new([
        "function",
        "inputs",
        "metric",
        "points",
        "max error, domain",
        "domain",
        "max error, whole range",
        "worst at",
        "non-finite",
    ]);
    for a in audits {
        t.row([
            format!("`{}`", a.function),
            a.inputs.to_string(),
            a.metric.to_string(),
            a.points.to_string(),
            a.in_domain_max_error
                .map_or("—".into(), |e| format!("{e:.3e}")),
            a.domain.to_string(),
            format!("{:.3e}", a.max_error),
            if a.worst_at.is_empty() {
                "—".to_string()
            } else {
                a.worst_at.to_string()
            },
            a.non_finite.to_string(),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\nThe α_me fit's own held-out study is in [multiscale-alpha-me.md](multiscale-alpha-me.md); the Λ refit's in [smith-lambda.md](smith-lambda.md); the filters' errors against the footprint-averaged BRDF in [filters.md](filters.md). The property tests of tests/codegen.rs sample the same ranges at random.\n");
    md
}

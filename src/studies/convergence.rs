//! Convergence study: error against integrand evaluations for every engine on three
//! integrands with closed forms, the fitted convergence order of each, a table
//! (results/convergence.md), the raw rows (results/convergence.json) and a log–log plot
//! (results/convergence.svg). Deterministic (fixed seeds); timing lives in the criterion
//! benches (benches/engines.rs → results/performance.md).

use crate::error::Result;
use crate::integrate::mc::{mis, CosineHemisphere, Strategy};
use crate::integrate::qmc::qmc_mis;
use crate::integrate::quad::{gl_2d, Tol};
use crate::integrate::sphere::{integrate_sphere, SphereRule};
use crate::integrate::{Estimate, Preset};
use crate::microfacet::sampling::NdfSampler;
use crate::microfacet::{Microsurface, Roughness};
use crate::report::plot::{loglog_svg, Panel, Series};
use crate::report::table::Table;
use nalgebra::Vector3;
use serde::Serialize;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// An integrand with a closed-form value.
pub struct Integrand {
    pub key: &'static str,
    pub title: &'static str,
    pub surface: Microsurface,
    /// Outgoing direction for projected-area integrands (None: plain normalisation).
    pub o: Option<V3>,
    pub exact: f64,
}

impl Integrand {
    pub fn eval(&self, m: &V3) -> f64 {
        let w = match self.o {
            Some(o) => o.dot(m).max(0.0),
            None => m.z.max(0.0),
        };
        w * self.surface.d(m)
    }
    pub fn rule(&self) -> SphereRule {
        // a coarse initial partition (1 t-panel × 2 ψ-panels, 225 nodes) so the study shows
        // the adaptive rule converging rather than its robust default start
        let mut r = SphereRule::hemisphere(self.surface.width());
        r.t_breaks = 0;
        r.phi_segments = 2;
        match self.o {
            Some(o) => r.with_kink(o),
            None => r,
        }
    }
}

/// The three integrands of the study.
pub fn integrands() -> Vec<Integrand> {
    let ggx = |a: f64| Microsurface::ggx(Roughness::iso(a).expect("valid α"));
    let beck = Microsurface::beckmann(Roughness::iso(0.3).expect("valid α"));
    let th = 88f64.to_radians();
    let o = V3::new(th.sin(), 0.0, th.cos());
    vec![
        Integrand {
            key: "ggx-norm-a0.01",
            title: "GGX ∫D cos, α = 0.01",
            surface: ggx(0.01),
            o: None,
            exact: 1.0,
        },
        // (α = 1 would make D·cos = cos/π, i.e. the cosine pdf itself: zero-variance MC)
        Integrand {
            key: "ggx-norm-a0.5",
            title: "GGX ∫D cos, α = 0.5",
            surface: ggx(0.5),
            o: None,
            exact: 1.0,
        },
        Integrand {
            key: "beckmann-lambda-88deg",
            title: "Beckmann ∫⟨o,m⟩D, α = 0.3, θo = 88° (= (1+Λ)o_z)",
            surface: beck,
            o: Some(o),
            exact: (1.0 + beck.lambda(&o)) * o.z,
        },
    ]
}

/// The engines compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Engine {
    /// MC, cosine-weighted hemisphere sampling; level = samples.
    McCosine,
    /// MC, MIS of NDF sampling and cosine sampling (balance heuristic); level = evaluations.
    McMis,
    /// RQMC (Owen-scrambled Sobol, 8 replicates), cosine mapping; level = points per replicate.
    Rqmc,
    /// Gauss–Legendre n×n tensor product in (t, φ) after the radial substitution; level = n.
    GaussLegendre,
    /// Adaptive G7–K15 on the sphere; level = k for tolerance 10^(−k).
    Adaptive,
}

impl Engine {
    pub const ALL: [Engine; 5] = [
        Engine::McCosine,
        Engine::McMis,
        Engine::Rqmc,
        Engine::GaussLegendre,
        Engine::Adaptive,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Engine::McCosine => "mc-cosine",
            Engine::McMis => "mc-mis",
            Engine::Rqmc => "rqmc",
            Engine::GaussLegendre => "gauss-legendre",
            Engine::Adaptive => "adaptive-gk",
        }
    }
    pub fn from_name(s: &str) -> Option<Engine> {
        Engine::ALL.into_iter().find(|e| e.name() == s)
    }
    /// Levels swept by the study.
    pub fn levels(self, p: Preset) -> Vec<u64> {
        let big = p != Preset::Quick;
        match self {
            Engine::McCosine | Engine::McMis => (4..=if big { 10 } else { 7 })
                .map(|k| 1u64 << (2 * k))
                .collect(),
            Engine::Rqmc => (3..=if big { 8 } else { 6 })
                .map(|k| 1u64 << (2 * k))
                .collect(),
            Engine::GaussLegendre => (2..=if big { 9 } else { 6 }).map(|k| 1u64 << k).collect(),
            Engine::Adaptive => (2..=if big { 12 } else { 8 }).collect(),
        }
    }
    /// The single setting each engine is timed at in benches/engines.rs.
    pub fn bench_level(self) -> u64 {
        match self {
            Engine::McCosine | Engine::McMis => 1 << 16,
            Engine::Rqmc => 1 << 13,
            Engine::GaussLegendre => 128,
            Engine::Adaptive => 8,
        }
    }
}

/// Run one engine at one level.
pub fn run_engine(ig: &Integrand, e: Engine, level: u64, seed: u64) -> Estimate {
    let f = |m: &V3| ig.eval(m);
    match e {
        Engine::McCosine => {
            let s: [&dyn Strategy<V3>; 1] = [&CosineHemisphere];
            mis(&f, &s, level, seed)
        }
        Engine::McMis => {
            let ns = NdfSampler {
                surface: ig.surface,
            };
            let s: [&dyn Strategy<V3>; 2] = [&ns, &CosineHemisphere];
            mis(&f, &s, level / 2, seed)
        }
        Engine::Rqmc => {
            let s: [&dyn Strategy<V3>; 1] = [&CosineHemisphere];
            qmc_mis(&f, &s, level, 8, seed).expect("level within sobol_burley limits")
        }
        Engine::GaussLegendre => {
            let rule = ig.rule();
            let g = |t: f64, phi: f64| {
                let (w, jac) = rule.point(t, phi);
                f(&w) * jac
            };
            gl_2d(
                &g,
                [0.0, 1.0],
                [0.0, 2.0 * PI],
                level as usize,
                level as usize,
            )
        }
        Engine::Adaptive => {
            let t = 10f64.powi(-(level as i32));
            integrate_sphere(&f, &ig.rule(), Tol::new(t, t, 50_000_000))
        }
    }
}

/// One measured point.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub integrand: &'static str,
    pub engine: Engine,
    pub level: u64,
    pub evals: u64,
    pub value: f64,
    pub abs_error: f64,
    pub reported_error: f64,
}

/// Least-squares slope of log(error) against log(evals): the convergence order is its
/// negative. Points at the rounding floor (< 1e-14) are excluded.
pub fn fitted_order(rows: &[&Row]) -> f64 {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.abs_error > 1e-14 && r.evals > 0)
        .map(|r| ((r.evals as f64).ln(), r.abs_error.ln()))
        .collect();
    if pts.len() < 2 {
        return f64::NAN;
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    -sxy / sxx
}

/// Run the study into `set` (results/convergence.{md,json,svg}); returns a one-line summary.
pub fn run(set: &mut crate::io::Outputs, p: Preset, dir: &std::path::Path) -> Result<String> {
    let igs = integrands();
    let mut rows = Vec::new();
    for ig in &igs {
        for e in Engine::ALL {
            for (k, l) in e.levels(p).into_iter().enumerate() {
                let est = run_engine(ig, e, l, 100 + k as u64);
                rows.push(Row {
                    integrand: ig.key,
                    engine: e,
                    level: l,
                    evals: est.evals,
                    value: est.value,
                    abs_error: (est.value - ig.exact).abs(),
                    reported_error: est.error,
                });
            }
        }
    }
    let mut md = String::from("# Convergence of the integration engines\n\n");
    md.push_str(&format!(
        "Written by `cargo run --release -- convergence --preset {}` (also part of the no-argument main job). \
Error = |estimate − closed form| against integrand evaluations; `reported` is the engine's own error \
(MC/RQMC: one standard error; quadrature: its error estimate). Order = −slope of a least-squares fit of \
log|error| on log(evaluations) (points below 1e-14 excluded). MC is expected at 0.5; RQMC up to ~1.5 for \
smooth integrands; Gauss–Legendre and adaptive GK converge faster than any power for analytic integrands, so \
their 'order' is only a summary of the range tried. Both quadratures integrate in (t, ψ) after the \
lobe-following substitution θ = atan(α t/(1 − t)) of `integrate::sphere`; for GGX this turns D·cos·sin θ·dθ/dt \
into the rational function 2t(1 − t)/((1 − t)² + t²)² of t alone, which is why a few hundred nodes reach \
machine precision at α = 0.01 while cosine-sampled MC and RQMC, which do not follow the lobe, stall. The \
Beckmann integrand has a kink along o·m = 0: tensor Gauss–Legendre (no break points) drops to algebraic order \
≈ 2 there, while the adaptive rule, told about the kink circle, keeps converging. Timings: \
results/performance.md.\n\n",
        p.name()
    ));
    md.push_str("## Fitted orders and cost to reach 1e-6\n\n");
    let mut t = Table::new([
        "integrand",
        "engine",
        "fitted order",
        "evals for \\|error\\| ≤ 1e-6",
        "best \\|error\\| (evals)",
    ]);
    for ig in &igs {
        for e in Engine::ALL {
            let rs: Vec<&Row> = rows
                .iter()
                .filter(|r| r.integrand == ig.key && r.engine == e)
                .collect();
            let order = fitted_order(&rs);
            let reach = rs
                .iter()
                .find(|r| r.abs_error <= 1e-6)
                .map(|r| r.evals.to_string())
                .unwrap_or_else(|| "not reached".into());
            let best = rs
                .iter()
                .min_by(|a, b| a.abs_error.total_cmp(&b.abs_error))
                .map(|r| format!("{:.2e} ({})", r.abs_error, r.evals))
                .unwrap_or_default();
            t.row([
                ig.title.to_string(),
                e.name().to_string(),
                format!("{order:.2}"),
                reach,
                best,
            ]);
        }
    }
    md.push_str(&t.to_string());
    md.push_str("\n## All points\n\n");
    let mut t = Table::new([
        "integrand",
        "engine",
        "level",
        "evals",
        "\\|error\\|",
        "reported error",
    ]);
    for r in &rows {
        t.row([
            r.integrand.to_string(),
            r.engine.name().to_string(),
            r.level.to_string(),
            r.evals.to_string(),
            format!("{:.3e}", r.abs_error),
            format!("{:.3e}", r.reported_error),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\n![convergence](convergence.svg)\n");
    let panels: Vec<Panel> = igs
        .iter()
        .map(|ig| Panel {
            title: ig.title.to_string(),
            x_label: "integrand evaluations".into(),
            y_label: "|error|".into(),
            series: Engine::ALL
                .iter()
                .map(|&e| Series {
                    name: e.name().to_string(),
                    points: rows
                        .iter()
                        .filter(|r| r.integrand == ig.key && r.engine == e)
                        .map(|r| (r.evals as f64, r.abs_error.max(1e-17)))
                        .collect(),
                })
                .collect(),
        })
        .collect();
    let svg = loglog_svg(&panels, 1500, 480)?;
    set.put(&dir.join("convergence.svg"), svg.as_bytes());
    set.put(&dir.join("convergence.md"), md.as_bytes());
    set.put(
        &dir.join("convergence.json"),
        serde_json::to_string_pretty(&rows)
            .expect("json")
            .as_bytes(),
    );
    Ok(format!(
        "wrote {}/convergence.md ({} points)",
        dir.display(),
        rows.len()
    ))
}

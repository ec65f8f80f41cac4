//! The `leadr-grids` study (its spec in fits/): the model in `crate::leadr`, measured
//! ([`compute`]), then reported (the `Computed` impl's `render`).
//!
//! - **Grid families** (seed 001 §3.4–3.7): uniform N-point grids in standardised slope
//!   units with the paper's spacing 0.9 (no node beyond ±3), uniform grids with the spacing
//!   h fitted per N (scan + Brent over h ∈ [0.2, 2.2]), Gauss–Hermite grids; nodes
//!   (k − (N−1)/2) h, weights ∝ φ(node), normalised.
//! - **Scenes:** σ × θ_o × {specular, diffuse}: training σ ∈ `train_sigma`,
//!   θ_o ∈ `train_theta_deg`; held out σ ∈ `held_sigma`, θ_o ∈ `held_theta_deg`.
//! - **Metric:** relative error of the shading ratio against nested adaptive quadrature
//!   (tolerance 1e-10): RMS and max per family and N ∈ `ns`.

use crate::error::Result;
use crate::io::Outputs;
use crate::leadr::*;
use crate::report::table::Table;
use crate::study::{Ctx, FitOutcome};
use nalgebra::Vector3;
type V3 = Vector3<f64>;

/// One row of the N study: N, the fitted spacing, and for each family (paper spacing,
/// fitted spacing, Gauss–Hermite) the held-out (RMS, max) errors (specular, diffuse).
type NRow = (usize, f64, Vec<((f64, f64), (f64, f64))>);

/// What the study computes.
struct Computed {
    rows: Vec<NRow>,
    /// (h, specular RMS, diffuse RMS) on the training set at N = 5.
    scan: Vec<(f64, f64, f64)>,
    h5: f64,
    without: f64,
    with: f64,
    paper_held: (f64, f64),
    /// The paper's spacing at each row's N.
    paper_h: Vec<f64>,
    /// The h of the scan's least specular and least diffuse error.
    scan_argmin: (f64, f64),
    /// The typed result (results/fits/leadr-grids.json).
    result: crate::results::leadr_grids::LeadrGrids,
}

/// What fits/leadr-grids.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Grid sizes N of the error-against-N table (must include 5: the h-scan's N).
    pub ns: Vec<usize>,
    /// Slope deviations σ and view angles θ_o (degrees) of the training scenes.
    pub train_sigma: Vec<f64>,
    pub train_theta_deg: Vec<f64>,
    /// The same for the held-out scenes.
    pub held_sigma: Vec<f64>,
    pub held_theta_deg: Vec<f64>,
}

impl crate::fit::spec::Params for Params {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::all_within;
        all_within("ns", &self.ns, 2, 64, 32)?;
        if !self.ns.contains(&5) {
            return Err("ns must include 5 (the h-scan's N and the verdict's row)".into());
        }
        all_within("train_sigma", &self.train_sigma, 1e-3, 2.0, 32)?;
        all_within("held_sigma", &self.held_sigma, 1e-3, 2.0, 32)?;
        all_within("train_theta_deg", &self.train_theta_deg, 0.0, 89.0, 32)?;
        all_within("held_theta_deg", &self.held_theta_deg, 0.0, 89.0, 32)
    }
}

/// Error against N for three grid families, the h-scan at N = 5 and the artificial
/// micronormal at a silhouette.
fn compute(c: &Ctx) -> Result<Computed> {
    let pa: Params = c.params()?;
    let train = configs(&pa.train_sigma, &pa.train_theta_deg)?;
    let held = configs(&pa.held_sigma, &pa.held_theta_deg)?;
    let ns = &pa.ns;
    let pb = crate::progress::Progress::new("leadr grids", ns.len() as u64);
    let mut rows = Vec::new();
    for &n in ns {
        let h = fit_spacing(n, &train);
        let fams = [
            Grid::riemann(n, paper_spacing(n)), // the paper: spacing 0.9, no node beyond ±3 (seed 001 §3.4)
            Grid::riemann(n, h),
            Grid::gauss_hermite(n),
        ];
        let errs: Vec<((f64, f64), (f64, f64))> = fams
            .iter()
            .map(|g| (grid_error(g, &held, true), grid_error(g, &held, false)))
            .collect();
        rows.push((n, h, errs));
        pb.inc(1);
    }
    pb.finish();
    // the h-scan at N = 5 (training set)
    let scan: Vec<(f64, f64, f64)> = (0..=24)
        .map(|i| {
            let h = 0.5 + 1.2 * i as f64 / 24.0;
            let g = Grid::riemann(5, h);
            (
                h,
                grid_error(&g, &train, true).0,
                grid_error(&g, &train, false).0,
            )
        })
        .collect();
    let h5 = rows
        .iter()
        .find(|r| r.0 == 5)
        .map(|r| r.1)
        .unwrap_or(f64::NAN);
    // artificial micronormal at a silhouette: the mean normal faces away from V
    let s = Slopes {
        x0: 3.0,
        y0: 0.0,
        sx: 0.05,
        sy: 0.05,
        rxy: 0.0,
    };
    let v = V3::new(0.999, 0.0, 0.0447).normalize();
    let env = |n: &V3| 0.5 + 0.5 * n.z;
    let without = grid_estimate(&Grid::paper5(), &s, &v, &env, None);
    let with = grid_estimate(&Grid::paper5(), &s, &v, &env, Some((1.01, 1e-5)));
    let paper_held = grid_error(&Grid::paper5(), &held, true);
    let argmin = |k: usize| {
        scan.iter()
            .min_by(|a, b| {
                (if k == 0 { a.1 } else { a.2 }).total_cmp(&(if k == 0 { b.1 } else { b.2 }))
            })
            .map(|r| r.0)
            .unwrap_or(f64::NAN)
    };
    let scan_argmin = (argmin(0), argmin(1));
    let paper_h = rows.iter().map(|r| paper_spacing(r.0)).collect();
    let result = result(c, &rows, &scan, h5, without, with);
    Ok(Computed {
        rows,
        scan,
        h5,
        without,
        with,
        paper_held,
        paper_h,
        scan_argmin,
        result,
    })
}

/// The typed result of the study.
fn result(
    c: &Ctx,
    rows: &[NRow],
    scan: &[(f64, f64, f64)],
    h5: f64,
    without: f64,
    with: f64,
) -> crate::results::leadr_grids::LeadrGrids {
    use crate::results::leadr_grids::{Families, LeadrGrids, Micronormal, Row};
    LeadrGrids {
        spec: c.spec.clone(),
        command: crate::results::command(&c.spec.name),
        rows: rows
            .iter()
            .map(|(n, h, e)| Row {
                n: *n,
                fitted_h: *h,
                specular: Families {
                    paper: e[0].0,
                    fitted: e[1].0,
                    gauss_hermite: e[2].0,
                },
                diffuse: Families {
                    paper: e[0].1,
                    fitted: e[1].1,
                    gauss_hermite: e[2].1,
                },
            })
            .collect(),
        h_scan_n5: scan.to_vec(),
        fitted_h_n5: h5,
        artificial_micronormal: Micronormal {
            without: (!without.is_nan()).then_some(without),
            with,
        },
    }
}

/// results/leadr-pareto.svg: held-out max error against the grid size, per family.
fn pareto_svg(rows: &[NRow]) -> Result<String> {
    use crate::report::plot::{loglog_svg, Panel, Series};
    let fam_names = [
        "uniform, h = 0.9 (paper)",
        "uniform, fitted h",
        "Gauss–Hermite",
    ];
    let pareto = |spec_kind: bool| -> Vec<Series> {
        (0..3)
            .map(|f| Series {
                name: fam_names[f].to_string(),
                points: rows
                    .iter()
                    .map(|(n, _, e)| {
                        (
                            (n * n) as f64,
                            if spec_kind { e[f].0 .1 } else { e[f].1 .1 }.max(1e-16),
                        )
                    })
                    .collect(),
            })
            .collect()
    };
    loglog_svg(
        &[
            Panel {
                title: "rough specular × environment: max rel. error (held-out)".into(),
                x_label: "grid points N²".into(),
                y_label: "max relative error".into(),
                series: pareto(true),
            },
            Panel {
                title: "rough diffuse × light: max rel. error (held-out)".into(),
                x_label: "grid points N²".into(),
                y_label: "max relative error".into(),
                series: pareto(false),
            },
        ],
        1400,
        520,
    )
}

/// results/leadr-grids.md.
fn markdown(k: &Computed) -> String {
    let Computed {
        ref rows,
        ref scan,
        h5,
        without,
        with,
        paper_held,
        ref paper_h,
        scan_argmin,
        ..
    } = *k;
    let mut md = String::from("# LEADR numerical integration (seed 001 §3.4–3.7)\n\n");
    md.push_str("Written by `cargo run --release -- regen --only leadr-grids` from `fits/leadr-grids.toml`. Estimator: the paper's simplified \
algorithms 1 and 3 (weighted sum of L(N) over an N×N slope grid, weights × projected area, normalised). Reference: the same ratio with \
the Gaussian slope density, by nested adaptive Gauss–Kronrod (tolerance 1e-10). Test scenes: rough specular under a smooth environment \
(sky gradient + a κ = 50 sun) and rough diffuse under one directional light; isotropic Beckmann σ. Training set σ ∈ {0.05, 0.15, 0.3, 0.5} × \
θ_o ∈ {0°, 30°, 60°, 75°}; held-out σ ∈ {0.1, 0.2, 0.4, 0.6} × θ_o ∈ {15°, 45°, 70°, 80°}.\n\n");
    md.push_str("## Error against N (held-out max relative error; RMS in parentheses)\n\n");
    let mut t = Table::new([
        "N",
        "grid points",
        "paper h",
        "fitted h",
        "specular: paper h",
        "specular: fitted h",
        "specular: Gauss–Hermite",
        "diffuse: paper h",
        "diffuse: fitted h",
        "diffuse: Gauss–Hermite",
    ]);
    for ((n, h, e), paper_h) in rows.iter().zip(paper_h) {
        // (RMS, max) per family: specular then diffuse
        let cell = |x: (f64, f64)| format!("{:.2e} ({:.1e})", x.1, x.0);
        t.row(
            [
                n.to_string(),
                (n * n).to_string(),
                format!("{paper_h:.3}"),
                format!("{h:.3}"),
            ]
            .into_iter()
            .chain((0..3).map(|k| cell(e[k].0)))
            .chain((0..3).map(|k| cell(e[k].1))),
        );
    }
    md.push_str(&t.to_string());
    md.push_str("\nCost is the same per grid point for every family (one normal, one projected area, one shading call): ns per evaluation at each N is in results/performance.md (bench group `leadr`). ![Pareto](leadr-pareto.svg)\n\n");
    md.push_str("## Why spacing 0.9 for 5×5\n\nThe paper's weights are exactly the normalised Gaussian density at the nodes (φ(p)/Σφ at h = 0.9 reproduces 0.0725, 0.2443, 0.3663 to four digits), i.e. its grid is a uniform Riemann sum of the slope density. RMS relative error on the training set against the spacing h (N = 5):\n\n");
    let mut t = Table::new(["h", "specular", "diffuse"]);
    for &(h, a, b) in scan {
        t.row([format!("{h:.2}"), format!("{a:.2e}"), format!("{b:.2e}")]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\nMeasured optima for N = 5: h ≈ {:.2} for the specular scenes, h ≈ {:.2} for the diffuse ones; the fit over both gives h = {h5:.3}. \
The paper's 0.9 lies between the two optima, in the region where neither error is far from its minimum — a sensible single choice for a \
renderer that uses one grid for both. Why a minimum exists: a uniform 5-point grid must trade two errors. Small h truncates the tails \
(the outer nodes sit at ±2h and the mass beyond ±2.5h is dropped and re-normalised away), which matters for the slowly varying diffuse \
term; large h under-resolves shading that varies across the lobe (the Riemann sum aliases), which matters for the sharper specular \
term. Gauss–Hermite is exact for polynomials in the slope, but the max(0, V·N) clamp of the projected area is not polynomial, so it \
does not dominate at grazing views.\n\n",
        scan_argmin.0,
        scan_argmin.1
    ));
    md.push_str(&format!("## Artificial micronormal (§3.7)\n\nSilhouette configuration (mean slope 3, σ = 0.05, view at 87.4° on the far side, so every grid normal faces away): without the artificial micronormal the 5×5 estimate is {without} (0/0); with ε = 1.01 and weight 1e-5 it is {with:.6} (finite, from the artificial normal alone). Held-out error of the plain paper grid elsewhere: max {:.2e} (RMS {:.1e}) — unchanged by the 1e-5 weight wherever any grid normal is visible.\n", paper_held.1, paper_held.0));
    md
}

/// results/leadr-grids.md, results/leadr-pareto.svg and results/fits/leadr-grids.json:
/// error against N for three grid families (paper spacing 0.9, fitted spacing,
/// Gauss–Hermite), the h-scan that explains 0.9, the artificial micronormal at silhouettes.
impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        set.put(results.join("leadr-pareto.svg"), pareto_svg(&self.rows)?);
        set.put(results.join("leadr-grids.md"), markdown(&self));
        crate::results::put(set, results, &self.result)?;
        Ok(())
    }
    /// The held-out max error (specular) of the fitted spacing at N = 5; passed when it
    /// and the artificial micronormal's estimate are finite.
    fn outcome(&self) -> FitOutcome {
        let at5 = |k: usize| {
            self.rows
                .iter()
                .find(|r| r.0 == 5)
                .map(|r| r.2[k].0 .1)
                .unwrap_or(f64::NAN)
        };
        let best = at5(1);
        let spec = &self.result.spec;
        FitOutcome {
            passed: self.with.is_finite() && best.is_finite(),
            ..FitOutcome::judged(
                spec,
                best,
                format!(
                    "N = 5: fitted h = {:.3}; held-out max rel. error (specular) paper h {:.2e}, fitted {:.2e}; artificial micronormal finite: {}",
                    self.h5,
                    at5(0),
                    best,
                    self.with.is_finite()
                ),
            )
        }
    }
}

crate::study::study! {
    /// The LEADR grid study, as the registry holds it.
    LeadrGrids = "leadr-grids", after [], on request false, params Params, computes compute
}

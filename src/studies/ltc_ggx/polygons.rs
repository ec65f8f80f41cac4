//! Polygonal lights (seed 000 §3 and the 2016 paper's §5): the θ/sin θ edge forms, a
//! closed-form rectangle, degenerate lights, the shipped shaders' clipped-sphere horizon,
//! and the fitted LTC × polygon against Monte Carlo of the true BRDF.

use super::compute::cell_ltc;
use crate::error::Result;
use crate::ltc::fit::Table;
use crate::ltc::polygon::{self, EdgeForm};
use crate::ltc::target::GgxTarget;
use crate::report::table::Table as MdTable;
use crate::results::ltc::{Degenerate, EdgeApproximation, PolygonRow, SphereHorizon};
use nalgebra::{Matrix3, Vector3};

type V3 = Vector3<f64>;

/// The polygon study's measures.
pub(super) struct Polygons {
    pub edge_approximations: Vec<EdgeApproximation>,
    /// The rectangle's Lambert form factor and the exact, rational and cubic edge forms'
    /// relative errors against it.
    closed_form: (f64, [f64; 3]),
    /// Each degenerate light and its exact, rational and cubic form factors.
    degenerate: Vec<(&'static str, Vec<f64>)>,
    pub sphere_horizon: SphereHorizon,
    mc_samples: usize,
    /// Per checked cell: (α, θ) and its polygon checks.
    mc: Vec<(f64, f64, Vec<polygon::PolygonCheck>)>,
}

impl Polygons {
    /// The degenerate lights as the result file holds them.
    pub fn degenerate_rows(&self) -> Vec<Degenerate> {
        self.degenerate
            .iter()
            .map(|(name, v)| Degenerate {
                light: name.to_string(),
                values: v.clone(),
            })
            .collect()
    }

    /// The Monte Carlo rows as the result file holds them.
    pub fn polygon_rows(&self) -> Vec<PolygonRow> {
        self.mc
            .iter()
            .flat_map(|&(alpha, theta, ref checks)| {
                checks.iter().map(move |c| PolygonRow {
                    alpha,
                    theta,
                    light: c.light.to_string(),
                    mc: c.mc,
                    ltc_exact: c.ltc_exact,
                    ltc_rational: c.ltc_rational,
                })
            })
            .collect()
    }
}

/// The edge forms' θ/sin θ against the exact one over x = cos θ.
fn edge_approximations() -> Vec<EdgeApproximation> {
    let mut approx = Vec::new();
    for form in [EdgeForm::Rational, EdgeForm::Cubic] {
        let (mut w, mut wx, mut w2) = (0.0f64, 0.0, 0.0f64);
        for k in 0..=200_000 {
            let x = (-1.0 + 2.0 * k as f64 / 200_000.0).clamp(-0.999999, 1.0);
            let s = (1.0 - x * x).max(0.0).sqrt();
            let e = polygon::theta_over_sin(EdgeForm::Exact, x, s);
            let r = (polygon::theta_over_sin(form, x, s) / e - 1.0).abs();
            if r > w {
                w = r;
                wx = x;
            }
            if x >= -0.99 {
                w2 = w2.max(r);
            }
        }
        approx.push(EdgeApproximation {
            form: format!("{form:?}"),
            max_rel: w,
            at_x: wx,
            max_rel_x_ge_m099: w2,
        });
    }
    approx
}

/// A rectangle with a corner above the shading point against its closed form.
fn closed_form() -> (f64, [f64; 3]) {
    let (a, b, c) = (1.0f64, 2.0f64, 1.5f64);
    let (x, y) = (a / c, b / c);
    let ff = (x / (1.0 + x * x).sqrt() * (y / (1.0 + x * x).sqrt()).atan()
        + y / (1.0 + y * y).sqrt() * (x / (1.0 + y * y).sqrt()).atan())
        / (2.0 * std::f64::consts::PI);
    let rect = vec![
        V3::new(0.0, 0.0, c),
        V3::new(a, 0.0, c),
        V3::new(a, b, c),
        V3::new(0.0, b, c),
    ];
    let err = |f: EdgeForm| (polygon::form_factor(&rect, f) / ff - 1.0).abs();
    (
        ff,
        [
            err(EdgeForm::Exact),
            err(EdgeForm::Rational),
            err(EdgeForm::Cubic),
        ],
    )
}

/// Degenerate lights through every edge form.
fn degenerate() -> Vec<(&'static str, Vec<f64>)> {
    let p = |x: f64, y: f64, z: f64| V3::new(x, y, z);
    let lights: Vec<(&'static str, Vec<V3>)> = vec![
        ("zero area (repeated vertex)", vec![p(0.1, 0.0, 1.0); 4]),
        (
            "a line",
            vec![p(-0.5, 0.0, 1.0), p(0.5, 0.0, 1.0), p(0.0, 0.0, 1.0)],
        ),
        (
            "a point",
            vec![p(0.2, 0.1, 1.0), p(0.2, 0.1, 1.0), p(0.2, 0.1, 1.0)],
        ),
        (
            "edge-on (plane through the point)",
            vec![
                p(1.0, 0.0, 0.5),
                p(2.0, 0.0, 0.5),
                p(2.0, 0.0, 1.5),
                p(1.0, 0.0, 1.5),
            ],
        ),
        (
            "entirely below the horizon",
            vec![
                p(-1.0, -1.0, -1.0),
                p(1.0, -1.0, -1.0),
                p(1.0, 1.0, -1.0),
                p(-1.0, 1.0, -1.0),
            ],
        ),
        (
            "straddling the horizon",
            vec![
                p(-1.0, 1.0, -0.5),
                p(1.0, 1.0, -0.5),
                p(1.0, 1.0, 0.5),
                p(-1.0, 1.0, 0.5),
            ],
        ),
        (
            "nearly antipodal edge (θ → π)",
            vec![p(1.0, 0.0, 1e-9), p(-1.0, 1e-9, 1e-9), p(0.0, 1.0, 0.2)],
        ),
    ];
    lights
        .iter()
        .map(|(name, poly)| {
            let v: Vec<f64> = [EdgeForm::Exact, EdgeForm::Rational, EdgeForm::Cubic]
                .iter()
                .map(|f| polygon::form_factor(poly, *f))
                .collect();
            (*name, v)
        })
        .collect()
}

/// The shipped shaders' clipped-sphere horizon against exact clipping.
fn sphere_horizon() -> SphereHorizon {
    let sphere_json = {
        let nb = 4096;
        let d = crate::kernels::bench_inputs(nb);
        let c = &d.cols;
        let (mut num, mut den, mut bad) = (0.0, 0.0, 0usize);
        for i in 0..nb {
            let f = |k: usize| c[k][i] as f64;
            let m = [f(15), f(16), f(17), f(18)];
            let p: [f64; 12] = std::array::from_fn(|k| f(19 + k));
            let approx = crate::kernels::ltc_quad_f64(m, p);
            let minv = Matrix3::new(m[0], 0.0, m[2], 0.0, 1.0, 0.0, m[1], 0.0, m[3]);
            let poly: Vec<V3> = (0..4)
                .map(|k| V3::new(p[3 * k], p[3 * k + 1], p[3 * k + 2]))
                .collect();
            let exact = polygon::ltc_integral(&minv, &poly, EdgeForm::Exact);
            num += (approx - exact).abs();
            den += exact;
            if (approx - exact).abs() > 0.1 * exact.max(1e-4) {
                bad += 1;
            }
        }
        SphereHorizon {
            energy_weighted_rel: num / den,
            cases: nb,
            off_by_more_than_10pct: bad,
        }
    };
    sphere_json
}

/// The fitted LTC × polygon against MC of the true BRDF, on four cells.
fn mc_checks(
    main: &Table,
    mc_samples: usize,
) -> Result<Vec<(f64, f64, Vec<polygon::PolygonCheck>)>> {
    let n = main.grid.n;
    let mut rows = Vec::new();
    for (ai, tj) in [
        (n / 2, n / 4),
        (n / 4, n / 2),
        (n - 1, 3 * n / 4),
        (n / 8 + 1, n / 8),
    ] {
        let cell = &main.cells[tj.min(n - 1)][ai.min(n - 1)];
        let t = GgxTarget::new(cell.alpha, cell.theta)?;
        let (minv, norm) = cell_ltc(cell);
        let checks = polygon::check_cell(&t, &minv, norm, cell.theta, mc_samples)?;
        rows.push((cell.alpha, cell.theta, checks));
    }
    Ok(rows)
}

/// The whole polygon study.
pub(super) fn measure(main: &Table, mc_samples: usize) -> Result<Polygons> {
    Ok(Polygons {
        edge_approximations: edge_approximations(),
        closed_form: closed_form(),
        degenerate: degenerate(),
        sphere_horizon: sphere_horizon(),
        mc_samples,
        mc: mc_checks(main, mc_samples)?,
    })
}

/// The polygon study's markdown.
pub(super) fn section(p: &Polygons) -> String {
    let mut md = String::from("## Polygonal lights\n\n### θ/sin θ of the edge integral\n\nRelative error of the production approximations against atan2(|p₁×p₂|, p₁·p₂)/|p₁×p₂| over x = cos θ ∈ [−1, 1] (200 001 points; near x = −1 the exact value diverges like π/sin θ):\n\n");
    let mut t = MdTable::new([
        "form",
        "max rel. error on [−1, 0.999999]",
        "where",
        "max on [−0.99, 1]",
    ]);
    for e in &p.edge_approximations {
        t.row([
            e.form.clone(),
            format!("{:.2e}", e.max_rel),
            format!("x = {:.6}", e.at_x),
            format!("{:.2e}", e.max_rel_x_ge_m099),
        ]);
    }
    md.push_str(&t.to_string());
    let (ff, [ex, ra, cu]) = p.closed_form;
    md.push_str(&format!("\nClosed-form check (a 1×2 rectangle 1.5 above the point, corner overhead; Lambert form factor {ff:.12}): exact edge integral {ex:.2e} off, rational {ra:.2e}, cubic {cu:.2e} (relative).\n\n"));
    md.push_str("### Degenerate lights (every form returns a finite, non-negative value)\n\n");
    let mut t = MdTable::new(["light", "exact", "rational", "cubic"]);
    for (name, v) in &p.degenerate {
        t.row([
            name.to_string(),
            format!("{:.6e}", v[0]),
            format!("{:.6e}", v[1]),
            format!("{:.6e}", v[2]),
        ]);
    }
    md.push_str(&t.to_string());
    let h = &p.sphere_horizon;
    md.push_str(&format!("\n### Horizon handling: clipped-sphere approximation vs exact clipping\n\nThe shipped shaders (and the generated `ltc_quad` of results/wgsl/ltc.wgsl) skip polygon clipping and correct the unclipped vector form factor F with max((|F|² + F_z)/(|F| + 1), 0). Over {nb} random quads and LTC matrices (the kernel benchmark inputs): energy-weighted error Σ|approx − exact|/Σ exact = {:.2} %; {} of {nb} cases off by more than 10 % (of max(value, 1e-4)).\n\n", 100.0 * h.energy_weighted_rel, h.off_by_more_than_10pct, nb = h.cases));
    md.push_str(&format!("\n### Fitted LTC × polygon against Monte Carlo of the true BRDF\n\nTruth: ∫_P f dl by MIS of light-area and VNDF sampling ({} samples each, ± standard error). LTC: norm × the edge integral of M⁻¹P (production M⁻¹ of the fitted cell nearest to (α, θ); no interpolation).\n\n", p.mc_samples));
    let mut t = MdTable::new([
        "α",
        "θ",
        "light",
        "MC truth",
        "LTC (exact edges)",
        "rel. error",
        "LTC (rational edges)",
        "rel. error",
    ]);
    for (alpha, theta, checks) in &p.mc {
        for c in checks {
            let (ex, ra) = (c.ltc_exact, c.ltc_rational);
            let rel = |x: f64| c.mc.rel_error_of(x);
            t.row([
                format!("{alpha:.3}"),
                format!("{:.1}°", theta.to_degrees()),
                c.light.to_string(),
                c.mc.sci(4, 1),
                format!("{ex:.4e}"),
                rel(ex),
                format!("{ra:.4e}"),
                rel(ra),
            ]);
        }
    }
    md.push_str(&t.to_string());
    md.push_str("\nThe LTC column's error is the fit's own error in the lobe restricted to the polygon (it is a lobe approximation, so small lights near the peak show it most); the rational edge form adds at most its θ/sin θ error (column above).\n");
    md
}

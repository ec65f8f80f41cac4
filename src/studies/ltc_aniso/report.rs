//! The anisotropic table's design study and report: what each dimension's resolution
//! costs (dense 1D lines through the domain, interpolated at coarser spacings), the
//! error predicted for other table sizes, the fitted cells and the cases between them
//! against the engines' isotropic substitutes, by anisotropy.

use super::compute::{fit_case, Between, Case, Fitted, Plan};
use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::ltc::aniso::{AnisoGgxTarget, Inv7};
use crate::ltc::table::FittedTable;
use crate::ltc::target::LtcTarget;
use serde::Serialize;

/// The dimensions of the table.
pub const DIMS: [&str; 4] = ["r_x = √α_x", "r_y = √α_y", "φ", "t = √(1 − cos θ)"];

/// One line of the design study: the fits at its nodes.
struct Line {
    dim: usize,
    nodes: Vec<Fitted>,
}

/// The interpolation penalty of one dimension at one resolution.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Penalty {
    pub dim: usize,
    /// Nodes over the dimension's whole range.
    pub n: usize,
    /// Mean held-out relative L2 at the dropped nodes, interpolated linearly from the kept
    /// ones (entries and norm), over every line of this dimension.
    pub interpolated: f64,
    /// Mean held-out relative L2 of the fits at the same nodes.
    pub fitted: f64,
}

/// The design study's output.
#[derive(Clone, Debug, Serialize)]
pub struct Design {
    pub bases: Vec<[f64; 4]>,
    pub penalties: Vec<Penalty>,
    /// The largest error bar of any held-out figure of the study.
    pub bar_max: f64,
}

fn case_at(base: &[f64; 4], dim: usize, u: f64, amin: f64) -> Case {
    let mut p = *base;
    p[dim] = if dim == 2 {
        u * std::f64::consts::FRAC_PI_2
    } else {
        u
    };
    Case {
        ax: (p[0] * p[0]).max(amin),
        ay: (p[1] * p[1]).max(amin),
        phi: p[2],
        theta: (1.0 - p[3] * p[3]).clamp(0.0, 1.0).acos(),
    }
}

/// Dense lines through the domain, one per dimension and base point, each node fitted as
/// a table cell is; then every coarser spacing 2, 4, … of the same nodes, the dropped
/// nodes interpolated linearly.
pub(super) fn design_study(iso: &FittedTable, pl: &Plan) -> Result<Design> {
    let bases: Vec<[f64; 4]> = if pl.line <= 5 {
        vec![[0.7, 0.35, std::f64::consts::FRAC_PI_6, 0.55]]
    } else {
        vec![
            [0.7, 0.35, std::f64::consts::FRAC_PI_6, 0.55],
            [0.45, 0.2, std::f64::consts::FRAC_PI_3, 0.8],
        ]
    };
    let amin = pl.grid.alpha_min;
    let l = pl.line;
    let jobs: Vec<(usize, usize, usize)> = (0..bases.len())
        .flat_map(|b| (0..4).flat_map(move |d| (0..l).map(move |k| (b, d, k))))
        .collect();
    let fits: Vec<Fitted> =
        crate::memo::map_items("ltc-aniso design lines", &jobs, |&(b, d, k)| {
            fit_case(
                iso,
                case_at(&bases[b], d, k as f64 / (l - 1) as f64, amin),
                pl,
            )
        })?;
    let lines: Vec<Line> = fits
        .chunks(l)
        .enumerate()
        .map(|(q, c)| Line {
            dim: q % 4,
            nodes: c.to_vec(),
        })
        .collect();
    // every interpolated node of every spacing that divides the line (n = (l − 1)/step + 1
    // nodes), judged in parallel: (dim, step, the entries, the norm, the case)
    let mut jobs: Vec<(usize, usize, Inv7, f64, Case)> = Vec::new();
    let mut fitted_at: Vec<(usize, usize, f64)> = Vec::new();
    for dim in 0..4 {
        for step in (2..l).filter(|s| (l - 1) % s == 0) {
            for line in lines.iter().filter(|x| x.dim == dim) {
                for k in (0..l).filter(|k| k % step != 0) {
                    let (k0, k1) = (k - k % step, k - k % step + step);
                    let w = (k - k0) as f64 / step as f64;
                    let (a, b) = (&line.nodes[k0], &line.nodes[k1]);
                    let inv: Inv7 = std::array::from_fn(|q| a.inv[q] * (1.0 - w) + b.inv[q] * w);
                    let norm = a.norm * (1.0 - w) + b.norm * w;
                    jobs.push((dim, step, inv, norm, line.nodes[k].case));
                    fitted_at.push((dim, step, line.nodes[k].err));
                }
            }
        }
    }
    let judged: Vec<(f64, f64)> = crate::memo::map_items(
        "ltc-aniso design interpolation",
        &jobs,
        |(_, _, inv, norm, c)| {
            let t = AnisoGgxTarget::new(c.ax, c.ay, c.theta, c.phi)?;
            let (albedo, _, _) = t.albedo(1e-7);
            let (l2, _, bar) = super::compute::held_out(&t, albedo, &[(*inv, *norm)]);
            Ok((l2[0], bar))
        },
    )?;
    let mut penalties = Vec::new();
    for dim in 0..4 {
        for step in (2..l).filter(|s| (l - 1) % s == 0) {
            let pick = |v: &dyn Fn(usize) -> f64| {
                let x: Vec<f64> = (0..jobs.len())
                    .filter(|&q| jobs[q].0 == dim && jobs[q].1 == step)
                    .map(v)
                    .collect();
                x.iter().sum::<f64>() / x.len().max(1) as f64
            };
            penalties.push(Penalty {
                dim,
                n: (l - 1) / step + 1,
                interpolated: pick(&|q| judged[q].0),
                fitted: pick(&|q| fitted_at[q].2),
            });
        }
    }
    let bar_max = judged
        .iter()
        .map(|x| x.1)
        .chain(fits.iter().map(|f| f.bar))
        .fold(0.0, f64::max);
    Ok(Design {
        bases,
        penalties,
        bar_max,
    })
}

pub use crate::results::ltc::MeanMax;

fn mean_max(v: impl Iterator<Item = f64>) -> MeanMax {
    let v: Vec<f64> = v.filter(|x| x.is_finite()).collect();
    let (mean, se) = crate::integrate::MeanSe::of(&v).pair();
    MeanMax {
        mean,
        se,
        max: v.iter().cloned().fold(0.0, f64::max),
        count: v.len(),
    }
}

/// A sample mean with its standard error, in percent.
fn pct_se(m: &MeanMax) -> String {
    crate::integrate::MeanSe {
        value: m.mean,
        se: m.se,
    }
    .pct(2)
}

/// A row of the per-anisotropy tables.
#[derive(Clone, Debug, Serialize)]
pub struct Bin {
    pub label: &'static str,
    pub ours: MeanMax,
    pub iso_geo: MeanMax,
    pub iso_max: MeanMax,
}

/// A predicted table size.
#[derive(Clone, Debug, Serialize)]
pub struct Prediction {
    pub size: [usize; 4],
    pub texels: usize,
    pub bytes_f16: usize,
    /// Predicted RMS relative L2 between cells.
    pub predicted_mean: f64,
    /// Whether a dimension's penalty was extrapolated (h² beyond the study's finest).
    pub extrapolated: bool,
}

/// Everything the report shows.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub fit_rms: f64,
    pub between_rms: f64,
    pub cells_fitted: usize,
    pub cells: Bin,
    pub between_table: MeanMax,
    pub between_table_f16: MeanMax,
    pub between_iso_geo: MeanMax,
    pub between_iso_max: MeanMax,
    pub by_anisotropy: Vec<Bin>,
    pub design: Design,
    pub predictions: Vec<Prediction>,
    /// The largest error bar of any held-out figure of a cell or a case.
    pub bar_max: f64,
    /// Relative L1 of the table: at its cells (mean / max) and between them.
    pub cells_l1: MeanMax,
    pub between_table_l1: MeanMax,
}

const BINS: [(&str, f64, f64); 5] = [
    ("α_max/α_min ≤ 1.5", 0.0, 1.5),
    ("1.5 – 3", 1.5, 3.0),
    ("3 – 10", 3.0, 10.0),
    ("10 – 100", 10.0, 100.0),
    ("> 100", 100.0, f64::INFINITY),
];

fn ratio(c: &Case) -> f64 {
    c.ax.max(c.ay) / c.ax.min(c.ay)
}

/// The interpolation penalty of `dim` at `n` nodes, in squares (e_interp² − e_fit²: the
/// interpolation's share of the squared relative L2): measured where the study has it,
/// else extrapolated from its finest measured spacing by h² in the error, h⁴ in squares
/// (linear interpolation of a smooth function).
fn penalty(d: &Design, dim: usize, n: usize) -> (f64, bool) {
    let rows: Vec<&Penalty> = d.penalties.iter().filter(|p| p.dim == dim).collect();
    if let Some(p) = rows.iter().find(|p| p.n == n) {
        return ((p.interpolated.powi(2) - p.fitted.powi(2)).max(0.0), false);
    }
    let Some(fine) = rows.iter().max_by_key(|p| p.n) else {
        return (f64::NAN, true);
    };
    let base = (fine.interpolated.powi(2) - fine.fitted.powi(2)).max(0.0);
    let h = (fine.n - 1) as f64 / (n.max(2) - 1) as f64;
    (base * h.powi(4), true)
}

pub(super) fn summarise(
    fitted: &[Fitted],
    cases: &[Between],
    design: &Design,
    pl: &Plan,
) -> Summary {
    // the fits' root-mean-square error: squares add for independent perturbations
    let fit_floor =
        (fitted.iter().map(|f| f.err * f.err).sum::<f64>() / fitted.len().max(1) as f64).sqrt();
    let predict = |size: [usize; 4]| {
        let mut ex = false;
        let mut e2 = fit_floor * fit_floor;
        for (dim, &n) in size.iter().enumerate() {
            let (p, x) = penalty(design, dim, n);
            e2 += p;
            ex |= x;
        }
        let e = e2.sqrt();
        let texels = size.iter().product::<usize>();
        Prediction {
            size,
            texels,
            // three RGBA16F texels per cell
            bytes_f16: texels * 3 * 8,
            predicted_mean: e,
            extrapolated: ex,
        }
    };
    let g = pl.grid;
    let sizes = [
        [g.n_r, g.n_r, g.n_phi, g.n_t],
        [8, 8, 8, 8],
        [16, 16, 16, 16],
        [32, 32, 8, 32],
    ];
    Summary {
        fit_rms: fit_floor,
        between_rms: (cases
            .iter()
            .map(|c| c.err_table.powi(2))
            .filter(|x| x.is_finite())
            .sum::<f64>()
            / cases.len().max(1) as f64)
            .sqrt(),
        cells_fitted: fitted.len(),
        cells: Bin {
            label: "table cells",
            ours: mean_max(fitted.iter().map(|f| f.err)),
            iso_geo: mean_max(fitted.iter().map(|f| f.err_iso_geo)),
            iso_max: mean_max(fitted.iter().map(|f| f.err_iso_max)),
        },
        between_table: mean_max(cases.iter().map(|c| c.err_table)),
        between_table_f16: mean_max(cases.iter().map(|c| c.err_table_f16)),
        between_iso_geo: mean_max(cases.iter().map(|c| c.err_iso_geo)),
        between_iso_max: mean_max(cases.iter().map(|c| c.err_iso_max)),
        by_anisotropy: BINS
            .iter()
            .map(|&(label, lo, hi)| {
                let inb: Vec<&Between> = cases
                    .iter()
                    .filter(|c| ratio(&c.case) > lo && ratio(&c.case) <= hi)
                    .collect();
                Bin {
                    label,
                    ours: mean_max(inb.iter().map(|c| c.err_table)),
                    iso_geo: mean_max(inb.iter().map(|c| c.err_iso_geo)),
                    iso_max: mean_max(inb.iter().map(|c| c.err_iso_max)),
                }
            })
            .collect(),
        design: design.clone(),
        predictions: sizes.into_iter().map(predict).collect(),
        bar_max: fitted
            .iter()
            .map(|f| f.bar)
            .chain(cases.iter().map(|c| c.bar))
            .fold(design.bar_max, f64::max),
        cells_l1: mean_max(fitted.iter().map(|f| f.err_l1)),
        between_table_l1: mean_max(cases.iter().map(|c| c.err_table_l1)),
    }
}

fn pct(x: f64) -> String {
    format!("{:.2} %", 100.0 * x)
}

/// results/ltc-aniso.md.
pub(super) fn markdown(
    spec: &FitSpec,
    preset: Preset,
    pl: &Plan,
    s: &Summary,
    command: &str,
) -> String {
    let g = pl.grid;
    let mut md = format!(
        "# Anisotropic GGX LTC table\n\nWritten by `{command}` (preset {}) from `fits/{}.toml`. Target: the cosine-weighted anisotropic GGX BRDF (height-correlated Smith G2, F = 1) with α_x along a tangent at azimuth φ from T1 and α_y across it, in the frame engines build for their LTC lookup (T1 = the view projected on the tangent plane). The lobe is not symmetric about the view plane, so M⁻¹ takes the general production form of `ltc::aniso`: M⁻¹ ∝ [[a, 0, c], [e, 1, g], [b, h, d]] (the rotation about z the clamped cosine ignores zeroes one entry, the scale another: seven numbers; e = g = h = 0 is the isotropic form).\n\n## Design\n\n- **Parameterisation:** (r_x = √α_x, r_y = √α_y, φ, t = √(1 − cos θ)), each uniform: the isotropic table's two coordinates plus the second roughness and the tangent's azimuth. α = max(r², {}).\n- **Symmetry:** the tangent is a line (φ ≡ φ + π) and the mirror y → −y maps φ to π − φ with M⁻¹ → S·M⁻¹·S (S = diag(1, −1, 1): e, g, h change sign), so φ ∈ [0, π/2] covers every case. Swapping α_x and α_y is a quarter turn of the tangent, (α_y, α_x, π/2 − φ) = S·(α_x, α_y, φ)·S: only cells with α_x ≥ α_y are fitted ({} of {}), the others are their mirrors.\n- **Fit:** Nelder–Mead (argmin) on the relative L2 ({s}×{s} stratified samples per technique, the LTC and the VNDF; ≤ {} iterations) from three starts — the isotropic table's entries at √(α_x α_y) (results/fits/ltc-ggx.json), the same stretched toward the tangent, the isotropic table at max(α_x, α_y) — the best on a validation set kept, and only if it beats its start there; norm and fresnel by nested adaptive quadrature in half-vector space with the polar grid stretched along the roughness ellipse (tolerance 1e-7). Fit cost: results/performance.md (criterion's time per cell; the main job's wall clock per study).\n- **Storage:** one RGBA16F 2D array texture, width n_r (r_x), height n_t (t), 3 layers per (r_y, φ) node: (a, b, c, d), (norm, fresnel, 0, 0), (e, g, h, 0). The sampler interpolates (r_x, t) in hardware; the lookup blends the four (r_y, φ) neighbours itself: 12 fetches (`ltc_aniso.wgsl`; its f64 reference `AnisoTable::lookup`). A 3D texture would interpolate a third coordinate in hardware but cannot hold the fourth; array layers keep every API (WebGPU included) and one layout. The texture is kept non-square (n_t ≠ n_r): wgpu's GL backend (Bevy on WebGL2) creates a square 2D texture whose layer count is a multiple of 6 as a cube-map array (wgpu-hal's `get_info_from_desc`), and 3·n_r·n_φ layers is one whenever n_r·n_φ is even.\n\n",
        preset.name(),
        spec.name,
        g.alpha_min,
        s.cells_fitted,
        g.cells(),
        pl.iters,
        s = pl.samples
    );
    md.push_str(&format!("## The size/error trade\n\nDense lines of {} nodes through the domain along each coordinate (others at the base points {}), every node fitted as a table cell is; then every coarser spacing of the same nodes, the dropped nodes interpolated linearly (entries and norm, as the lookup does). Mean held-out relative L2 at the dropped nodes, and of the fits there (converged integrals, each within the error bar stated below):\n\n| dimension | nodes over its range | interpolated | fitted | penalty |\n|---|---|---|---|---|\n", pl.line, s.design.bases.iter().map(|b| format!("(r_x {:.2}, r_y {:.2}, φ {:.0}°, t {:.2})", b[0], b[1], b[2].to_degrees(), b[3])).collect::<Vec<_>>().join(" and ")));
    for p in &s.design.penalties {
        md.push_str(&format!(
            "| {} | {} | {} | {} | {:+.2} points |\n",
            DIMS[p.dim],
            p.n,
            pct(p.interpolated),
            pct(p.fitted),
            100.0 * (p.interpolated - p.fitted)
        ));
    }
    md.push_str(&format!("\n![penalties](ltc-aniso.svg)\n\nPredicted RMS error of a table between its cells: the fits' RMS at the cells ({}) and each dimension's penalty at its resolution added in squares (e² = e_fit² + Σ_d (e_interp,d² − e_fit,d²), the errors of independent perturbations adding in squares); beyond the study's finest spacing the penalty is extrapolated by h² (marked *):\n\n| r_x × r_y × φ × t | texels | RGBA16F bytes | predicted RMS rel. L2 |\n|---|---|---|---|\n", pct(s.fit_rms)));
    for p in &s.predictions {
        md.push_str(&format!(
            "| {}×{}×{}×{} | {} | {:.1} KiB | {}{} |\n",
            p.size[0],
            p.size[1],
            p.size[2],
            p.size[3],
            p.texels,
            p.bytes_f16 as f64 / 1024.0,
            pct(p.predicted_mean),
            if p.extrapolated { " *" } else { "" }
        ));
    }
    md.push_str(&format!(
        "\nThe shipped table ({}×{}×{}×{}) measured at {} random cases between its cells (below): RMS {} (mean {}), against its prediction {} in the first row.\n\n",
        g.n_r, g.n_r, g.n_phi, g.n_t, s.between_table.count, pct(s.between_rms), pct(s.between_table.mean), pct(s.predictions[0].predicted_mean)
    ));
    md.push_str(&format!(
        "## Against what engines do today\n\n![cell errors](ltc-aniso-error.svg)\n\nEvery figure below is a held-out integral of `ltc::lobe_error` (relative L2 ‖f − norm·γ_M‖/‖f‖, and relative L1 where named), converged to its tolerance: the largest error bar of any cell's or case's figure is {:.1e} (as a fraction), far below the spread across cases, so a mean's ± is the standard error of the random sample of cases.\n\nAt the table's cells (mean / max over {} fitted cells): this fit {} / {} (relative L1 {} / {}); the isotropic table at α = √(α_x α_y) {} / {}; at max(α_x, α_y) {} / {}.\n\nAt {} random cases between cells (α_x, α_y uniform in √α, φ uniform on [0, π), θ uniform in t), each with the lookup a shader does (the interpolated norm included):\n\n| | mean ± s.e. | max |\n|---|---|---|\n| this table (f64) | {} | {} |\n| this table (f64), relative L1 | {} | {} |\n| this table (binary16, as stored in the texture) | {} | {} |\n| isotropic table at √(α_x α_y) | {} | {} |\n| isotropic table at max(α_x, α_y) | {} | {} |\n\nBy anisotropy (mean ± s.e. / max):\n\n| α_max/α_min | cases | this table | isotropic at √(α_x α_y) | isotropic at max |\n|---|---|---|---|---|\n",
        s.bar_max,
        s.cells.ours.count, pct(s.cells.ours.mean), pct(s.cells.ours.max), pct(s.cells_l1.mean), pct(s.cells_l1.max), pct(s.cells.iso_geo.mean), pct(s.cells.iso_geo.max), pct(s.cells.iso_max.mean), pct(s.cells.iso_max.max),
        s.between_table.count,
        pct_se(&s.between_table), pct(s.between_table.max), pct_se(&s.between_table_l1), pct(s.between_table_l1.max), pct_se(&s.between_table_f16), pct(s.between_table_f16.max),
        pct_se(&s.between_iso_geo), pct(s.between_iso_geo.max), pct_se(&s.between_iso_max), pct(s.between_iso_max.max)
    ));
    for b in &s.by_anisotropy {
        md.push_str(&format!(
            "| {} | {} | {} / {} | {} / {} | {} / {} |\n",
            b.label,
            b.ours.count,
            pct_se(&b.ours),
            pct(b.ours.max),
            pct_se(&b.iso_geo),
            pct(b.iso_geo.max),
            pct_se(&b.iso_max),
            pct(b.iso_max.max)
        ));
    }
    md.push_str("\nThe isotropic substitutes cannot turn their lobe toward the tangent, so their error grows with the anisotropy; at α_max/α_min ≤ 1.5 they are the isotropic table itself, and the anisotropic table's own interpolation error is what it pays for the extra dimensions.\n");
    md
}

/// results/ltc-aniso.svg: the interpolation penalty of each dimension against its
/// resolution.
pub(super) fn plot(d: &Design, pl: &Plan) -> Result<String> {
    use crate::report::plot::{loglog_svg, Panel, Series};
    let series = (0..4)
        .map(|dim| Series {
            name: DIMS[dim].into(),
            points: d
                .penalties
                .iter()
                .filter(|p| p.dim == dim)
                .map(|p| (p.n as f64, (p.interpolated - p.fitted).max(1e-6)))
                .collect(),
        })
        .collect();
    loglog_svg(
        &[Panel {
            title: format!(
                "interpolation penalty per dimension ({} node lines)",
                pl.line
            ),
            x_label: "nodes over the dimension's range".into(),
            y_label: "mean rel. L2 interpolated − fitted".into(),
            series,
        }],
        720,
        480,
    )
}

/// The polygon-light section.
pub(super) fn polygon_section(rows: &[super::compute::PolygonRow], mc: usize) -> String {
    let mut md = format!("\n## Polygon lights\n\nThe table as a shader reads it (binary16, interpolated at the case) × the quad (exact edges), and the isotropic table at √(α_x α_y), against MC of the true lobe over the quad (MIS of light-area and VNDF sampling, {mc} samples each, ± standard error); the error also as a fraction of the lobe's albedo:\n\n| α_x | α_y | φ | θ | light | MC truth | this table | rel. error | error / albedo | isotropic at √(α_x α_y) | rel. error |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let c = &r.check;
        let rel = |x: f64| crate::report::rel_vs_mc(x, c.mc, c.mc_se);
        md.push_str(&format!(
            "| {:.3} | {:.3} | {:.0}° | {:.0}° | {} | {:.4e} ± {:.1e} | {:.4e} | {} | {:+.2} % | {:.4e} | {} |\n",
            r.case.ax, r.case.ay, r.case.phi.to_degrees(), r.case.theta.to_degrees(), c.light, c.mc, c.mc_se, c.ltc_exact, rel(c.ltc_exact),
            100.0 * (c.ltc_exact - c.mc) / r.albedo.max(1e-300), r.iso_geo_exact, rel(r.iso_geo_exact)
        ));
    }
    md
}

/// results/ltc-aniso-error.svg: the fitted cells' held-out error, averaged over (φ, t)
/// on the (r_x, r_y) plane (fitted cells have r_x ≥ r_y; the mirror half is grey) and
/// over (r_x, r_y) on the (φ, t) plane.
pub(super) fn heatmap(fitted: &[Fitted], pl: &Plan) -> Result<String> {
    use crate::report::plot::{heatmap_svg, HeatPanel};
    let g = pl.grid;
    let idx = |x: f64, n: usize| ((x * (n - 1) as f64).round() as usize).min(n - 1);
    let mut a = vec![vec![(0.0, 0usize); g.n_r]; g.n_r];
    let mut b = vec![vec![(0.0, 0usize); g.n_phi]; g.n_t];
    for f in fitted.iter().filter(|f| f.err.is_finite()) {
        let c = &f.case;
        let (ix, iy) = (idx(c.ax.sqrt(), g.n_r), idx(c.ay.sqrt(), g.n_r));
        let k = idx(c.phi / std::f64::consts::FRAC_PI_2, g.n_phi);
        let j = idx((1.0 - c.theta.cos()).max(0.0).sqrt(), g.n_t);
        a[iy][ix].0 += f.err;
        a[iy][ix].1 += 1;
        b[j][k].0 += f.err;
        b[j][k].1 += 1;
    }
    let mean = |m: Vec<Vec<(f64, usize)>>| -> Vec<Vec<f64>> {
        m.into_iter()
            .map(|r| {
                r.into_iter()
                    .map(|(s, n)| if n > 0 { (s / n as f64).max(1e-8) } else { 0.0 })
                    .collect()
            })
            .collect()
    };
    let axis = |n: usize, top: f64| {
        (0..n)
            .map(|i| top * i as f64 / (n - 1) as f64)
            .collect::<Vec<f64>>()
    };
    heatmap_svg(
        &[
            HeatPanel {
                title: "mean over φ and θ (α_x ≥ α_y fitted)".into(),
                x: axis(g.n_r, 1.0),
                y: axis(g.n_r, 1.0),
                values: mean(a),
                log_range: (-2.0, 0.3),
                x_label: "r_x = √α_x".into(),
                y_label: "r_y = √α_y".into(),
                log_axes: false,
                y_down: false,
                colour_label: "log10 relative L2 (held out)".into(),
            },
            HeatPanel {
                title: "mean over α_x and α_y".into(),
                x: axis(g.n_phi, 90.0),
                y: axis(g.n_t, 1.0),
                values: mean(b),
                log_range: (-2.0, 0.3),
                x_label: "φ (degrees)".into(),
                y_label: "t = √(1 − cos θ)  (t = 0: normal incidence, top)".into(),
                log_axes: false,
                y_down: true,
                colour_label: "log10 relative L2 (held out)".into(),
            },
        ],
        1300,
        620,
    )
}

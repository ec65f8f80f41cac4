//! results/filters-survey.md, results/filters-survey.svg and the survey's JSON: the representations of
//! seed 004 §3.2 next to the footprint study's filters, on the same cases. [`summarise`]
//! computes every number; [`markdown`] and [`pareto_svg`] only render them.

use super::cases::{aggregate, MapCase};
use super::plan::kind_name;
use super::survey::{Diag, SurveyCases, FOURNIER_K, MIP_K, ROWS};
use crate::error::Result;
use crate::filters::registry::MAP;
use crate::filters::truth::CaseResult;
use crate::integrate::{Figure, Preset};
use crate::microfacet::NdfKind;
use crate::report::plot::{loglog_svg_legend, Panel, Series};
use crate::report::table::Table;
use crate::survey::em::EmLog;
use crate::survey::sh::coefficients_needed;
use crate::survey::tools::TOOLS;

/// Storage budgets (parameters per texel) of the verdicts.
pub const BUDGETS: [usize; 8] = [2, 3, 5, 9, 16, 32, 64, 256];

pub use crate::results::filters::{
    AlignmentRow, LevelPair, RowSummary, RuleOfThumb, Summary, Verdict,
};

/// Row `r` of the combined table for case `ci`: the filters first, then the survey.
fn result<'a>(c: &'a MapCase, sv: &'a SurveyCases, ci: usize, r: usize) -> &'a CaseResult {
    if r < MAP.len() {
        &c.results[r]
    } else {
        &sv.results[ci][r - MAP.len()]
    }
}

/// The combined-table index of the survey row named `name` (a name of [`ROWS`]).
fn row_index(name: &str) -> usize {
    MAP.len()
        + ROWS
            .iter()
            .position(|r| r.name == name)
            .expect("a survey row of that name")
}

fn n_rows() -> usize {
    MAP.len() + ROWS.len()
}

fn row_meta(r: usize) -> (String, String, Option<usize>) {
    if r < MAP.len() {
        let f = &MAP[r];
        (f.label.to_string(), f.family.to_string(), Some(f.params))
    } else {
        let row = ROWS[r - MAP.len()];
        (row.name.to_string(), row.family.to_string(), row.params)
    }
}

fn paired(cases: &[(usize, &MapCase)], sv: &SurveyCases, a: usize, b: usize) -> Figure {
    let d: Vec<f64> = cases
        .iter()
        .map(|(ci, c)| result(c, sv, *ci, a).l2.value - result(c, sv, *ci, b).l2.value)
        .collect();
    Figure::mean_of_finite(&d)
}

fn verdicts(
    maps: &[String],
    cases: &[(usize, &MapCase)],
    sv: &SurveyCases,
    rows: &[RowSummary],
) -> Vec<Verdict> {
    let mut out = Vec::new();
    for (m, name) in maps.iter().enumerate() {
        let mc: Vec<(usize, &MapCase)> =
            cases.iter().filter(|(_, c)| c.map == m).copied().collect();
        for &b in &BUDGETS {
            let mut cand: Vec<usize> = (0..rows.len())
                .filter(|&r| rows[r].params.is_some_and(|p| p <= b))
                .collect();
            cand.sort_by(|&x, &y| {
                rows[x].by_map[m]
                    .l2
                    .value
                    .total_cmp(&rows[y].by_map[m].l2.value)
            });
            if cand.len() < 2 {
                continue;
            }
            let (best, second) = (cand[0], cand[1]);
            out.push(Verdict {
                map: name.clone(),
                budget: b,
                best: rows[best].name.clone(),
                best_params: rows[best].params.unwrap_or(0),
                l2: rows[best].by_map[m].l2,
                runner_up: rows[second].name.clone(),
                margin: paired(&mc, sv, second, best),
            });
        }
    }
    out
}

fn alignment(maps: &[String], cases: &[(usize, &MapCase)], sv: &SurveyCases) -> Vec<AlignmentRow> {
    let frac = |d: &[&Diag], k: usize, tan: bool| {
        let (mis, pairs) = d.iter().fold((0, 0), |a, x| {
            let v = if tan { &x.tan_align } else { &x.vmf_align };
            (a.0 + v[k].0, a.1 + v[k].1)
        });
        mis as f64 / pairs.max(1) as f64
    };
    let em4 = row_index("Tan et al., 4 lobes, EM");
    let mip4 = row_index("Tan et al., 4 lobes, MIP-mapped (aligned)");
    maps.iter()
        .enumerate()
        .map(|(m, name)| {
            let d: Vec<&Diag> = cases
                .iter()
                .filter(|(ci, c)| c.map == m && ci % sv.views == 0)
                .map(|(ci, _)| &sv.diags[ci / sv.views])
                .collect();
            let split = |want: bool| {
                let x: Vec<f64> = cases
                    .iter()
                    .filter(|(ci, c)| {
                        c.map == m && (sv.diags[ci / sv.views].tan_align[1].0 > 0) == want
                    })
                    .map(|(ci, c)| {
                        result(c, sv, *ci, mip4).l2.value - result(c, sv, *ci, em4).l2.value
                    })
                    .collect();
                (Figure::mean_of_finite(&x), x.len() / sv.views.max(1))
            };
            AlignmentRow {
                map: name.clone(),
                tan_misaligned: (0..MIP_K.len()).map(|k| frac(&d, k, true)).collect(),
                vmf_misaligned: (0..MIP_K.len()).map(|k| frac(&d, k, false)).collect(),
                tan_cost_misaligned: split(true),
                tan_cost_aligned: split(false),
            }
        })
        .collect()
}

/// Every number of the report.
pub(super) fn summarise(maps: &[String], cases: &[&MapCase], sv: &SurveyCases) -> Summary {
    let idx: Vec<(usize, &MapCase)> = cases.iter().copied().enumerate().collect();
    let agg = |r: usize, f: &dyn Fn(&MapCase) -> bool| {
        let v: Vec<&CaseResult> = idx
            .iter()
            .filter(|(_, c)| f(c))
            .map(|(ci, c)| result(c, sv, *ci, r))
            .collect();
        aggregate(&v)
    };
    let rows: Vec<RowSummary> = (0..n_rows())
        .map(|r| {
            let (name, family, params) = row_meta(r);
            RowSummary {
                name,
                family,
                params,
                all: agg(r, &|_| true),
                ggx: agg(r, &|c| c.kind == NdfKind::Ggx),
                beckmann: agg(r, &|c| c.kind == NdfKind::Beckmann),
                by_map: (0..maps.len()).map(|m| agg(r, &|c| c.map == m)).collect(),
            }
        })
        .collect();
    let (sr, sm) = (
        row_index("Schilling, recomputed per level"),
        row_index("Schilling, MIP-mapped linearly (one level)"),
    );
    let mut levels: Vec<usize> = cases.iter().map(|c| c.level).collect();
    levels.sort_unstable();
    levels.dedup();
    let schilling = levels
        .iter()
        .map(|&l| {
            let lc: Vec<(usize, &MapCase)> =
                idx.iter().filter(|(_, c)| c.level == l).copied().collect();
            let a = |r: usize| {
                let v: Vec<f64> = lc
                    .iter()
                    .map(|(ci, c)| result(c, sv, *ci, r).l2.value)
                    .collect();
                Figure::mean_of_finite(&v)
            };
            LevelPair {
                level: l,
                recomputed: a(sr),
                mipped: a(sm),
                cost: paired(&lc, sv, sm, sr),
            }
        })
        .collect();
    let mut em = EmLog::default();
    for d in &sv.diags {
        em.iterations += d.em.iterations;
        em.reseeded += d.em.reseeded;
        em.dropped += d.em.dropped;
        em.floored += d.em.floored;
        em.kappa_capped += d.em.kappa_capped;
    }
    let nd = sv.diags.len().max(1) as f64;
    let fournier_fit_l2 = FOURNIER_K
        .iter()
        .enumerate()
        .map(|(i, &k)| {
            let v: Vec<f64> = sv.diags.iter().map(|d| d.fournier_fit_l2[i]).collect();
            (k, Figure::mean_of_finite(&v))
        })
        .collect();
    let fournier_iters = FOURNIER_K
        .iter()
        .enumerate()
        .map(|(i, &k)| {
            (
                k,
                sv.diags
                    .iter()
                    .map(|d| d.fournier_iters[i] as f64)
                    .sum::<f64>()
                    / nd,
            )
        })
        .collect();
    let rule_eps = vec![0.10, 0.05, 0.01];
    let rule_of_thumb = [1.0, 4.0, 16.0, 64.0, 256.0, 1024.0]
        .iter()
        .map(|&e: &f64| RuleOfThumb {
            exponent: e,
            rule: 4.0 * (e + e.sqrt()),
            needed: rule_eps
                .iter()
                .map(|&eps| coefficients_needed(e, eps))
                .collect(),
        })
        .collect();
    Summary {
        maps: maps.to_vec(),
        verdicts: verdicts(maps, &idx, sv, &rows),
        alignment: alignment(maps, &idx, sv),
        rows,
        schilling,
        em,
        fournier_fit_l2,
        fournier_iters,
        olano_north_z_err_max: sv
            .diags
            .iter()
            .map(|d| d.olano_north_z_err)
            .fold(0.0, f64::max),
        vmf_terms_max: sv.diags.iter().map(|d| d.vmf_terms).max().unwrap_or(0),
        rule_of_thumb,
        rule_eps,
    }
}

/// A mean ± s.e. over a subset, "—" when the subset is empty.
fn pm_or_dash(x: (Figure, usize)) -> String {
    if x.1 == 0 {
        "—".into()
    } else {
        x.0.pct(1)
    }
}

/// The Pareto plot: per family, mean relative L2 against parameters per texel (one panel
/// per NDF), the best row of a family at each count, and the front over all of them.
pub(super) fn pareto_svg(s: &Summary) -> Result<String> {
    let panel = |kind: NdfKind| {
        let pick = |r: &RowSummary| {
            if kind == NdfKind::Ggx {
                r.ggx
            } else {
                r.beckmann
            }
        };
        let mut fams: Vec<String> = Vec::new();
        for r in &s.rows {
            if r.params.is_some() && !fams.contains(&r.family) {
                fams.push(r.family.clone());
            }
        }
        let mut series: Vec<Series> = fams
            .iter()
            .map(|f| {
                let mut pts: Vec<(f64, f64)> = Vec::new();
                for r in s.rows.iter().filter(|r| &r.family == f) {
                    let (p, e) = (r.params.unwrap_or(0) as f64, pick(r).l2.value);
                    match pts.iter_mut().find(|q| q.0 == p) {
                        Some(q) => q.1 = q.1.min(e),
                        None => pts.push((p, e)),
                    }
                }
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                Series {
                    name: f.clone(),
                    points: pts,
                }
            })
            .collect();
        let mut all: Vec<(f64, f64)> = series.iter().flat_map(|x| x.points.clone()).collect();
        all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let mut front: Vec<(f64, f64)> = Vec::new();
        for p in all {
            if front.last().is_none_or(|q| p.1 < q.1) {
                front.push(p);
            }
        }
        series.push(Series {
            name: "Pareto front".into(),
            points: front,
        });
        Panel {
            title: format!("{}: error against storage", kind_name(kind)),
            x_label: "parameters per texel".into(),
            y_label: "mean relative L2 lobe error".into(),
            series,
        }
    };
    loglog_svg_legend(
        &[panel(NdfKind::Ggx), panel(NdfKind::Beckmann)],
        1500,
        700,
        plotters::prelude::SeriesLabelPosition::LowerRight,
    )
}

/// results/filters-survey.md.
pub(super) fn markdown(s: &Summary, preset: Preset, cases: usize) -> String {
    let mut md = String::from(
        "# The survey's normal-map pre-filtering families, measured (seed 004 §3.2, §7)\n\n",
    );
    md.push_str(&format!(
        "Written by `cargo run --release -- regen --only filters` (preset {}) from `fits/filters.toml`, with results/filters.md: \
the same {} map cases (footprints at MIP levels, base α, GGX and Beckmann, views), the same light samples and the same truth \
(seed 004 Eq 11: the footprint average of every texel's own lobe). Five maps: the four of results/filters.md and seed 002's \
scratches (which do not enter the filters' fitted constants). Every number is a mean over cases ± its standard error.\n\n",
        preset.name(),
        cases
    ));
    md.push_str(METHOD);
    md.push_str("\n## The generic tools (§7)\n\n");
    let mut t = Table::new(["representation", "tool", "method"]);
    for (n, tool, m) in TOOLS {
        t.row([n.to_string(), format!("{tool:?}"), format!("{m:?}")]);
    }
    md.push_str(&t.to_string());
    md.push_str("\n## Every row: error against storage\n\n");
    md.push_str(&format!("Mean relative L2 error of the lobe over all light directions (± s.e. over cases), parameters per texel, by NDF and by map. \
The first {} rows are results/filters.md's filters on the same samples.\n\n", MAP.len()));
    let mut t = Table::new(
        ["representation", "params", "GGX", "Beckmann"]
            .into_iter()
            .map(String::from)
            .chain(s.maps.iter().map(|m| m.to_string())),
    );
    for r in &s.rows {
        let p = r.params.map_or("all texels".into(), |p| p.to_string());
        t.row(
            [r.name.to_string(), p, r.ggx.l2.pct(1), r.beckmann.l2.pct(1)]
                .into_iter()
                .chain(r.by_map.iter().map(|a| a.l2.pct(1))),
        );
    }
    md.push_str(&t.to_string());
    md.push_str("\n![error against storage](filters-survey.svg)\n\nThe cost per evaluation of each representation (criterion, ns) is in \
results/performance.md (\"Survey representations\"), beside these errors.\n\n");
    md.push_str(&verdict_section(s));
    md.push_str(&diagnostics_section(s));
    md
}

fn verdict_section(s: &Summary) -> String {
    let mut md = String::from("## Verdicts: the best representation within each storage budget, per map\n\n\
The winner is the row with the lowest mean L2 among those with at most that many parameters per texel (the exact distribution excluded); \
the margin is the paired difference runner-up − winner over the map's cases (± s.e.): a margin within 2 s.e. of zero is a tie.\n\n");
    let mut t = Table::new(["map", "budget", "winner", "its L2", "runner-up", "margin"]);
    for v in &s.verdicts {
        let tie = if v.margin.value.abs() < 2.0 * v.margin.error {
            " (tie)"
        } else {
            ""
        };
        t.row([
            v.map.to_string(),
            format!("≤ {}", v.budget),
            format!("{} ({})", v.best, v.best_params),
            v.l2.pct(1),
            v.runner_up.to_string(),
            format!("{}{tie}", v.margin.pct(1)),
        ]);
    }
    md.push_str(&t.to_string());
    md
}

fn diagnostics_section(s: &Summary) -> String {
    let mut md = String::from("\n## Schilling: the cost of MIP-mapping a per-frame covariance linearly\n\n\
The recomputed row evaluates each level's slope covariance in its own mean normal's frame from the base texels; the MIP-mapped row averages \
the four children's matrices (each in its own frame) as if they shared the parent's. Built this way from the base level, every level would \
hold only the base lobe (one texel has no spread), which is the first row of the table above; one level of linear averaging already costs:\n\n");
    let mut t = Table::new(["level", "recomputed", "MIP-mapped", "cost (paired)"]);
    for l in &s.schilling {
        t.row([
            l.level.to_string(),
            l.recomputed.pct(1),
            l.mipped.pct(1),
            l.cost.pct(1),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\n## Lobe alignment and sharp edges (Tan et al., Han et al.)\n\n\
A MIP-mapped parent takes its lobes from its four children, each fitted by EM; the children's lobes are matched to the first child's by the \
permutation with the smallest total distance, and the interpolable quantities are averaged. A matched pair is *misaligned* when its means lie \
farther apart than twice the sum of the two lobes' widths: at a sharp edge (flakes' cell borders, a bump's rim) there is no lobe to match. \
What we do there is what linear filtering does: the average is one wide lobe between the two (the best single Gaussian of the pair), and the \
table shows what that costs against the per-footprint EM fit.\n\n");
    let mut t = Table::new([
        "map",
        "misaligned pairs, Tan 2 / 4 lobes",
        "vMF 2 / 4 lobes",
        "Tan 4: MIP − EM where misaligned (footprints)",
        "where aligned",
    ]);
    for a in &s.alignment {
        t.row([
            a.map.to_string(),
            format!(
                "{:.0} % / {:.0} %",
                100.0 * a.tan_misaligned[0],
                100.0 * a.tan_misaligned[1]
            ),
            format!(
                "{:.0} % / {:.0} %",
                100.0 * a.vmf_misaligned[0],
                100.0 * a.vmf_misaligned[1]
            ),
            format!(
                "{} ({})",
                pm_or_dash(a.tan_cost_misaligned),
                a.tan_cost_misaligned.1
            ),
            format!(
                "{} ({})",
                pm_or_dash(a.tan_cost_aligned),
                a.tan_cost_aligned.1
            ),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\n## Han et al.'s rule of thumb: SH coefficients for a Blinn–Phong exponent\n\n\
The survey quotes about 4(α + √α) coefficients for exponent α. Measured: the smallest (L + 1)² whose truncated series of the normalised lobe \
(α + 1)/(2π) t₊^α has relative L2 error at most ε on the sphere (Parseval over the zonal coefficients, exact up to the quadrature's 1e-9).\n\n");
    let mut t = Table::new(
        ["exponent".to_string(), "4(α + √α)".to_string()]
            .into_iter()
            .chain(
                s.rule_eps
                    .iter()
                    .map(|e| format!("needed at ε = {:.0} %", 100.0 * e)),
            ),
    );
    for r in &s.rule_of_thumb {
        t.row(
            [r.exponent.to_string(), format!("{:.0}", r.rule)]
                .into_iter()
                .chain(
                    r.needed
                        .iter()
                        .map(|n| n.map_or("> 361 201".into(), |n| n.to_string())),
                ),
        );
    }
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\n## Fits and EM\n\n\
- Fournier's least squares (L-BFGS, ≤ 100 iterations, from the vMF EM fit): relative L2 of the fit to the footprint distribution on its 256 \
directions, mean ± s.e. over footprints: {}; mean iterations {}.\n\
- EM over every footprint and child (Tan and vMF): {} iterations; {} empty components re-seeded, {} dropped (fewer distinct texels than lobes), \
{} variances floored (identical slopes), {} concentrations capped at κ = 1e8.\n\
- Olano & North's normalisation on the sphere: worst relative quadrature error {:.1e}.\n\
- The vMF zonal series ran to at most {} terms (each lobe's series stops below 1e-9 of its first term).\n",
        s.fournier_fit_l2
            .iter()
            .map(|(k, m)| format!("{k} lobe{}: {}", if *k == 1 { "" } else { "s" }, m.pct(1)))
            .collect::<Vec<_>>()
            .join(", "),
        s.fournier_iters
            .iter()
            .map(|(k, i)| format!("{i:.0} ({k})"))
            .collect::<Vec<_>>()
            .join(", "),
        s.em.iterations,
        s.em.reseeded,
        s.em.dropped,
        s.em.floored,
        s.em.kappa_capped,
        s.olano_north_z_err_max,
        s.vmf_terms_max
    ));
    md
}

const METHOD: &str = "## Method\n\n\
- Every representation reconstructs the footprint's distribution of microfacet normals q_A(η) = Σ ŵ_x D_x(η)(η·n_x)₊ (seed 004 Eq 13: \
each texel's base lobe about its own normal) from the numbers it stores, and is shaded by one rule, the separable form of Eq 12: \
ρ(l, v)(n·l) ≈ max(q̂_A(h), 0) G2(l, v)/(4 v·h), G2 the height-correlated Smith term of the isotropic lobe around the mean normal with the \
vMF 2/κ roughness. The exact q_A under the same rule (first survey row) is the floor: what is left is the error of Eq 12 itself.\n\
- **Single lobe** (`survey::single`): Schilling's slope covariance about the mean normal (recomputed per level, and MIP-mapped linearly); \
Olano & North's 3D Gaussian of η (Eq 17, the texels' first and second moments averaged, normalised on the sphere); Neyret's ellipsoid as SGGX \
(Eq 18, S = Σ ŵ(α²I + (1 − α²)nnᵀ), each texel's S exactly its GGX lobe); Olano & Baker's Gaussian of slopes (Eq 19 as printed: a Gaussian, \
the base lobe's α²/2 added — next to LEAN, which uses the case's NDF with the same moments).\n\
- **Multiple lobes**: Fournier's Blinn–Phong sums (Eq 20) by L-BFGS on the L2 distance to q_A, 1–7 lobes (`survey::fournier`); Tan et al.'s \
isotropic slope Gaussians (Eq 21) and Han et al.'s vMF lobes (Eq 22) by EM, per footprint and MIP-mapped from four children by aligned lobes \
(`survey::em`); Han et al.'s spherical harmonics of the macroscopic NDF times the base lobe's zonal coefficients (degree 3, 7, 15; they average \
linearly, so MIP-mapping them is exact), and their vMF lobes convolved by the survey's zonal form Σ_l (2l+1)/(4π) k̂_l e^{−l²/(2κ)} P_l (`survey::sh`).\n\
- Parameters per texel count what a texture stores: a lobe's weight, direction (2) and width; mixtures' weights sum to 1; SH drops p_00.\n";

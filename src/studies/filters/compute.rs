//! The footprint study's computation: the cases ([`super::cases`]), the fitted
//! constants ([`super::constants`]), the survey, and every aggregate the report shows —
//! per map and per kernel tables, the curves of the plots, the clamp table and the
//! verdicts' figures. The report formats these and computes nothing.

use super::cases::{self, aggregate, Agg, MapCase, ScreenCase};
use super::constants::{self, Fitted};
use super::plan::{kind_name, Plan, KINDS};
use super::{summary, survey, survey_report, verdicts};
use crate::error::Result;
use crate::filters::footprint::{NormalMap, Procedural, Stats};
use crate::filters::registry::{screen_index, MAP, SCREEN};
use crate::filters::study::PixelFilter;
use crate::filters::truth::CaseResult;
use crate::fit::spec::FitSpec;
use crate::integrate::{Figure, Preset};
use crate::microfacet::NdfKind;
use crate::results::filters::{FilterRow, FilterSummary, MapRows, NdfAgg, ScreenRow};
use std::collections::BTreeMap;
use std::path::Path;

/// One row of a filter table: the filter's label and its aggregate per NDF ([`KINDS`]).
pub(super) struct Row {
    pub label: &'static str,
    pub by_ndf: Vec<Agg>,
}

/// One of the largest single-case energy errors of a map.
pub(super) struct Worst {
    pub filter: &'static str,
    pub kind: NdfKind,
    pub alpha: f64,
    pub level: usize,
    pub stats: Stats,
    pub view: usize,
    pub energy: Figure,
    pub l2: Figure,
}

/// A curve of a plot: the series' name and its points.
pub(super) type Curve = (&'static str, Vec<(f64, f64)>);

/// One map's section.
pub(super) struct MapSection {
    pub name: String,
    pub rows: Vec<Row>,
    /// The four largest energy errors.
    pub worst: Vec<Worst>,
    /// The largest single-case MC s.e. of an L2 error on the map.
    pub mc_se_max: f64,
    /// L2 error against footprint width per filter (GGX).
    pub curves: Vec<Curve>,
}

/// The clamp table's columns: (registry key, header).
pub(super) const CLAMP_COLUMNS: [(&str, &str); 7] = [
    ("none", "none"),
    ("tokuyoshi-deferred", "Eq 13 (δ 0.18)"),
    ("eq13-unclamped", "Eq 13 unclamped"),
    ("eigen-eq10", "Eq 10"),
    ("eq10-unclamped", "Eq 10 unclamped"),
    ("godot", "Godot (on α)"),
    ("filament", "Filament"),
];

/// The screen-space section.
pub(super) struct ScreenSection {
    /// Per pixel footprint, the kernels' rows.
    pub tables: Vec<(PixelFilter, Vec<Row>)>,
    /// L2 error against κ per kernel (GGX, Gaussian pixel).
    pub curves: Vec<Curve>,
    /// Per κ, the clamp table's aggregates in [`CLAMP_COLUMNS`] order.
    pub clamp: Vec<(f64, Vec<Agg>)>,
}

/// Everything the footprint study computed.
pub struct Computed {
    pub(super) spec: FitSpec,
    pub(super) preset: Preset,
    pub(super) plan: Plan,
    pub(super) maps: Vec<MapSection>,
    pub(super) screen: ScreenSection,
    pub(super) fits: Vec<Fitted>,
    pub(super) verdicts: verdicts::Verdicts,
    pub(super) per_filter: BTreeMap<String, FilterSummary>,
    pub(super) by_level: Vec<crate::results::filters::LevelRow>,
    pub(super) survey: crate::results::filters::Summary,
    /// Map cases of the filters' maps, of all maps (the survey's scratches included),
    /// and screen cases.
    pub(super) counts: (usize, usize, usize),
    /// The LEADR and Λ reports, as results/filters.md embeds them.
    pub(super) embedded: Vec<(&'static str, &'static str, String)>,
}

fn rows(
    labels: impl Iterator<Item = &'static str>,
    agg: impl Fn(usize, NdfKind) -> Agg,
) -> Vec<Row> {
    labels
        .enumerate()
        .map(|(fi, label)| Row {
            label,
            by_ndf: KINDS.iter().map(|&k| agg(fi, k)).collect(),
        })
        .collect()
}

pub(super) fn map_section(
    m: usize,
    map: &NormalMap,
    map_cases: &[MapCase],
    plan: &Plan,
) -> MapSection {
    let of_map = || map_cases.iter().filter(move |c| c.map == m);
    let agg = |pick: &dyn Fn(&MapCase) -> bool, fi: usize| {
        let rs: Vec<&CaseResult> = of_map()
            .filter(|c| pick(c))
            .map(|c| &c.results[fi])
            .collect();
        aggregate(&rs)
    };
    let rows = rows(MAP.iter().map(|f| f.label), |fi, kind| {
        agg(&|c| c.kind == kind, fi)
    });
    let mc_se_max = of_map()
        .flat_map(|c| c.results.iter().map(|r| r.l2.error))
        .filter(|x| x.is_finite())
        .fold(0.0, f64::max);
    let mut worst: Vec<(f64, &MapCase, usize)> = of_map()
        .flat_map(|c| (0..MAP.len()).map(move |fi| (c.results[fi].energy.value.abs(), c, fi)))
        .filter(|w| w.0.is_finite())
        .collect();
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    let worst = worst
        .iter()
        .take(4)
        .map(|(_, c, fi)| Worst {
            filter: MAP[*fi].label,
            kind: c.kind,
            alpha: c.alpha,
            level: c.level,
            stats: c.stats,
            view: c.view,
            energy: c.results[*fi].energy,
            l2: c.results[*fi].l2,
        })
        .collect();
    let curves = MAP
        .iter()
        .enumerate()
        .map(|(fi, f)| {
            let points = plan
                .levels
                .iter()
                .map(|&lv| {
                    let a = agg(&|c| c.kind == NdfKind::Ggx && c.level == lv, fi);
                    ((1usize << lv) as f64, a.l2.value.max(1e-6))
                })
                .collect();
            (f.label, points)
        })
        .collect();
    MapSection {
        name: map.name.clone(),
        rows,
        worst,
        mc_se_max,
        curves,
    }
}

fn screen_section(plan: &Plan, screen: &[ScreenCase]) -> ScreenSection {
    let agg = |pick: &dyn Fn(&ScreenCase) -> bool, fi: usize| {
        let rs: Vec<&CaseResult> = screen
            .iter()
            .filter(|c| pick(c))
            .map(|c| &c.results[fi])
            .collect();
        aggregate(&rs)
    };
    let tables = [PixelFilter::Gaussian, PixelFilter::Box]
        .into_iter()
        .map(|pixel| {
            let rows = rows(SCREEN.iter().map(|f| f.label), |fi, kind| {
                agg(&|c| c.kind == kind && c.pixel == pixel, fi)
            });
            (pixel, rows)
        })
        .collect();
    let mut kappas: Vec<f64> = plan.screen_pairs.iter().map(|p| p.1).collect();
    kappas.sort_by(f64::total_cmp);
    kappas.dedup();
    let at = |k: f64, fi: usize| {
        agg(
            &|c| c.kind == NdfKind::Ggx && c.pixel == PixelFilter::Gaussian && c.field.kappa_u == k,
            fi,
        )
    };
    let curves = SCREEN
        .iter()
        .enumerate()
        .map(|(fi, f)| {
            let points = kappas
                .iter()
                .map(|&k| (k, at(k, fi).l2.value.max(1e-6)))
                .collect();
            (f.label, points)
        })
        .collect();
    let clamp = kappas
        .iter()
        .map(|&k| {
            let cells = CLAMP_COLUMNS
                .iter()
                .map(|c| at(k, screen_index(c.0)))
                .collect();
            (k, cells)
        })
        .collect();
    ScreenSection {
        tables,
        curves,
        clamp,
    }
}

/// The LEADR and Λ reports that results/filters.md embeds, read from `results`
/// (absent ones are left out).
fn embedded(results: &Path) -> Vec<(&'static str, &'static str, String)> {
    [
        ("leadr-grids.md", "LEADR numerical integration"),
        ("smith-lambda.md", "Smith Λ approximations"),
    ]
    .into_iter()
    .filter_map(|(file, title)| {
        std::fs::read_to_string(results.join(file))
            .ok()
            .map(|t| (file, title, t))
    })
    .collect()
}

/// The study: compute the cases, the fitted constants and every aggregate.
pub fn compute(c: &crate::study::Ctx) -> Result<Computed> {
    let (spec, results, preset) = (c.spec, c.results, c.preset);
    let plan: Plan = c.params()?;
    let seed = spec.seed;
    // the filters' four maps, then seed 002's scratches for the survey only: its cases come
    // last, so the filters' cases keep their indices (and seeds) bit for bit
    let mut all_maps: Vec<NormalMap> = Procedural::ALL
        .iter()
        .map(|&k| NormalMap::procedural(k, plan.map_size, seed + 1))
        .collect::<Result<_>>()?;
    all_maps.push(NormalMap::procedural(
        Procedural::Scratches,
        plan.map_size,
        seed + 1,
    )?);
    let mut map_cases = cases::map_study(&all_maps, &plan, seed)?;
    let views = plan.views_deg.len();
    let survey_cases = survey::survey_study(&all_maps, &map_cases, views, seed)?;
    let first_extra = map_cases
        .iter()
        .position(|c| c.map >= Procedural::ALL.len())
        .unwrap_or(map_cases.len());
    let extra_cases = map_cases.split_off(first_extra);
    let maps = &all_maps[..Procedural::ALL.len()];
    let survey = {
        let names: Vec<String> = all_maps.iter().map(|m| m.name.clone()).collect();
        let all: Vec<&MapCase> = map_cases.iter().chain(&extra_cases).collect();
        survey_report::summarise(&names, &all, &survey_cases)
    };
    let screen_cases = cases::screen_study(&plan, seed)?;
    let fits = constants::fit_constants(&map_cases, &screen_cases);
    let sections = maps
        .iter()
        .enumerate()
        .map(|(m, map)| map_section(m, map, &map_cases, &plan))
        .collect();
    Ok(Computed {
        spec: spec.clone(),
        preset,
        maps: sections,
        screen: screen_section(&plan, &screen_cases),
        verdicts: verdicts::measure(&map_cases, &screen_cases, &fits),
        per_filter: summary::per_filter(&map_cases, &screen_cases),
        by_level: summary::by_level(&map_cases, &plan, maps.len()),
        survey,
        counts: (
            map_cases.len(),
            map_cases.len() + extra_cases.len(),
            screen_cases.len(),
        ),
        embedded: embedded(results),
        fits,
        plan,
    })
}

impl MapSection {
    /// A map's table as the result file holds it.
    pub(super) fn rows(&self) -> MapRows {
        MapRows {
            map: self.name.clone(),
            filters: self
                .rows
                .iter()
                .map(|r| FilterRow {
                    filter: r.label.into(),
                    by_ndf: KINDS
                        .iter()
                        .zip(&r.by_ndf)
                        .map(|(&kind, a)| NdfAgg {
                            ndf: kind_name(kind).into(),
                            all: *a,
                        })
                        .collect(),
                })
                .collect(),
        }
    }
}

impl ScreenSection {
    /// The screen-space tables as the result file holds them.
    pub(super) fn rows(&self) -> Vec<ScreenRow> {
        let mut out = Vec::new();
        for (pixel, rows) in &self.tables {
            for r in rows {
                for (&kind, a) in KINDS.iter().zip(&r.by_ndf) {
                    out.push(ScreenRow {
                        pixel: format!("{pixel:?}"),
                        ndf: kind_name(kind).into(),
                        kernel: r.label.into(),
                        all: *a,
                    });
                }
            }
        }
        out
    }
}

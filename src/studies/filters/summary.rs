//! The machine-readable summaries of the footprint study in results/fits/filters.json:
//! per filter (read by the speed/accuracy table of results/performance.md) and per level.

use super::cases::{aggregate, MapCase, ScreenCase};
use super::plan::{kind_name, Plan, KINDS};
use crate::filters::registry::{MAP, SCREEN};
use crate::filters::study::PixelFilter;
use crate::filters::truth::CaseResult;
use crate::microfacet::NdfKind;
use crate::results::filters::{FilterSummary, LevelRow};
use std::collections::BTreeMap;

/// One summary entry: mean L2 ± s.e. of `rs` under `id` (GGX) or `beckmann:id`.
fn insert(
    summary: &mut BTreeMap<String, FilterSummary>,
    id: &str,
    kind: NdfKind,
    name: &str,
    rs: &[&CaseResult],
    study: &str,
) {
    let a = aggregate(rs);
    let key = if kind == NdfKind::Ggx {
        id.to_string()
    } else {
        format!("beckmann:{id}")
    };
    summary.insert(
        key,
        FilterSummary {
            name: name.into(),
            l2: a.l2,
            study: study.into(),
        },
    );
}

/// Per filter (GGX unprefixed, Beckmann as `beckmann:<id>`): mean L2 ± s.e. over the
/// map cases (map filters) or the Gaussian-pixel screen cases (kernels).
pub(super) fn per_filter(
    map_cases: &[MapCase],
    screen_cases: &[ScreenCase],
) -> BTreeMap<String, FilterSummary> {
    let mut summary = BTreeMap::new();
    // the filters the registry gives a summary id, at their place in the study's lists
    for (fi, f) in MAP.iter().enumerate() {
        let Some(id) = f.uses.summary else { continue };
        for kind in KINDS {
            let rs: Vec<&CaseResult> = map_cases
                .iter()
                .filter(|c| c.kind == kind)
                .map(|c| &c.results[fi])
                .collect();
            insert(&mut summary, id, kind, f.label, &rs, "maps");
        }
    }
    for (fi, f) in SCREEN.iter().enumerate() {
        let Some(id) = f.uses.summary else { continue };
        for kind in KINDS {
            let rs: Vec<&CaseResult> = screen_cases
                .iter()
                .filter(|c| c.kind == kind && c.pixel == PixelFilter::Gaussian)
                .map(|c| &c.results[fi])
                .collect();
            insert(
                &mut summary,
                id,
                kind,
                f.label,
                &rs,
                "screen (Gaussian pixel)",
            );
        }
    }
    summary
}

/// Per (level, map, NDF, map filter): L2 and energy, mean ± s.e.
pub(super) fn by_level(map_cases: &[MapCase], plan: &Plan, maps: usize) -> Vec<LevelRow> {
    let mut out = Vec::new();
    for &level in &plan.levels {
        for map in 0..maps {
            for &kind in &KINDS {
                for filter in 0..MAP.len() {
                    let rs: Vec<&CaseResult> = map_cases
                        .iter()
                        .filter(|c| c.map == map && c.kind == kind && c.level == level)
                        .map(|c| &c.results[filter])
                        .collect();
                    let a = aggregate(&rs);
                    out.push(LevelRow {
                        level,
                        map,
                        ndf: kind_name(kind).into(),
                        filter,
                        l2: a.l2,
                        energy: a.energy,
                    });
                }
            }
        }
    }
    out
}

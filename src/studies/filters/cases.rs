//! The cases of the footprint study: every (map, NDF, α, level, footprint, view) and
//! every screen-space (NDF, pixel, α, κ, anisotropy, view), drawn and measured; their
//! aggregation into mean ± standard error.

use super::plan::{dir, seed_of, Plan, KINDS};
use crate::error::Result;
use crate::filters::footprint::{MipChain, NormalMap, Stats};
use crate::filters::study::{self, Field, PixelFilter};
use crate::filters::truth::{draw, CaseResult, CaseSamples, Truth};
use crate::microfacet::NdfKind;
use nalgebra::Vector3;
use rayon::prelude::*;

type V3 = Vector3<f64>;

/// One map case: a footprint at a level, a base α, a view, with its drawn samples.
pub(super) struct MapCase {
    pub map: usize,
    pub kind: NdfKind,
    pub alpha: f64,
    pub level: usize,
    pub footprint: usize,
    /// The footprint's texel index at its level (row-major).
    pub idx: usize,
    pub view: usize,
    pub stats: Stats,
    pub samples: CaseSamples,
    pub results: Vec<CaseResult>,
}

/// One screen case.
pub(super) struct ScreenCase {
    pub kind: NdfKind,
    pub pixel: PixelFilter,
    pub alpha: f64,
    pub field: Field,
    pub view: usize,
    pub samples: CaseSamples,
    pub results: Vec<CaseResult>,
}

use crate::integrate::Figure;
pub use crate::results::filters::Agg;

pub fn aggregate(rs: &[&CaseResult]) -> Agg {
    let e: Vec<f64> = rs.iter().map(|r| r.energy.value).collect();
    let ea: Vec<f64> = e.iter().map(|x| x.abs()).collect();
    let l: Vec<f64> = rs.iter().map(|r| r.l2.value).collect();
    let p: Vec<f64> = rs.iter().map(|r| r.peak).collect();
    Agg {
        cases: rs.len(),
        energy: Figure::mean_of_finite(&e),
        energy_abs_mean: Figure::mean_of_finite(&ea).value,
        l2: Figure::mean_of_finite(&l),
        l2_max: l
            .iter()
            .copied()
            .filter(|x| x.is_finite())
            .fold(0.0, f64::max),
        peak: Figure::mean_of_finite(&p),
        l2_mc_se_max: rs
            .iter()
            .map(|r| r.l2.error)
            .filter(|x| x.is_finite())
            .fold(0.0, f64::max),
    }
}

/// Every (map, NDF, α, level, footprint, view) case of the map study, with its samples
/// and the measured filters.
pub(super) fn map_study(maps: &[NormalMap], plan: &Plan, seed: u64) -> Result<Vec<MapCase>> {
    let chains: Vec<MipChain> = maps.iter().map(MipChain::build).collect();
    let mut descs = Vec::new();
    for m in 0..maps.len() {
        for &kind in &KINDS {
            for &alpha in &plan.alphas {
                for &level in &plan.levels {
                    let lv = &chains[m].levels[level];
                    for fp in 0..plan.footprints_per_level {
                        // spread the footprints over the level deterministically
                        let idx = (fp * 2654435761usize + 12345) % (lv.width * lv.height);
                        for (vi, _) in plan.views_deg.iter().enumerate() {
                            descs.push((m, kind, alpha, level, idx, fp, vi));
                        }
                    }
                }
            }
        }
    }
    let pb = crate::progress::Progress::new("filters: map footprints", descs.len() as u64);
    let map_cases: Vec<MapCase> = descs
        .par_iter()
        .enumerate()
        .map(
            |(ci, &(m, kind, alpha, level, idx, fp, vi))| -> Result<MapCase> {
                let lv = &chains[m].levels[level];
                let (i, j) = (idx % lv.width, idx / lv.width);
                let stats = lv.stats[idx];
                let fpn = crate::filters::truth::Footprint::uniform(maps[m].block(level, i, j));
                let truth = Truth::new(kind, alpha, &fpn)?;
                let (t, p) = plan.views_deg[vi];
                let v = dir(t, p);
                let cands = study::map_candidates(kind, alpha, &stats)?;
                let props: Vec<(V3, f64)> = cands
                    .iter()
                    .zip(&crate::filters::registry::MAP)
                    .filter(|(_, f)| f.proposes)
                    .map(|(c, _)| c.proposal)
                    .collect();
                let samples = draw(&truth, &v, &props, plan.samples, seed_of(seed, ci))?;
                let results = cands
                    .iter()
                    .map(|c| samples.measure(&*c.value, &c.proposal.0))
                    .collect();
                pb.inc(1);
                Ok(MapCase {
                    map: m,
                    kind,
                    alpha,
                    level,
                    footprint: fp,
                    idx,
                    view: vi,
                    stats,
                    samples,
                    results,
                })
            },
        )
        .collect::<Result<_>>()?;
    pb.finish();
    crate::report::stage("regen filters: map footprints done");
    Ok(map_cases)
}

/// Every screen-space case, with its samples and the measured kernels.
pub(super) fn screen_study(plan: &Plan, seed: u64) -> Result<Vec<ScreenCase>> {
    let mut sdesc = Vec::new();
    for &kind in &KINDS {
        for pixel in [PixelFilter::Gaussian, PixelFilter::Box] {
            for &(alpha, kap) in &plan.screen_pairs {
                for &an in &plan.anisotropy {
                    for vi in 0..plan.screen_views_deg.len() {
                        sdesc.push((kind, pixel, alpha, kap, an, vi));
                    }
                }
            }
        }
    }
    let pb = crate::progress::Progress::new("filters: screen-space kernels", sdesc.len() as u64);
    let screen_cases: Vec<ScreenCase> = sdesc
        .par_iter()
        .enumerate()
        .map(
            |(ci, &(kind, pixel, alpha, kap, an, vi))| -> Result<ScreenCase> {
                let field = Field {
                    kappa_u: kap,
                    kappa_v: kap * an,
                    psi: 30f64.to_radians(),
                };
                let fpn = study::pixel_footprint(&field, pixel, alpha);
                let truth = Truth::new(kind, alpha, &fpn)?;
                let v = dir(plan.screen_views_deg[vi], 20.0);
                let cands = study::screen_candidates(kind, alpha, &field)?;
                let props: Vec<(V3, f64)> = cands.iter().map(|c| c.proposal).collect();
                let samples = draw(&truth, &v, &props, plan.samples, seed_of(seed ^ 0x5C, ci))?;
                let results = cands
                    .iter()
                    .map(|c| samples.measure(&*c.value, &c.proposal.0))
                    .collect();
                pb.inc(1);
                Ok(ScreenCase {
                    kind,
                    pixel,
                    alpha,
                    field,
                    view: vi,
                    samples,
                    results,
                })
            },
        )
        .collect::<Result<_>>()?;
    pb.finish();
    crate::report::stage("regen filters: screen-space kernels done");

    Ok(screen_cases)
}

//! The fitted constants of the footprint study: one constant per rule family (vMF c,
//! Toksvig c, the screen kernels' σ²), by argmin scan + Brent on the mean L2 error of
//! the training cases (even footprints / views), judged on the held-out rest.

use super::cases::{aggregate, Agg, MapCase, ScreenCase};
use super::plan::KINDS;
use crate::filters::rules;
use crate::filters::study::PixelFilter;
use crate::filters::truth::{Candidate, CaseResult};
use crate::microfacet::NdfKind;
use nalgebra::Vector3;
use rayon::prelude::*;

type V3 = Vector3<f64>;

/// One fitted constant with its training error and its held-out aggregate.
pub(super) struct Fitted {
    pub family: &'static str,
    pub kind: NdfKind,
    pub constant: f64,
    pub train_mean_l2: f64,
    pub held_out: Agg,
    /// The held-out cases' L2 errors, in case order (for paired comparisons).
    pub held_out_l2: Vec<f64>,
}

impl Fitted {
    fn new(family: &'static str, kind: NdfKind, f: (f64, f64, Agg, Vec<f64>)) -> Fitted {
        Fitted {
            family,
            kind,
            constant: f.0,
            train_mean_l2: f.1,
            held_out: f.2,
            held_out_l2: f.3,
        }
    }
}

/// Fit one constant c of a family α′(c) by scan + Brent on the mean L2 error over the
/// training cases; returns (c, train mean L2, held-out Agg).
fn fit_constant<C: Sync>(
    cases: &[C],
    train: &(dyn Fn(usize) -> bool + Sync),
    lobe_l2: &(dyn Fn(&C, f64) -> CaseResult + Sync),
    grid: &[f64],
) -> (f64, f64, Agg, Vec<f64>) {
    let obj = |c: f64| {
        let v: Vec<f64> = cases
            .par_iter()
            .enumerate()
            .filter(|(i, _)| train(*i))
            .map(|(_, k)| lobe_l2(k, c).l2.value)
            .collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    let c = crate::optimize::scan_brent(&obj, grid, (1e-6, 1e-8), 60);
    let held: Vec<CaseResult> = cases
        .par_iter()
        .enumerate()
        .filter(|(i, _)| !train(*i))
        .map(|(_, k)| lobe_l2(k, c))
        .collect();
    let l2: Vec<f64> = held.iter().map(|r| r.l2.value).collect();
    (c, obj(c), aggregate(&held.iter().collect::<Vec<_>>()), l2)
}

/// Every fitted constant, per NDF: the map families, then per pixel filter the kernels.
pub(super) fn fit_constants(map_cases: &[MapCase], screen_cases: &[ScreenCase]) -> Vec<Fitted> {
    let mut fits = Vec::new();
    for &kind in &KINDS {
        let cases: Vec<&MapCase> = map_cases.iter().filter(|c| c.kind == kind).collect();
        let iso = |c: &&MapCase, a: f64| -> CaseResult {
            let mu = V3::from(c.stats.mean_normal);
            let nbar = mu / mu.norm();
            match Candidate::iso("", kind, nbar, a.max(1e-4)) {
                Ok(cd) => c.samples.measure(&*cd.value, &nbar),
                Err(_) => c.samples.measure(&|_, _| f64::NAN, &nbar),
            }
        };
        let grid: Vec<f64> = (0..=20)
            .map(|i| 0.05 * 2f64.powf(i as f64 * 0.35))
            .collect();
        let train = |i: usize| cases[i].footprint % 2 == 0;
        let (c, tr, ho, hl) = fit_constant(
            &cases,
            &train,
            &|c, k| {
                let r = V3::from(c.stats.mean_normal).norm().min(1.0);
                iso(c, rules::vmf(c.alpha, r, k))
            },
            &grid,
        );
        fits.push(Fitted::new("vMF α² + c/κ", kind, (c, tr, ho, hl)));
        let (c, tr, ho, hl) = fit_constant(
            &cases,
            &train,
            &|c, k| {
                let r = V3::from(c.stats.mean_normal).norm().min(1.0);
                iso(c, rules::toksvig_alpha2(c.alpha, r, k))
            },
            &grid,
        );
        fits.push(Fitted::new("Toksvig α² + c·σ²", kind, (c, tr, ho, hl)));
        for pixel in [PixelFilter::Gaussian, PixelFilter::Box] {
            let sc: Vec<&ScreenCase> = screen_cases
                .iter()
                .filter(|c| c.kind == kind && c.pixel == pixel)
                .collect();
            let strain = |i: usize| sc[i].view % 2 == 0;
            let sgrid: Vec<f64> = (0..=30).map(|i| 0.01 * 2f64.powf(i as f64 * 0.3)).collect();
            let lobe = |c: &&ScreenCase, a: f64| -> CaseResult {
                let n0 = c.field.normal(0.0, 0.0);
                match Candidate::iso("", kind, n0, a.max(1e-4)) {
                    Ok(cd) => c.samples.measure(&*cd.value, &n0),
                    Err(_) => c.samples.measure(&|_, _| f64::NAN, &n0),
                }
            };
            // the screen-space kernel added to α² (Eq 13) and to α (Godot), each with its
            // own fitted σ²
            type Rule = fn(f64, [f64; 3], [f64; 3], f64, f64) -> f64;
            let gaussian = pixel == PixelFilter::Gaussian;
            let families: [(Rule, &'static str); 2] = [
                (
                    rules::deferred::<f64>,
                    if gaussian {
                        "Eq 13 σ² (Gaussian pixel)"
                    } else {
                        "Eq 13 σ² (box pixel)"
                    },
                ),
                (
                    rules::deferred_on_alpha::<f64>,
                    if gaussian {
                        "kernel on α σ² (Gaussian pixel)"
                    } else {
                        "kernel on α σ² (box pixel)"
                    },
                ),
            ];
            for (rule, family) in families {
                let fitted = fit_constant(
                    &sc,
                    &strain,
                    &|c, s2| {
                        let (du, dv) = (
                            c.field.normal(1.0, 0.0) - c.field.normal(0.0, 0.0),
                            c.field.normal(0.0, 1.0) - c.field.normal(0.0, 0.0),
                        );
                        lobe(
                            c,
                            rule(c.alpha, [du.x, du.y, du.z], [dv.x, dv.y, dv.z], s2, 0.18),
                        )
                    },
                    &sgrid,
                );
                fits.push(Fitted::new(family, kind, fitted));
            }
        }
    }

    fits
}

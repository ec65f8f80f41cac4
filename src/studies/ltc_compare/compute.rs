//! The comparison's computation: every table an engine may hold, judged at every cell and
//! square centre, and the summary of ours against the shipped.

use crate::error::Result;
use crate::integrate::{Figure, Quad};
use crate::ltc::compare::{alpha_theta, cell_error_of, square_entries, Shipped};
use crate::ltc::lobe_error::{LobeError, Spread};
use crate::ltc::target::{GgxTarget, LtcTarget};
use crate::ltc::upload;
use crate::results::compare::Summary;

pub use crate::results::compare::{Form, Pair};

/// The entries every table holds at one place (cell or square centre): the same place in
/// every table, `None` where a table leaves it out.
pub(super) fn entries_at(t: &Shipped, square: bool, i: usize, j: usize) -> Option<([f64; 4], f64)> {
    if square {
        square_entries(t, i, j)
    } else {
        let k = i + t.n * j;
        let e = (t.mat[k], t.mag[k][0]);
        (e.0.iter().all(|v| v.is_finite()) && e.1.is_finite()).then_some(e)
    }
}

/// The tables an engine may hold, in the order of [`TABLES`].
pub(super) struct Tables {
    pub(super) ours_f32: Shipped,
    pub(super) ours_f16: Shipped,
    pub(super) three_f32: Shipped,
    pub(super) three_f16: Shipped,
    pub(super) bevy: Option<Shipped>,
}

/// The held-out figures of every table at a place, and the earlier sampled estimate.
pub(super) type Judged = ([Option<LobeError>; 5], [f64; 5]);

/// Every place of every table, judged in one cubature per place.
pub(super) fn judge_places(tables: &Tables, square: bool) -> Result<Vec<Judged>> {
    let n = tables.ours_f32.n;
    let w = if square { n - 1 } else { n };
    let off = if square { 0.5 } else { 0.0 };
    let list: [Option<&Shipped>; 5] = [
        Some(&tables.ours_f32),
        Some(&tables.ours_f16),
        Some(&tables.three_f32),
        Some(&tables.three_f16),
        tables.bevy.as_ref(),
    ];
    let label = format!(
        "ltc-compare {} {n}²",
        if square { "squares" } else { "cells" }
    );
    crate::memo::map(&label, w * w, |k| {
        let (i, j) = (k % w, k / w);
        let r = (i as f64 + off) / (n - 1) as f64;
        let (alpha, theta) = alpha_theta(r, (j as f64 + off) / (n - 1) as f64);
        let t = GgxTarget::new(alpha, theta)?;
        let (albedo, _, _) = t.albedo(1e-8);
        // three.js never reads below its roughness clamp
        let reachable = |q: usize| q < 2 || q == 4 || r >= upload::THREE_MIN_ROUGHNESS;
        let places: Vec<(usize, ([f64; 4], f64))> = list
            .iter()
            .enumerate()
            .filter(|(q, _)| reachable(*q))
            .filter_map(|(q, t)| t.and_then(|t| entries_at(t, square, i, j)).map(|e| (q, e)))
            .collect();
        let e = cell_error_of(
            &t,
            albedo,
            &places.iter().map(|(_, e)| *e).collect::<Vec<_>>(),
            crate::ltc::lobe_error::Tolerance::default(),
        );
        let mut out = [None; 5];
        let mut sampled = [f64::NAN; 5];
        for ((q, entries), e) in places.iter().zip(e) {
            out[*q] = e;
            sampled[*q] =
                crate::ltc::fit::production_metrics(&t, &entries.0, entries.1, SAMPLED_SIDE, 0.25)
                    .map_or(f64::NAN, |m| m.1);
        }
        Ok((out, sampled))
    })
}

/// Every cell and square of both tables in each engine's upload.
pub(super) fn compare_all(tables: &Tables) -> Result<Vec<Form>> {
    crate::report::stage("ltc-compare: cells");
    let cells = judge_places(tables, false)?;
    crate::report::stage("ltc-compare: squares");
    let squares = judge_places(tables, true)?;
    let n = tables.ours_f32.n;
    let pick = |v: &[Judged], ours: usize, theirs: usize, r_min: f64, w: usize, off: f64| {
        v.iter()
            .enumerate()
            .map(|(k, (e, sm))| {
                let r = ((k % w) as f64 + off) / (n - 1) as f64;
                if r < r_min {
                    Pair {
                        ours: None,
                        shipped: None,
                        ours_sampled: f64::NAN,
                        shipped_sampled: f64::NAN,
                    }
                } else {
                    Pair {
                        ours: e[ours],
                        shipped: e[theirs],
                        ours_sampled: sm[ours],
                        shipped_sampled: sm[theirs],
                    }
                }
            })
            .collect::<Vec<_>>()
    };
    let mut forms = vec![
        Form {
            name: "three.js FloatType".into(),
            holds: "ours: our table in f32 (ltc_ggx.js); shipped: LTC_MAT_1/2 as Float32Array".into(),
            r_min: upload::THREE_MIN_ROUGHNESS,
            cells: pick(&cells, 0, 2, upload::THREE_MIN_ROUGHNESS, n, 0.0),
            squares: pick(&squares, 0, 2, upload::THREE_MIN_ROUGHNESS, n - 1, 0.5),
        },
        Form {
            name: "three.js HalfFloatType".into(),
            holds: "ours: our stored binary16 table (ltc_ggx_*_f16.bin); shipped: DataUtils.toHalfFloat of LTC_MAT_1/2 (truncated)".into(),
            r_min: upload::THREE_MIN_ROUGHNESS,
            cells: pick(&cells, 1, 3, upload::THREE_MIN_ROUGHNESS, n, 0.0),
            squares: pick(&squares, 1, 3, upload::THREE_MIN_ROUGHNESS, n - 1, 0.5),
        },
    ];
    if tables.bevy.is_some() {
        forms.push(Form {
            name: "Bevy ltc.ktx2".into(),
            holds: "ours: our stored binary16 table (ltc_ggx.ktx2); shipped: bevy_pbr's embedded ltc.ktx2 (RGBA16F, zstd)".into(),
            r_min: 0.0,
            cells: pick(&cells, 1, 4, 0.0, n, 0.0),
            squares: pick(&squares, 1, 4, 0.0, n - 1, 0.5),
        });
    }
    Ok(forms)
}

pub(super) fn worse(a: &Figure<Quad>, b: &Figure<Quad>) -> bool {
    a.value - a.error > b.value + b.error
}

pub fn summarise<'a>(v: impl Iterator<Item = &'a Pair>) -> Summary {
    let pairs: Vec<&Pair> = v
        .filter(|p| p.ours.is_some() && p.shipped.is_some())
        .collect();
    let both: Vec<(&LobeError, &LobeError)> = pairs
        .iter()
        .filter_map(|p| Some((p.ours.as_ref()?, p.shipped.as_ref()?)))
        .collect();
    let sampled: Vec<(f64, f64)> = pairs
        .iter()
        .map(|p| (p.ours_sampled, p.shipped_sampled))
        .filter(|x| x.0.is_finite() && x.1.is_finite())
        .collect();
    let ms = sampled.len().max(1) as f64;
    Summary {
        count: both.len(),
        ours_l2: Spread::of(both.iter().map(|p| Some(&p.0.l2))),
        shipped_l2: Spread::of(both.iter().map(|p| Some(&p.1.l2))),
        ours_l1: Spread::of(both.iter().map(|p| Some(&p.0.l1))),
        shipped_l1: Spread::of(both.iter().map(|p| Some(&p.1.l1))),
        ours_better: both.iter().filter(|p| worse(&p.1.l2, &p.0.l2)).count(),
        ours_worse: both.iter().filter(|p| worse(&p.0.l2, &p.1.l2)).count(),
        sampled_ours_mean: sampled.iter().map(|x| x.0).sum::<f64>() / ms,
        sampled_shipped_mean: sampled.iter().map(|x| x.1).sum::<f64>() / ms,
        sampled_no_worse: sampled.iter().filter(|x| x.0 <= x.1 * 1.001).count(),
    }
}

/// Every aggregate the report and the plots show of one engine path, computed once.
pub struct FormSummary {
    pub cells: Summary,
    pub squares: Summary,
    /// The grazing rows (t ≥ [`GRAZING`]) of the cells and of the squares.
    pub cells_grazing: Summary,
    pub squares_grazing: Summary,
    /// Per view row j, its cells.
    pub rows: Vec<Summary>,
    /// The places where ours is worse beyond both error bars, the largest ratio ours /
    /// shipped of the relative L2 first: (index, ours, shipped).
    pub worse_cells: Vec<(usize, LobeError, LobeError)>,
    pub worse_squares: Vec<(usize, LobeError, LobeError)>,
}

/// The places of `v` where ours is worse, worst ratio first.
fn worse_places(v: &[Pair]) -> Vec<(usize, LobeError, LobeError)> {
    let mut bad: Vec<(usize, LobeError, LobeError)> = v
        .iter()
        .enumerate()
        .filter_map(|(k, p)| Some((k, p.ours?, p.shipped?)))
        .filter(|(_, o, s)| worse(&o.l2, &s.l2))
        .collect();
    bad.sort_by(|a, b| {
        (b.1.l2.value / b.2.l2.value.max(1e-300))
            .total_cmp(&(a.1.l2.value / a.2.l2.value.max(1e-300)))
    });
    bad
}

/// The grazing rows start at t = GRAZING.0/GRAZING.1 (of the shipped 64-row grid: the
/// last eight rows).
pub const GRAZING: (usize, usize) = (56, 63);
/// The side of the stratified sample set of the earlier, sampled estimate.
pub const SAMPLED_SIDE: usize = 48;

/// The aggregates of every form of an `n`×`n` comparison.
pub fn summaries(n: usize, forms: &[Form]) -> Vec<FormSummary> {
    let grazing = |v: &[Pair], w: usize| {
        summarise(
            v.iter()
                .enumerate()
                .filter(|(k, _)| GRAZING.1 * (k / w) >= GRAZING.0 * (n - 1))
                .map(|x| x.1),
        )
    };
    forms
        .iter()
        .map(|f| FormSummary {
            cells: summarise(f.cells.iter()),
            squares: summarise(f.squares.iter()),
            cells_grazing: grazing(&f.cells, n),
            squares_grazing: grazing(&f.squares, n - 1),
            rows: (0..n)
                .map(|j| summarise(f.cells[n * j..n * (j + 1)].iter()))
                .collect(),
            worse_cells: worse_places(&f.cells),
            worse_squares: worse_places(&f.squares),
        })
        .collect()
}

/// Order statistics of the ratios shipped norm / our albedo over some cells.
pub struct RatioStats {
    pub count: usize,
    pub min: f64,
    pub median: f64,
    pub max: f64,
    /// Mean |ratio − 1|.
    pub mean_abs_dev: f64,
    /// How many ratios are below 1 (less energy than the BRDF).
    pub below_one: usize,
}

impl RatioStats {
    fn of(v: &[f64]) -> RatioStats {
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        RatioStats {
            count: v.len(),
            min: s.first().copied().unwrap_or(f64::NAN),
            median: s.get(s.len() / 2).copied().unwrap_or(f64::NAN),
            max: s.last().copied().unwrap_or(f64::NAN),
            mean_abs_dev: v.iter().map(|r| (r - 1.0).abs()).sum::<f64>() / v.len().max(1) as f64,
            below_one: v.iter().filter(|r| **r < 1.0).count(),
        }
    }
}

/// The shipped norms against our albedo: over every cell, and over the cells of `f32_cells`
/// where the shipped table is better beyond both error bars.
pub struct NormRatios {
    pub all: RatioStats,
    pub where_shipped_better: RatioStats,
}

pub fn norm_ratios(ours: &Shipped, shipped: &Shipped, f32_cells: &Form) -> NormRatios {
    let ratio = |k: usize| shipped.mag[k][0] / ours.mag[k][0];
    let all: Vec<f64> = (0..ours.mat.len())
        .map(ratio)
        .filter(|r| r.is_finite())
        .collect();
    let better: Vec<f64> = f32_cells
        .cells
        .iter()
        .enumerate()
        .filter(|(_, p)| match (&p.ours, &p.shipped) {
            (Some(o), Some(s)) => worse(&o.l2, &s.l2),
            _ => false,
        })
        .map(|(k, _)| ratio(k))
        .filter(|r| r.is_finite())
        .collect();
    NormRatios {
        all: RatioStats::of(&all),
        where_shipped_better: RatioStats::of(&better),
    }
}

/// How three.js's and Bevy's binary16 tables relate to round-to-nearest of the shipped
/// numbers.
pub struct HalfCounts {
    /// Matrix values of the shipped table.
    pub values: usize,
    /// Of them, where three.js's truncation differs from round-to-nearest.
    pub three_below_nearest: usize,
    /// Bevy's (values, equal to round-to-nearest, equal to three.js's truncation).
    pub bevy: Option<(usize, usize, usize)>,
}

pub fn half_counts(shipped: &Shipped, three_f16: &Shipped, bevy: Option<&Shipped>) -> HalfCounts {
    let values = |t: &Shipped| -> Vec<f64> { t.mat.iter().flatten().copied().collect::<Vec<_>>() };
    let src = values(shipped);
    let nearest: Vec<f64> = src
        .iter()
        .map(|x| half::f16::from_f64(*x).to_f64())
        .collect();
    let three = values(three_f16);
    HalfCounts {
        values: src.len(),
        three_below_nearest: three.iter().zip(&nearest).filter(|(a, b)| a != b).count(),
        bevy: bevy.map(|b| {
            let bv = values(b);
            (
                bv.len(),
                bv.iter().zip(&nearest).filter(|(a, b)| a == b).count(),
                bv.iter().zip(&three).filter(|(a, b)| a == b).count(),
            )
        }),
    }
}

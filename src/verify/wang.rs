//! Seed 002 §5.5, Wang tiles (`tensor::wang`): a footprint's NDF image summed from the
//! tiles it covers equals the brute-force P-NDF (Eq 2) of the explicitly synthesised map
//! (Fig 14), anywhere on the unbounded map; and the store that answers every footprint has
//! one size, whatever area it synthesises, because the per-vertex hash stands in for an
//! index map — neighbours agree on every edge and every tile is drawn equally often.

use super::outcome::{Outcome, Worst};
use crate::filters::footprint::{NormalMap, Procedural};
use crate::integrate::Preset;
use crate::tensor::pndf::{pndf_image, sigma_p, window_reach};
use crate::tensor::wang::{explicit, Colouring, Level, TileImages, TileSet, TILES};

const SIDE: usize = 16;
const RES: usize = 16;
const SIGMA_R: f64 = 0.05;
/// Cells from the origin the far regions start at.
const FAR: i64 = 1 << 40;

fn levels(p: Preset) -> Vec<Level> {
    let strides: &[usize] = match p {
        Preset::Quick => &[4],
        _ => &[2, 4, 8],
    };
    strides
        .iter()
        .map(|&s| Level {
            stride: s,
            sigma_p: sigma_p(s, 0),
        })
        .collect()
}

fn tiles(kind: Procedural, seed: u64, p: Preset) -> crate::error::Result<(TileSet, TileImages)> {
    let example = NormalMap::procedural(kind, 64, seed)?;
    let set = TileSet::build(&example, SIDE, 4, seed)?;
    let images = TileImages::build(&set, &levels(p), RES, SIGMA_R)?;
    Ok((set, images))
}

/// |tiles − explicit| / peak at every stride-grid centre whose window lies inside the
/// 3×3-tile region from `origin`, per level.
fn compare(
    set: &TileSet,
    images: &TileImages,
    c: &Colouring,
    origin: (i64, i64),
    w: &mut Worst,
) -> crate::error::Result<()> {
    let map = explicit(set, c, origin, (3, 3))?;
    let size = 3 * SIDE;
    for (l, lv) in images.levels.iter().enumerate() {
        let (s, reach) = (lv.level.stride, window_reach(lv.level.sigma_p) as usize);
        let axis: Vec<usize> = (s / 2..size)
            .step_by(s)
            .filter(|&x| x >= reach && x + reach < size)
            .collect();
        for &y in &axis {
            for &x in &axis {
                let g = (
                    origin.0 * SIDE as i64 + x as i64,
                    origin.1 * SIDE as i64 + y as i64,
                );
                let brute = pndf_image(&map, x as f64, y as f64, lv.level.sigma_p, SIGMA_R, RES)?;
                let tiled = images.combined(c, l, g)?;
                let covered = images.cover(l, g)?.len();
                let peak = brute.iter().cloned().fold(0.0, f64::max);
                let dev = brute
                    .iter()
                    .zip(&tiled)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                w.update(dev / peak, || {
                    format!(
                        "{}, stride {s}, centre {g:?} across {covered} tiles",
                        map.name
                    )
                });
            }
        }
    }
    Ok(())
}

pub fn implicit_explicit(p: Preset) -> Outcome {
    let kinds: &[Procedural] = match p {
        Preset::Quick => &[Procedural::IsotropicNoise],
        _ => &[
            Procedural::IsotropicNoise,
            Procedural::Flakes,
            Procedural::Scratches,
        ],
    };
    let origins = [(0, 0), (-1, 7), (FAR, -FAR), (-FAR - 3, FAR - 5)];
    let mut w = Worst::default();
    for (q, &kind) in kinds.iter().enumerate() {
        let seed = 3 + q as u64;
        let c = Colouring { seed };
        let run = tiles(kind, seed, p).and_then(|(set, images)| {
            origins
                .iter()
                .try_for_each(|&o| compare(&set, &images, &c, o, &mut w))
        });
        if let Err(e) = run {
            w.update(f64::NAN, || format!("{}: {e}", kind.name()));
        }
    }
    Outcome {
        id: "wang-implicit-explicit",
        title: "a footprint's image summed from its Wang tiles = the P-NDF of the explicit map",
        source: "seed 002 §5.5, Figs 12–14, Eq 2",
        ranges: format!(
            "{} example maps, {SIDE}² tiles, strides {:?}, every grid centre inside 3×3-tile regions at 4 places up to 2^40 cells from the origin (footprints across 1, 2 and 4 tiles)",
            kinds.len(),
            levels(p).iter().map(|l| l.stride).collect::<Vec<_>>()
        ),
        cases: w.n,
        worst_error: w.err,
        error_kind: "max |tiles − explicit| / the image's peak",
        worst_case: w.case.clone(),
        tolerance: 1e-12,
        passed: w.err <= 1e-12,
        seconds: 0.0,
        notes: vec![],
    }
}

pub fn constant_storage(p: Preset) -> Outcome {
    let mut w = Worst::default();
    let mut notes = Vec::new();
    let c = Colouring { seed: 21 };
    match tiles(Procedural::IsotropicNoise, 21, p) {
        Err(e) => w.update(f64::NAN, || e.to_string()),
        Ok((set, images)) => {
            let stored = images.values();
            // the store's size from its parameters alone
            let formula: usize = images
                .levels
                .iter()
                .map(|l| {
                    let (s, r) = (l.level.stride as i64, l.reach);
                    // centres stride/2 + k·s within [−reach, side − 1 + reach]
                    let ks = (-r..SIDE as i64 + r)
                        .filter(|x| (x - s / 2).rem_euclid(s) == 0)
                        .count();
                    TILES * ks * ks * RES * RES
                })
                .sum();
            w.update((stored as f64 - formula as f64).abs(), || {
                format!("stored {stored} values, formula {formula}")
            });
            // footprints ever further out, answered by the same store
            for e in [0u32, 10, 20, 30, 40] {
                let o = (1i64 << e, -(1i64 << e) + 1);
                if let Err(err) = compare(&set, &images, &c, o, &mut w) {
                    w.update(f64::NAN, || format!("region at {o:?}: {err}"));
                }
            }
            // no index map: neighbours agree on every edge, and the tiles are uniform
            let n = match p {
                Preset::Quick => 64i64,
                _ => 256,
            };
            let (i0, j0) = (-FAR, FAR / 3);
            let mut counts = [0usize; TILES];
            let mut disagree = 0usize;
            for j in j0..j0 + n {
                for i in i0..i0 + n {
                    let e = c.edges(i, j);
                    counts[e.index()] += 1;
                    disagree += (e.right != c.edges(i + 1, j).left) as usize
                        + (e.bottom != c.edges(i, j + 1).top) as usize;
                }
            }
            w.update(disagree as f64, || format!("{disagree} edges disagree"));
            let expected = (n * n) as f64 / TILES as f64;
            let chi2: f64 = counts
                .iter()
                .map(|&k| (k as f64 - expected).powi(2) / expected)
                .sum();
            // χ² with 15 degrees of freedom exceeds 45 with probability < 1e-4
            notes.push(format!(
                "tile counts over {n}×{n} cells from ({i0}, {j0}): χ² = {chi2:.1} against uniform (15 d.o.f.; 45 is the 1e-4 tail)"
            ));
            if chi2 > 45.0 {
                w.update(f64::INFINITY, || {
                    format!("tile frequencies not uniform: χ² = {chi2:.1}")
                });
            }
            notes.push(format!(
                "{stored} image values answer every footprint of every region tried, from the origin to 2^40 cells out"
            ));
        }
    }
    Outcome {
        id: "wang-constant-storage",
        title: "one store of tile images answers footprints anywhere on the unbounded map",
        source: "seed 002 §5.5, Fig 13 (Lagae and Dutré 2005's implicit colouring)",
        ranges: "store size against its formula; regions 2^0 … 2^40 cells out from the one store; edges and tile frequencies over a block of cells 2^40 out".into(),
        cases: w.n,
        worst_error: w.err,
        error_kind: "max of: |stored − formula| values, |tiles − explicit| / peak, edges that disagree",
        worst_case: w.case.clone(),
        tolerance: 1e-12,
        passed: w.err <= 1e-12,
        seconds: 0.0,
        notes,
    }
}

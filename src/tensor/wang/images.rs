//! NDF images per Wang tile, and the image of a footprint anywhere on the infinite
//! synthesised map as the sum of its tiles' images (seed 002 §5.5, Fig 12).
//!
//! The P-NDF of Eq 2 is a footprint-weighted sum over texels divided by the footprint's
//! total weight, so it splits over any partition of the plane: with W(x) = Σ_u G_P(u; x)
//! over every texel of the window,
//!
//!   D(x, h) = Σ_tiles Σ_{u ∈ tile} G_P(u; x) G_r(n(u); h) / W(x).
//!
//! Each tile stores, for every footprint centre on the stride grid whose window reaches
//! it — centres outside the tile included — its own term of that sum
//! ([`crate::tensor::pndf::pndf_partial_separable`]); a query adds the terms of the tiles
//! its window covers. The stride divides the tile side, so the grid of centres is the same
//! in every tile's frame. The storage depends on the tile side, the levels and the image
//! size only: not on how much map is synthesised.

use super::synth::Colouring;
use super::tiles::{TileSet, TILES};
use crate::error::{Error, Result};
use crate::tensor::brdf::CompressedNdf;
use crate::tensor::cluster::stack_blocks;
use crate::tensor::cp::AlsOptions;
use crate::tensor::pndf::{pndf_partial_separable, window_reach};
use rayon::prelude::*;

/// One footprint level: centres every `stride` texels (at stride/2 + k·stride), width σ_P.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    pub stride: usize,
    pub sigma_p: f64,
}

/// One level's images of every tile.
#[derive(Clone, Debug)]
pub struct LevelImages {
    pub level: Level,
    /// The window's reach (texels each side of its centre).
    pub reach: i64,
    /// The first centre of a tile's frame on each axis; `count` centres per axis.
    pub first: i64,
    pub count: usize,
    /// images[tile][ky · count + kx]: res² values, row-major over h_xy ∈ [−1, 1]².
    pub images: Vec<Vec<Vec<f64>>>,
}

/// The per-tile NDF images of a tile set.
#[derive(Clone, Debug)]
pub struct TileImages {
    pub side: usize,
    pub res: usize,
    pub sigma_r: f64,
    pub levels: Vec<LevelImages>,
}

impl TileImages {
    /// Every tile's term for every centre that reaches it, per level (rayon over tiles and
    /// centres; the same bits at any thread count). A typed error when a stride does not
    /// divide the side, or for σ values the P-NDF refuses.
    pub fn build(set: &TileSet, levels: &[Level], res: usize, sigma_r: f64) -> Result<TileImages> {
        let side = set.side;
        let mut out = Vec::with_capacity(levels.len());
        for &level in levels {
            let s = level.stride;
            if s == 0 || side % s != 0 || !(level.sigma_p > 0.0 && level.sigma_p <= side as f64) {
                return Err(Error::InvalidArgument(format!(
                    "a Wang level needs a stride dividing the tile side {side} and 0 < σ_P ≤ {side} (got stride {s}, σ_P {:e})",
                    level.sigma_p
                )));
            }
            let reach = window_reach(level.sigma_p);
            let (h, st) = ((s / 2) as i64, s as i64);
            let first = h - (reach + h).div_euclid(st) * st;
            let last = h + (side as i64 - 1 + reach - h).div_euclid(st) * st;
            let count = ((last - first) / st + 1) as usize;
            let jobs: Vec<(usize, usize)> = (0..TILES)
                .flat_map(|t| (0..count * count).map(move |k| (t, k)))
                .collect();
            let flat: Vec<Vec<f64>> = jobs
                .par_iter()
                .map(|&(t, k)| {
                    let tile = &set.tiles[t];
                    let lookup = |x: i64, y: i64| {
                        let inside = (0..side as i64).contains(&x) && (0..side as i64).contains(&y);
                        inside.then(|| tile[y as usize * side + x as usize])
                    };
                    let (cx, cy) = (
                        first + (k % count) as i64 * st,
                        first + (k / count) as i64 * st,
                    );
                    pndf_partial_separable(
                        &lookup,
                        cx as f64,
                        cy as f64,
                        level.sigma_p,
                        sigma_r,
                        res,
                    )
                })
                .collect::<Result<_>>()?;
            let mut it = flat.into_iter();
            let images = (0..TILES)
                .map(|_| it.by_ref().take(count * count).collect())
                .collect();
            out.push(LevelImages {
                level,
                reach,
                first,
                count,
                images,
            });
        }
        Ok(TileImages {
            side,
            res,
            sigma_r,
            levels: out,
        })
    }

    /// Values stored: the images of every tile and level.
    pub fn values(&self) -> usize {
        self.levels
            .iter()
            .map(|l| TILES * l.count * l.count * self.res * self.res)
            .sum()
    }

    /// The cells a footprint of `level` centred at global texel (cx, cy) covers, in scan
    /// order, each with the index of its centre in that tile's frame. A typed error for a
    /// level out of range, a centre off the stride grid or one whose window overflows.
    pub fn cover(&self, level: usize, (cx, cy): (i64, i64)) -> Result<Vec<((i64, i64), usize)>> {
        let l = self.levels.get(level).ok_or_else(|| {
            Error::InvalidArgument(format!("Wang level {level} of {}", self.levels.len()))
        })?;
        let (st, h) = (l.level.stride as i64, (l.level.stride / 2) as i64);
        let ok = |c: i64| {
            (c - h).rem_euclid(st) == 0
                && c.checked_sub(l.reach + self.side as i64).is_some()
                && c.checked_add(l.reach + self.side as i64).is_some()
        };
        if !(ok(cx) && ok(cy)) {
            return Err(Error::InvalidArgument(format!(
                "a level-{level} footprint centre lies at stride/2 + k·{st} on each axis, within the grid's range (got ({cx}, {cy}))"
            )));
        }
        let s = self.side as i64;
        let span = |c: i64| (c - l.reach).div_euclid(s)..=(c + l.reach).div_euclid(s);
        let mut cells = Vec::new();
        for j in span(cy) {
            for i in span(cx) {
                let (lx, ly) = (cx - i * s, cy - j * s);
                let (kx, ky) = ((lx - l.first) / st, (ly - l.first) / st);
                cells.push(((i, j), ky as usize * l.count + kx as usize));
            }
        }
        Ok(cells)
    }

    /// The NDF image of the footprint of `level` centred at global texel (cx, cy) of the
    /// infinite map `c` synthesises: the sum of its tiles' terms.
    pub fn combined(&self, c: &Colouring, level: usize, centre: (i64, i64)) -> Result<Vec<f64>> {
        let cells = self.cover(level, centre)?;
        let l = &self.levels[level];
        let mut img = vec![0.0; self.res * self.res];
        for ((i, j), k) in cells {
            for (v, t) in img.iter_mut().zip(&l.images[c.tile(i, j)][k]) {
                *v += t;
            }
        }
        Ok(img)
    }
}

/// The per-tile images CP-compressed, one CP per tile and level (seed 002 §5.5:
/// "we then compress the NDF images for each Wang tile as described in Sec. 4.2").
#[derive(Clone, Debug)]
pub struct CompressedTiles {
    /// tiles[level][tile]; `None` for a tile whose images are all zero.
    pub tiles: Vec<Vec<Option<CompressedNdf>>>,
    pub res: usize,
}

impl CompressedTiles {
    /// Compress each tile's images of each level in t × t blocks with `opts`.
    pub fn compress(images: &TileImages, t: usize, opts: &AlsOptions) -> Result<CompressedTiles> {
        let jobs: Vec<(usize, usize)> = (0..images.levels.len())
            .flat_map(|l| (0..TILES).map(move |k| (l, k)))
            .collect();
        let flat: Vec<Option<CompressedNdf>> = jobs
            .par_iter()
            .map(|&(l, k)| {
                let imgs: Vec<&[f64]> = images.levels[l].images[k]
                    .iter()
                    .map(|v| v.as_slice())
                    .collect();
                match stack_blocks(&imgs, images.res, t)? {
                    None => Ok(None),
                    Some(stack) => {
                        let o = AlsOptions {
                            rank: opts.rank.min(stack.tensor.data.len()),
                            ..*opts
                        };
                        CompressedNdf::compress(&stack, images.res, &o).map(Some)
                    }
                }
            })
            .collect::<Result<_>>()?;
        let mut it = flat.into_iter();
        let tiles = (0..images.levels.len())
            .map(|_| it.by_ref().take(TILES).collect())
            .collect();
        Ok(CompressedTiles {
            tiles,
            res: images.res,
        })
    }

    /// Values stored: every CP's factors and weights.
    pub fn values(&self) -> usize {
        self.tiles
            .iter()
            .flatten()
            .flatten()
            .map(|n| n.cp().storage())
            .sum()
    }

    /// The P-NDF at h_xy of a footprint, per unit projected area: one point query (Eq 6)
    /// per covered tile, summed. `cells` from [`TileImages::cover`]; 0 for a level out of
    /// range (as [`CompressedNdf::d`] reads an image out of range).
    pub fn d(
        &self,
        c: &Colouring,
        level: usize,
        cells: &[((i64, i64), usize)],
        hx: f64,
        hy: f64,
    ) -> f64 {
        let Some(tiles) = self.tiles.get(level) else {
            return 0.0;
        };
        cells
            .iter()
            .map(|&((i, j), k)| tiles[c.tile(i, j)].as_ref().map_or(0.0, |n| n.d(k, hx, hy)))
            .sum()
    }

    /// The whole image of a footprint, each pixel by [`CompressedTiles::d`] at its centre.
    pub fn image(&self, c: &Colouring, level: usize, cells: &[((i64, i64), usize)]) -> Vec<f64> {
        let res = self.res;
        let h = |q: usize| -1.0 + (q as f64 + 0.5) * 2.0 / res as f64;
        (0..res * res)
            .map(|p| self.d(c, level, cells, h(p % res), h(p / res)))
            .collect()
    }
}

//! Sixteen Wang tiles cut from an example normal map (seed 002 §5.5, after Cohen et al.
//! 2003's diamond construction).
//!
//! Each edge colour owns one source patch of the example, side × side texels at a seeded
//! offset (the example read periodically): two patches for the horizontal edges (top and
//! bottom of a tile), two for the vertical ones. A tile with edge colours (top, right,
//! bottom, left) is four triangles, one per edge, each filled from its edge's patch placed
//! with the patch's centre on the edge's midpoint:
//!
//! - top: tile (x, y) ← patch (x, y + side/2); bottom: (x, y − side/2);
//! - right: (x − side/2, y); left: (x + side/2, y).
//!
//! So the texels on both sides of a shared edge are consecutive rows (or columns) of the
//! same patch, whichever two tiles meet there: the edges are seamless by construction, and
//! every seam lies inside a tile, between two triangles. Those seams follow a minimum-error
//! boundary cut (image quilting's dynamic programme) within a band about each diagonal
//! that narrows to nothing at the tile's corner and centre, so a cut never moves a texel of
//! an edge row or column off its edge's patch. `band = 0` gives the straight diagonals.

use crate::error::{Error, Result};
use crate::filters::footprint::NormalMap;
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Colours per edge direction: 2 horizontal × 2 vertical, every combination a tile.
pub const COLOURS: u8 = 2;
/// The complete tile set: COLOURS⁴ (seed 002 §5.5 uses 16 tiles).
pub const TILES: usize = 16;
/// Largest tile side accepted (the paper's tiles are 512²).
pub const MAX_SIDE: usize = 1024;

/// The edge colours of one tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edges {
    pub top: u8,
    pub right: u8,
    pub bottom: u8,
    pub left: u8,
}

impl Edges {
    /// The tile's index in the set: top + 2·right + 4·bottom + 8·left.
    pub fn index(self) -> usize {
        let c = COLOURS as usize;
        self.top as usize
            + c * (self.right as usize + c * (self.bottom as usize + c * self.left as usize))
    }

    /// The edges of tile `index` (< [`TILES`]).
    pub fn of(index: usize) -> Edges {
        let c = COLOURS as usize;
        Edges {
            top: (index % c) as u8,
            right: (index / c % c) as u8,
            bottom: (index / (c * c) % c) as u8,
            left: (index / (c * c * c) % c) as u8,
        }
    }
}

/// Where one tile texel comes from: its source patch (0, 1: horizontal-edge colours;
/// 2, 3: vertical) and the texel in that patch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Source {
    pub patch: u8,
    pub x: u16,
    pub y: u16,
}

/// The sixteen tiles, with where each texel came from.
#[derive(Clone, Debug)]
pub struct TileSet {
    pub side: usize,
    /// Each patch's offset in the example (texels).
    pub offsets: [(usize, usize); 4],
    /// tiles[index][y · side + x].
    pub tiles: Vec<Vec<Vector3<f64>>>,
    pub sources: Vec<Vec<Source>>,
}

/// Triangle k of a tile: 0 top, 1 right, 2 bottom, 3 left (clockwise).
fn patch_of(e: Edges, k: usize) -> u8 {
    match k {
        0 => e.top,
        1 => COLOURS + e.right,
        2 => e.bottom,
        _ => COLOURS + e.left,
    }
}

/// Triangle k's patch coordinates of tile texel (x, y).
fn patch_xy(k: usize, x: usize, y: usize, half: usize) -> (usize, usize) {
    match k {
        0 => (x, y + half),
        1 => (x - half, y),
        2 => (x, y - half),
        _ => (x + half, y),
    }
}

/// Tile texel (x, y) turned a quarter clockwise about the tile's centre, q times.
fn turn(q: usize, x: usize, y: usize, side: usize) -> (usize, usize) {
    (0..q).fold((x, y), |(x, y), _| (side - 1 - y, x))
}

impl TileSet {
    /// Cut the sixteen tiles of `side` texels from `example` (patch offsets from `seed`),
    /// with minimum-error cuts within `band` texels of each diagonal (0: straight).
    pub fn build(example: &NormalMap, side: usize, band: usize, seed: u64) -> Result<TileSet> {
        if side < 4 || side % 2 != 0 || side > MAX_SIDE {
            return Err(Error::InvalidArgument(format!(
                "a Wang tile's side must be even, in 4..={MAX_SIDE} (got {side})"
            )));
        }
        if example.width < side || example.height < side {
            return Err(Error::InvalidArgument(format!(
                "Wang tiles of side {side} need an example of at least {side}² texels (got {}×{})",
                example.width, example.height
            )));
        }
        if example.normals.len() != example.width * example.height
            || example
                .normals
                .iter()
                .any(|n| !(n.iter().all(|v| v.is_finite()) && n.z > 0.0))
        {
            return Err(Error::InvalidArgument(format!(
                "example map '{}': {} normals for {}×{} texels, or a normal that is not finite and above the surface",
                example.name,
                example.normals.len(),
                example.width,
                example.height
            )));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut offsets = [(0, 0); 4];
        for o in &mut offsets {
            *o = (
                rng.random_range(0..example.width),
                rng.random_range(0..example.height),
            );
        }
        let patch = |p: u8, x: usize, y: usize| -> Vector3<f64> {
            let (ox, oy) = offsets[p as usize];
            example.normals[(oy + y) % example.height * example.width + (ox + x) % example.width]
        };
        let (mut tiles, mut sources) = (Vec::with_capacity(TILES), Vec::with_capacity(TILES));
        for index in 0..TILES {
            let e = Edges::of(index);
            let owner = owners(side, band, &|k, x, y| {
                let (px, py) = patch_xy(k, x, y, side / 2);
                patch(patch_of(e, k), px, py)
            });
            let src: Vec<Source> = (0..side * side)
                .map(|q| {
                    let (x, y) = (q % side, q / side);
                    let k = owner[q] as usize;
                    let (px, py) = patch_xy(k, x, y, side / 2);
                    Source {
                        patch: patch_of(e, k),
                        x: px as u16,
                        y: py as u16,
                    }
                })
                .collect();
            tiles.push(
                src.iter()
                    .map(|s| patch(s.patch, s.x as usize, s.y as usize))
                    .collect(),
            );
            sources.push(src);
        }
        Ok(TileSet {
            side,
            offsets,
            tiles,
            sources,
        })
    }

    /// Values stored: side² normals per tile.
    pub fn texels(&self) -> usize {
        TILES * self.side * self.side
    }
}

/// The triangle owning each texel of a tile: per quadrant q (0 top-right, 1 bottom-right,
/// 2 bottom-left, 3 top-left, each the top-right one turned q quarters) the seam between
/// triangles q and q + 1 is the minimum-error path of image quilting, one boundary column
/// per row of the turned quadrant, its offset from the diagonal changing by at most one
/// texel per row, within
/// min(band, y, side/2 − 1 − y) of the diagonal (so it meets the corner and the centre,
/// and edge texels stay with their edge). `normal(k, x, y)` is triangle k's candidate at
/// tile texel (x, y).
fn owners(
    side: usize,
    band: usize,
    normal: &dyn Fn(usize, usize, usize) -> Vector3<f64>,
) -> Vec<u8> {
    let half = side / 2;
    let mut owner = vec![0u8; side * side];
    for q in 0..4 {
        let (a, b) = (q, (q + 1) % 4);
        // overlap error of the two triangles at canonical texel (x, y), x ≥ half
        let err = |x: usize, y: usize| {
            let (tx, ty) = turn(q, x, y, side);
            (normal(a, tx, ty) - normal(b, tx, ty)).norm_squared()
        };
        let range = |y: usize| {
            let diag = side - 1 - y;
            let w = band.min(y).min(half - 1 - y);
            (diag - w, diag + w)
        };
        // cost of boundary column c in row y: the quadrant's texels on both sides of it
        let cost = |y: usize, c: usize| if c > half { err(c - 1, y) } else { 0.0 } + err(c, y);
        // dynamic programme over rows 0..half, columns within the band
        let mut best: Vec<Vec<(f64, usize)>> = Vec::with_capacity(half);
        for y in 0..half {
            let (lo, hi) = range(y);
            let row: Vec<(f64, usize)> = (lo..=hi)
                .map(|c| {
                    let here = cost(y, c);
                    if y == 0 {
                        return (here, c);
                    }
                    let (plo, phi) = range(y - 1);
                    let prev = &best[y - 1];
                    let mut pick = (f64::INFINITY, c);
                    for pc in c.max(plo)..=(c + 2).min(phi) {
                        let v = prev[pc - plo].0;
                        if v < pick.0 {
                            pick = (v, pc);
                        }
                    }
                    (pick.0 + here, pick.1)
                })
                .collect();
            best.push(row);
        }
        // trace back from the centre row (its range is the diagonal alone)
        let mut cut = vec![0usize; half];
        let (lo, _) = range(half - 1);
        cut[half - 1] = lo;
        for y in (1..half).rev() {
            let (lo, _) = range(y);
            cut[y - 1] = best[y][cut[y] - lo].1;
        }
        for (y, &c) in cut.iter().enumerate() {
            for x in half..side {
                let (tx, ty) = turn(q, x, y, side);
                owner[ty * side + tx] = if x < c { a as u8 } else { b as u8 };
            }
        }
    }
    owner
}

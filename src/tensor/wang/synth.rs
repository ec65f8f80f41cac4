//! Which tile lies where, with no index map (seed 002 §5.5, Fig 13): every vertex (i, j)
//! of the infinite tile grid draws two numbers from a generator seeded by its own index,
//! and they become the colours of its right edge (the top edge of cell (i, j)) and its
//! bottom edge (the left edge of cell (i, j)). Cell (i, j)'s bottom edge is then vertex
//! (i, j + 1)'s right edge and its right edge vertex (i + 1, j)'s bottom edge, so two
//! neighbours always agree on their shared edge, and with the complete set of
//! [`super::tiles::TILES`] tiles every colouring has its tile. Rows grow downwards.
//!
//! The explicit synthesis lays the same tiles out as one normal map ([`explicit`]), which
//! is what the implicit queries of [`super::images`] are checked against.

use super::tiles::{Edges, TileSet, COLOURS};
use crate::error::{Error, Result};
use crate::filters::footprint::NormalMap;
use rand::{RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The implicit edge colouring of the tile grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Colouring {
    pub seed: u64,
}

/// Largest explicit map: 2^26 texels (a 8192² map).
pub const MAX_EXPLICIT: usize = 1 << 26;

impl Colouring {
    /// Colours of vertex (i, j)'s right and bottom edges: two draws of ChaCha8 keyed by
    /// (i, j, seed) — one 32-byte key per vertex, so distinct vertices never share a stream.
    pub fn vertex(&self, i: i64, j: i64) -> (u8, u8) {
        let mut key = [0u8; 32];
        key[..8].copy_from_slice(&i.to_le_bytes());
        key[8..16].copy_from_slice(&j.to_le_bytes());
        key[16..24].copy_from_slice(&self.seed.to_le_bytes());
        let mut r = ChaCha8Rng::from_seed(key);
        let c = COLOURS as u32;
        ((r.next_u32() % c) as u8, (r.next_u32() % c) as u8)
    }

    /// The edges of cell (i, j).
    pub fn edges(&self, i: i64, j: i64) -> Edges {
        let (top, left) = self.vertex(i, j);
        Edges {
            top,
            left,
            bottom: self.vertex(i, j + 1).0,
            right: self.vertex(i + 1, j).1,
        }
    }

    /// The tile of cell (i, j).
    pub fn tile(&self, i: i64, j: i64) -> usize {
        self.edges(i, j).index()
    }
}

/// The map of the nx × ny cells from (i0, j0), laid out explicitly (its texel (0, 0) is
/// cell (i0, j0)'s first). A typed error for an empty or oversized map, or cells whose
/// indices overflow.
pub fn explicit(
    set: &TileSet,
    c: &Colouring,
    (i0, j0): (i64, i64),
    (nx, ny): (usize, usize),
) -> Result<NormalMap> {
    if i0.checked_add(nx as i64 + 1).is_none() || j0.checked_add(ny as i64 + 1).is_none() {
        return Err(Error::InvalidArgument(format!(
            "Wang cells from ({i0}, {j0}) overflow the grid's indices"
        )));
    }
    layout(
        set,
        (nx, ny),
        format!("wang-{i0}-{j0}-{nx}x{ny}"),
        &|ci, cj| c.tile(i0 + ci as i64, j0 + cj as i64),
    )
}

/// The map of nx × ny cells holding the tiles `tile_of(ci, cj)` picks. A typed error for
/// an empty map, one over [`MAX_EXPLICIT`] texels or a pick that is no tile.
pub fn layout(
    set: &TileSet,
    (nx, ny): (usize, usize),
    name: String,
    tile_of: &dyn Fn(usize, usize) -> usize,
) -> Result<NormalMap> {
    let s = set.side;
    let texels = nx
        .checked_mul(s)
        .zip(ny.checked_mul(s))
        .and_then(|(w, h)| w.checked_mul(h));
    if nx == 0 || ny == 0 || texels.is_none_or(|t| t > MAX_EXPLICIT) {
        return Err(Error::InvalidArgument(format!(
            "a Wang map of {nx}×{ny} tiles of {s}² texels is empty or over {MAX_EXPLICIT} texels"
        )));
    }
    let (w, h) = (nx * s, ny * s);
    let mut normals = vec![nalgebra::Vector3::zeros(); w * h];
    for cj in 0..ny {
        for ci in 0..nx {
            let tile = set
                .tiles
                .get(tile_of(ci, cj))
                .ok_or_else(|| Error::InvalidArgument(format!("no tile for cell ({ci}, {cj})")))?;
            for y in 0..s {
                let row = (cj * s + y) * w + ci * s;
                normals[row..row + s].copy_from_slice(&tile[y * s..(y + 1) * s]);
            }
        }
    }
    Ok(NormalMap {
        name,
        width: w,
        height: h,
        normals,
    })
}

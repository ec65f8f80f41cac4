//! How visible the seams of a synthesised map are: the mean squared difference of
//! neighbouring normals, |n(u) − n(u')|², over every horizontally or vertically adjacent
//! pair of an explicit map, by kind of pair. A pair is *continuous* when both texels come
//! from the same source patch at consecutive texels (as any two neighbours of the example
//! itself do); otherwise it crosses a seam. Exact sums over the map, not estimates.

use super::synth::Colouring;
use super::tiles::{Source, TileSet};
use crate::error::Result;
use crate::filters::footprint::NormalMap;
use serde::{Deserialize, Serialize};

/// A count of pairs and their mean |Δn|² (0 for no pairs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PairMean {
    pub pairs: usize,
    pub mean: f64,
}

impl PairMean {
    fn add(&mut self, d2: f64) {
        self.pairs += 1;
        self.mean += d2;
    }
    fn finish(mut self) -> PairMean {
        if self.pairs > 0 {
            self.mean /= self.pairs as f64;
        }
        self
    }
}

/// The pairs of a tiled map by kind.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeamStats {
    /// Pairs inside a tile from consecutive texels of one patch.
    pub continuous: PairMean,
    /// Pairs inside a tile across a seam between two triangles.
    pub cuts: PairMean,
    /// Pairs across a tile edge, and how many of them are continuous.
    pub edges: PairMean,
    pub edges_continuous: usize,
}

/// Mean |Δn|² over the pairs of `map` that cross the edges of its side × side cells.
pub fn edge_mean(map: &NormalMap, side: usize) -> PairMean {
    let mut m = PairMean::default();
    each_pair(map, |(x, y), (x2, y2), d2| {
        if x / side != x2 / side || y / side != y2 / side {
            m.add(d2);
        }
    });
    m.finish()
}

/// Every pair of the nx × ny cells from (i0, j0) that `c` synthesises, by kind.
pub fn stats(
    set: &TileSet,
    c: &Colouring,
    origin: (i64, i64),
    cells: (usize, usize),
) -> Result<SeamStats> {
    let map = super::synth::explicit(set, c, origin, cells)?;
    let s = set.side;
    let tiles: Vec<usize> = (0..cells.0 * cells.1)
        .map(|q| {
            c.tile(
                origin.0 + (q % cells.0) as i64,
                origin.1 + (q / cells.0) as i64,
            )
        })
        .collect();
    let source = |x: usize, y: usize| -> Source {
        set.sources[tiles[(y / s) * cells.0 + x / s]][(y % s) * s + x % s]
    };
    let (mut continuous, mut cuts, mut edges, mut edges_continuous) = (
        PairMean::default(),
        PairMean::default(),
        PairMean::default(),
        0,
    );
    each_pair(&map, |(x, y), (x2, y2), d2| {
        let (a, b) = (source(x, y), source(x2, y2));
        let next = a.patch == b.patch
            && b.x as usize == a.x as usize + (x2 - x)
            && b.y as usize == a.y as usize + (y2 - y);
        if x / s != x2 / s || y / s != y2 / s {
            edges.add(d2);
            edges_continuous += next as usize;
        } else if next {
            continuous.add(d2);
        } else {
            cuts.add(d2);
        }
    });
    Ok(SeamStats {
        continuous: continuous.finish(),
        cuts: cuts.finish(),
        edges: edges.finish(),
        edges_continuous,
    })
}

/// Call `f(u, u', |n(u) − n(u')|²)` for every pair u, u' = u + (1, 0) or u + (0, 1).
fn each_pair(map: &NormalMap, mut f: impl FnMut((usize, usize), (usize, usize), f64)) {
    let (w, h) = (map.width, map.height);
    for y in 0..h {
        for x in 0..w {
            let n = map.normals[y * w + x];
            if x + 1 < w {
                f(
                    (x, y),
                    (x + 1, y),
                    (map.normals[y * w + x + 1] - n).norm_squared(),
                );
            }
            if y + 1 < h {
                f(
                    (x, y),
                    (x, y + 1),
                    (map.normals[(y + 1) * w + x] - n).norm_squared(),
                );
            }
        }
    }
}

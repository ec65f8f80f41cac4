//! results/fits/tensor-wang.json: seed 002 §5.5's Wang tiles — the seams of the
//! synthesised map, the tiles' NDF images against the explicit map's, storage and ranks.

use crate::fit::spec::FitSpec;
use crate::tensor::wang::seams::{PairMean, SeamStats};
use serde::{Deserialize, Serialize};

/// One footprint level's implicit-against-explicit check over every region.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LevelCheck {
    pub stride: usize,
    pub sigma_p: f64,
    /// Footprints compared, and how many covered 1, 2, 3–4 and more tiles.
    pub footprints: usize,
    pub by_tiles: [usize; 4],
    /// Largest |combined − explicit| over the image's peak.
    pub worst: f64,
}

/// One CP rank of the per-tile images.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RankCheck {
    pub rank: usize,
    /// Values the compressed tiles store.
    pub values: usize,
    /// Over every compared footprint: ‖combined compressed − explicit‖ / ‖explicit‖ (the
    /// sums run over all their pixels), and the largest |difference| over a footprint's peak.
    pub rel_l2: f64,
    pub worst: f64,
    /// The same explicit images CP-compressed directly at this rank, one CP per level and
    /// region (as the tensor study clusters a map): its ‖T − T̂‖/‖T‖ over them all, and
    /// the values those CPs store.
    pub explicit_rel_l2: f64,
    pub explicit_values: usize,
}

/// Storage of a synthesised area of `tiles`² tiles.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct AreaStorage {
    pub tiles: u64,
    /// Image values an explicit map of that area needs (all levels).
    pub explicit: f64,
}

/// Fig 14's comparison for one footprint across the most tiles: its image from the
/// explicit map (brute force) and summed from the tiles, row-major res².
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Fig14 {
    pub level: usize,
    pub tiles_covered: usize,
    pub res: usize,
    pub explicit: Vec<f64>,
    pub tiles: Vec<f64>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Wang {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    /// What the tiles were cut from, in words (generator or file, and size).
    pub example_map: String,
    /// The example's own neighbour pairs (every pair of the example).
    pub example: PairMean,
    /// Seams with the minimum-error cut, and with straight diagonals.
    pub cut: SeamStats,
    pub straight: SeamStats,
    /// The same tiles laid out at random, colours ignored: the pairs across tile edges.
    pub unmatched_edges: PairMean,
    /// The regions' first cells, and the checks per level.
    pub regions: Vec<(i64, i64)>,
    pub levels: Vec<LevelCheck>,
    /// Values the uncompressed tile images store (all levels), and the tiles' texels.
    pub tile_values: usize,
    pub tile_texels: usize,
    pub ranks: Vec<RankCheck>,
    pub areas: Vec<AreaStorage>,
    pub fig14: Fig14,
    /// Fig 14's claim (implicit and explicit synthesis give identical NDFs), judged.
    pub verdict: String,
}

impl super::ResultFile for Wang {
    const NAME: &'static str = super::names::TENSOR_WANG;
}

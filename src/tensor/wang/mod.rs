//! Constant storage by Wang tiles (seed 002 §5.5, Figs 12–14): sixteen tiles cut from an
//! example normal map ([`tiles`]), laid out over an unbounded plane by a per-vertex hash
//! with no index map ([`synth`]), with NDF images precomputed per tile for every footprint
//! centre that reaches it and summed over the tiles a footprint covers ([`images`]), and
//! the seams of the result measured ([`seams`]).

pub mod images;
pub mod seams;
pub mod synth;
pub mod tiles;

pub use images::{CompressedTiles, Level, TileImages};
pub use synth::{explicit, Colouring};
pub use tiles::{Edges, TileSet, TILES};

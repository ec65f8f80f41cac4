//! Spatio-angular NDF prefiltering with tensor decomposition (seed 002, in
//! progress): P-NDF images (Eq 2, §4.1), CP decomposition by ALS (Eq 5, §4.2), point and
//! range queries with 1D summed-area tables (Eq 6–7, Appendix Eq 10–12), and the BRDF
//! built on them beside a plain microfacet BRDF (§5.1–5.2, Table 3).

pub mod brdf;
pub mod cluster;
pub mod compare;
pub mod cp;
pub mod envsg;
mod mttkrp;
pub mod pndf;
pub mod query;
pub mod sample;
pub mod scale;
pub mod wang;
pub mod wave;

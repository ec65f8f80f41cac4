//! Linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016; seed 000 Eq 1) and
//! what is built on them:
//!
//! - `dist`: the LTC distribution (eval through the proved Jacobian, sampling);
//! - `polygon`: polygon lights — horizon clipping, the exact edge integral and the
//!   production θ/sin θ forms, the LTC integral, MC truth (MIS);
//! - `target`: what a table is fitted to (the `LtcTarget` trait; the GGX lobe);
//! - `fit`: the per-cell fit of a table, generic over the target (all four
//!   production-form parameters);
//! - `samples`: the balance sample sets a fit measures trial lobes on, the target's half
//!   drawn once per cell;
//! - `compare`: our table against a shipped one (per cell, per row, between cells);
//! - `compact`: a table as tensor-product Chebyshev series, rebuilt or evaluated per pixel;
//! - `compact_fit`: such a series fitted by the lobe error after bilinear reading;
//! - `chart`: the linearly transformed hemispheres held-out integrals follow a lobe on;
//! - `held`: the held-out figures of a fitted table, every cell in every precision;
//! - `lobe_error`: the held-out error of an LTC against its lobe (relative L2 and L1)
//!   as converged integrals with their error bars;
//! - `upload`: how three.js and Bevy upload and sample a table (three's truncating
//!   half floats, Bevy's zstd KTX2);
//! - `storage`: the binary16 storage of a cell, chosen by the fit's error;
//! - `spread`: whether another fitting route is no worse than the reference, judged
//!   against the reference's own spread over draws of its training samples;
//! - `table`: the one reader of a fitted table (results/fits/ltc-ggx.json);
//! - `pipeline`: the multi-scale shading pipeline of seed 000 §3–4 against brute force;
//! The `ltc-ggx` study that fits the table and measures all of the above is
//! `crate::studies::ltc_ggx`.

pub mod aniso;
pub mod aniso_table;
pub mod chart;
pub mod compact;
pub mod compact_fit;
pub mod compare;
pub mod diffuse;
pub mod dist;
pub mod fit;
pub mod gauss_newton;
pub mod held;
pub mod hemisphere;
pub mod lobe_error;
pub mod lobe_nodes;
pub mod lobes;
pub mod objective;
pub mod params;
pub mod pipeline;
pub mod polish;
pub mod polygon;
pub mod samples;
pub mod sheen;
pub mod smooth;
pub mod spread;
pub mod storage;
pub mod table;
pub mod target;
pub mod upload;

pub use dist::*;

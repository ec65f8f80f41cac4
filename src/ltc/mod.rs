//! Linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016; seed 000 Eq 1) and
//! what is built on them:
//!
//! - `dist`: the LTC distribution (eval through the proved Jacobian, sampling);
//! - `polygon`: polygon lights — horizon clipping, the exact edge integral and the
//!   production θ/sin θ forms, the LTC integral, MC truth (MIS);
//! - `fit`: the per-cell fit of the GGX table (all four production-form parameters);
//! - `compare`: our table against a shipped one (per cell, per row, between cells);
//! - `table`: the one reader of a fitted table (results/fits/ltc-ggx.json);
//! - `pipeline`: the multi-scale shading pipeline of seed 000 §3–4 against brute force;
//! The `ltc-ggx` study that fits the table and measures all of the above is
//! `crate::studies::ltc_ggx`.

pub mod compare;
pub mod dist;
pub mod fit;
pub mod pipeline;
pub mod polygon;
pub mod table;

pub use dist::*;

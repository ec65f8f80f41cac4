//! ndfbench: a numerical verification and fitting workbench for microfacet NDF
//! prefiltering and specular antialiasing.
//!
//! Pipeline: [`integrate`] → [`microfacet`] / [`jacobian`] → [`verify`] (proofs) →
//! [`report`]. Every estimate carries its error; every f32 shading form has an f64
//! reference; bad input gives a typed [`error::Error`].
//!
//! ```
//! use ndfbench::integrate::quad::Tol;
//! use ndfbench::integrate::sphere::{integrate_sphere, SphereRule};
//! use ndfbench::microfacet::{Microsurface, Roughness};
//!
//! // ∫ D(m)(m·n) dm = 1 for GGX at α = 1e-4, with its error estimate and cost
//! let s = Microsurface::ggx(Roughness::iso(1e-4)?);
//! let e = integrate_sphere(&|m| s.d(m) * m.z.max(0.0), &SphereRule::hemisphere(1e-4), Tol::new(1e-10, 1e-10, 10_000_000));
//! assert!((e.value - 1.0).abs() < 1e-9 && e.converged);
//! # Ok::<(), ndfbench::Error>(())
//! ```

// `!(x > 0.0)` is used on purpose throughout: it is true for NaN, which is the point.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod cli;
pub mod codegen;
pub mod engines;
pub mod error;
pub mod filters;
pub mod fit;
pub mod generated;
pub mod gpu;
pub mod integrate;
pub mod io;
pub mod jacobian;
pub mod kernels;
pub mod ktx2;
pub mod lanes;
pub mod leadr;
pub mod linalg;
pub mod ltc;
pub mod memo;
pub mod microfacet;
pub mod multiscale;
pub mod optimize;
pub mod parmap;
pub mod prefilter;
pub mod progress;
pub mod render;
pub mod report;
pub mod results;
pub mod scene;
pub mod studies;
pub mod study;
pub mod survey;
pub mod tensor;
pub mod verify;
pub mod visibility;

pub use error::{Error, Result};

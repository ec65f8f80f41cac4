//! ndfbench: a numerical verification and fitting workbench for microfacet NDF
//! prefiltering and specular antialiasing.
//!
//! Pipeline: [`integrate`] → [`microfacet`] / [`jacobian`] → [`verify`] (proofs) →
//! [`report`]. Every estimate carries its error; every f32 shading form has an f64
//! reference; bad input gives a typed [`error::Error`].

pub mod cli;
pub mod error;
pub mod integrate;
pub mod io;
pub mod jacobian;
pub mod linalg;
pub mod microfacet;
pub mod report;
pub mod verify;

pub use error::{Error, Result};

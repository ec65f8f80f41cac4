//! Integration engines. Every result is an [`Estimate`]: value, error, evaluations.
//!
//! - [`mc`]: Monte Carlo with importance sampling and MIS (balance heuristic), rayon,
//!   bit-identical per seed at any thread count.
//! - [`qmc`]: randomised QMC (Owen-scrambled Sobol, replicates for the error).
//! - [`quad`]: Gauss–Legendre (1D, 2D tensor), adaptive Gauss–Kronrod, substitutions.
//! - [`cubature`]: adaptive tensor G7/K15 cubature of vector integrands on rectangles.
//! - [`sphere`]: adaptive quadrature over the sphere with a peak-following substitution.
//! - [`trig`]: sin and cos remembered per thread (the nested rules' repeated φ nodes).
//! - [`auto`]: tolerance-driven entry point.
//! - [`preset`]: quick / default / precise.

pub mod auto;
pub mod cubature;
pub mod estimate;
pub mod mc;
pub mod preset;
pub mod qmc;
pub mod quad;
pub mod sphere;
pub mod trig;

pub use estimate::{ErrorKind, Estimate, Figure, Kind, Quad, StdErr};
pub use preset::Preset;
pub use quad::Tol;

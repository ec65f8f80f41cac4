//! Multi-scale LTC (seed 000): mean resultant length ‖b̄‖ ↔ α_me, fits of its inverse.

pub mod alpha_me;
pub mod convolution;
pub mod mrl;
pub mod overall;

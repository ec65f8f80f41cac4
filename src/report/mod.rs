//! Reports: convergence study of the engines and the criterion performance summary.

pub mod convergence;
pub mod performance;
pub mod plot;

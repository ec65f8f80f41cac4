//! Fit specifications (fits/*.toml): model form, domain, training and held-out points,
//! metric, optimiser and its settings, seed and tolerance, each bounded (`spec`). The
//! studies that run them are registered in `crate::studies`.

pub mod spec;

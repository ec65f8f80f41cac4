//! Study specifications (fits/*.toml): a shared header (name, seed, tolerance) and each
//! study's own typed, bounded parameters per preset (`spec`). The studies that read them
//! are registered in `crate::studies`.

pub mod spec;

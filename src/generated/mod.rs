//! Generated code (see src/codegen). Regenerate with `cargo run --release -- regen`.

#[rustfmt::skip]
pub mod shading;

#[rustfmt::skip]
pub mod ltc_table;

#[rustfmt::skip]
pub mod ltc_compact;

#[rustfmt::skip]
pub mod ltc_sheen;

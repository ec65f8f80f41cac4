//! Batched f32 shading kernels over structure-of-arrays inputs, with an
//! AVX2+FMA backend chosen at run time and the scalar generated twins as fallback.
//!
//! The compact LTC table's two per-pixel forms, the texture-free series and the bilinear
//! lookup of its rebuilt table, are `compact` (their own inputs and layout).
//!
//! Kernels: (a) GGX point-light specular with height-correlated Smith G2
//! ([`ggx_specular`]), (b) the deferred specular-AA roughness update of seed 003 Eq 13
//! ([`deferred_roughness`]), (c) the multi-scale α, y_me, y_mi → α through the α_me fit
//! ([`multiscale_alpha`]). The scalar backend calls `crate::generated::shading` (the
//! same source text as the WGSL); the AVX2 backend (`avx2.rs`) re-implements the same
//! arithmetic 8 lanes at a time. Agreement (tests/kernels.rs): SIMD vs scalar ≤ 16 ulp
//! relative for (a), ≤ 2 ulp for (b) and ≤ 512 ulp for (c) (its fitted Horner sum is
//! ill-conditioned near α = 1 and its logarithm is a series); both vs the f64 references
//! within the bounds of tests/codegen.rs.

mod accuracy;
#[cfg(target_arch = "x86_64")]
mod avx2;
mod batch;
mod compact;
mod dispatch;
mod inputs;

pub use dispatch::{deferred_roughness, ggx_specular, leadr5, ltc_quad, multiscale_alpha, Backend};

pub use batch::{DeferredIn, LeadrIn, LtcQuadIn, SpecularIn, ALPHA_ME_C, ALPHA_ME_D};
pub use compact::{ltc_compact_lookup, ltc_compact_series, CompactF32, TableF32};

pub use accuracy::{accuracy, ltc_quad_conditioning, ltc_quad_f64};
pub use inputs::{bench_inputs, BenchInputs};

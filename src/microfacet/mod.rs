//! Microfacet core: roughness matrices, Beckmann/GGX slope distributions (P22, D),
//! Smith Λ (exact and Walter's approximation), G1/G2, sampling, and f32 shading forms.

pub mod lambda;
pub mod lambda_fit;
pub mod lobe;
pub mod roughness;
pub mod sampling;
pub mod sggx;
pub mod shading;
pub mod surface;
mod surface_lanes;
pub use surface_lanes::g2_lanes;

pub use roughness::Roughness;
pub use surface::{unit, LambdaKind, Microsurface, NdfKind};

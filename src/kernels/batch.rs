//! The SoA f32 input batches every kernel reads, and the constants the kernels share (the
//! α_me rational's coefficients).

use crate::generated::shading as g;

/// The generated α_me coefficients as arrays (α ≤ 1 branch in 1/s, α > 1 branch in ‖b̄‖),
/// for code that evaluates the same form lane-wise or in a loop.
pub const ALPHA_ME_C: [f32; 7] = [
    g::ALPHA_ME_C1,
    g::ALPHA_ME_C2,
    g::ALPHA_ME_C3,
    g::ALPHA_ME_C4,
    g::ALPHA_ME_C5,
    g::ALPHA_ME_C6,
    g::ALPHA_ME_C7,
];

pub const ALPHA_ME_D: [f32; 8] = [
    g::ALPHA_ME_D1,
    g::ALPHA_ME_D2,
    g::ALPHA_ME_D3,
    g::ALPHA_ME_D4,
    g::ALPHA_ME_D5,
    g::ALPHA_ME_D6,
    g::ALPHA_ME_D7,
    g::ALPHA_ME_D8,
];

/// Inputs of the GGX specular kernel: tangent-space unit light and view directions and α.
pub struct SpecularIn<'a> {
    pub l: [&'a [f32]; 3],
    pub v: [&'a [f32]; 3],
    pub alpha: &'a [f32],
}

/// Inputs of the deferred roughness update: α and the screen derivatives of the normal.
pub struct DeferredIn<'a> {
    pub alpha: &'a [f32],
    pub du: [&'a [f32]; 3],
    pub dv: [&'a [f32]; 3],
}

/// Inputs of the LTC quad-light kernel: the table's production M⁻¹ (a, b, c, d) per pixel
/// and the quad's 4 vertices in the pixel's shading frame (12 columns p0x, p0y, p0z, …).
pub struct LtcQuadIn<'a> {
    pub m: [&'a [f32]; 4],
    pub p: [&'a [f32]; 12],
}

/// Inputs of the LEADR 5×5 kernel: slope statistics (x0, y0, sx, sy, rxy) and the view.
pub struct LeadrIn<'a> {
    pub s: [&'a [f32]; 5],
    pub v: [&'a [f32]; 3],
}

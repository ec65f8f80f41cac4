//! What fits/multiscale-convolution.toml sets.

/// The convolution study's parameters.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// The (α_mi, α_me) square, both axes.
    pub alpha_min: f64,
    pub alpha_max: f64,
    /// Points per axis of the dense grid of closed-form targets (held out: one fewer, half
    /// a step off).
    pub dense_points: usize,
    /// Points per axis of the grid fitted by quadrature (~1.6 s per point; held out: one
    /// fewer, half a step off).
    pub metric_points: usize,
}

impl crate::fit::spec::Params for Params {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::{alpha_range, within};
        // the quadrature metrics' bracket (multiscale::overall::QUAD_DOMAIN)
        alpha_range(self.alpha_min, self.alpha_max, 1e-3, 3.0)?;
        within("dense_points", self.dense_points, 4, 400)?;
        within("metric_points", self.metric_points, 2, 16)
    }
}

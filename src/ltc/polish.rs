//! The L2 polish of a cell fitted under the cubic metric: which route, and how a report
//! names it. The polish itself runs in `ltc::fit` (Nelder–Mead on its objective) or
//! `ltc::gauss_newton` (Levenberg–Marquardt on fixed nodes).

use serde::Serialize;

/// How a cell fitted under the cubic metric is polished under the relative L2 (the
/// metric the table is judged by); each kept only where the validation set's relative L2
/// drops too.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Polish {
    /// Nelder–Mead on the fit's own sample sets (≤ half the cubic stage's cap): the
    /// reference route. Its objective draws half of its samples from the trial LTC, so it
    /// is noisy and the search stays near its start.
    NelderMead,
    /// Levenberg–Marquardt on 2n×2n fixed nodes per technique (`ltc::gauss_newton`), all
    /// four parameters: each cell goes to its own L2 optimum.
    LevenbergMarquardt,
    /// The same with the frame turn φ held at the cubic fit's, which the warm-start chain
    /// keeps smooth from cell to cell: the L2 trades φ against m13/m11 along a flat valley,
    /// and a free φ lands anywhere in it, which a bilinear lookup between cells pays for.
    LevenbergMarquardtTurnHeld,
}

impl Polish {
    /// The route in words, for a report: `n` is the cubic stage's samples per axis.
    pub fn describe(self, n: usize) -> String {
        let lm = |held: &str| {
            format!(
                "Levenberg–Marquardt on the relative L2 over {m}×{m} fixed nodes per technique (`ltc::gauss_newton`){held}",
                m = 2 * n
            )
        };
        match self {
            Polish::NelderMead => "Nelder–Mead on the relative L2 over the cubic stage's sample sets (≤ half its iterations)".into(),
            Polish::LevenbergMarquardt => lm(""),
            Polish::LevenbergMarquardtTurnHeld => lm(", the frame turn φ held at the cubic stage's"),
        }
    }
}

/// Levenberg–Marquardt iteration cap per pass of the L2 polish.
pub const POLISH_ITERS: usize = 400;

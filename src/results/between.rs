//! Held-out figures over a set of places ([`Located`]), and the error between the cells of
//! an LTC table built on it ([`Between`]: its squares, where a shader's bilinear lookup
//! lands) as results/fits/ltc-ggx.json and the lobe tables' results record it;
//! `studies::ltc_between` measures it.

use crate::fit::spec::FitSpec;
use crate::integrate::{Figure, Quad, StdErr};
use serde::{Deserialize, Serialize};

/// Both held-out figures over a set of places (a table's cells or squares), with where
/// the largest relative L2 is.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Located {
    pub l2: crate::ltc::lobe_error::Spread,
    pub l1: crate::ltc::lobe_error::Spread,
    /// (α, θ°) of the largest relative L2; `None` where no place has a figure.
    pub at: Option<(f64, f64)>,
}

impl Located {
    /// The figures of `v` (each place's error, `None` where it has none, and its (α, θ°)).
    pub fn of(v: &[(Option<crate::ltc::lobe_error::LobeError>, (f64, f64))]) -> Located {
        use crate::ltc::lobe_error::Spread;
        let l2 = Spread::of(v.iter().map(|x| x.0.as_ref().map(|e| &e.l2)));
        let l1 = Spread::of(v.iter().map(|x| x.0.as_ref().map(|e| &e.l1)));
        Located {
            l2,
            l1,
            at: (l2.count > 0)
                .then(|| v.get(l2.argmax).map(|x| x.1))
                .flatten(),
        }
    }
    /// Both figures in words, for a report: "relative L2 mean …, max … at (α, θ°);
    /// relative L1 mean …, max …".
    pub fn words(&self) -> String {
        let at = self
            .at
            .map_or(String::new(), |(a, t)| format!(" at ({a:.3}, {t:.1}°)"));
        format!(
            "relative L2 mean {}, max {}{at}; relative L1 mean {}, max {}",
            self.l2.mean.pct(2),
            self.l2.max.pct(1),
            self.l1.mean.pct(2),
            self.l1.max.pct(1)
        )
    }
}

/// The error between cells: the table interpolated at square centres as a shader reads it,
/// judged against the lobe there.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Between {
    /// Over the judged squares (their count, mean, largest and where).
    pub judged: Located,
    /// Squares whose lobe has an albedo of at least `studies::ltc_between::VISIBLE_ALBEDO` (the population),
    /// and those below it, left out: between corners whose albedos differ by orders of
    /// magnitude (sheen seen head-on at small α) the interpolated norm dwarfs such a lobe.
    pub visible: usize,
    pub left_out: usize,
    /// Whether `judged` holds every visible square (its means are then exact).
    pub all: bool,
    /// Visible squares judged whatever the sample (those touching the
    /// `studies::ltc_between::BETWEEN_WORST_CELLS` worst cells and those whose corners' entries jump most;
    /// every one when `all`), and the rest, of which a random sample was judged.
    pub census: usize,
    pub rest: usize,
    /// The mean relative L2 and L1 over every visible square: the census squares' sum plus
    /// the rest's from a random sample of them by `Figure::difference_mean`, with the mean
    /// of each square's four corner cells' held-out figures as the control (± the sample's
    /// standard error scaled by the rest's share; exact, ± 0, when all are judged). A
    /// judged square without a figure (a singular interpolated matrix; none in the
    /// published tables) adds nothing to the census sum and is left out of the sample.
    pub mean_l2: Figure<StdErr>,
    pub mean_l1: Figure<StdErr>,
}

/// results/fits/ltc-between-sample.json (on request): how well the between-cell sample
/// estimates the mean over every square, per published table and sample size.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BetweenSample {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    /// The samples redrawn per size (each with its own seed).
    pub redraws: usize,
    pub tables: Vec<SampleCurve>,
}

impl super::ResultFile for BetweenSample {
    const NAME: &'static str = super::names::LTC_BETWEEN_SAMPLE;
}

/// One table: every visible square judged (the exact means), and one point per size.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SampleCurve {
    pub table: String,
    /// The SHA-256 of results/fits/<table>.json's table part (`results::fits_sha256`).
    pub sha256: String,
    pub visible: usize,
    /// Visible squares with no figure (a singular interpolated matrix).
    pub without_figure: usize,
    /// The means over every visible square, ± the mean of their integrals' bars.
    pub exact_l2: Figure<Quad>,
    pub exact_l1: Figure<Quad>,
    /// What the table's own spec draws (`between_sample`, resolved at its preset;
    /// `usize::MAX`: every square).
    pub published_sample: usize,
    pub points: Vec<SamplePoint>,
}

/// One sample size, over the redraws.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct SamplePoint {
    /// `between_sample`: the squares drawn at random beyond the census.
    pub sample: usize,
    /// Squares judged per draw (census and drawn); every visible one when the sample
    /// reaches the rest (then the estimate is exact and the calibration is empty).
    pub judged: usize,
    /// The first draw's estimates (relative L2, L1) ± their s.e.: the studies' own draw,
    /// what a table's report publishes at this size.
    pub own: [Figure<StdErr>; 2],
    pub l2: Calibration,
    pub l1: Calibration,
}

/// The estimator over the redraws, each draw's error e = estimate − exact mean and its
/// reported s.e. (plain means over the draws, each ± its own s.e.; no ratio or root).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Calibration {
    /// The share of draws with |e| ≤ 2 s.e. (0.954 for a normal estimate with an
    /// honest s.e.).
    pub coverage: Figure<StdErr>,
    /// The mean of e (0 for an unbiased estimator).
    pub bias: Figure<StdErr>,
    /// The mean of (e / s.e.)² (1 when the s.e. is honest).
    pub z2: Figure<StdErr>,
    /// The mean reported s.e.
    pub se: Figure<StdErr>,
}

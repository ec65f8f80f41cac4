//! The value every engine returns: a number together with its error and its cost.

use serde::{Deserialize, Serialize};
use std::fmt;

/// What the `error` field of an [`Estimate`] means.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorKind {
    /// One standard error of a (quasi-)Monte Carlo mean: the true value lies within
    /// ±3 of them with probability ≈ 0.997 if the CLT applies.
    StandardError,
    /// A deterministic quadrature error estimate (|Kronrod − Gauss|, or the difference
    /// between two rule orders): conservative for smooth integrands, not a bound.
    Quadrature,
}

/// An integral estimate with its error and the number of integrand evaluations used.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Estimate {
    pub value: f64,
    pub error: f64,
    pub evals: u64,
    pub kind: ErrorKind,
    /// False when an adaptive engine stopped on its budget before meeting its tolerance.
    pub converged: bool,
}

impl Estimate {
    /// Relative error estimate (error / |value|; the absolute error when value is 0).
    pub fn rel_error(&self) -> f64 {
        if self.value != 0.0 {
            self.error / self.value.abs()
        } else {
            self.error
        }
    }

    /// Whether `reference` lies within `k` errors of the estimate (plus `slack`).
    pub fn agrees_with(&self, reference: f64, k: f64, slack: f64) -> bool {
        (self.value - reference).abs() <= k * self.error + slack
    }
}

impl fmt::Display for Estimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = match self.kind {
            ErrorKind::StandardError => "s.e.",
            ErrorKind::Quadrature => "quad. est.",
        };
        write!(
            f,
            "{:.12e} ± {:.2e} ({kind}, {} evals{})",
            self.value,
            self.error,
            self.evals,
            if self.converged {
                ""
            } else {
                ", NOT converged"
            }
        )
    }
}

/// Welford running mean/variance, mergeable with Chan et al.'s pairwise formula.
#[derive(Clone, Copy, Debug, Default)]
pub struct Welford {
    pub n: u64,
    pub mean: f64,
    pub m2: f64,
}

impl Welford {
    pub fn push(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
    }

    pub fn merge(self, o: Welford) -> Welford {
        if self.n == 0 {
            return o;
        }
        if o.n == 0 {
            return self;
        }
        let n = self.n + o.n;
        let d = o.mean - self.mean;
        let mean = self.mean + d * (o.n as f64 / n as f64);
        let m2 = self.m2 + o.m2 + d * d * (self.n as f64 * o.n as f64 / n as f64);
        Welford { n, mean, m2 }
    }

    /// Standard error of the mean (0 for fewer than two observations).
    pub fn std_error(&self) -> f64 {
        if self.n < 2 {
            return 0.0;
        }
        (self.m2 / ((self.n - 1) as f64) / self.n as f64).sqrt()
    }
}

/// A sample mean (or a ratio of means) with its standard error: how every report writes a
/// measured spread as "value ± error". The one constructor from samples is [`MeanSe::of`];
/// the formatters below are the only ones reports use for it, and all write a value that
/// is not finite (a mean over no sample) as "—".
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeanSe {
    pub value: f64,
    pub se: f64,
}

impl MeanSe {
    /// The mean of `v` and its standard error (the n − 1 sample variance over n); NaN
    /// for an empty sample, and a zero error for a single sample.
    pub fn of(v: &[f64]) -> MeanSe {
        if v.is_empty() {
            return MeanSe {
                value: f64::NAN,
                se: f64::NAN,
            };
        }
        let n = v.len() as f64;
        let m = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
        MeanSe {
            value: m,
            se: (var / n).sqrt(),
        }
    }

    /// As a pair (value, s.e.).
    pub fn pair(self) -> (f64, f64) {
        (self.value, self.se)
    }

    /// "12.3 % ± 0.4": value and error in percent, `d` decimals each.
    pub fn pct(&self, d: usize) -> String {
        self.shown(|v, e| format!("{:.d$} % ± {:.d$}", 100.0 * v, 100.0 * e))
    }

    /// "+12.3 % ± 0.4": [`MeanSe::pct`] with the sign always written (a bias).
    pub fn pct_signed(&self, d: usize) -> String {
        self.shown(|v, e| format!("{:+.d$} % ± {:.d$}", 100.0 * v, 100.0 * e))
    }

    /// "1.234e-3 ± 5.6e-5": the value with `vd` decimals of mantissa, the error with `ed`.
    pub fn sci(&self, vd: usize, ed: usize) -> String {
        self.shown(|v, e| format!("{v:.vd$e} ± {e:.ed$e}"))
    }

    fn shown(&self, f: impl Fn(f64, f64) -> String) -> String {
        if self.value.is_finite() {
            f(self.value, self.se)
        } else {
            "—".into()
        }
    }
}

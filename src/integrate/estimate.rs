//! The value every engine returns: a number together with its error and its cost.

use serde::{Deserialize, Serialize};
use std::fmt;

/// What the `error` field of an [`Estimate`] means.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
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

    /// "1.234e-3 ± 5.6e-5", as [`Figure::sci`] writes a figure of this estimate's kind.
    pub fn sci(&self, vd: usize, ed: usize) -> String {
        match self.kind {
            ErrorKind::StandardError => Figure::<StdErr>::new(self.value, self.error).sci(vd, ed),
            ErrorKind::Quadrature => Figure::<Quad>::new(self.value, self.error).sci(vd, ed),
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

/// What a [`Figure`]'s error means, as a type: the kind of a figure is part of its type,
/// so an s.e. is never added to a quadrature bar by mistake, and the stored form stays
/// `{value, error}` (the result's type says which kind it holds).
pub trait Kind: Copy + Default + fmt::Debug + PartialEq + Send + Sync + 'static {
    const KIND: ErrorKind;
}

/// A standard error of a mean over independent samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StdErr;
impl Kind for StdErr {
    const KIND: ErrorKind = ErrorKind::StandardError;
}

/// A deterministic error estimate of a quadrature (or the half-width of the interval a
/// quadrature's error estimates allow a ratio of integrals).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quad;
impl Kind for Quad {
    const KIND: ErrorKind = ErrorKind::Quadrature;
}

/// A measured value with its error and the error's kind: how every studied number is
/// stored and reported. The constructor from samples is [`Figure::mean_of`]; the
/// formatters below are the only ones reports use for a measurement, and all write a
/// value that is not finite (a mean over no sample) as "—".
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound = "")]
pub struct Figure<K: Kind = StdErr> {
    #[serde(deserialize_with = "f64_or_nan")]
    pub value: f64,
    #[serde(deserialize_with = "f64_or_nan")]
    pub error: f64,
    #[serde(skip)]
    kind: std::marker::PhantomData<K>,
}

/// A number written as `null` (serde_json writes a NaN or an infinity so) reads back as
/// NaN, the value it stood for in the statistics that may hold one.
pub fn f64_or_nan<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

impl<K: Kind> Figure<K> {
    pub const fn new(value: f64, error: f64) -> Figure<K> {
        Figure {
            value,
            error,
            kind: std::marker::PhantomData,
        }
    }

    /// No value (a mean over no sample): NaN ± NaN, written "—".
    pub const NONE: Figure<K> = Figure::new(f64::NAN, f64::NAN);

    /// What the error means.
    pub fn kind(&self) -> ErrorKind {
        K::KIND
    }

    /// As a pair (value, error).
    pub fn pair(self) -> (f64, f64) {
        (self.value, self.error)
    }

    /// "12.3 % ± 0.4": value and error in percent, `d` decimals each.
    pub fn pct_fixed(&self, d: usize) -> String {
        self.shown(|v, e| format!("{:.d$} % ± {:.d$}", 100.0 * v, 100.0 * e))
    }

    /// "+12.3 % ± 0.4": [`Figure::pct_fixed`] with the sign always written (a bias).
    pub fn pct_signed(&self, d: usize) -> String {
        self.shown(|v, e| format!("{:+.d$} % ± {:.d$}", 100.0 * v, 100.0 * e))
    }

    /// "+1.23 ± 0.45 points": a change of a percentage, in percentage points.
    pub fn points_signed(&self, d: usize) -> String {
        self.shown(|v, e| format!("{:+.d$} ± {:.d$} points", 100.0 * v, 100.0 * e))
    }

    /// The figure in other units: value and error times `k` (e.g. 100 for a percentage,
    /// or seconds to minutes over a whole run).
    pub fn scaled(self, k: f64) -> Figure<K> {
        Figure::new(k * self.value, k.abs() * self.error)
    }

    /// "0.1234 ± 0.0056": value and error as they are, `d` decimals each.
    pub fn fixed(&self, d: usize) -> String {
        self.shown(|v, e| format!("{v:.d$} ± {e:.d$}"))
    }

    /// "+1.234e-3 ± 5.6e-5": [`Figure::sci`] with the sign always written (a bias).
    pub fn sci_signed(&self, vd: usize, ed: usize) -> String {
        self.shown(|v, e| format!("{v:+.vd$e} ± {e:.ed$e}"))
    }

    /// "1.234e-3 ± 5.6e-5": the value with `vd` decimals of mantissa, the error with `ed`.
    pub fn sci(&self, vd: usize, ed: usize) -> String {
        self.shown(|v, e| format!("{v:.vd$e} ± {e:.ed$e}"))
    }

    /// As a percentage to its error bar: to the bar's first significant digit, at least
    /// `min_decimals` decimals and at most six significant digits of the value. A bar
    /// below the last printed digit is written as a bound: "6.96844 ± <0.00001 %", never
    /// as "± 0.00000". A zero bar (a difference of exactly known values) prints the value
    /// alone.
    fn pct_to_bar(&self, min_decimals: usize) -> String {
        if !self.value.is_finite() {
            return "—".into();
        }
        let (v, e) = (100.0 * self.value, 100.0 * self.error);
        if e == 0.0 {
            return format!("{v:.min_decimals$} %");
        }
        let bar_digits = if e > 0.0 && e.is_finite() {
            (-e.log10()).ceil().max(0.0) as usize
        } else {
            usize::MAX
        };
        let value_digits = if v != 0.0 {
            (5.0 - v.abs().log10().floor()).clamp(0.0, 9.0) as usize
        } else {
            6
        };
        let d = bar_digits.min(value_digits).max(min_decimals);
        if !e.is_finite() {
            return format!("{v:.d$} ± — %");
        }
        let last = 10f64.powi(-(d as i32));
        if e < 0.5 * last {
            format!("{v:.d$} ± <{last:.d$} %")
        } else {
            format!("{v:.d$} ± {e:.d$} %")
        }
    }

    fn shown(&self, f: impl Fn(f64, f64) -> String) -> String {
        if self.value.is_finite() {
            f(self.value, self.error)
        } else {
            "—".into()
        }
    }
}

/// How each kind is written in percent: a deterministic bar to its own first digit, a
/// standard error (itself noisy) at a fixed number of decimals.
impl Figure<Quad> {
    /// "6.96844 ± <0.00001 %" (see `pct_to_bar`): at least `min_decimals` decimals.
    pub fn pct(&self, min_decimals: usize) -> String {
        self.pct_to_bar(min_decimals)
    }

    /// The mean of figures each within its bar of its true value: the mean of the values,
    /// within the mean of the bars of the mean of the true values (|Σ eᵢ|/n ≤ Σ bᵢ/n).
    /// NaN for none.
    pub fn mean_bounded(v: &[Figure<Quad>]) -> Figure<Quad> {
        if v.is_empty() {
            return Figure::NONE;
        }
        let n = v.len() as f64;
        Figure::new(
            v.iter().map(|f| f.value).sum::<f64>() / n,
            v.iter().map(|f| f.error).sum::<f64>() / n,
        )
    }
}

impl Figure<StdErr> {
    /// A mean and its standard error.
    pub const fn with_se(value: f64, se: f64) -> Figure {
        Figure::new(value, se)
    }

    /// "12.3 % ± 0.4" with `d` decimals each ([`Figure::pct_fixed`]).
    pub fn pct(&self, d: usize) -> String {
        self.pct_fixed(d)
    }

    /// The mean of `v` and its standard error (the n − 1 sample variance over n); NaN
    /// for an empty sample, and a zero error for a single sample.
    pub fn mean_of(v: &[f64]) -> Figure {
        if v.is_empty() {
            return Figure::NONE;
        }
        let n = v.len() as f64;
        let m = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
        Figure::with_se(m, (var / n).sqrt())
    }

    /// An estimate `x`'s relative error against this truth, "+1.2 % ± 0.3" (the ± is the
    /// truth's s.e. relative to it); "—" for a truth that is not positive.
    pub fn rel_error_of(&self, x: f64) -> String {
        if self.value > 0.0 {
            Figure::with_se(x / self.value - 1.0, self.error / self.value).pct_signed(1)
        } else {
            "—".into()
        }
    }

    /// The mean of y over a population of `population` places from a simple random sample
    /// of them (drawn without replacement) by the difference estimator with a control x
    /// known at every place: `control_mean` (x's mean over the population) plus the mean of
    /// `diffs` (y − x at the sampled places), with the standard error
    /// √((1 − m/N)·s²/m) of m differences (s² their n − 1 variance; Cochran 1977, §7.2 and
    /// §2.5). Unbiased for the population mean whatever the control; the closer x follows
    /// y, the smaller the error. The whole population sampled: the exact mean, error 0.
    /// NaN for no sample or more sampled places than the population holds.
    pub fn difference_mean(control_mean: f64, diffs: &[f64], population: usize) -> Figure {
        let m = diffs.len();
        if m == 0 || m > population {
            return Figure::NONE;
        }
        let d = Figure::mean_of(diffs);
        let fpc = 1.0 - m as f64 / population as f64;
        Figure::with_se(control_mean + d.value, d.error * fpc.sqrt())
    }

    /// [`Figure::mean_of`] over the finite values of `v` only.
    pub fn mean_of_finite(v: &[f64]) -> Figure {
        let f: Vec<f64> = v.iter().copied().filter(|a| a.is_finite()).collect();
        Figure::mean_of(&f)
    }
}

//! Compact LTC tables: each channel of a fitted n×n table (a, b, c, d, norm, fresnel on
//! the (r = √α, t = √(1 − cos θ)) grid of `ltc::table`) as a tensor-product Chebyshev
//! series of degree < p in each of r and t — p² coefficients per channel instead of n².
//!
//! - A channel is fitted on its transformed values ([`Transform`]): `Raw`, or `Log` for a
//!   positive channel whose relative error is what the lobe feels (M⁻¹'s d ∝ α at small
//!   α, a sheen norm spanning 18 decades).
//! - The fit is linear least squares over the table's n² entries. On a full tensor grid
//!   with a tensor-product basis it separates: with A the n×p Chebyshev–Vandermonde matrix
//!   at the grid's nodes x_i = 2i/(n − 1) − 1, the coefficients are C = A⁺ V (A⁺)ᵀ, A⁺
//!   the pseudo-inverse (nalgebra's SVD). The fit is judged elsewhere by the lobe error
//!   after rebuilding (`studies::ltc_compact`), not by the distance to the entries.
//! - Evaluation is Clenshaw's recurrence along r for each t-degree, then along t: p² + p
//!   multiply-adds per channel. [`Compact::eval`] is the f64 reference, [`Compact::eval_f32`]
//!   the shading form (the same recurrence in f32, as generated shader code runs it).
//! - [`Compact::rebuild`] evaluates the series at the texel centres, as an engine's
//!   start-up code would fill its textures; the binary16 entries are the nearest.

use crate::error::{Error, Result};
use crate::ltc::table::FittedTable;
use nalgebra::{DMatrix, RealField};

/// The largest series degree per axis (p): 64² coefficients per channel already match a
/// 64² table entry for entry.
pub const MAX_P: usize = 64;

/// How a channel is fitted: on its values, on their logarithm (a positive channel), or
/// on the values over α(r) = max(r², α_min) (a channel that vanishes like α as α → 0,
/// GGX M⁻¹'s b and d: the series then stays O(1) down to the smallest α, and its absolute
/// error shrinks with the lobe).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Transform {
    Raw,
    Log,
    OverAlpha,
}

impl Transform {
    /// The series value of channel value `v` where the roughness is `alpha`.
    pub(crate) fn forward(self, v: f64, alpha: f64) -> f64 {
        match self {
            Transform::Raw => v,
            Transform::Log => v.ln(),
            Transform::OverAlpha => v / alpha,
        }
    }
    /// The inverse, in the precision of the caller's evaluation.
    pub(crate) fn inverse<T: RealField + Copy>(self, v: T, alpha: T) -> T {
        match self {
            Transform::Raw => v,
            Transform::Log => v.exp(),
            Transform::OverAlpha => v * alpha,
        }
    }
    /// d(inverse)/d(series value) at series value `v`.
    pub(crate) fn slope(self, v: f64, alpha: f64) -> f64 {
        match self {
            Transform::Raw => 1.0,
            Transform::Log => v.exp(),
            Transform::OverAlpha => alpha,
        }
    }
}

/// One channel: `coeffs[k + p·l]` multiplies T_k(2r − 1)·T_l(2t − 1); the channel's value
/// is the transform's inverse of the sum.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Series {
    pub transform: Transform,
    pub coeffs: Vec<f64>,
}

/// A compact table: the six channels of `ltc::table::FittedTable`, each a p×p series.
/// Read back (results/fits/ltc-compact.json), it is checked as [`Compact::check`] does.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "Unchecked")]
pub struct Compact {
    pub p: usize,
    /// The α floor of α(r) = max(r², α_min) that `OverAlpha` channels divide by (the
    /// table's grid's; 0 when no channel uses it).
    #[serde(default)]
    pub alpha_min: f64,
    pub channels: Vec<Series>,
}

/// A [`Compact`] as a file holds it, before its shape is checked.
#[derive(serde::Deserialize)]
struct Unchecked {
    p: usize,
    #[serde(default)]
    alpha_min: f64,
    channels: Vec<Series>,
}

impl TryFrom<Unchecked> for Compact {
    type Error = Error;
    fn try_from(u: Unchecked) -> Result<Compact> {
        let c = Compact {
            p: u.p,
            alpha_min: u.alpha_min,
            channels: u.channels,
        };
        c.check()?;
        Ok(c)
    }
}

/// Σ_k c_k T_k(x) by Clenshaw's recurrence, in the coefficients' precision.
fn clenshaw<T: RealField + Copy>(c: &[T], x: T) -> T {
    let (mut b1, mut b2) = (T::zero(), T::zero());
    for &ck in c.iter().skip(1).rev() {
        let b0 = ck + (x + x) * b1 - b2;
        b2 = b1;
        b1 = b0;
    }
    c.first().copied().unwrap_or_else(T::zero) + x * b1 - b2
}

/// Σ_kl c[k + p·l]·T_k(x)·T_l(y): Clenshaw along x for each l, then along y.
fn series_at<T: RealField + Copy>(c: &[T], p: usize, x: T, y: T) -> T {
    let mut g = [T::zero(); MAX_P];
    for (l, gl) in g.iter_mut().enumerate().take(p) {
        *gl = clenshaw(&c[p * l..p * (l + 1)], x);
    }
    clenshaw(&g[..p], y)
}

/// The n×p Chebyshev–Vandermonde matrix at x_i = 2i/(n − 1) − 1 (T_k by its three-term
/// recurrence).
pub(crate) fn vandermonde(n: usize, p: usize) -> DMatrix<f64> {
    DMatrix::from_fn(n, p, |i, k| {
        let x = 2.0 * i as f64 / (n - 1) as f64 - 1.0;
        let (mut t0, mut t1) = (1.0, x);
        if k == 0 {
            return t0;
        }
        for _ in 1..k {
            (t0, t1) = (t1, 2.0 * x * t1 - t0);
        }
        t1
    })
}

impl Compact {
    /// Fit every channel of `table` as a p×p series under its transform (no `OverAlpha`
    /// channel: see [`Compact::fit_scaled`]). A typed error when p is 0 or exceeds the
    /// table's side, when an entry is not finite, or when a `Log` channel has an entry ≤ 0.
    pub fn fit(table: &FittedTable, p: usize, transforms: [Transform; 6]) -> Result<Compact> {
        Compact::fit_scaled(table, p, transforms, 0.0)
    }

    /// [`Compact::fit`] with the table grid's α floor, which `OverAlpha` channels need
    /// (a typed error when one is asked for with `alpha_min` not in (0, 1)).
    pub fn fit_scaled(
        table: &FittedTable,
        p: usize,
        transforms: [Transform; 6],
        alpha_min: f64,
    ) -> Result<Compact> {
        let n = table.n;
        if transforms.contains(&Transform::OverAlpha) && !(alpha_min > 0.0 && alpha_min < 1.0) {
            return Err(Error::InvalidArgument(format!(
                "compact LTC: an over-alpha channel needs the grid's α floor in (0, 1); it is {alpha_min}"
            )));
        }
        if n < 2 || table.cells.len() != n * n {
            return Err(Error::InvalidArgument(format!(
                "compact LTC: a table of side {n} with {} cells",
                table.cells.len()
            )));
        }
        if p == 0 || p > n.min(MAX_P) {
            return Err(Error::InvalidArgument(format!(
                "compact LTC: degree p = {p} must lie in 1..={} (the table's side, at most {MAX_P})",
                n.min(MAX_P)
            )));
        }
        let a = vandermonde(n, p);
        let pinv = a
            .clone()
            .pseudo_inverse(1e-12)
            .map_err(|e| Error::InvalidArgument(format!("compact LTC: pseudo-inverse: {e}")))?;
        let channels = transforms
            .iter()
            .enumerate()
            .map(|(ch, &tr)| {
                // V[i, j]: r index i, t index j
                let mut v = DMatrix::zeros(n, n);
                for j in 0..n {
                    for i in 0..n {
                        let x = table.cells[i + n * j][ch];
                        let r = i as f64 / (n - 1) as f64;
                        let y = tr.forward(x, (r * r).max(alpha_min));
                        if !x.is_finite() || !y.is_finite() {
                            return Err(Error::InvalidArgument(format!(
                                "compact LTC: channel {ch} at cell ({i}, {j}) is {x}, which the {tr:?} transform cannot fit"
                            )));
                        }
                        v[(i, j)] = y;
                    }
                }
                let c = &pinv * v * pinv.transpose();
                Ok(Series {
                    transform: tr,
                    coeffs: (0..p * p).map(|q| c[(q % p, q / p)]).collect(),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Compact {
            p,
            alpha_min,
            channels,
        })
    }

    /// Six channels of p² finite coefficients each, 1 ≤ p ≤ [`MAX_P`]: what evaluation
    /// indexes. A typed error naming what is wrong otherwise.
    pub fn check(&self) -> Result<()> {
        let p = self.p;
        let scaled = self
            .channels
            .iter()
            .any(|s| s.transform == Transform::OverAlpha);
        if scaled && !(self.alpha_min > 0.0 && self.alpha_min < 1.0) {
            return Err(Error::InvalidArgument(format!(
                "compact LTC: an over-alpha channel with α floor {} (need one in (0, 1))",
                self.alpha_min
            )));
        }
        if p == 0 || p > MAX_P || self.channels.len() != 6 {
            return Err(Error::InvalidArgument(format!(
                "compact LTC: p = {p} (1..={MAX_P}) with {} channels (6)",
                self.channels.len()
            )));
        }
        match self
            .channels
            .iter()
            .position(|s| s.coeffs.len() != p * p || s.coeffs.iter().any(|c| !c.is_finite()))
        {
            Some(ch) => {
                Err(Error::InvalidArgument(format!(
                "compact LTC: channel {ch} needs {} finite coefficients; it has {} ({} not finite)",
                p * p,
                self.channels[ch].coeffs.len(),
                self.channels[ch].coeffs.iter().filter(|c| !c.is_finite()).count()
            )))
            }
            None => Ok(()),
        }
    }

    /// The same transforms at degree `q`: coefficient (k, l) kept where both are below q,
    /// zero where the series had none. The cost of evaluating a series depends on q alone,
    /// so this times (and counts the instructions of) a degree no fit stored. A typed error
    /// for q outside 1..=`MAX_P`.
    pub fn resized(&self, q: usize) -> Result<Compact> {
        if !(1..=MAX_P).contains(&q) {
            return Err(Error::InvalidArgument(format!(
                "compact LTC: p = {q} (1..={MAX_P})"
            )));
        }
        let p = self.p;
        let channels = self
            .channels
            .iter()
            .map(|s| Series {
                transform: s.transform,
                coeffs: (0..q * q)
                    .map(|i| {
                        let (k, l) = (i % q, i / q);
                        if k < p && l < p {
                            s.coeffs[k + p * l]
                        } else {
                            0.0
                        }
                    })
                    .collect(),
            })
            .collect();
        Ok(Compact {
            p: q,
            alpha_min: self.alpha_min,
            channels,
        })
    }

    /// The number of coefficients (all channels).
    pub fn coefficients(&self) -> usize {
        self.channels.iter().map(|s| s.coeffs.len()).sum()
    }

    /// The six channels at (r, t) ∈ [0, 1]² (clamped), in f64: the reference.
    pub fn eval(&self, r: f64, t: f64) -> [f64; 6] {
        let (r, t) = (r.clamp(0.0, 1.0), t.clamp(0.0, 1.0));
        let (x, y) = (2.0 * r - 1.0, 2.0 * t - 1.0);
        let alpha = (r * r).max(self.alpha_min);
        let p = self.p;
        std::array::from_fn(|ch| {
            let s = &self.channels[ch];
            s.transform.inverse(series_at(&s.coeffs, p, x, y), alpha)
        })
    }

    /// The coefficients rounded to f32, as a shader holds them.
    pub fn coeffs_f32(&self) -> Vec<Vec<f32>> {
        self.channels
            .iter()
            .map(|s| s.coeffs.iter().map(|&c| c as f32).collect())
            .collect()
    }

    /// [`Compact::eval`] in f32 from f32 coefficients (`coeffs_f32`): the shading form.
    pub fn eval_f32(&self, coeffs: &[Vec<f32>], r: f32, t: f32) -> [f32; 6] {
        let (r, t) = (r.clamp(0.0, 1.0), t.clamp(0.0, 1.0));
        let (x, y) = (2.0 * r - 1.0, 2.0 * t - 1.0);
        let alpha = (r * r).max(self.alpha_min as f32);
        let p = self.p;
        std::array::from_fn(|ch| {
            self.channels[ch]
                .transform
                .inverse(series_at(&coeffs[ch], p, x, y), alpha)
        })
    }

    /// The n×n table the series give at the texel centres (r, t) = (i, j)/(n − 1), with
    /// its binary16 storage the nearest binary16 of each entry. A typed error for a side
    /// below 2 (no grid spacing).
    pub fn rebuild(&self, n: usize) -> Result<FittedTable> {
        if !(2..=crate::ltc::table::MAX_SIDE).contains(&n) {
            return Err(Error::InvalidArgument(format!(
                "compact LTC: a rebuilt table of side {n} (2..={})",
                crate::ltc::table::MAX_SIDE
            )));
        }
        let cells: Vec<[f64; 6]> = (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                self.eval(i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64)
            })
            .collect();
        let half = cells.iter().map(|c| c.map(half::f16::from_f64)).collect();
        Ok(FittedTable {
            n,
            cells,
            half: Some(half),
        })
    }
}

//! Overall roughness of a footprint: one isotropic LTC fitted to γ_me ∗ γ_mi (seed 000
//! §3.4–3.5) under selectable metrics, the paper's Eq 7, its refit, the rules engines
//! ship, and a model with both limits built in.

use super::convolution::{
    density_table, l2_distance2, ltc_cap_integral, Convolution, Polygon, ZonalTable,
};
use super::mrl::{alpha_from_one_minus, mrl_pair};
use crate::error::{Error, Result};
use crate::integrate::quad::{adaptive_batched, Tol};
use crate::ltc::LtcDist;
use serde::Serialize;
use std::f64::consts::PI;

/// Fitting metric for the one-LTC approximation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Metric {
    /// Match the unclipped mean resultant length: ρ(α) = ρ(α_me)·ρ(α_mi) (closed form).
    MomentUnclipped,
    /// Match the clipped, renormalised mean resultant length (horizon-aware).
    MomentClipped,
    /// Minimise the L2 distance between densities over the sphere.
    L2,
    /// Minimise the squared relative error of the energy in a set of lights: spherical
    /// caps and convex polygons.
    Caps,
}

impl Metric {
    pub const ALL: [Metric; 4] = [
        Metric::MomentUnclipped,
        Metric::MomentClipped,
        Metric::L2,
        Metric::Caps,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Metric::MomentUnclipped => "moment (unclipped ‖b̄‖)",
            Metric::MomentClipped => "moment (clipped ‖b̄‖)",
            Metric::L2 => "L2 of densities",
            Metric::Caps => "lights: caps + polygons (rel. energy)",
        }
    }
}

/// Nodes per panel of the coarser density table whose caps bound the fine table's error.
const CAP_CHECK_NODES: usize = 12;

/// Cap lights of the rendering metric: (polar angle of the axis, half-angle), radians.
pub const CAPS: [(f64, f64); 9] = [
    (0.0, 0.05),
    (0.0, 0.2),
    (0.0, 0.6),
    (0.5, 0.1),
    (0.5, 0.3),
    (1.0, 0.2),
    (1.0, 0.5),
    (1.3, 0.3),
    (0.8, 1.0),
];

/// Polygon lights of the rendering metric.
pub fn polygons() -> Vec<Polygon> {
    vec![
        Polygon::quad("quad θ=0.4, 0.3×0.3", 0.4, 0.15, 0.15),
        Polygon::quad("quad θ=0, 1.0×0.4", 0.0, 0.5, 0.2),
        Polygon::quad("quad θ=1.2, 0.3×0.1", 1.2, 0.15, 0.05),
        Polygon::quad("quad θ=0.8, 0.04×0.04", 0.8, 0.02, 0.02),
    ]
}

/// Under the unclipped moment metric the overall α is closed form: ρ(α) = ρ_me·ρ_mi, i.e.
/// α = ρ⁻¹(‖b̄‖·ρ(α_mi)) — the mip chain's ‖b̄‖ times the micro lobe's ρ, fed to the same
/// inverse as α_me (proofs/mrl-product.md). No Eq 7 is needed for this metric.
pub fn alpha_moment(alpha_mi: f64, alpha_me: f64) -> Result<f64> {
    let (b_me, y_me) = mrl_pair(alpha_me);
    let (b_mi, y_mi) = mrl_pair(alpha_mi);
    // ρ = ρ_me ρ_mi and 1 − ρ = y_me + y_mi − y_me y_mi, each without cancellation (the
    // inverse takes whichever is small)
    super::mrl::alpha_from_pair(b_me * b_mi, y_me + y_mi - y_me * y_mi)
}

/// Seed 000 Eq 7.
pub fn eq7(alpha_mi: f64, alpha_me: f64) -> f64 {
    0.07 * alpha_mi * alpha_mi + 0.94 * alpha_mi + alpha_me - 0.83 * alpha_mi * alpha_me
}

/// α² = α_mi² + α_me².
pub fn sum_of_squares(alpha_mi: f64, alpha_me: f64) -> f64 {
    alpha_mi.hypot(alpha_me)
}

/// vMF rules: α′² = α_mi² + k/κ with κ = (3r − r³)/(1 − r²) (Banerjee) and r = ρ(α_me);
/// k = 2, 1, 1/2 as shipped by different engines.
pub fn vmf(alpha_mi: f64, alpha_me: f64, k: f64) -> f64 {
    let (r, y) = mrl_pair(alpha_me);
    let kappa = (3.0 * r - r * r * r) / (y * (1.0 + r));
    (alpha_mi * alpha_mi + k / kappa).sqrt()
}

/// The polynomial model: α² = α_mi² + α_me² + α_mi α_me Σ c_ij α_mi^i α_me^j (i + j ≤ 2).
/// Both limits α(α_mi, 0) = α_mi and α(0, α_me) = α_me hold for any coefficients, and the
/// small-α behaviour is the hypot of the two (as the moment identity implies there).
pub fn improved(c: &[f64], alpha_mi: f64, alpha_me: f64) -> f64 {
    let (x, y) = (alpha_mi, alpha_me);
    let p = c[0] + c[1] * x + c[2] * y + c[3] * x * x + c[4] * x * y + c[5] * y * y;
    (x * x + y * y + x * y * p).max(0.0).sqrt()
}

/// Linear least squares (nalgebra SVD) with the given design rows and targets.
fn lstsq(rows: &[Vec<f64>], t: &[f64]) -> Result<Vec<f64>> {
    let (n, k) = (rows.len(), rows[0].len());
    let a = nalgebra::DMatrix::from_fn(n, k, |i, j| rows[i][j]);
    let b = nalgebra::DVector::from_column_slice(t);
    let x = a
        .svd(true, true)
        .solve(&b, 1e-14)
        .map_err(|e| Error::InvalidArgument(format!("least squares: {e}")))?;
    Ok(x.iter().copied().collect())
}

/// Refit Eq 7's basis {α_mi², α_mi, α_me, α_mi α_me} to (α_mi, α_me, α) samples; returns
/// (coefficients, SSE).
pub fn refit_eq7(samples: &[(f64, f64, f64)]) -> Result<(Vec<f64>, f64)> {
    let rows: Vec<Vec<f64>> = samples
        .iter()
        .map(|&(x, y, _)| vec![x * x, x, y, x * y])
        .collect();
    let t: Vec<f64> = samples.iter().map(|s| s.2).collect();
    let c = lstsq(&rows, &t)?;
    let sse = samples
        .iter()
        .map(|&(x, y, a)| (c[0] * x * x + c[1] * x + c[2] * y + c[3] * x * y - a).powi(2))
        .sum();
    Ok((c, sse))
}

/// Fit the polynomial model by relative least squares on α² (weights 1/α²).
pub fn fit_improved(samples: &[(f64, f64, f64)]) -> Result<Vec<f64>> {
    let rows: Vec<Vec<f64>> = samples
        .iter()
        .map(|&(x, y, a)| {
            let w = x * y / (a * a);
            vec![w, w * x, w * y, w * x * x, w * x * y, w * y * y]
        })
        .collect();
    let t: Vec<f64> = samples
        .iter()
        .map(|&(x, y, a)| (a * a - x * x - y * y) / (a * a))
        .collect();
    lstsq(&rows, &t)
}

/// Energy of the one-LTC fit in each light (caps, then polygons).
fn lights_of_ltc(alpha: f64, polys: &[Polygon]) -> Vec<f64> {
    let t = Tol::new(1e-10, 1e-9, 2_000_000);
    let d = LtcDist::isotropic(alpha).expect("α > 0");
    let mut v: Vec<f64> = CAPS
        .iter()
        .map(|&(th, r)| {
            ltc_cap_integral(alpha, th, r, t)
                .map(|e| e.value)
                .unwrap_or(f64::NAN)
        })
        .collect();
    v.extend(polys.iter().map(|p| p.integral(&|m| d.eval(m), t).value));
    v
}

/// The azimuthal length Φ(θ) of the circle at polar angle θ inside the cap with axis at
/// θ_c and half-angle r: 2 acos((cos r − cos θ cos θ_c)/(sin θ sin θ_c)), 2π when the
/// circle is inside.
fn cap_arc(t: f64, theta_c: f64, r: f64) -> f64 {
    let (st, ct) = t.sin_cos();
    let (sc, cc) = theta_c.sin_cos();
    if st * sc == 0.0 {
        return if (t - theta_c).abs() <= r {
            2.0 * PI
        } else {
            0.0
        };
    }
    let x = (r.cos() - ct * cc) / (st * sc);
    if x <= -1.0 {
        2.0 * PI
    } else if x >= 1.0 {
        0.0
    } else {
        2.0 * x.acos()
    }
}

/// ∫_cap of a zonal density `c` (`c(θs)` gives its values at up to 15 θ, with their errors
/// and the evaluations spent) as a 1D integral over θ: the circle at θ meets the cap in an
/// arc of length [`cap_arc`]. Panels break at the cap's edges, its axis, and geometrically
/// from a quarter of the lobe `width` (as the radial moments do).
fn zonal_cap(
    c: &dyn Fn(&[f64; 15]) -> ([f64; 15], [f64; 15], u64),
    width: f64,
    theta_c: f64,
    r: f64,
    tol: Tol,
) -> crate::integrate::Estimate {
    let lo = (theta_c - r).max(0.0);
    let hi = (theta_c + r).min(PI);
    let mut breaks = vec![lo, hi];
    if theta_c > r && theta_c + r < PI {
        breaks.push(theta_c);
    }
    let mut th = 0.25 * width;
    while th < hi {
        if th > lo {
            breaks.push(th);
        }
        th *= 2.0;
    }
    breaks.sort_by(|a, b| a.total_cmp(b));
    breaks.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let eval = |xs: &[f64; 15]| {
        let (cv, ce, n) = c(xs);
        let mut v = [0.0; 15];
        let mut e = [0.0; 15];
        for (i, &t) in xs.iter().enumerate() {
            let k = cap_arc(t, theta_c, r) * t.sin();
            v[i] = k * cv[i];
            e[i] = (k * ce[i]).abs();
        }
        (v, e, n)
    };
    adaptive_batched(&eval, &breaks, tol)
}

/// The lobe width the convolution's θ panels follow.
fn conv_width(conv: &Convolution) -> f64 {
    conv.alpha_me.max(conv.alpha_mi).min(1.0)
}

/// ∫_cap c for the convolution, every c(θ) by its own adaptive sphere quadrature
/// (`Convolution::density`, a tenth of `tol`): the reference of [`table_cap`].
pub fn conv_cap(conv: &Convolution, theta_c: f64, r: f64, tol: Tol) -> crate::integrate::Estimate {
    let inner = Tol::new(tol.abs * 0.1, tol.rel * 0.1, 2_000_000);
    let c = |xs: &[f64; 15]| {
        use rayon::prelude::*;
        let r: Vec<crate::integrate::Estimate> =
            xs.par_iter().map(|&t| conv.density(t, inner)).collect();
        let mut v = [0.0; 15];
        let mut e = [0.0; 15];
        let mut n = 0;
        for (i, est) in r.iter().enumerate() {
            v[i] = est.value;
            e[i] = est.error;
            n += est.evals;
        }
        (v, e, n)
    };
    zonal_cap(&c, conv_width(conv), theta_c, r, tol)
}

/// ∫_cap c for the convolution read from its tabulated density (`density_table`): the same
/// θ integral as [`conv_cap`] over the interpolant, so each cap costs no sphere quadrature.
/// The error is the θ quadrature's plus the table's: |∫_cap fine − ∫_cap coarse|, the
/// same cap over `coarse`, a table of the same convolution on fewer nodes per panel (an
/// estimate of the coarse table's interpolation error, and so, the interpolant converging
/// spectrally, an overestimate of the fine one's).
pub fn table_cap(
    fine: &ZonalTable,
    coarse: &ZonalTable,
    width: f64,
    theta_c: f64,
    r: f64,
    tol: Tol,
) -> crate::integrate::Estimate {
    fn read(t: &ZonalTable) -> impl Fn(&[f64; 15]) -> ([f64; 15], [f64; 15], u64) + '_ {
        move |xs| (xs.map(|x| t.eval(x)), [0.0; 15], 15)
    }
    let mut e = zonal_cap(&read(fine), width, theta_c, r, tol);
    let c = zonal_cap(&read(coarse), width, theta_c, r, tol);
    e.error += c.error + (e.value - c.value).abs();
    e.evals += c.evals;
    e
}

/// The best α for one (α_mi, α_me) pair under each metric (Brent via argmin for L2 and caps).
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct PairFit {
    pub alpha_mi: f64,
    pub alpha_me: f64,
    pub moment_unclipped: f64,
    pub moment_clipped: f64,
    pub l2: f64,
    pub caps: f64,
    /// Relative quadrature error reached by the cap integrals of the convolution (worst).
    pub cap_quad_rel_error: f64,
}

/// The coarse log scan [`brent_min`] brackets its minimum with: 41 points from lo to hi.
fn scan_points(lo: f64, hi: f64) -> Vec<f64> {
    let n = 40;
    (0..=n)
        .map(|i| lo * (hi / lo).powf(i as f64 / n as f64))
        .collect()
}

fn brent_min(f: &dyn Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    // coarse log scan for a bracket, then Brent inside it
    crate::optimize::scan_brent(f, &scan_points(lo, hi), (1e-10, 1e-12), 200)
}

/// The one-LTC energies in every light ([`lights_of_ltc`]) at the points of the caps
/// metric's scan over [`QUAD_DOMAIN`]. They depend on α alone, not on the pair, so a set
/// of pair fits computes them once ([`fit_pair_with`]) instead of once per pair; every
/// value is the one [`lights_of_ltc`] gives at that α, so the fits do not change by a bit.
pub struct LightScan {
    /// (α's bits, the energies) at every scan point.
    at: Vec<(u64, Vec<f64>)>,
}

impl LightScan {
    /// The 41 light sets of the scan (adaptive quadratures, in parallel).
    pub fn compute() -> LightScan {
        use rayon::prelude::*;
        let polys = polygons();
        let xs = scan_points(QUAD_DOMAIN.0, QUAD_DOMAIN.1);
        LightScan {
            at: xs
                .par_iter()
                .map(|&a| (a.to_bits(), lights_of_ltc(a, &polys)))
                .collect(),
        }
    }

    /// The energies at α: from the scan where α is one of its points, else computed.
    fn lights(&self, alpha: f64, polys: &[Polygon]) -> std::borrow::Cow<'_, [f64]> {
        match self.at.iter().find(|(b, _)| *b == alpha.to_bits()) {
            Some((_, v)) => std::borrow::Cow::Borrowed(v),
            None => std::borrow::Cow::Owned(lights_of_ltc(alpha, polys)),
        }
    }
}

/// Roughness range on which the quadrature metrics (clipped moment, L2, caps) are fitted:
/// the bracket of their Brent search. Outside it [`fit_pair`] is a typed error and
/// [`evaluate_pair`] gives the closed form and the limits instead.
pub const QUAD_DOMAIN: (f64, f64) = (1e-3, 3.0);

/// Fit one pair under every metric (both α in [`QUAD_DOMAIN`]; about 1 s of quadrature,
/// every integral under an evaluation budget).
pub fn fit_pair(alpha_mi: f64, alpha_me: f64) -> Result<PairFit> {
    // refuse a pair outside the domain before the scan's 41 quadratures
    in_quad_domain(alpha_mi, alpha_me)?;
    fit_pair_with(&LightScan::compute(), alpha_mi, alpha_me)
}

/// Both α inside [`QUAD_DOMAIN`] (NaN is not), or the typed error naming the one outside.
fn in_quad_domain(alpha_mi: f64, alpha_me: f64) -> Result<()> {
    for a in [alpha_mi, alpha_me] {
        if !(QUAD_DOMAIN.0..=QUAD_DOMAIN.1).contains(&a) {
            return Err(Error::InvalidArgument(format!(
                "overall α by quadrature needs α_mi and α_me in [{:e}, {:e}], got {a:e}",
                QUAD_DOMAIN.0, QUAD_DOMAIN.1
            )));
        }
    }
    Ok(())
}

/// [`fit_pair`] with the caps metric's scan computed beforehand (shared by a set of pairs).
pub fn fit_pair_with(scan: &LightScan, alpha_mi: f64, alpha_me: f64) -> Result<PairFit> {
    in_quad_domain(alpha_mi, alpha_me)?;
    let conv = Convolution::new(alpha_me, alpha_mi)?;
    let tol = Tol::new(1e-8, 1e-8, 5_000_000);
    let m = conv.moments_quad(tol);
    let moment_clipped = alpha_from_one_minus(1.0 - m.mrl_clipped)?;
    let table_tol = Tol::new(1e-10, 1e-9, 2_000_000);
    let table = density_table(&conv, 16, table_tol);
    // the cap integrals' table error: the same caps over a table on fewer nodes
    let coarse = density_table(&conv, CAP_CHECK_NODES, table_tol);
    let l2 = brent_min(&|a| l2_distance2(&table, a), 1e-3, 3.0);
    let mut cap_err = 0.0f64;
    let mut target: Vec<f64> = CAPS
        .iter()
        .map(|&(t, r)| {
            let e = table_cap(
                &table,
                &coarse,
                conv_width(&conv),
                t,
                r,
                Tol::new(1e-11, 1e-9, 5_000_000),
            );
            cap_err = cap_err.max(e.error / e.value.abs().max(1e-300));
            e.value
        })
        .collect();
    // polygons: c is zonal, so integrate the interpolated table over each polygon
    let polys = polygons();
    for p in &polys {
        let over = |t: &ZonalTable| {
            p.integral(
                &|m| t.eval(m.z.clamp(-1.0, 1.0).acos()),
                Tol::new(1e-11, 1e-8, 5_000_000),
            )
        };
        let (e, c) = (over(&table), over(&coarse));
        // the quadratures' errors and the table's (as for the caps)
        let err = e.error + c.error + (e.value - c.value).abs();
        cap_err = cap_err.max(err / e.value.abs().max(1e-300));
        target.push(e.value);
    }
    let caps = brent_min(
        &|a| {
            let c = scan.lights(a, &polys);
            c.iter()
                .zip(&target)
                .map(|(x, t)| ((x - t) / t).powi(2))
                .sum::<f64>()
        },
        QUAD_DOMAIN.0,
        QUAD_DOMAIN.1,
    );
    Ok(PairFit {
        alpha_mi,
        alpha_me,
        moment_unclipped: alpha_moment(alpha_mi, alpha_me)?,
        moment_clipped,
        l2,
        caps,
        cap_quad_rel_error: cap_err,
    })
}

/// Per-metric model on top of the moment identity:
/// α_k = α_mom·exp(Σ c_i b_i(α_mi, α_me)) with α_mom = ρ⁻¹(ρ_me ρ_mi) and ten basis
/// functions built from s = α_mi/(α_mi + α_me), g = 4s(1 − s), p = α_mi α_me and
/// ℓ = ln √(α_mi² + α_me²): {g, g(s − ½)², g², p, p², g p, g √p, p √p, g ℓ, g ℓ²}.
/// Every basis function vanishes when α_mi → 0 or α_me → 0, so both limits are those of
/// α_mom (exact). The g-terms carry the scale-invariant shape difference between metrics
/// (largest at s = ½), the p-terms the horizon clipping of rough pairs, the ℓ-terms the
/// fixed angular size of the lights.
pub fn corrected(c: &[f64], alpha_mi: f64, alpha_me: f64) -> f64 {
    let m = alpha_moment(alpha_mi, alpha_me).unwrap_or(f64::NAN);
    m * corr_basis(alpha_mi, alpha_me)
        .iter()
        .zip(c)
        .map(|(b, k)| b * k)
        .sum::<f64>()
        .exp()
}

fn corr_basis(alpha_mi: f64, alpha_me: f64) -> [f64; 10] {
    let (x, y) = (alpha_mi, alpha_me);
    let s = x / (x + y);
    let g = 4.0 * s * (1.0 - s);
    let dd = (s - 0.5) * (s - 0.5);
    let p = x * y;
    let q = p.sqrt();
    let l = x.hypot(y).ln();
    [
        g,
        g * dd,
        g * g,
        p,
        p * p,
        g * p,
        g * q,
        q * p,
        g * l,
        g * l * l,
    ]
}

/// Fit the ten coefficients by linear least squares on ln(α_k/α_mom).
pub fn fit_corrected(samples: &[(f64, f64, f64)]) -> Result<Vec<f64>> {
    let mut rows = Vec::new();
    let mut t = Vec::new();
    for &(x, y, a) in samples {
        let m = alpha_moment(x, y)?;
        rows.push(corr_basis(x, y).to_vec());
        t.push((a / m).ln());
    }
    lstsq(&rows, &t)
}

/// What can be said of one (α_mi, α_me) pair at any roughness, without unbounded work.
#[derive(Clone, Debug, Serialize)]
pub struct PairEval {
    /// The unclipped-moment α (closed form, every pair).
    pub moment_unclipped: f64,
    /// The quadrature fit, when both α lie in [`QUAD_DOMAIN`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit: Option<PairFit>,
    /// When one α is below 1e-3 of the other: every metric tends to the larger α (the
    /// convolution with a near-delta lobe is the other lobe); its stated relative error is
    /// the unclipped moment's distance from that limit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limit: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limit_rel_error: Option<f64>,
    /// Why a metric is absent.
    pub note: String,
}

/// Every pair: the closed form always, the quadrature fit inside [`QUAD_DOMAIN`], the
/// small-ratio limit where it holds; never more than one bounded `fit_pair`.
pub fn evaluate_pair(alpha_mi: f64, alpha_me: f64) -> Result<PairEval> {
    let moment_unclipped = alpha_moment(alpha_mi, alpha_me)?;
    let inside = [alpha_mi, alpha_me]
        .iter()
        .all(|a| (QUAD_DOMAIN.0..=QUAD_DOMAIN.1).contains(a));
    let (lo, hi) = (alpha_mi.min(alpha_me), alpha_mi.max(alpha_me));
    if inside {
        return Ok(PairEval {
            moment_unclipped,
            fit: Some(fit_pair(alpha_mi, alpha_me)?),
            limit: None,
            limit_rel_error: None,
            note: "every metric by quadrature".into(),
        });
    }
    if lo < 1e-3 * hi {
        return Ok(PairEval {
            moment_unclipped,
            fit: None,
            limit: Some(hi),
            limit_rel_error: Some((moment_unclipped - hi).abs() / hi),
            note: format!(
                "outside the quadrature domain [{:e}, {:e}]; the smaller α is below 1e-3 of the larger, so every metric takes the limit α = max(α_mi, α_me) (relative error ≈ the moment metric's distance from it)",
                QUAD_DOMAIN.0, QUAD_DOMAIN.1
            ),
        });
    }
    Ok(PairEval {
        moment_unclipped,
        fit: None,
        limit: None,
        limit_rel_error: None,
        note: format!(
            "outside the quadrature domain [{:e}, {:e}]: only the closed-form moment metric is given (the clipped moment equals it up to the mass below the horizon; L2 and caps are not evaluated)",
            QUAD_DOMAIN.0, QUAD_DOMAIN.1
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shared scan holds, at every point the caps metric's Brent search scans, the
    /// energies a fresh [`lights_of_ltc`] gives there, bit for bit; any other α is
    /// computed afresh.
    #[test]
    fn the_shared_scan_is_what_each_pair_would_compute() {
        let scan = LightScan::compute();
        let polys = polygons();
        let xs = scan_points(QUAD_DOMAIN.0, QUAD_DOMAIN.1);
        assert_eq!(scan.at.len(), xs.len());
        for &a in xs.iter().step_by(10) {
            let got = scan.lights(a, &polys);
            assert!(
                matches!(got, std::borrow::Cow::Borrowed(_)),
                "α = {a} not in the scan"
            );
            let fresh = lights_of_ltc(a, &polys);
            assert_eq!(got.len(), fresh.len());
            for (x, y) in got.iter().zip(&fresh) {
                assert_eq!(x.to_bits(), y.to_bits());
            }
        }
        let off = 0.5 * (xs[3] + xs[4]);
        // a pair outside the domain (NaN, 1e300, 0) is refused before any quadrature
        for bad in [f64::NAN, 1e300, 0.0] {
            assert!(fit_pair(bad, 0.1).is_err());
            assert!(fit_pair_with(&scan, 0.1, bad).is_err());
        }
        assert!(matches!(
            scan.lights(off, &polys),
            std::borrow::Cow::Owned(_)
        ));
    }
}

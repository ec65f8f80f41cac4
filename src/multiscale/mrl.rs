//! Mean resultant length ‖b̄‖ of the isotropic LTC M = diag(α, α, 1) (seed 000 Eq 3–4),
//! in closed form, and its robust inverse α(‖b̄‖).
//!
//! Closed form (derivation: proofs/mrl-closed-form.md). The LTC with M = diag(α, α, 1) is
//! the GGX projected NDF D_α(b)(b·n), so ‖b̄‖ = E[cos θ] with slope² u ~ α²/(α² + u)² du:
//!
//!   ‖b̄‖(α) = (1 − α² h)/(1 − α²),  h = artanh(k)/k, k = √(1 − α²)  (α < 1)
//!                                   h = atan(κ)/κ,   κ = √(α² − 1)  (α > 1)
//!   ‖b̄‖(1) = 2/3, and near α = 1: ‖b̄‖ = Σ_{n≥0} 2 sⁿ/((2n+1)(2n+3)), s = 1 − α².
//!
//! Limits: 1 − ‖b̄‖ = α²(ln(2/α) − 1) + O(α⁴ ln α) as α → 0; ‖b̄‖ → π/(2α) as α → ∞.

use crate::error::{Error, Result};

/// (‖b̄‖, 1 − ‖b̄‖) for α > 0, each computed without cancellation, finite over the whole
/// positive f64 range (subnormals to 1.8e308).
///
/// For α > 1 the closed form is written in t = 1/α, so that nothing overflows:
/// with κ = √(α² − 1), atan κ = acos t and ‖b̄‖ = t (acos t/√(1 − t²) − t)/(1 − t²),
/// which tends to πt/2 − 2t² as t → 0 (‖b̄‖ ~ π/(2α)).
pub fn mrl_pair(alpha: f64) -> (f64, f64) {
    let a2 = alpha * alpha;
    let s = 1.0 - a2;
    if s.abs() < 0.1 {
        // series around α = 1: ‖b̄‖ = Σ 2 sⁿ/((2n+1)(2n+3))
        let mut b = 0.0;
        let mut p = 1.0;
        for n in 0..40 {
            let t = 2.0 * p / (((2 * n + 1) * (2 * n + 3)) as f64);
            b += t;
            if t.abs() < 1e-18 {
                break;
            }
            p *= s;
        }
        return (b, 1.0 - b);
    }
    if s > 0.0 {
        // α < 1: artanh(k) = ln((1 + k)/α) since 1 − k = α²/(1 + k); the logarithm is
        // split so that a subnormal α does not overflow (1 + k)/α
        let k = s.sqrt();
        let h = ((1.0 + k).ln() - alpha.ln()) / k;
        let one_minus = a2 * (h - 1.0) / s;
        (1.0 - one_minus, one_minus)
    } else {
        let t = 1.0 / alpha;
        let q = 1.0 - t * t;
        let b = t * (t.acos() / q.sqrt() - t) / q;
        (b, 1.0 - b)
    }
}

/// ‖b̄‖(α) (seed 000 Eq 4 in closed form).
pub fn mrl(alpha: f64) -> f64 {
    mrl_pair(alpha).0
}

/// d‖b̄‖/dα, analytic: with a = α², d‖b̄‖/da = (3/2 − h − a h/2)/(1 − a)².
pub fn mrl_derivative(alpha: f64) -> f64 {
    let a = alpha * alpha;
    let s = 1.0 - a;
    if s.abs() < 0.1 {
        // differentiate the series in s: d/da = −d/ds
        let mut d = 0.0;
        let mut p = 1.0;
        for n in 1..40 {
            let t = 2.0 * n as f64 * p / (((2 * n + 1) * (2 * n + 3)) as f64);
            d += t;
            if t.abs() < 1e-18 {
                break;
            }
            p *= s;
        }
        return -d * 2.0 * alpha;
    }
    let h = if s > 0.0 {
        let k = s.sqrt();
        ((1.0 + k) / alpha).ln() / k
    } else {
        let kap = (-s).sqrt();
        kap.atan() / kap
    };
    (1.5 - h - 0.5 * a * h) / (s * s) * 2.0 * alpha
}

/// Inverse α(‖b̄‖) from y = 1 − ‖b̄‖ ∈ (0, 1). Giving y rather than ‖b̄‖ keeps full
/// relative accuracy as ‖b̄‖ → 1 (α → 0); see [`alpha_from_pair`] for both ends.
pub fn alpha_from_one_minus(y: f64) -> Result<f64> {
    alpha_from_pair(1.0 - y, y)
}

/// Inverse α from (‖b̄‖, 1 − ‖b̄‖) = (b, y), whichever of the two is known more precisely
/// is used, over the whole open interval:
/// - y < 1e-30 (α ≲ 1e-16): the small-α series 1 − ‖b̄‖ = α²(ln(2/α) − 1)(1 + O(α² ln α)),
///   solved by fixed-point iteration in ln α (the neglected term is below 1e-30 relative);
/// - b < 1e-9 (α ≳ 1.6e9): the large-α series α = π/(2b) − 4/π + O(b) (relative error O(b²));
/// - otherwise safeguarded Newton in u = ln α on ln y (y ≤ ½) or ln b (y > ½), bracketed
///   in α ∈ [1e-17, 1e10], at most 100 steps.
pub fn alpha_from_pair(b: f64, y: f64) -> Result<f64> {
    // either of the pair may round to 1 when the other is tiny; neither may be 0
    if !(y > 0.0 && y <= 1.0 && b > 0.0 && b <= 1.0) {
        return Err(Error::InvalidArgument(format!(
            "‖b̄‖ and 1 − ‖b̄‖ must lie in (0, 1), got ‖b̄‖ = {b:e}, 1 − ‖b̄‖ = {y:e}"
        )));
    }
    if y < 1e-30 {
        let ly = y.ln();
        let mut l = 0.5 * ly;
        for _ in 0..60 {
            let next = 0.5 * (ly - (std::f64::consts::LN_2 - 1.0 - l).ln());
            if (next - l).abs() <= 1e-16 * l.abs() {
                l = next;
                break;
            }
            l = next;
        }
        return Ok(l.exp());
    }
    if b < 1e-9 {
        return Ok(std::f64::consts::FRAC_PI_2 / b - 4.0 / std::f64::consts::PI);
    }
    let use_y = y <= 0.5;
    let target = if use_y { y.ln() } else { b.ln() };
    let g = |u: f64| {
        let (bb, yy) = mrl_pair(u.exp());
        if use_y {
            yy.ln() - target
        } else {
            bb.ln() - target
        }
    };
    // initial guess from the asymptotes: α² ≈ y/(ln(2/α) − 1) for small y, π/(2b) for small b
    let mut u = if y < 0.05 {
        let mut a2 = y;
        for _ in 0..4 {
            let l = (2.0 / a2.sqrt()).ln() - 1.0;
            a2 = y / l.max(0.1);
        }
        0.5 * a2.ln()
    } else if b < 0.3 {
        (std::f64::consts::FRAC_PI_2 / b).ln()
    } else {
        0.0
    };
    // g is increasing in u for the ln y target and decreasing for ln b
    let sign = if use_y { 1.0 } else { -1.0 };
    let (mut lo, mut hi) = (-39.2f64, 23.1f64);
    for _ in 0..100 {
        let gu = g(u);
        if gu == 0.0 {
            break;
        }
        if sign * gu > 0.0 {
            hi = hi.min(u);
        } else {
            lo = lo.max(u);
        }
        let a = u.exp();
        let (bb, om) = mrl_pair(a);
        // d ln(1 − b)/du = −α b′(α)/(1 − b); d ln b/du = α b′(α)/b
        let db = a * mrl_derivative(a);
        let dg = if use_y { -db / om } else { db / bb };
        let mut next = u - gu / dg;
        if !(next > lo && next < hi) || !next.is_finite() {
            next = 0.5 * (lo + hi);
        }
        if (next - u).abs() <= 1e-15 * (1.0 + u.abs()) {
            u = next;
            break;
        }
        u = next;
    }
    Ok(u.exp())
}

/// Inverse α(‖b̄‖) for ‖b̄‖ ∈ (0, 1).
pub fn alpha_from_mrl(b: f64) -> Result<f64> {
    if !(b > 0.0 && b < 1.0) {
        return Err(Error::InvalidArgument(format!(
            "‖b̄‖ must lie in (0, 1), got {b:e}"
        )));
    }
    alpha_from_pair(b, 1.0 - b)
}

/// Seed 000 Eq 5: the paper's rational fit α_me(‖b̄‖).
pub fn alpha_me_paper(b: f64) -> f64 {
    let num = (((1.629 * b + 17.05) * b - 18.96) * b - 23.37) * b + 23.65;
    let den = ((b - 28.07) * b + 31.1) * b - 3.545;
    num / den
}

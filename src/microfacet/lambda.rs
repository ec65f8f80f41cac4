//! Smith Λ as a function of the normalised slope ν = (cot θ − μ(φ)) / α(φ)
//! (seed 001 §3.2, with α(φ) = σ(φ)√2), exact and approximate.

use std::f64::consts::PI;

/// Exact Beckmann Λ(ν) = (e^(−ν²)/(√π ν) − erfc ν) / 2 (Smith 1967; seed 001 §3.2).
/// ν ≤ 0 (direction at or below the mean surface) gives +∞; ν = ∞ gives 0.
/// For ν ≥ 6 an asymptotic series replaces the difference of two nearly equal terms,
/// keeping full relative accuracy until e^(−ν²) underflows.
pub fn beckmann(nu: f64) -> f64 {
    if nu.is_nan() {
        return f64::NAN;
    }
    if nu <= 0.0 {
        return f64::INFINITY;
    }
    if nu >= 6.0 {
        if nu * nu > UNDERFLOW_NU2 {
            // e^(−ν²) rounds to +0, and so does the product below: that zero, without
            // summing the series (most directions of a narrow lobe land here)
            return 0.0;
        }
        // erfc ν ~ e^(−ν²)/(ν√π) · Σ (−1)^k (2k−1)!!/(2ν²)^k
        // ⇒ Λ = e^(−ν²)/(2ν√π) · Σ_{k≥1} (−1)^(k+1) (2k−1)!!/(2ν²)^k
        let x = 1.0 / (2.0 * nu * nu);
        let mut term = 1.0;
        let mut sum = 0.0;
        for k in 1..30 {
            term *= (2 * k - 1) as f64 * x;
            let t = if k % 2 == 1 { term } else { -term };
            sum += t;
            if term < 1e-18 * sum.abs() {
                break;
            }
        }
        return (-nu * nu).exp() / (2.0 * nu * PI.sqrt()) * sum;
    }
    0.5 * ((-nu * nu).exp() / (PI.sqrt() * nu) - libm::erfc(nu))
}

/// Past this ν², e^(−ν²) < 2^−1076 is below half the smallest subnormal: it rounds to +0.
const UNDERFLOW_NU2: f64 = 746.0;

/// Exact GGX Λ(ν) = (√(1 + 1/ν²) − 1)/2 (Heitz 2014; seed 003 App. A Eq 16 with
/// ν = cot θ/α(φ)), written as 1/(2ν²(1 + √(1 + 1/ν²))) to avoid cancellation.
pub fn ggx(nu: f64) -> f64 {
    if nu.is_nan() {
        return f64::NAN;
    }
    if nu <= 0.0 {
        return f64::INFINITY;
    }
    let inv2 = 1.0 / (nu * nu);
    if inv2.is_infinite() {
        // ν → 0⁺: Λ ≈ 1/(2ν)
        return 0.5 / nu;
    }
    inv2 / (2.0 * (1.0 + (1.0 + inv2).sqrt()))
}

/// The ν coefficient of Walter et al.'s denominator (seed 001 §3.2): the ν → 0 limit it
/// implies is Λ ≈ 1/(3.535ν), against the exact 1/(2√π ν).
pub const WALTER_B1: f64 = 3.535;

/// Where Walter et al.'s printed form sets Λ = 0 (seed 001 §3.2).
pub const WALTER_CUT: f64 = 1.6;

/// Walter et al. 2007's rational approximation of the Beckmann Λ exactly as printed in
/// seed 001 §3.2: (1 − 1.259ν + 0.396ν²)/(3.535ν + 2.181ν²) for ν < 1.6, else 0.
pub fn walter_printed(nu: f64) -> f64 {
    if nu.is_nan() {
        return f64::NAN;
    }
    if nu <= 0.0 {
        return f64::INFINITY;
    }
    if nu >= WALTER_CUT {
        return 0.0;
    }
    (1.0 - 1.259 * nu + 0.396 * nu * nu) / (WALTER_B1 * nu + 2.181 * nu * nu)
}

/// The shader listing of seed 001 §3.2: ν clamped to [0.001, 1.599] then the same
/// rational (the listing's `nu`/`nu_v` name mismatch is read as one variable). Note the
/// clamp: for ν ≥ 1.6 it returns Λ(1.599) < 0 instead of 0.
pub fn walter_listing(nu: f64) -> f64 {
    if nu.is_nan() {
        return f64::NAN;
    }
    let v = nu.clamp(0.001, 1.599);
    (1.0 - 1.259 * v + 0.396 * v * v) / (WALTER_B1 * v + 2.181 * v * v)
}

/// Root of Walter's numerator 0.396ν² − 1.259ν + 1 = 0 below 1.6: past it the printed
/// approximation is negative (G1 > 1) up to the cut at ν = 1.6.
pub fn walter_numerator_root() -> f64 {
    let (a, b, c) = (0.396_f64, -1.259_f64, 1.0_f64);
    let disc = b * b - 4.0 * a * c;
    // smaller root, computed without cancellation
    let q = -0.5 * (b - disc.sqrt());
    c / q
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Beckmann Λ as written before its underflow shortcut: the series summed
    /// whatever ν.
    fn beckmann_full_series(nu: f64) -> f64 {
        if nu.is_nan() {
            return f64::NAN;
        }
        if nu <= 0.0 {
            return f64::INFINITY;
        }
        if nu >= 6.0 {
            let x = 1.0 / (2.0 * nu * nu);
            let mut term = 1.0;
            let mut sum = 0.0;
            for k in 1..30 {
                term *= (2 * k - 1) as f64 * x;
                let t = if k % 2 == 1 { term } else { -term };
                sum += t;
                if term < 1e-18 * sum.abs() {
                    break;
                }
            }
            return (-nu * nu).exp() / (2.0 * nu * PI.sqrt()) * sum;
        }
        0.5 * ((-nu * nu).exp() / (PI.sqrt() * nu) - libm::erfc(nu))
    }

    #[test]
    fn beckmann_underflow_shortcut_is_the_full_series_bits() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let edge = UNDERFLOW_NU2.sqrt();
        let mut nus = vec![f64::INFINITY, f64::MAX, 6.0, edge, 27.0, 28.0, 1e-300];
        // ulps either side of the shortcut's edge
        let mut lo = edge;
        let mut hi = edge;
        for _ in 0..2000 {
            lo = lo.next_down();
            hi = hi.next_up();
            nus.extend([lo, hi]);
        }
        for _ in 0..12_000 {
            // log-uniform over [1e-3, 1e300], and uniform over [26, 28] where e^(−ν²)
            // reaches the subnormals
            nus.push(10f64.powf(rng.random_range(-3.0..300.0)));
            nus.push(rng.random_range(26.0..28.0));
        }
        let mut zeros = 0;
        for nu in nus {
            let (a, b) = (beckmann(nu), beckmann_full_series(nu));
            assert_eq!(a.to_bits(), b.to_bits(), "ν = {nu:e}: {a:e} against {b:e}");
            zeros += usize::from(a == 0.0);
        }
        // the shortcut's side is exercised, and so is the series' nonzero side
        assert!(zeros > 1000, "{zeros} zeros");
        assert!(beckmann(edge.next_down().min(27.0)) > 0.0);
    }
}

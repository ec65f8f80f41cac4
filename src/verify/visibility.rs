//! The identities and limits seed 004 states for visibility and procedural maps (§4–6):
//! - Eq 28's and Ashikhmin's joint forms give 1 at l = v and V_A(l) when V_A(v) = 1, as
//!   the exact Eq 23 does (on height-field footprints);
//! - the Legendre coefficients of the horizon step are linear, so pre-filtering them
//!   commutes with the footprint average (and their closed form matches quadrature);
//! - Chebyshev's bound (VSM) is exact for one planar occluder parallel to the receiver;
//! - F(b) − F(a) is the box integral of Fig. 6's pulse train.

use super::outcome::{Outcome, Worst};
use crate::integrate::quad::gauss_legendre;
use crate::integrate::Preset;
use crate::visibility::horizon::{self, legendre_coeffs, legendre_eval, Dir};
use crate::visibility::procedural::{box_average, pulse_integral, pulse_integral_by_cells};
use crate::visibility::shadow::{chebyshev, Method, Precision};
use crate::visibility::{HeightField, Relief};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Eq 28 and Ashikhmin's form at their two limits; Eq 23 on height-field footprints.
pub fn horizon_joint_limits(p: Preset) -> Outcome {
    let n = if p == Preset::Quick { 40 } else { 200 };
    let mut w = Worst::default();
    let mut product_gap = 0.0f64;
    for a in 0..=n {
        let v = (a as f64 / n as f64).max(1e-12);
        // l = v: cos = 1, V_A(l) = V_A(v)
        w.update((horizon::joint_eq28(v, v, 1.0) - 1.0).abs(), || {
            format!("Eq 28 at l = v, V = {v}")
        });
        w.update(
            (horizon::joint_ashikhmin(v, v, 1.0, 0.25) - 1.0).abs(),
            || format!("Ashikhmin at l = v, V = {v}"),
        );
        product_gap = product_gap.max((horizon::joint_product(v, v) - 1.0).abs());
        for c in [-1.0, -0.3, 0.0, 0.5, 0.99, 1.0] {
            // fully visible from v: V_A(l, v) = V_A(l)
            w.update((horizon::joint_eq28(v, 1.0, c) - v).abs(), || {
                format!("Eq 28 with V_A(v) = 1, V_A(l) = {v}, cos = {c}")
            });
            w.update(
                (horizon::joint_ashikhmin(v, 1.0, c, 0.25) - v).abs(),
                || format!("Ashikhmin with V_A(v) = 1, V_A(l) = {v}, cos = {c}"),
            );
        }
    }
    // the exact joint fraction (Eq 23) satisfies both on real footprints
    let hf = HeightField::procedural(Relief::Bumps, 64, 3).expect("64 is a valid size");
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut w23 = Worst::default();
    for k in 0..(n / 4) {
        let texels = hf.block(2, k % 16, (k / 16) % 16);
        let v = Dir {
            elev: (5.0 + 40.0 * rng.random::<f64>()).to_radians(),
            azim: 6.3 * rng.random::<f64>(),
        };
        if let (_, Some(x)) = horizon::exact(&hf, &texels, &v, &v) {
            w23.update((x - 1.0).abs(), || format!("Eq 23 at l = v, footprint {k}"));
        }
        let top = Dir {
            elev: 89.9f64.to_radians(),
            azim: 0.0,
        };
        let (vl, _) = horizon::exact(&hf, &texels, &v, &v);
        if let (_, Some(x)) = horizon::exact(&hf, &texels, &top, &v) {
            w23.update((x - vl).abs(), || {
                format!("Eq 23 with v at the zenith, footprint {k}")
            });
        }
    }
    let worst = w.err.max(w23.err);
    Outcome {
        id: "horizon-joint-limits",
        title: "Joint visibility: 1 at l = v (hotspot) and V_A(l) when V_A(v) = 1",
        source: "seed 004 §4.2 (Eq 23, Eq 28; Ashikhmin et al.)",
        ranges: format!("V_A from 1e-12 to 1 ({n} steps), cos(l, v) from −1 to 1; Eq 23 on {} footprints of the bumps height field", n / 4),
        cases: w.n + w23.n,
        worst_error: worst,
        error_kind: "abs",
        worst_case: if w.err >= w23.err { w.case } else { w23.case },
        tolerance: 1e-14,
        passed: worst <= 1e-14,
        seconds: 0.0,
        notes: vec![
            format!("the uncorrelated product V_A(l)V_A(v) misses the hotspot by up to {product_gap:.3} (it returns V_A(v), not 1)"),
            format!("Eq 23 on height-field footprints: worst {:.1e}", w23.err),
        ],
    }
}

/// The Legendre coefficients against quadrature, and pre-filtering commuting with the
/// footprint average.
pub fn legendre_horizon_linearity(p: Preset) -> Outcome {
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let (x, wq) = gauss_legendre(64);
    let mut wc = Worst::default();
    for _ in 0..if p == Preset::Quick { 20 } else { 100 } {
        let s: f64 = rng.random();
        let k = 24;
        let a = legendre_coeffs(s, k);
        // ∫_s¹ P̂_k(μ) dμ by Gauss–Legendre on [s, 1] (P̂_k as evaluated by legendre_eval)
        for (kk, ak) in a.iter().enumerate() {
            let mut e = vec![0.0; k];
            e[kk] = 1.0;
            let q: f64 = x
                .iter()
                .zip(&wq)
                .map(|(xi, wi)| {
                    0.5 * (1.0 - s) * wi * legendre_eval(&e, s + 0.5 * (1.0 - s) * (xi + 1.0))
                })
                .sum();
            wc.update((q - ak).abs(), || format!("a_{kk}(s = {s:.4})"));
        }
    }
    let mut wl = Worst::default();
    let mut l1 = Vec::new();
    for case in 0..if p == Preset::Quick { 10 } else { 40 } {
        let n = 2 + case % 30;
        let ss: Vec<f64> = (0..n).map(|_| rng.random::<f64>()).collect();
        let ws: Vec<f64> = {
            let w: Vec<f64> = (0..n).map(|_| rng.random::<f64>() + 0.1).collect();
            let t: f64 = w.iter().sum();
            w.iter().map(|x| x / t).collect()
        };
        for k in [4usize, 16, 64] {
            let mut avg = vec![0.0; k];
            for (s, w) in ss.iter().zip(&ws) {
                for (a, c) in avg.iter_mut().zip(legendre_coeffs(*s, k)) {
                    *a += w * c;
                }
            }
            for t in 0..50 {
                let mu = (t as f64 + 0.5) / 50.0;
                let direct: f64 = ss
                    .iter()
                    .zip(&ws)
                    .map(|(s, w)| w * legendre_eval(&legendre_coeffs(*s, k), mu))
                    .sum();
                wl.update((legendre_eval(&avg, mu) - direct).abs(), || {
                    format!("{n} texels, K = {k}, μ = {mu}")
                });
            }
        }
    }
    // the series' L1 error against the step, by order (a finding, not a pass criterion)
    for k in [4usize, 16, 64] {
        let e: f64 = (0..400)
            .map(|t| {
                let mu = (t as f64 + 0.5) / 400.0;
                (legendre_eval(&legendre_coeffs(0.4, k), mu) - (mu > 0.4) as u8 as f64).abs()
                    / 400.0
            })
            .sum();
        l1.push(format!("K = {k}: {e:.2e}"));
    }
    let worst = wc.err.max(wl.err);
    Outcome {
        id: "legendre-horizon-linearity",
        title: "Legendre horizon coefficients: closed form, and pre-filtering commutes with the average",
        source: "seed 004 §4.2 (Nowrouzezahrai & Snyder, Eq 29–30) and §7.3.1",
        ranges: "s = sin Θ uniform in [0, 1], 24 coefficients against 64-node quadrature; footprints of 2–31 texels with random weights, K = 4, 16, 64".into(),
        cases: wc.n + wl.n,
        worst_error: worst,
        error_kind: "abs",
        worst_case: if wc.err >= wl.err { wc.case } else { wl.case },
        tolerance: 1e-12,
        passed: worst <= 1e-12,
        seconds: 0.0,
        notes: vec![
            format!("closed form against quadrature: worst {:.1e}; averaged coefficients against averaged series: worst {:.1e}", wc.err, wl.err),
            format!("L1 error of the truncated step at s = 0.4: {}", l1.join(", ")),
        ],
    }
}

/// VSM is exact for one planar occluder parallel to the receiver.
pub fn vsm_single_plane(p: Preset) -> Outcome {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let mut w = Worst::default();
    let mut bleed = 0.0f64;
    let cases = if p == Preset::Quick { 200 } else { 2000 };
    for k in 0..cases {
        let n = 4 + k % 60;
        let covered = 1 + (rng.random::<f64>() * (n - 1) as f64) as usize;
        let d: f64 = 0.2 + 0.8 * rng.random::<f64>();
        let zo = d * rng.random::<f64>() * 0.95;
        let z: Vec<f64> = (0..n).map(|i| if i < covered { zo } else { d }).collect();
        let texels: Vec<(usize, usize)> = (0..n).map(|i| (i, 0)).collect();
        let m = Method::Vsm.filter(&z, n, &texels, Precision::F64);
        let truth = 1.0 - covered as f64 / n as f64;
        let u = Method::Vsm.lookup(&m, d);
        // the variance E[z²] − E[z]² cancels: the n-term sums carry γ_n ≈ nε of E[z²]
        // (the standard summation bound), relative to the bound's denominator σ² + (d − μ)²
        let (m1, m2) = (m.0[0], m.0[1]);
        let var = m2 - m1 * m1;
        let bound = 4.0 * (n as f64 + 4.0) * f64::EPSILON * m2 / (var + (d - m1).powi(2)) + 1e-15;
        w.update((u - truth).abs() / bound, || {
            format!(
                "{covered}/{n} texels at z = {zo:.4}, receiver d = {d:.4}: |U − (1 − p)| = {:.2e}, bound {bound:.2e}",
                (u - truth).abs()
            )
        });
        // two occluders at different depths: the bound leaks light
        let z2: Vec<f64> = (0..n)
            .map(|i| {
                if i < covered {
                    zo
                } else if i < covered + (n - covered) / 2 {
                    0.5 * (zo + d)
                } else {
                    d
                }
            })
            .collect();
        let lit = (n - covered - (n - covered) / 2) as f64 / n as f64;
        let m2 = Method::Vsm.filter(&z2, n, &texels, Precision::F64);
        bleed = bleed.max(Method::Vsm.lookup(&m2, d) - lit);
    }
    // the bound itself at the exact moments of the two-value distribution
    let e = chebyshev(0.5 * 0.2 + 0.5 * 0.9, 0.5 * 0.04 + 0.5 * 0.81, 0.9, 0.0);
    Outcome {
        id: "vsm-single-plane",
        title: "VSM's Chebyshev bound is exact for one planar occluder parallel to the receiver",
        source: "seed 004 §5.2 (Donnelly & Lauritzen)",
        ranges: format!("{cases} footprints of 4–63 texels, coverage 1/n…(n−1)/n, receiver depth 0.2–1, occluder 0–0.95 of it"),
        cases,
        worst_error: w.err,
        error_kind: "|U − (1 − p)| / its a-priori rounding bound 4(n + 4)ε E[z²]/(σ² + (d − μ)²)",
        worst_case: w.case,
        tolerance: 1.0,
        passed: w.err <= 1.0 && (e - 0.5).abs() < 1e-12,
        seconds: 0.0,
        notes: vec![format!("with a second occluder half-way the bound overestimates the lit fraction by up to {bleed:.3} (light bleeding)")],
    }
}

/// F(b) − F(a) against the pulse train's integral summed cell by cell.
pub fn box_filter_analytic(p: Preset) -> Outcome {
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let mut w = Worst::default();
    let mut far = 0.0f64;
    let cases = if p == Preset::Quick { 2000 } else { 20000 };
    for _ in 0..cases {
        let a = 1e3 * (2.0 * rng.random::<f64>() - 1.0);
        let len = 10f64.powf(-4.0 + 6.0 * rng.random::<f64>());
        let b = a + len;
        let exact = pulse_integral_by_cells(a, b);
        let an = pulse_integral(b) - pulse_integral(a);
        // F's terms are of size |x|/2: rounding of one ulp of 500 bounds the difference
        w.update((an - exact).abs() / (1.0 + a.abs().max(b.abs())), || {
            format!("[{a}, {b}]")
        });
        let big = 1e12 + a;
        far = far.max(
            (box_average(big, big + len) - pulse_integral_by_cells(big, big + len) / len).abs(),
        );
    }
    Outcome {
        id: "box-filter-analytic-integration",
        title: "Analytic integration: F(b) − F(a) is the box integral of the pulse train",
        source: "seed 004 §6.1.2, Fig. 6",
        ranges: format!("{cases} seeded intervals with a ∈ [−1000, 1000], lengths 1e-4…100"),
        cases,
        worst_error: w.err,
        error_kind: "abs / (1 + |x|)",
        worst_case: w.case,
        tolerance: 1e-15,
        passed: w.err <= 1e-15,
        seconds: 0.0,
        notes: vec![format!(
            "at x ≈ 1e12 the box average F(b) − F(a) over (b − a) loses digits to F's size: worst {far:.1e} (an f64 has 1e-4 of absolute resolution there)"
        )],
    }
}

//! Seed 002 Appendix Eq 10–12: the box average of a rank-1 (and, by linearity, rank-R)
//! tensor is the product of 1D box averages; the O(R) range query equals the naive
//! average up to rounding.

use super::outcome::{Outcome, Worst};
use crate::integrate::Preset;
use crate::tensor::query::{range, range_error_bound, range_f32, range_naive, Sat};
use rand::{Rng, SeedableRng};

pub use crate::tensor::cp::random_cp;

pub fn rank1_box(p: Preset) -> Outcome {
    let (models, boxes) = match p {
        Preset::Quick => (12, 40),
        Preset::Default => (48, 200),
        Preset::Precise => (200, 1000),
    };
    let mut w = Worst::default();
    let mut w32 = Worst::default();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
    for mi in 0..models {
        let rank = [1usize, 1, 4, 16, 32][mi % 5];
        let t = [1usize, 16, 64, 256][mi % 4];
        let cp = random_cp(rank, [t, t, 8], 100 + mi as u64);
        let sat = Sat::build(&cp);
        for b in 0..boxes {
            // single cells, whole range, and random boxes
            let (x, y) = match b {
                0 => ((0, 0), (0, 0)),
                1 => ((0, t - 1), (0, t - 1)),
                _ => {
                    let a = rng.random_range(0..t);
                    let c = rng.random_range(a..t);
                    let d = rng.random_range(0..t);
                    let e = rng.random_range(d..t);
                    ((a, c), (d, e))
                }
            };
            let z = b % 8;
            let naive = range_naive(&cp, x, y, z);
            let fast = range(&cp, &sat, x, y, z);
            // a-priori rounding bounds (proofs/tensor-rank1-box.md): f64 prefix sums of
            // length ≤ t, Kahan-built f32 prefixes; the compensated naive sum adds a few ε
            let bound = 2.0 * range_error_bound(&cp, x, y, z, f64::EPSILON, t as f64)
                + 8.0 * f64::EPSILON * naive.abs();
            let d = (fast - naive).abs();
            w.update(d / bound, || format!("R = {rank}, t = {t}, box {x:?}×{y:?}, z = {z}: |Δ| {d:.2e} (bound {bound:.1e})"));
            let f = range_f32(&cp, &sat, x, y, z) as f64;
            let b32 = 2.0 * range_error_bound(&cp, x, y, z, f32::EPSILON as f64, 2.0)
                + 8.0 * f32::EPSILON as f64 * naive.abs();
            let d32 = (f - naive).abs();
            w32.update(d32 / b32, || {
                format!("R = {rank}, t = {t}, box {x:?}×{y:?}: f32 |Δ| {d32:.2e} (bound {b32:.1e})")
            });
        }
    }
    Outcome {
        id: "tensor-rank1-box",
        title: "Box average of a rank-R tensor = Σ_r C_r × product of 1D box averages (O(R) range query)",
        source: "seed 002 Eq 7, Appendix Eq 10–12",
        ranges: format!("{models} random non-negative CP models, R ∈ {{1, 4, 16, 32}}, t ∈ {{1, 16, 64, 256}}, {boxes} boxes each (single cells, whole range, random)"),
        cases: w.n,
        worst_error: w.err,
        error_kind: "ratio |range − naive| / a-priori f64 rounding bound",
        worst_case: w.case.clone(),
        tolerance: 1.0,
        passed: w.err <= 1.0 && w32.err <= 1.0,
        seconds: 0.0,
        notes: vec![format!(
            "f32 summed-area tables (Kahan-built prefixes): worst ratio to the a-priori f32 bound {:.3} at {}",
            w32.err, w32.case
        )],
    }
}

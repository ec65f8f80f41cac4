//! What a table keeps when it is stored in binary16 (three.js `HalfFloatType`, Bevy's
//! RGBA16F KTX2): rounding each entry to nearest loses most digits of the entries that
//! leave f16's normal range (below 6.1e-5: b, c and d of M⁻¹ at small α near grazing),
//! and the lobe those digits shape. The LTC is judged as a whole, so the stored entries
//! are chosen as a whole: a coordinate search over the f16 neighbours of a, b, c and d
//! (up to 4 binary16 steps either way of round-to-nearest), on the training sample set, keeps the
//! matrix whose relative L2 against the target is lowest, if a validation set agrees.
//! Below α ≈ 5e-4 no f16 matrix can do well: c ≈ −a·tan θ_r sets the lobe's direction,
//! and its f16 spacing (2⁻¹¹ relative) exceeds the lobe's width. norm and fresnel round to
//! nearest (norm is the albedo: its half-ulp, ≤ 2.5e-4, is the energy error stored).
//!
//! Every stored matrix keeps its lobe: the determinant ad − bc of M⁻¹ stays positive (a
//! negative one mirrors the lobe across the view plane, which rounding to nearest does at
//! the smallest α near grazing, where d and b fall below binary16's subnormals) and b keeps
//! the sign of the f64 entry (or is 0). Candidates that break this are never chosen; where
//! no neighbour keeps it, the smallest change that does is made ([`keep_lobe`]).

use crate::ltc::fit::{production_metrics_on, Sets, TargetSamples};
use crate::ltc::target::LtcTarget;
use half::f16;

/// Position of a binary16 number on the line of all of them (−0 and +0 both 0): the
/// distance in steps between two numbers is the difference of their ordinals.
fn ordinal(h: f16) -> i32 {
    let b = h.to_bits() as i32;
    if b & 0x8000 != 0 {
        -(b & 0x7fff)
    } else {
        b
    }
}

/// The next binary16 number above (`up`) or below `x` (no NaN; ±∞ stays).
fn step(x: f16, up: bool) -> f16 {
    if x.is_infinite() {
        return x;
    }
    let b = x.to_bits();
    let pos = b & 0x8000 == 0;
    let bits = match (pos, up) {
        (true, true) => b + 1,
        (true, false) if b == 0 => 0x8001,
        (true, false) => b - 1,
        (false, false) => b + 1,
        (false, true) if b == 0x8000 => 0x0001,
        (false, true) => b - 1,
    };
    f16::from_bits(bits)
}

/// Whether stored entries (a, b, c, d) keep the lobe of the f64 entries `inv`: all finite,
/// ad − bc > 0, and b of the same sign as inv's b (or 0).
pub fn keeps_lobe(q: &[f64; 4], inv: &[f64; 4]) -> bool {
    q.iter().all(|x| x.is_finite()) && q[0] * q[3] - q[1] * q[2] > 0.0 && q[1] * inv[1] >= 0.0
}

/// The nearest binary16 entries that keep the lobe: round to nearest, then, if that
/// breaks [`keeps_lobe`], move b toward zero and d up by single binary16 steps (d grows
/// the determinant through a·d; b shrinks −bc), at most 64 steps each.
pub fn keep_lobe(inv: &[f64; 4]) -> [f16; 4] {
    let mut q = inv.map(f16::from_f64);
    let ok = |q: &[f16; 4]| keeps_lobe(&q.map(|x| x.to_f64()), inv);
    if ok(&q) {
        return q;
    }
    // b of the wrong sign (or rounded across zero) goes to zero first
    if q[1].to_f64() * inv[1] < 0.0 {
        q[1] = f16::from_f64(0.0);
    }
    for _ in 0..64 {
        if ok(&q) {
            return q;
        }
        q[3] = step(q[3], true);
    }
    q
}

/// The binary16 storage of one cell [a, b, c, d, norm, fresnel] (returned as f64): the
/// matrix entries chosen by the training relative L2 (n×n set, offset 0.5) among the
/// neighbours that keep the lobe ([`keeps_lobe`]), never worse there or on the validation
/// set ((n + 7)², offset 0.37) than the nearest entries that keep it ([`keep_lobe`]).
pub fn half_storage<T: LtcTarget + ?Sized>(
    t: &T,
    inv: &[f64; 4],
    norm: f64,
    fresnel: f64,
    n: usize,
) -> [f64; 6] {
    let normh = f16::from_f64(norm);
    // the target's half of both sample sets, drawn once for every candidate
    let sets = Sets::new(t, n);
    let on = |q: &[f16; 4], s: &TargetSamples| {
        production_metrics_on(t, s, &q.map(|x| x.to_f64()), normh.to_f64())
            .map(|m| m.1)
            .filter(|x| x.is_finite())
            .unwrap_or(f64::INFINITY)
    };
    let valid = |q: &[f16; 4]| keeps_lobe(&q.map(|x| x.to_f64()), inv);
    let score = |q: &[f16; 4]| {
        if valid(q) {
            on(q, &sets.train)
        } else {
            f64::INFINITY
        }
    };
    let nearest = keep_lobe(inv);
    let mut best = nearest;
    let mut best_score = score(&best);
    // coordinate passes: move one entry by one ulp while that lowers the score, at most
    // 4 binary16 steps from nearest per entry
    for _ in 0..3 {
        let mut moved = false;
        for k in 0..4 {
            for up in [true, false] {
                loop {
                    let mut q = best;
                    q[k] = step(q[k], up);
                    if !q[k].is_finite() || (ordinal(q[k]) - ordinal(nearest[k])).abs() > 4 {
                        break;
                    }
                    let s = score(&q);
                    if s < best_score {
                        best = q;
                        best_score = s;
                        moved = true;
                    } else {
                        break;
                    }
                }
            }
        }
        if !moved {
            break;
        }
    }
    // kept only if a separate validation set agrees (the training set cannot resolve the
    // narrowest lobes, where a search would fit its noise)
    if !(valid(&best) && on(&best, &sets.val) < on(&nearest, &sets.val)) {
        best = nearest;
    }
    [
        best[0].to_f64(),
        best[1].to_f64(),
        best[2].to_f64(),
        best[3].to_f64(),
        normh.to_f64(),
        f16::from_f64(fresnel).to_f64(),
    ]
}

/// The binary16 storage of every cell of a fitted table (`Cell::half`), each chosen by
/// [`half_storage`] against its own target (`target(α, θ)`).
pub fn store_table<T: LtcTarget>(
    pm: &impl crate::parmap::ParMap,
    table: &mut crate::ltc::fit::Table,
    target: &(dyn Fn(f64, f64) -> crate::error::Result<T> + Sync),
    n: usize,
) -> crate::error::Result<()> {
    // one column per item of the caller's map
    let g = table.cells.len();
    let cols = &table.cells;
    let halves: Vec<Vec<[f64; 6]>> = pm.map(&format!("binary16 storage {g} columns"), g, |j| {
        cols[j]
            .iter()
            .map(|c| {
                Ok(half_storage(
                    &target(c.alpha, c.theta)?,
                    &c.inv,
                    c.norm,
                    c.fresnel,
                    n,
                ))
            })
            .collect()
    })?;
    for (col, h) in table.cells.iter_mut().zip(halves) {
        for (c, h) in col.iter_mut().zip(h) {
            c.half = h;
        }
    }
    Ok(())
}

/// A table as stored: [j][i] = [a, b, c, d, norm, fresnel] (f64), and its binary16
/// storage in the same layout.
pub fn stored(t: &crate::ltc::fit::Table) -> (Vec<Vec<[f64; 6]>>, Vec<Vec<[f64; 6]>>) {
    let full = t
        .cells
        .iter()
        .map(|col| {
            col.iter()
                .map(|c| [c.inv[0], c.inv[1], c.inv[2], c.inv[3], c.norm, c.fresnel])
                .collect()
        })
        .collect();
    let half = t
        .cells
        .iter()
        .map(|col| col.iter().map(|c| c.half).collect())
        .collect();
    (full, half)
}

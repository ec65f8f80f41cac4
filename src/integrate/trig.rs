//! sin and cos of an angle, remembered per thread.
//!
//! The nested quadratures (`sphere`, the LTC albedos) evaluate their inner rule in φ at
//! every node of their outer rule in θ: where the inner break points do not move with θ,
//! the same φ nodes come back, bit for bit, for every outer node, and each costs a
//! `sin`/`cos` pair again. [`sin_cos`] keeps the last pair seen at each of 2048 slots
//! (direct-mapped on the angle's bits, one table per thread), so a repeated angle is a
//! load and a compare. The values are `f64::sin` and `f64::cos` of the angle, computed the
//! first time it is asked for in a slot: a hit and a miss give the same bits, so results
//! do not depend on the hit rate, the thread or the order of the calls.

use std::cell::RefCell;

const SLOTS: usize = 2048;

/// Every slot starts holding the angle +0 (key 0) with its own pair, so a slot's key
/// alone says what its pair is the sine and cosine of.
struct Memo {
    keys: [u64; SLOTS],
    vals: [(f64, f64); SLOTS],
}

thread_local! {
    static MEMO: RefCell<Box<Memo>> = RefCell::new(Box::new(Memo {
        keys: [0.0f64.to_bits(); SLOTS],
        vals: [(0.0f64.sin(), 0.0f64.cos()); SLOTS],
    }));
}

/// The slot of an angle's bits: the high bits of a multiplicative hash.
#[inline]
fn slot(bits: u64) -> usize {
    ((bits ^ (bits >> 31)).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - 11)) as usize
}

/// (`a.sin()`, `a.cos()`), from this thread's memo where `a` was asked for before and
/// its slot still holds it.
#[inline]
pub fn sin_cos(a: f64) -> (f64, f64) {
    let b = a.to_bits();
    let k = slot(b);
    MEMO.with(|m| {
        let mut m = m.borrow_mut();
        if m.keys[k] == b {
            return m.vals[k];
        }
        let v = (a.sin(), a.cos());
        m.keys[k] = b;
        m.vals[k] = v;
        v
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Every answer is the direct pair's bits: first asks, repeats, evicted and re-asked
    /// angles, signed zeros, infinities and NaNs, on this thread and on others.
    #[test]
    fn memo_gives_the_direct_bits() {
        let same = |a: f64| {
            let (s, c) = sin_cos(a);
            assert_eq!(s.to_bits(), a.sin().to_bits(), "sin {a:e}");
            assert_eq!(c.to_bits(), a.cos().to_bits(), "cos {a:e}");
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut angles: Vec<f64> = vec![
            0.0,
            -0.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
            f64::MIN_POSITIVE,
            1e300,
            std::f64::consts::PI,
        ];
        for _ in 0..20_000 {
            angles.push(rng.random_range(-10.0..10.0));
            angles.push(10f64.powf(rng.random_range(-300.0..300.0)));
        }
        // three passes: the second finds most in the memo, the third after the first
        // pass's later angles evicted some of them
        for _ in 0..3 {
            angles.iter().copied().for_each(same);
        }
        let counted = std::thread::spawn(move || {
            // a fresh thread: +0 is found in any slot's initial state, −0 is not
            same(0.0);
            same(-0.0);
            angles.iter().rev().copied().for_each(same);
            angles.len()
        })
        .join()
        .unwrap();
        assert!(counted > 40_000);
    }

    /// A repeated angle is found in the memo: its value comes back even when the slot's
    /// stored pair is the only place it could come from.
    #[test]
    fn repeats_are_found() {
        let a = 0.123_456_789_f64;
        let first = sin_cos(a);
        let k = slot(a.to_bits());
        MEMO.with(|m| m.borrow_mut().vals[k] = (7.0, 8.0));
        assert_eq!(sin_cos(a), (7.0, 8.0));
        MEMO.with(|m| m.borrow_mut().vals[k] = first);
        assert_eq!(sin_cos(a), first);
    }
}

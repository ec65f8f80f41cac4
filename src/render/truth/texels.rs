//! The sampled lights (quad, SG) of an exact footprint: every texel with k light samples
//! per replicate ([`Shader::every_texel`]), or, above the scene's draw budget, texels drawn
//! in proportion to their overlap with one light sample each ([`Shader::drawn_texels`]).
//! Both estimate the same overlap-weighted mean of seed 004 Eq 11 without bias; the draws
//! bound a pixel's work at the budget where the every-texel form's grows with the
//! footprint (2 samples per texel once it holds more than n/2 texels). A pixel without an
//! exact footprint is supersampled ([`Shader::supersampled`]).

use super::PixelTruth;
use super::{Shader, Viewed, V3};
use crate::lanes::LANES;
use crate::render::coverage::Share;
use crate::render::geometry::{Camera, Hit, Surface};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// A footprint texel prepared for shading: its hit at the overlap's centroid, its normal,
/// its lobe seen from the eye, and its point and directional lights' exact part.
pub(super) type Texel = (Hit, V3, Viewed, f64);

/// Sample `i` of an Owen-scrambled Sobol sequence (sobol_burley, scramble `scr`) in three
/// dimensions, each coordinate jittered below its 2⁻²⁴ grid from `rng`. The first three of
/// `sample_4d`'s four dimensions, which the crate computes together and guarantees equal
/// to `sample`'s one by one (`tests::four_dimensions_are_sample_one_by_one`).
fn uniforms(i: usize, scr: u32, rng: &mut ChaCha8Rng) -> [f64; 3] {
    let i = (i as u32).min((1 << 16) - 1);
    let s = sobol_burley::sample_4d(i, 0, scr);
    let mut u = [0.0; 3];
    for (x, v) in u.iter_mut().zip(s) {
        let jit = rng.random::<f64>() * (1.0 / (1u64 << 24) as f64);
        *x = (v as f64 + jit).min(1.0 - f64::EPSILON / 2.0);
    }
    u
}

/// The index of (i, j) on the Z-order (Morton) curve, after offsetting both to ≥ 0: texels
/// close on the map are close in this order, so one stratum of a systematic draw along it
/// is a compact patch.
fn morton(i: u64, j: u64) -> u64 {
    let spread = |mut x: u64| {
        x &= 0xffff_ffff;
        x = (x | (x << 16)) & 0x0000_ffff_0000_ffff;
        x = (x | (x << 8)) & 0x00ff_00ff_00ff_00ff;
        x = (x | (x << 4)) & 0x0f0f_0f0f_0f0f_0f0f;
        x = (x | (x << 2)) & 0x3333_3333_3333_3333;
        (x | (x << 1)) & 0x5555_5555_5555_5555
    };
    spread(i) | (spread(j) << 1)
}

/// The shares in Z order of their texels.
fn z_order(shares: &[Share]) -> Vec<&Share> {
    let (i0, j0) = shares
        .iter()
        .fold((i64::MAX, i64::MAX), |(i, j), s| (i.min(s.i), j.min(s.j)));
    let mut order: Vec<(u64, &Share)> = shares
        .iter()
        .map(|s| (morton((s.i - i0) as u64, (s.j - j0) as u64), s))
        .collect();
    order.sort_by_key(|&(z, _)| z);
    order.into_iter().map(|(_, s)| s).collect()
}

/// `m` systematic draws along `order` at offset `off` ∈ [0, 1): each share owns its area's
/// stretch of [0, A), and draw j takes the share whose stretch holds (j + off) A/m (the
/// last one where rounding runs past the end). Over a uniform `off`, share i is drawn
/// m aᵢ/A times on average.
fn systematic<'s>(order: &[&'s Share], m: usize, off: f64) -> Vec<&'s Share> {
    let total: f64 = order.iter().map(|s| s.area).sum();
    let (mut at, mut below) = (0, 0.0);
    let mut out = Vec::with_capacity(m);
    for j in 0..m {
        let t = (j as f64 + off) / m as f64 * total;
        while at + 1 < order.len() && below + order[at].area <= t {
            below += order[at].area;
            at += 1;
        }
        out.push(order[at]);
    }
    out
}

impl Shader<'_> {
    /// The prepared texels (their exact part 0) with their point and directional lights'
    /// exact parts, every texel's at once ([`Shader::exact_texels`]). Each texel is built
    /// once where it stays and its exact part written into it: a texel is some 300 bytes,
    /// and moving every one into a second vector took a tenth of a render's time.
    pub(super) fn with_exact(&self, prepared: impl Iterator<Item = Texel>) -> Vec<Texel> {
        let mut texels: Vec<Texel> = prepared.collect();
        let exact = {
            let at: Vec<(&Viewed, &Hit, &V3)> =
                texels.iter().map(|(h, n, w, _)| (w, h, n)).collect();
            self.exact_texels(&at)
        };
        for (t, e) in texels.iter_mut().zip(exact) {
            t.3 = e;
        }
        texels
    }

    /// The sampled lights' values of `texels[of[s]]` at the uniforms `us[s]`, four samples
    /// at a time ([`Shader::sampled_lanes`]).
    fn light_values(
        &self,
        texels: &[Texel],
        of: impl Fn(usize) -> usize,
        us: &[[f64; 3]],
    ) -> Vec<f64> {
        let mut q = Vec::with_capacity(us.len());
        for (c, u) in us.chunks(LANES).enumerate() {
            let at = |i: usize| {
                let (hit, nt, w, _) = &texels[of(c * LANES + i.min(u.len() - 1))];
                (w, hit, nt)
            };
            let got = self.sampled_lanes(
                std::array::from_fn(at),
                std::array::from_fn(|i| u[i.min(u.len() - 1)]),
            );
            q.extend_from_slice(&got[..u.len()]);
        }
        q
    }

    /// The two replicates' overlap-weighted sums over every texel, with k samples of the
    /// sampled lights per texel and replicate: their uniforms drawn first (texel by texel,
    /// replicate by replicate), then the samples four at a time across texels, then summed
    /// texel by texel.
    pub(super) fn every_texel(
        &self,
        shares: &[Share],
        texels: &[Texel],
        k: usize,
        scrambles: [u32; 2],
        rng: &mut ChaCha8Rng,
    ) -> [f64; 2] {
        // texel si's replicate r, sample j at (2 si + r) k + j
        let mut us = Vec::with_capacity(2 * k * shares.len());
        for si in 0..shares.len() {
            for &scr in &scrambles {
                for j in 0..k {
                    us.push(uniforms(si * k + j, scr, rng));
                }
            }
        }
        let q = self.light_values(texels, |s| s / (2 * k), &us);
        let mut reps = [0.0f64; 2];
        for (si, (s, t)) in shares.iter().zip(texels).enumerate() {
            for (r, rep) in reps.iter_mut().enumerate() {
                let mut qs = 0.0;
                for x in &q[(2 * si + r) * k..(2 * si + r + 1) * k] {
                    qs += x;
                }
                *rep += s.area * (t.3 + qs / k as f64);
            }
        }
        reps
    }

    /// The two replicates' means over `m` texels each, drawn in proportion to their
    /// overlap: the texels in Z order, each owning its overlap's stretch of [0, A) (A the
    /// footprint's area), and replicate r takes the texel at (j + u_r) A/m for j < m, one
    /// uniform u_r per replicate (systematic sampling: every point is uniform on [0, A), so
    /// each draw is a texel with probability area/A and the mean of its radiance estimates
    /// the overlap-weighted mean without bias; the replicates' offsets are independent, so
    /// their half difference is still the standard error). Each drawn texel takes its exact
    /// part and one sample of the sampled lights, the j-th point of its replicate's Sobol
    /// sequence (each replicate's own scramble). `prepare` places and prepares a texel; its
    /// exact part is computed here.
    pub(super) fn drawn_texels(
        &self,
        shares: &[Share],
        m: usize,
        prepare: impl Fn(&Share) -> Texel,
        rng: &mut ChaCha8Rng,
    ) -> [f64; 2] {
        let order = z_order(shares);
        // the offsets first, then the scrambles: a pixel's drawn truth takes other numbers
        // of its stream than its every-texel truth, so the two are independent
        let offsets: [f64; 2] = [rng.random(), rng.random()];
        let scrambles: [u32; 2] = [rng.random(), rng.random()];
        // replicate r's draws at r m .. (r + 1) m
        let picked: Vec<&Share> = offsets
            .iter()
            .flat_map(|&off| systematic(&order, m, off))
            .collect();
        let texels = self.with_exact(picked.iter().map(|s| prepare(s)));
        let mut us = Vec::with_capacity(2 * m);
        for &scr in &scrambles {
            for j in 0..m {
                us.push(uniforms(j, scr, rng));
            }
        }
        let q = self.light_values(&texels, |s| s, &us);
        let mut reps = [0.0f64; 2];
        for (r, rep) in reps.iter_mut().enumerate() {
            let mut s = 0.0;
            for (t, x) in texels[r * m..(r + 1) * m]
                .iter()
                .zip(&q[r * m..(r + 1) * m])
            {
                s += t.3 + x;
            }
            *rep = s / m as f64;
        }
        reps
    }

    /// n footprint samples as two replicates of n/2 (each a jittered grid when n/2 is a
    /// square, else uniform).
    pub(super) fn supersampled(
        &self,
        cam: &Camera,
        surf: &Surface,
        x: usize,
        y: usize,
        n: usize,
        rng: &mut ChaCha8Rng,
    ) -> PixelTruth {
        let half = (n / 2).max(1);
        let g = (half as f64).sqrt().round() as usize;
        let grid = g * g == half;
        let mut covered = true;
        let mut reps = [0.0f64; 2];
        for rep in &mut reps {
            let mut s = 0.0;
            for k in 0..half {
                let (jx, jy): (f64, f64) = (rng.random(), rng.random());
                let (ox, oy) = if grid {
                    (
                        ((k % g) as f64 + jx) / g as f64,
                        ((k / g) as f64 + jy) / g as f64,
                    )
                } else {
                    (jx, jy)
                };
                let d = cam.dir(x as f64 + ox, y as f64 + oy);
                s += match surf.intersect(&cam.eye, &d) {
                    Some(hit) => {
                        let nt = self.tex.texel(hit.uv);
                        self.sample(&hit, &cam.eye, &nt, rng)
                    }
                    None => {
                        covered = false;
                        0.0
                    }
                };
            }
            *rep = s / half as f64;
        }
        PixelTruth {
            value: 0.5 * (reps[0] + reps[1]),
            diff: 0.5 * (reps[0] - reps[1]),
            covered,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Averaged over the offset (a midpoint grid of 1024 offsets), the systematic draws take
    /// each texel m aᵢ/A times: 400 random footprints of 1–300 texels with areas spread over
    /// six decades, scattered over the map, and 1 ≤ m ≤ 2 × texels. Each texel's draws are
    /// intervals of the offset, two ends each, so the grid's count is within
    /// 2 (m aᵢ/A + 2)/1024 of the exact mean.
    #[test]
    fn draws_take_each_texel_in_proportion_to_its_overlap() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        const K: usize = 1024;
        for _ in 0..400 {
            let t = rng.random_range(1..=300usize);
            let shares: Vec<Share> = (0..t)
                .map(|k| Share {
                    i: (k % 37) as i64 - 18 + rng.random_range(-3..=3) * 40,
                    j: (k / 37) as i64 * 3 - 7,
                    area: 10f64.powf(rng.random_range(-6.0..0.0)),
                    centroid: [0.0; 2],
                })
                .collect();
            let m = rng.random_range(1..=2 * t);
            let order = z_order(&shares);
            let total: f64 = order.iter().map(|s| s.area).sum();
            let mut count = std::collections::HashMap::new();
            for g in 0..K {
                for s in systematic(&order, m, (g as f64 + 0.5) / K as f64) {
                    *count.entry((s.i, s.j, s.area.to_bits())).or_insert(0usize) += 1;
                }
            }
            for s in &shares {
                let got = count
                    .get(&(s.i, s.j, s.area.to_bits()))
                    .copied()
                    .unwrap_or(0) as f64
                    / K as f64;
                let want = m as f64 * s.area / total;
                assert!(
                    (got - want).abs() <= 2.0 * (want + 2.0) / K as f64,
                    "{t} texels, m = {m}: drawn {got} times on average, {want} expected"
                );
            }
        }
    }

    /// The guarantee `uniforms` relies on, over the indices and scrambles the truth uses:
    /// sobol_burley's four dimensions at once are its one-at-a-time samples, bit for bit.
    #[test]
    fn four_dimensions_are_sample_one_by_one() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for k in 0..20_000u32 {
            let i = if k < 4096 {
                k
            } else {
                rng.random_range(0..1 << 16)
            };
            let scr: u32 = rng.random();
            let four = sobol_burley::sample_4d(i, 0, scr);
            for (d, v) in four.iter().enumerate().take(3) {
                assert_eq!(
                    v.to_bits(),
                    sobol_burley::sample(i, d as u32, scr).to_bits(),
                    "index {i}, dimension {d}, scramble {scr:#x}"
                );
            }
        }
    }
}

//! The mip pyramid of a normal map's footprint statistics: per texel of every level the
//! mean of the unit normals under it (its length is r = ‖μ‖, seed 004 §3.2.1), the mean
//! base α² and the mean perceptual roughness. Each level is the equal-weight average of
//! the (up to) 2×2 texels of the one above, so the whole chain costs O(N) for N base
//! texels — against O(N log N) for a tool that re-reads the base level for every mip
//! (Filament's roughness-prefilter). `direct` is the f64 reference: the plain average of
//! the base block.

use super::input::{Normals, Roughness};
use rayon::prelude::*;

/// One level's statistics (row-major).
#[derive(Clone, Debug)]
pub struct Level {
    pub width: usize,
    pub height: usize,
    /// Mean of the unit normals of the footprint (not renormalised).
    pub mean_n: Vec<[f32; 3]>,
    /// Mean base α² (α = p²).
    pub mean_a2: Vec<f32>,
    /// Mean perceptual roughness p (what an engine's box-filtered roughness mip holds).
    pub mean_p: Vec<f32>,
}

impl Level {
    /// r = ‖μ‖ of texel k, in f64.
    pub fn r(&self, k: usize) -> f64 {
        let m = self.mean_n[k];
        let (x, y, z) = (m[0] as f64, m[1] as f64, m[2] as f64);
        (x * x + y * y + z * z).sqrt()
    }
}

/// Level 0: the map's own normals and roughness (consumes the normals).
pub fn level0(normals: Normals, rough: &Roughness) -> Level {
    let (w, h) = (normals.width, normals.height);
    let mean_p: Vec<f32> = (0..w * h).map(|k| rough.perceptual(k % w, k / w)).collect();
    let mean_a2 = mean_p.iter().map(|&p| {
        let a = p as f64 * p as f64;
        (a * a) as f32
    });
    Level {
        width: w,
        height: h,
        mean_a2: mean_a2.collect(),
        mean_p,
        mean_n: normals.n,
    }
}

/// The next level: each texel the average (in f64, rounded once to f32) of the 2×2
/// texels above it, or 2×1 / 1×2 once one side is 1. Rows in parallel; every texel is
/// computed the same way at any thread count.
pub fn reduce(prev: &Level) -> Level {
    let w = (prev.width / 2).max(1);
    let h = (prev.height / 2).max(1);
    let (sx, sy) = (prev.width / w, prev.height / h);
    let rows: Vec<(Vec<[f32; 3]>, Vec<f32>, Vec<f32>)> = (0..h)
        .into_par_iter()
        .map(|j| {
            let mut n = Vec::with_capacity(w);
            let mut a2 = Vec::with_capacity(w);
            let mut p = Vec::with_capacity(w);
            for i in 0..w {
                let mut s = [0f64; 5];
                for dy in 0..sy {
                    for dx in 0..sx {
                        let k = (j * sy + dy) * prev.width + i * sx + dx;
                        let m = prev.mean_n[k];
                        s[0] += m[0] as f64;
                        s[1] += m[1] as f64;
                        s[2] += m[2] as f64;
                        s[3] += prev.mean_a2[k] as f64;
                        s[4] += prev.mean_p[k] as f64;
                    }
                }
                let c = (sx * sy) as f64;
                n.push([(s[0] / c) as f32, (s[1] / c) as f32, (s[2] / c) as f32]);
                a2.push((s[3] / c) as f32);
                p.push((s[4] / c) as f32);
            }
            (n, a2, p)
        })
        .collect();
    let mut out = Level {
        width: w,
        height: h,
        mean_n: Vec::with_capacity(w * h),
        mean_a2: Vec::with_capacity(w * h),
        mean_p: Vec::with_capacity(w * h),
    };
    for (n, a2, p) in rows {
        out.mean_n.extend(n);
        out.mean_a2.extend(a2);
        out.mean_p.extend(p);
    }
    out
}

/// Every level from 0 down to 1×1.
pub fn pyramid(normals: Normals, rough: &Roughness) -> Vec<Level> {
    let mut levels = vec![level0(normals, rough)];
    while levels.last().is_some_and(|l| l.width > 1 || l.height > 1) {
        let next = reduce(levels.last().expect("level"));
        levels.push(next);
    }
    levels
}

/// The f64 reference of texel (i, j) of level `l`: the direct average over the base
/// block it covers — (mean normal, mean α², mean p).
pub fn direct(base: &Level, l: usize, i: usize, j: usize) -> ([f64; 3], f64, f64) {
    let bw = (base.width >> l).max(1);
    let bh = (base.height >> l).max(1);
    let (sx, sy) = (base.width / bw, base.height / bh);
    let mut s = [0f64; 5];
    for y in j * sy..(j + 1) * sy {
        for x in i * sx..(i + 1) * sx {
            let k = y * base.width + x;
            for c in 0..3 {
                s[c] += base.mean_n[k][c] as f64;
            }
            s[3] += base.mean_a2[k] as f64;
            s[4] += base.mean_p[k] as f64;
        }
    }
    let c = (sx * sy) as f64;
    ([s[0] / c, s[1] / c, s[2] / c], s[3] / c, s[4] / c)
}

/// Box mips of a two-channel map (w × h, row-major) down to 1×1: each level the 2×2
/// average of the one above. For the channels a glTF-layout output carries along
/// (occlusion, metallic), at the roughness map's own resolution.
pub fn box_mips(w: usize, h: usize, v: Vec<[f32; 2]>) -> Vec<(usize, usize, Vec<[f32; 2]>)> {
    let mut out = vec![(w, h, v)];
    loop {
        let (pw, ph, prev) = out.last().expect("level");
        if *pw == 1 && *ph == 1 {
            break;
        }
        let (nw, nh) = ((pw / 2).max(1), (ph / 2).max(1));
        let (sx, sy) = (pw / nw, ph / nh);
        let mut next = Vec::with_capacity(nw * nh);
        for j in 0..nh {
            for i in 0..nw {
                let mut s = [0f64; 2];
                for dy in 0..sy {
                    for dx in 0..sx {
                        let t = prev[(j * sy + dy) * pw + i * sx + dx];
                        s[0] += t[0] as f64;
                        s[1] += t[1] as f64;
                    }
                }
                let c = (sx * sy) as f64;
                next.push([(s[0] / c) as f32, (s[1] / c) as f32]);
            }
        }
        out.push((nw, nh, next));
    }
    out
}

//! The normal map as the renderer reads it: the texel's own normal (nearest, level 0:
//! what the truth shades) and the linear statistics of the mip chain read trilinearly at
//! the footprint's level (what a shader's filtered fetch returns; the chain stores the
//! unnormalised mean normal and the slope moments, both linear, so bilinear and trilinear
//! filtering of them is exact averaging).

use crate::filters::footprint::{MipChain, NormalMap, Stats};
use nalgebra::Vector3;

type V3 = Vector3<f64>;

/// A periodic normal map and its mip chain.
pub struct Texture {
    pub map: NormalMap,
    pub chain: MipChain,
}

fn wrap(i: i64, n: usize) -> usize {
    i.rem_euclid(n as i64) as usize
}

impl Texture {
    pub fn new(map: NormalMap) -> Texture {
        let chain = MipChain::build(&map);
        Texture { map, chain }
    }

    /// The level-0 texel containing map coordinates uv (periodic).
    pub fn texel(&self, uv: [f64; 2]) -> V3 {
        let (w, h) = (self.map.width, self.map.height);
        let i = wrap((uv[0] * w as f64).floor() as i64, w);
        let j = wrap((uv[1] * h as f64).floor() as i64, h);
        self.map.normals[j * w + i]
    }

    /// Texel coordinates (i, j) of uv at level 0, for a footprint sum.
    pub fn texel_coords(&self, uv: [f64; 2]) -> [f64; 2] {
        [
            uv[0] * self.map.width as f64,
            uv[1] * self.map.height as f64,
        ]
    }

    /// The level-0 texel (i, j), periodic.
    pub fn at(&self, i: i64, j: i64) -> V3 {
        let (w, h) = (self.map.width, self.map.height);
        self.map.normals[wrap(j, h) * w + wrap(i, w)]
    }

    /// The GPU's isotropic level of detail for the footprint (∂uv/∂x, ∂uv/∂y):
    /// log2 of the longer derivative in level-0 texels, clamped to the chain.
    pub fn lod(&self, fp: &[[f64; 2]; 2]) -> f64 {
        let (w, h) = (self.map.width as f64, self.map.height as f64);
        let len = |d: &[f64; 2]| ((d[0] * w).powi(2) + (d[1] * h).powi(2)).sqrt();
        let l = len(&fp[0]).max(len(&fp[1]));
        let top = (self.chain.levels.len() - 1) as f64;
        if !(l.is_finite()) {
            return top;
        }
        l.max(1.0).log2().min(top)
    }

    fn bilinear(&self, level: usize, uv: [f64; 2]) -> Stats {
        let lv = &self.chain.levels[level];
        let x = uv[0] * lv.width as f64 - 0.5;
        let y = uv[1] * lv.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |i: i64, j: i64| &lv.stats[wrap(j, lv.height) * lv.width + wrap(i, lv.width)];
        let (i, j) = (x0 as i64, y0 as i64);
        blend(&[
            (at(i, j), (1.0 - fx) * (1.0 - fy)),
            (at(i + 1, j), fx * (1.0 - fy)),
            (at(i, j + 1), (1.0 - fx) * fy),
            (at(i + 1, j + 1), fx * fy),
        ])
    }

    /// Trilinear statistics at uv and level λ.
    pub fn stats(&self, uv: [f64; 2], lod: f64) -> Stats {
        let top = self.chain.levels.len() - 1;
        let l0 = (lod.floor().max(0.0) as usize).min(top);
        let l1 = (l0 + 1).min(top);
        let f = (lod - l0 as f64).clamp(0.0, 1.0);
        let a = self.bilinear(l0, uv);
        if l1 == l0 || f == 0.0 {
            return a;
        }
        let b = self.bilinear(l1, uv);
        blend(&[(&a, 1.0 - f), (&b, f)])
    }
}

fn blend(parts: &[(&Stats, f64)]) -> Stats {
    let mut o = Stats {
        mean_normal: [0.0; 3],
        m1: [0.0; 2],
        m2: [0.0; 3],
    };
    for (s, w) in parts {
        for k in 0..3 {
            o.mean_normal[k] += w * s.mean_normal[k];
            o.m2[k] += w * s.m2[k];
        }
        for k in 0..2 {
            o.m1[k] += w * s.m1[k];
        }
    }
    o
}

//! The anisotropic GGX LTC table: its grid, its layout, and the lookup a shader does.
//!
//! Grid: r_x = √α_x and r_y = √α_y uniform on [0, 1] (α = max(r², α_min)), the tangent
//! azimuth φ uniform on [0, π/2] (the symmetries of `ltc::aniso` cover the rest), and
//! t = √(1 − cos θ) uniform on [0, 1] — the isotropic table's coordinates plus two.
//! Cell (i_x, i_y, k, j) holds (a, b, c, d, e, g, h, norm, fresnel).
//!
//! Texture layout (`<stem>.ktx2`, RGBA16F 2D array): width = n_r (r_x), height = n_t
//! (t), and 3 layers per (i_y, k) pair at 3·(k·n_r + i_y) + {0: (a, b, c, d), 1: (norm,
//! fresnel, 0, 0), 2: (e, g, h, 0)}. The sampler interpolates (r_x, t); the lookup blends
//! the four (r_y, φ) neighbours by hand: 12 fetches.

use super::aniso::{mirror_y, Inv7};

/// One cell: (a, b, c, d, e, g, h, norm, fresnel).
pub type AnisoCell = [f64; 9];

/// The grid of the table.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AnisoGrid {
    pub n_r: usize,
    pub n_phi: usize,
    pub n_t: usize,
    pub alpha_min: f64,
}

impl AnisoGrid {
    /// α at roughness index i.
    pub fn alpha(&self, i: usize) -> f64 {
        let r = i as f64 / (self.n_r - 1) as f64;
        (r * r).max(self.alpha_min)
    }
    /// φ at index k.
    pub fn phi(&self, k: usize) -> f64 {
        std::f64::consts::FRAC_PI_2 * k as f64 / (self.n_phi - 1) as f64
    }
    /// θ at view index j.
    pub fn theta(&self, j: usize) -> f64 {
        let t = j as f64 / (self.n_t - 1) as f64;
        (1.0 - t * t).clamp(0.0, 1.0).acos()
    }
    /// The flat index of cell (i_x, i_y, k, j).
    pub fn index(&self, ix: usize, iy: usize, k: usize, j: usize) -> usize {
        ix + self.n_r * (iy + self.n_r * (k + self.n_phi * j))
    }
    pub fn cells(&self) -> usize {
        self.n_r * self.n_r * self.n_phi * self.n_t
    }
    /// The cells a fit computes, (i_x, i_y, k, j) in fit order: α_x ≥ α_y, and on the
    /// diagonal only φ ≤ π/4 (the others follow by the symmetry (α_y, α_x, π/2 − φ)).
    pub fn fitted_cells(&self) -> Vec<(usize, usize, usize, usize)> {
        let mut todo = Vec::new();
        for j in 0..self.n_t {
            for k in 0..self.n_phi {
                for iy in 0..self.n_r {
                    for ix in iy..self.n_r {
                        if ix == iy && 2 * k > self.n_phi - 1 {
                            continue;
                        }
                        todo.push((ix, iy, k, j));
                    }
                }
            }
        }
        todo
    }
}

/// The fitted table.
#[derive(Clone, Debug, PartialEq)]
pub struct AnisoTable {
    pub grid: AnisoGrid,
    pub cells: Vec<AnisoCell>,
}

/// (φ reduced to [0, π/2], whether the lobe is the y-mirror of the reduced one).
pub fn reduce_phi(phi: f64) -> (f64, bool) {
    use std::f64::consts::{FRAC_PI_2, PI};
    // the tangent is a line: φ ≡ φ + π
    let p = phi.rem_euclid(PI);
    if p <= FRAC_PI_2 {
        (p, false)
    } else {
        (PI - p, true)
    }
}

impl AnisoTable {
    /// The FNV-1a hash of the grid's sides and every entry's bits, in hex: which table a
    /// study read.
    pub fn fingerprint(&self) -> String {
        let g = self.grid;
        let mut bytes = Vec::new();
        for n in [g.n_r, g.n_phi, g.n_t] {
            bytes.extend_from_slice(&(n as u64).to_le_bytes());
        }
        for v in self.cells.iter().flatten() {
            bytes.extend_from_slice(&v.to_bits().to_le_bytes());
        }
        format!("{:016x}", crate::io::fnv1a(&bytes))
    }
    /// The table looked up as a shader does at (α_x, α_y, φ, cos θ): φ reduced by the
    /// symmetries, the four neighbours of every coordinate blended multilinearly (the
    /// texture sampler's bilinear step in (r_x, t) and the lookup's own in (r_y, φ)),
    /// then mirrored back. The f64 reference of the WGSL lookup.
    pub fn lookup(&self, ax: f64, ay: f64, phi: f64, cos_theta: f64) -> AnisoCell {
        let g = &self.grid;
        let (p, mirrored) = reduce_phi(phi);
        let coord = |x: f64, n: usize| -> (usize, f64) {
            let x = x.clamp(0.0, 1.0) * (n - 1) as f64;
            let i = (x.floor() as usize).min(n - 2);
            (i, x - i as f64)
        };
        let (ix, fx) = coord(ax.clamp(0.0, 1.0).sqrt(), g.n_r);
        let (iy, fy) = coord(ay.clamp(0.0, 1.0).sqrt(), g.n_r);
        let (k, fk) = coord(p / std::f64::consts::FRAC_PI_2, g.n_phi);
        let (j, fj) = coord((1.0 - cos_theta.clamp(0.0, 1.0)).sqrt(), g.n_t);
        let mut out = [0.0; 9];
        for (dx, wx) in [(0, 1.0 - fx), (1, fx)] {
            for (dy, wy) in [(0, 1.0 - fy), (1, fy)] {
                for (dk, wk) in [(0, 1.0 - fk), (1, fk)] {
                    for (dj, wj) in [(0, 1.0 - fj), (1, fj)] {
                        let w = wx * wy * wk * wj;
                        let c = &self.cells[g.index(ix + dx, iy + dy, k + dk, j + dj)];
                        for q in 0..9 {
                            out[q] += w * c[q];
                        }
                    }
                }
            }
        }
        if mirrored {
            let m = mirror_y(&inv7(&out));
            out[..7].copy_from_slice(&m);
        }
        out
    }

    /// The texture's binary16 storage: the matrix by `aniso::half_keeping_lobe` (to
    /// nearest, unless that would mirror the lobe), norm and fresnel to nearest.
    pub fn to_half(&self) -> AnisoTable {
        AnisoTable {
            grid: self.grid,
            cells: self.cells.iter().map(half_cell).collect(),
        }
    }
}

/// One cell as binary16 stores it (see [`AnisoTable::to_half`]).
pub fn half_cell(c: &AnisoCell) -> AnisoCell {
    let m = super::aniso::half_keeping_lobe(&inv7(c));
    let mut out = c.map(|x| half::f16::from_f64(x).to_f64());
    out[..7].copy_from_slice(&m);
    out
}

/// The production inverse of a cell.
pub fn inv7(c: &AnisoCell) -> Inv7 {
    [c[0], c[1], c[2], c[3], c[4], c[5], c[6]]
}

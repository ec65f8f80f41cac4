//! A fitted LTC table as shaders sample it: cells [a, b, c, d, norm, fresnel] on the
//! (√α, √(1 − cos θ)) grid, their binary16 storage and the bilinear lookup engines do.
//! Read from results/ by `crate::results::ltc::table`.

/// Grid parameterisation: perceptual roughness r = √α (α = max(r², α_min)) and
/// t = √(1 − cos θ), both uniform on [0, 1] with `n` points.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Grid {
    pub n: usize,
    pub alpha_min: f64,
}

impl Grid {
    pub fn alpha(&self, i: usize) -> f64 {
        let r = i as f64 / (self.n - 1) as f64;
        (r * r).max(self.alpha_min)
    }
    pub fn theta(&self, j: usize) -> f64 {
        let t = j as f64 / (self.n - 1) as f64;
        (1.0 - t * t).clamp(0.0, 1.0).acos()
    }
}

/// A fitted table: `cells[i + n·j]` = [a, b, c, d, norm, fresnel] at roughness index i
/// (r = √α = i/(n − 1)) and view index j (t = √(1 − cos θ) = j/(n − 1)).
#[derive(Clone, Debug, PartialEq)]
pub struct FittedTable {
    pub n: usize,
    pub cells: Vec<[f64; 6]>,
    /// The binary16 table chosen for storage (`table_f16`: per cell the f16 neighbours
    /// of the f64 entries that minimise the fit's error), in the same layout; `None` for
    /// a file without one (then f16 storage rounds to nearest).
    pub half: Option<Vec<[half::f16; 6]>>,
}

/// Largest table side read from a file.
pub const MAX_SIDE: usize = 1024;

impl FittedTable {
    /// A fingerprint of the f64 table (FNV-1a over its side and every entry's bits, in
    /// file order), as hex: what identifies the table a stored comparison was made
    /// against, whatever tolerance its held-out figures were judged to.
    pub fn fingerprint(&self) -> String {
        let mut bytes = (self.n as u64).to_le_bytes().to_vec();
        for c in &self.cells {
            for v in c {
                bytes.extend_from_slice(&v.to_bits().to_le_bytes());
            }
        }
        format!("{:016x}", crate::io::fnv1a(&bytes))
    }

    /// Cell (i, j).
    pub fn cell(&self, i: usize, j: usize) -> &[f64; 6] {
        &self.cells[i + self.n * j]
    }
    /// The binary16 entries of cell `k` (= i + n·j) as stored in every f16 file.
    pub fn half_cell(&self, k: usize) -> [half::f16; 6] {
        match &self.half {
            Some(h) => h[k],
            None => self.cells[k].map(half::f16::from_f64),
        }
    }
}

impl FittedTable {
    /// The table interpolated bilinearly at (α, cos θ) as a GPU's linear, clamp-to-edge
    /// sampler reads the texture at uv = ((r, t)(n − 1) + ½)/n: texel coordinates
    /// x = r(n − 1), y = t(n − 1) with r = √α, t = √(1 − cos θ) (α and cos θ clamped to
    /// [0, 1]). `half`: the binary16 entries as stored in every f16 file, else the f64
    /// table. The f64 reference of the WGSL lookup (codegen/lut.rs).
    pub fn bilinear(&self, alpha: f64, cos_theta: f64, half: bool) -> [f64; 6] {
        let n = self.n;
        let r = alpha.clamp(0.0, 1.0).sqrt();
        let t = (1.0 - cos_theta.clamp(0.0, 1.0)).sqrt();
        bilinear(n, r, t, |i, j| {
            let k = i + n * j;
            if half {
                self.half_cell(k).map(|h| h.to_f64())
            } else {
                self.cells[k]
            }
        })
    }
}

/// The bilinear lookup engines do in an n×n table (n ≥ 2) at (r, t) ∈ [0, 1]²: texel
/// centres at (i, j)/(n − 1) (uv = (r, t)·(n − 1)/n + 0.5/n), the four texels around the
/// point weighted linearly, clamped at the edges; `at(i, j)` gives a texel.
pub fn bilinear<const K: usize>(
    n: usize,
    r: f64,
    t: f64,
    at: impl Fn(usize, usize) -> [f64; K],
) -> [f64; K] {
    let (x, y) = (
        r.clamp(0.0, 1.0) * (n - 1) as f64,
        t.clamp(0.0, 1.0) * (n - 1) as f64,
    );
    let (i0, j0) = (
        (x.floor() as usize).min(n - 2),
        (y.floor() as usize).min(n - 2),
    );
    let (fx, fy) = (x - i0 as f64, y - j0 as f64);
    let (c00, c10, c01, c11) = (
        at(i0, j0),
        at(i0 + 1, j0),
        at(i0, j0 + 1),
        at(i0 + 1, j0 + 1),
    );
    std::array::from_fn(|c| {
        (c00[c] * (1.0 - fx) + c10[c] * fx) * (1.0 - fy) + (c01[c] * (1.0 - fx) + c11[c] * fx) * fy
    })
}

/// The settings of a spec that fits an LTC table through `ltc::fit::fit_table`: cells per axis
/// `n`, the α floor, stratified samples per axis and technique, the Nelder–Mead cap per
/// cell, and the MC samples of its polygon checks. The error names the key.
pub fn check_table_settings(
    n: usize,
    alpha_min: f64,
    samples: usize,
    max_iters: u64,
    mc: usize,
) -> std::result::Result<(), String> {
    use crate::fit::spec::within;
    within("n", n, 2, 256)?;
    within("alpha_min", alpha_min, 1e-6, 0.5)?;
    within("samples", samples, 2, 128)?;
    within("max_iters", max_iters, 1, 100_000)?;
    within("mc", mc, 16, 1 << 24)
}

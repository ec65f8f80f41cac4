//! P-NDF images (seed 002 Eq 2, §4.1) by brute force over texels: the footprint-weighted
//! sum of each texel's normal smeared by the intrinsic roughness,
//! D(h) = Σ_u G_P(u; x, σ_P) · G_r(n(u)_xy; h_xy, σ_r) (both Gaussians normalised), on a
//! res × res grid over the projected hemisphere h_xy ∈ [−1, 1]². Rayon over image rows.
//! Footprints: stride s at level 0 with σ_P = 1.5 s/√12, each level 2×2 sparser.

use crate::error::{Error, Result};
use crate::filters::footprint::NormalMap;
use nalgebra::Vector3;
use rayon::prelude::*;

/// The footprint's texels within 4σ_P of (cx, cy) (periodic map) as (n_x, n_y, weight)
/// in scan order, and the weights' sum; the arguments checked.
fn footprint_texels(
    map: &NormalMap,
    cx: f64,
    cy: f64,
    sigma_p: f64,
    sigma_r: f64,
    res: usize,
) -> Result<(Vec<(f64, f64, f64)>, f64)> {
    let (w, h) = (map.width as i64, map.height as i64);
    window_texels(
        &|px, py| Some(map.normals[(py.rem_euclid(h) * w + px.rem_euclid(w)) as usize]),
        cx,
        cy,
        sigma_p,
        sigma_r,
        res,
    )
}

/// A normal per texel (x, y) of the plane, or `None` for a texel the sum leaves out (it
/// still counts in the footprint's weight).
pub type Lookup<'a> = &'a dyn Fn(i64, i64) -> Option<Vector3<f64>>;

/// [`footprint_texels`] over any texel lookup: the window, the cut-off and the scan order
/// are the same, so a map split into pieces ([`pndf_partial_separable`]) gives the whole
/// map's weight sum bit for bit and its texels piece by piece.
fn window_texels(
    lookup: Lookup,
    cx: f64,
    cy: f64,
    sigma_p: f64,
    sigma_r: f64,
    res: usize,
) -> Result<(Vec<(f64, f64, f64)>, f64)> {
    if !(sigma_p > 0.0 && sigma_r > 0.0 && res >= 2 && cx.is_finite() && cy.is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "P-NDF needs σ_P > 0, σ_r > 0, res ≥ 2 and a finite centre (got {sigma_p:e}, {sigma_r:e}, {res}, ({cx:e}, {cy:e}))"
        )));
    }
    let rad = (4.0 * sigma_p).ceil() as i64;
    let mut texels = Vec::new();
    let mut wsum = 0.0;
    for dy in -rad..=rad {
        for dx in -rad..=rad {
            let (px, py) = (cx.floor() as i64 + dx, cy.floor() as i64 + dy);
            let (ux, uy) = (px as f64 + 0.5 - cx, py as f64 + 0.5 - cy);
            let g = (-(ux * ux + uy * uy) / (2.0 * sigma_p * sigma_p)).exp();
            if g < 1e-12 {
                continue;
            }
            wsum += g;
            if let Some(n) = lookup(px, py) {
                texels.push((n.x, n.y, g));
            }
        }
    }
    Ok((texels, wsum))
}

/// The window's reach in texels: a footprint of σ_P centred at c reads the texels
/// ⌊c⌋ − reach ..= ⌊c⌋ + reach on each axis.
pub fn window_reach(sigma_p: f64) -> i64 {
    (4.0 * sigma_p).ceil() as i64
}

/// One footprint's NDF image, row-major, values per unit projected area.
pub fn pndf_image(
    map: &NormalMap,
    cx: f64,
    cy: f64,
    sigma_p: f64,
    sigma_r: f64,
    res: usize,
) -> Result<Vec<f64>> {
    let (texels, wsum) = footprint_texels(map, cx, cy, sigma_p, sigma_r, res)?;
    let norm_r = 1.0 / (2.0 * std::f64::consts::PI * sigma_r * sigma_r);
    let cell = 2.0 / res as f64;
    let img: Vec<f64> = (0..res)
        .into_par_iter()
        .flat_map_iter(|j| {
            let hy = -1.0 + (j as f64 + 0.5) * cell;
            let texels = &texels;
            (0..res).map(move |i| {
                let hx = -1.0 + (i as f64 + 0.5) * cell;
                let mut s = 0.0;
                for &(nx, ny, g) in texels {
                    let d2 = (nx - hx).powi(2) + (ny - hy).powi(2);
                    let e = d2 / (2.0 * sigma_r * sigma_r);
                    if e < 40.0 {
                        s += g * (-e).exp();
                    }
                }
                s * norm_r / wsum
            })
        })
        .collect();
    Ok(img)
}

/// σ_P of level ℓ for base stride s (seed 002 §4.1): 1.5·s·2^ℓ/√12.
pub fn sigma_p(stride: usize, level: usize) -> f64 {
    1.5 * (stride << level) as f64 / 12f64.sqrt()
}

/// What both splats start from: the footprint's texels and weight sum, the bin width, how
/// many bins from a normal's own the cut-off e < 40 reaches, and G_r's normalisation.
struct Splat {
    texels: Vec<(f64, f64, f64)>,
    wsum: f64,
    cell: f64,
    reach: i64,
    norm_r: f64,
}

impl Splat {
    fn new(map: &NormalMap, cx: f64, cy: f64, sp: f64, sr: f64, res: usize) -> Result<Splat> {
        Splat::of(footprint_texels(map, cx, cy, sp, sr, res)?, sr, res)
    }

    fn of((texels, wsum): (Vec<(f64, f64, f64)>, f64), sr: f64, res: usize) -> Result<Splat> {
        let cell = 2.0 / res as f64;
        Ok(Splat {
            texels,
            wsum,
            cell,
            reach: (80f64.sqrt() * sr / cell).ceil() as i64 + 1,
            norm_r: 1.0 / (2.0 * std::f64::consts::PI * sr * sr),
        })
    }
}

/// The same image as [`pndf_image`] computed by splatting: each texel adds its Gaussian
/// to the bins within the cut-off (exp(−e), e < 40) of its normal instead of every bin
/// visiting every texel — O(texels × bins near a normal) rather than O(texels × res²),
/// which makes footprint grids of 1K² maps affordable. Equal to [`pndf_image`] up to the
/// order of the additions (tests/render.rs bounds the difference).
pub fn pndf_image_splat(
    map: &NormalMap,
    cx: f64,
    cy: f64,
    sigma_p: f64,
    sigma_r: f64,
    res: usize,
) -> Result<Vec<f64>> {
    let Splat {
        texels,
        wsum,
        cell,
        reach,
        norm_r,
    } = Splat::new(map, cx, cy, sigma_p, sigma_r, res)?;
    let mut img = vec![0.0; res * res];
    for &(nx, ny, g) in &texels {
        let (bi, bj) = (((nx + 1.0) / cell) as i64, ((ny + 1.0) / cell) as i64);
        for j in (bj - reach).max(0)..=(bj + reach).min(res as i64 - 1) {
            let hy = -1.0 + (j as f64 + 0.5) * cell;
            for i in (bi - reach).max(0)..=(bi + reach).min(res as i64 - 1) {
                let hx = -1.0 + (i as f64 + 0.5) * cell;
                let e = ((nx - hx).powi(2) + (ny - hy).powi(2)) / (2.0 * sigma_r * sigma_r);
                if e < 40.0 {
                    img[j as usize * res + i as usize] += g * (-e).exp();
                }
            }
        }
    }
    let k = norm_r / wsum;
    img.iter_mut().for_each(|v| *v *= k);
    Ok(img)
}

/// The same image as [`pndf_image_splat`] with the Gaussian in h factored: each texel's
/// exp(−e) = exp(−e_x)·exp(−e_y) (e = e_x + e_y, the cut-off e < 40 applied to their sum),
/// so a texel costs 2·(2·reach + 1) exponentials and one multiply-add per bin near its
/// normal instead of one exponential per bin. This is what makes seed 002's scale (2K²
/// maps, 256² images, seed 002 §4.1) affordable on a few cores. Equal to [`pndf_image`]
/// up to rounding (exp(a)·exp(b) against exp(a + b), the order of the additions):
/// tests/tensor.rs bounds the difference at 1e-12 of the image's peak.
pub fn pndf_image_separable(
    map: &NormalMap,
    cx: f64,
    cy: f64,
    sigma_p: f64,
    sigma_r: f64,
    res: usize,
) -> Result<Vec<f64>> {
    Ok(separable(
        Splat::new(map, cx, cy, sigma_p, sigma_r, res)?,
        sigma_r,
        res,
    ))
}

/// The separable splat of one piece of the plane: the texels `lookup` returns, weighted
/// by the whole footprint's weight sum (texels it leaves out count in that sum). Pieces
/// that partition the plane add up to [`pndf_image`] of the whole up to rounding (seed
/// 002 §5.5: a footprint that crosses Wang tiles is the sum of the tiles' images).
pub fn pndf_partial_separable(
    lookup: Lookup,
    cx: f64,
    cy: f64,
    sigma_p: f64,
    sigma_r: f64,
    res: usize,
) -> Result<Vec<f64>> {
    let s = Splat::of(
        window_texels(lookup, cx, cy, sigma_p, sigma_r, res)?,
        sigma_r,
        res,
    )?;
    Ok(separable(s, sigma_r, res))
}

fn separable(s: Splat, sigma_r: f64, res: usize) -> Vec<f64> {
    let Splat {
        texels,
        wsum,
        cell,
        reach,
        norm_r,
    } = s;
    let inv = 1.0 / (2.0 * sigma_r * sigma_r);
    let mut img = vec![0.0; res * res];
    let span = (2 * reach + 1) as usize;
    let (mut ex, mut wx) = (vec![0.0; span], vec![0.0; span]);
    let last = res as i64 - 1;
    for &(nx, ny, g) in &texels {
        let (bi, bj) = (((nx + 1.0) / cell) as i64, ((ny + 1.0) / cell) as i64);
        let (i0, i1) = ((bi - reach).max(0), (bi + reach).min(last));
        let (j0, j1) = ((bj - reach).max(0), (bj + reach).min(last));
        if i0 > i1 || j0 > j1 {
            continue;
        }
        let w = (i1 - i0 + 1) as usize;
        for q in 0..w {
            let hx = -1.0 + ((i0 + q as i64) as f64 + 0.5) * cell;
            ex[q] = (nx - hx).powi(2) * inv;
            wx[q] = (-ex[q]).exp();
        }
        for j in j0..=j1 {
            let hy = -1.0 + (j as f64 + 0.5) * cell;
            let ey = (ny - hy).powi(2) * inv;
            if ey >= 40.0 {
                continue;
            }
            let gy = g * (-ey).exp();
            let row = &mut img[j as usize * res + i0 as usize..][..w];
            for q in 0..w {
                if ex[q] + ey < 40.0 {
                    row[q] += gy * wx[q];
                }
            }
        }
    }
    let k = norm_r / wsum;
    img.iter_mut().for_each(|v| *v *= k);
    img
}

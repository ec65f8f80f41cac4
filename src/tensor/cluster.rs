//! The tensors of a normal map (seed 002 §4.1–4.2): P-NDF images over the footprint
//! pyramid, cut into blocks and clustered by region into t×t×L tensors.

use super::cp::Tensor3;
use super::pndf::{pndf_image, sigma_p};
use crate::error::Result;
use crate::filters::footprint::NormalMap;
use rayon::prelude::*;

/// The block settings of a spec that clusters P-NDF images ([`cluster_tensors`]) and
/// CP-compresses them: block side `t`, image side `res` (whole blocks), CP ranks (≤ t², so
/// a rank never exceeds a block's own size), intrinsic roughness `sigma_r`. The error names
/// the key.
pub fn check_blocks(
    t: usize,
    res: usize,
    ranks: &[usize],
    sigma_r: f64,
) -> std::result::Result<(), String> {
    use crate::fit::spec::{all_within, splits, within};
    within("t", t, 2, 64)?;
    within("res", res, t, 1024)?;
    splits("res", res, "t", t)?;
    all_within("ranks", ranks, 1, t * t, 16)?;
    within("sigma_r", sigma_r, 1e-4, 1.0)
}

/// P-NDF images of `map` over the footprint pyramid (stride s, σ_P = 1.5 s/√12, each level
/// 2×2 sparser and twice wider, until the stride reaches the map size), cut into t×t blocks, all-zero blocks dropped, clustered by
/// quarter-map regions into t×t×L tensors (seed 002 §4.1–4.2).
pub fn cluster_tensors(
    map: &NormalMap,
    res: usize,
    stride: usize,
    t: usize,
    sigma_r: f64,
) -> Result<Vec<Tensor3>> {
    let size = map.width.min(map.height);
    if map.width != map.height || size < 2 * stride || res % t != 0 {
        return Err(crate::error::Error::InvalidArgument(format!(
            "tensor prefiltering needs a square map of at least {}² texels and an image size divisible by t = {t} (got {}×{}, image {res})",
            2 * stride, map.width, map.height
        )));
    }
    let region = size / 2;
    // footprints of both levels, with their region
    let mut fps = Vec::new();
    // levels until the stride reaches the map size (seed 002 §4.1)
    let levels = (0..).take_while(|l| (stride << l) <= size).count().max(1);
    for level in 0..levels {
        let st = stride << level;
        for cy in (st / 2..size).step_by(st) {
            for cx in (st / 2..size).step_by(st) {
                fps.push((
                    cx as f64,
                    cy as f64,
                    sigma_p(stride, level),
                    (cy / region) * (size / region) + cx / region,
                ));
            }
        }
    }
    let images: Vec<(usize, Vec<f64>)> = fps
        .par_iter()
        .map(|&(cx, cy, sp, reg)| pndf_image(&map, cx, cy, sp, sigma_r, res).map(|img| (reg, img)))
        .collect::<Result<_>>()?;
    let nreg = (size / region) * (size / region);
    let mut tensors = Vec::new();
    for reg in 0..nreg {
        let imgs: Vec<&[f64]> = images
            .iter()
            .filter(|(r, _)| *r == reg)
            .map(|(_, img)| img.as_slice())
            .collect();
        if let Some(stack) = stack_blocks(&imgs, res, t)? {
            tensors.push(stack.tensor);
        }
    }
    Ok(tensors)
}

/// Images cut into t×t blocks and stacked along the third mode, all-zero blocks dropped,
/// with where each block went.
#[derive(Clone, Debug)]
pub struct BlockStack {
    /// t × t × L.
    pub tensor: Tensor3,
    /// slots[image][by · (res/t) + bx]: the depth of that block, `None` for an all-zero one.
    pub slots: Vec<Vec<Option<usize>>>,
}

/// Cut res × res images (row-major) into t×t blocks in scan order (block rows, then
/// columns) and stack the non-zero ones (seed 002 §4.2). `None` when every block is zero;
/// a typed error when an image has the wrong size or t does not divide res.
pub fn stack_blocks(images: &[&[f64]], res: usize, t: usize) -> Result<Option<BlockStack>> {
    if t == 0 || res % t != 0 || images.iter().any(|img| img.len() != res * res) {
        return Err(crate::error::Error::InvalidArgument(format!(
            "blocks of side {t} need res × res images with t dividing res = {res}"
        )));
    }
    let nb = res / t;
    let mut data = Vec::new();
    let mut slots = Vec::with_capacity(images.len());
    let mut l = 0;
    for img in images {
        let mut row = Vec::with_capacity(nb * nb);
        for by in 0..nb {
            for bx in 0..nb {
                let block: Vec<f64> = (0..t * t)
                    .map(|q| img[(by * t + q / t) * res + bx * t + q % t])
                    .collect();
                if block.iter().any(|v| *v > 0.0) {
                    data.extend(block);
                    row.push(Some(l));
                    l += 1;
                } else {
                    row.push(None);
                }
            }
        }
        slots.push(row);
    }
    if l == 0 {
        return Ok(None);
    }
    Ok(Some(BlockStack {
        tensor: Tensor3::new([t, t, l], data)?,
        slots,
    }))
}

//! Seed 002 at its own scale, one spatial cluster at a time (§4.1–4.2): the P-NDF images of
//! the footprints centred in one region of the map at one footprint level, cut into t × t
//! blocks, the all-zero blocks dropped, stacked into one t × t × L tensor and CP-compressed
//! at each rank. A cluster is a pure function of its index, so clusters are the unit of
//! sharding; its images (L·t² values, tens of MB at 256² images) live only while it runs.

use super::cp::{cp_als, AlsOptions, Tensor3};
use super::pndf::{pndf_image_separable, sigma_p};
use crate::error::{Error, Result};
use crate::filters::footprint::NormalMap;
use serde::{Deserialize, Serialize};

/// The set-up of one run: the paper's choices by default (seed 002 §4.1–4.2: stride 32,
/// σ_P = 1.5 s/√12, 256² images, t = 16, an 8 × 8 grid of regions, tolerance 1e-4, at
/// most 500 iterations).
#[derive(Clone, Debug, Serialize)]
pub struct ScalePlan {
    pub stride: usize,
    pub level: usize,
    pub res: usize,
    pub t: usize,
    /// Regions per side of the map (the paper's 8 × 8).
    pub regions: usize,
    pub sigma_r: f64,
    pub ranks: Vec<usize>,
    pub tol: f64,
    pub max_iters: usize,
    pub seed: u64,
    /// Seeded ALS starts per CP (the best kept).
    pub starts: usize,
}

/// One rank's CP of a cluster.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RankRun {
    pub rank: usize,
    /// ‖T − T̂‖/‖T‖ in f64.
    pub rel_error: f64,
    pub iterations: usize,
    /// CP values stored: R(2t + L + 1).
    pub storage: usize,
    /// Wall clock of this CP (measured when computed).
    pub seconds: f64,
}

/// One cluster: its footprints, its non-empty blocks and each rank's CP.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ClusterRun {
    pub cluster: usize,
    pub footprints: usize,
    /// L: non-empty t × t blocks.
    pub blocks: usize,
    /// Blocks of all its images, empty ones included (footprints · (res/t)²).
    pub blocks_all: usize,
    pub pndf_seconds: f64,
    pub ranks: Vec<RankRun>,
}

impl ScalePlan {
    /// The footprint centres of `cluster` at the plan's level: every stride·2^level
    /// texels, centred in the cell, those inside the cluster's region.
    pub fn footprints(&self, size: usize, cluster: usize) -> Result<Vec<(f64, f64)>> {
        let st = self.stride << self.level;
        if self.regions == 0 || size % self.regions != 0 || st > size / self.regions {
            return Err(Error::InvalidArgument(format!(
                "tensor scale: a {size}² map in {0}×{0} regions needs regions of at least one footprint stride ({st})",
                self.regions
            )));
        }
        if cluster >= self.regions * self.regions {
            return Err(Error::InvalidArgument(format!(
                "tensor scale: cluster {cluster} of {}",
                self.regions * self.regions
            )));
        }
        let region = size / self.regions;
        let (rx, ry) = (cluster % self.regions, cluster / self.regions);
        let mut out = Vec::new();
        for cy in (st / 2..size).step_by(st) {
            for cx in (st / 2..size).step_by(st) {
                if cx / region == rx && cy / region == ry {
                    out.push((cx as f64, cy as f64));
                }
            }
        }
        Ok(out)
    }
}

/// Cluster `cluster` of `map` under `plan`: images, blocks, tensor, one CP per rank.
pub fn run_cluster(map: &NormalMap, plan: &ScalePlan, cluster: usize) -> Result<ClusterRun> {
    let (res, t) = (plan.res, plan.t);
    if map.width != map.height || t == 0 || res % t != 0 {
        return Err(Error::InvalidArgument(format!(
            "tensor scale needs a square map and an image size divisible by t (got {}×{}, image {res}, t = {t})",
            map.width, map.height
        )));
    }
    let fps = plan.footprints(map.width, cluster)?;
    let clock = std::time::Instant::now();
    let sp = sigma_p(plan.stride, plan.level);
    let mut data = Vec::new();
    let mut blocks = 0;
    let per_side = res / t;
    for &(cx, cy) in &fps {
        let img = pndf_image_separable(map, cx, cy, sp, plan.sigma_r, res)?;
        for by in 0..per_side {
            for bx in 0..per_side {
                let at = |q: usize| img[(by * t + q / t) * res + bx * t + q % t];
                if (0..t * t).any(|q| at(q) > 0.0) {
                    data.extend((0..t * t).map(at));
                    blocks += 1;
                }
            }
        }
    }
    let pndf_seconds = clock.elapsed().as_secs_f64();
    let mut ranks = Vec::new();
    if blocks > 0 {
        let tensor = Tensor3::new([t, t, blocks], data)?;
        for &r in &plan.ranks {
            let clock = std::time::Instant::now();
            let cp = cp_als(
                &tensor,
                &AlsOptions {
                    rank: r.min(t * t).min(t * blocks),
                    tol: plan.tol,
                    max_iters: plan.max_iters,
                    restarts: plan.starts,
                    seed: plan.seed,
                    nonnegative: false,
                },
            )?;
            ranks.push(RankRun {
                rank: r,
                rel_error: cp.rel_error,
                iterations: cp.iterations,
                storage: cp.storage(),
                seconds: clock.elapsed().as_secs_f64(),
            });
        }
    }
    Ok(ClusterRun {
        cluster,
        footprints: fps.len(),
        blocks,
        blocks_all: fps.len() * per_side * per_side,
        pndf_seconds,
        ranks,
    })
}

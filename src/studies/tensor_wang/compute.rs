//! The tensor-wang study's computation: tiles, seams, the tiles' images against the
//! explicit map's, per-tile CP, storage (seed 002 §5.5).

use crate::error::{Error, Result};
use crate::filters::footprint::{NormalMap, Procedural};
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::results::wang::{AreaStorage, Fig14, LevelCheck, RankCheck, Wang};
use crate::study::Ctx;
use crate::tensor::cluster::stack_blocks;
use crate::tensor::cp::{cp_als, AlsOptions};
use crate::tensor::pndf::{pndf_image, sigma_p};
use crate::tensor::wang::seams::{edge_mean, stats};
use crate::tensor::wang::synth::layout;
use crate::tensor::wang::{explicit, Colouring, CompressedTiles, Level, TileImages, TileSet};
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// What fits/tensor-wang.toml sets.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// The example map: a generator's name (`filters::footprint::Procedural`, made
    /// `example_size`² texels), or a normal-map PNG (a path; its own size is used, at least
    /// `side` texels each way).
    pub example: String,
    pub example_size: usize,
    /// Tile side, and the cut's band about each diagonal (0: straight).
    pub side: usize,
    pub band: usize,
    /// Footprint levels: stride s, σ_P = 1.5 s/√12 (seed 002 §4.1).
    pub strides: Vec<usize>,
    /// NDF image side over h_xy ∈ [−1, 1]², intrinsic roughness σ_r.
    pub res: usize,
    pub sigma_r: f64,
    /// Tiles per side of each explicit region, and each region's first cell.
    pub region: usize,
    pub regions: Vec<(i64, i64)>,
    /// Tiles per side of the map whose seams are measured.
    pub seam_cells: usize,
    /// Blocks and CP of the per-tile images.
    pub t: usize,
    pub ranks: Vec<usize>,
    pub iters: usize,
    pub als_tolerance: f64,
    /// Synthesised areas (tiles per side) of the storage table.
    pub areas: Vec<u64>,
}

/// The generators an example may name.
fn generators() -> impl Iterator<Item = Procedural> {
    Procedural::ALL.into_iter().chain([Procedural::Scratches])
}

/// The generator `name` names, if any.
fn generator(name: &str) -> Option<Procedural> {
    generators().find(|k| k.name() == name)
}

impl Params {
    /// The example map: generated, or read from the PNG (`NormalMap::from_png`: a broken
    /// file, or texels that are not unit upper-hemisphere normals, are typed errors).
    pub fn example_map(&self, seed: u64) -> Result<NormalMap> {
        match generator(&self.example) {
            Some(k) => NormalMap::procedural(k, self.example_size, seed),
            None => NormalMap::from_png(std::path::Path::new(&self.example)),
        }
    }
}

/// Cells from the origin a region may start at (its texels' coordinates stay exact in f64).
const FAR: i64 = 1 << 40;

impl crate::fit::spec::Params for Params {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::{all_within, power_of_two, within};
        if generator(&self.example).is_none() && !std::path::Path::new(&self.example).is_file() {
            return Err(format!(
                "example = {:?} is neither a generator ({}) nor a PNG file",
                self.example,
                generators()
                    .map(|k| k.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        power_of_two("example_size", self.example_size, 16, 1024)?;
        within("side", self.side, 8, self.example_size)?;
        if self.side % 2 != 0 {
            return Err(format!("side = {} must be even", self.side));
        }
        within("band", self.band, 0, self.side / 2)?;
        all_within("strides", &self.strides, 2, self.side, 4)?;
        for &s in &self.strides {
            if self.side % s != 0 {
                return Err(format!("strides: {s} does not divide side = {}", self.side));
            }
            // the window of the widest footprint fits inside a region
            let reach = crate::tensor::pndf::window_reach(sigma_p(s, 0)) as usize;
            if 2 * reach + 1 > self.region * self.side {
                return Err(format!(
                    "strides: a footprint of stride {s} is wider than a region of {} tiles",
                    self.region
                ));
            }
        }
        crate::tensor::cluster::check_blocks(self.t, self.res, &self.ranks, self.sigma_r)?;
        if !self.t.is_power_of_two() {
            return Err(format!("t = {} must be a power of two", self.t));
        }
        within("region", self.region, 2, 16)?;
        if self.regions.is_empty() || self.regions.len() > 8 {
            return Err("regions: 1 to 8 first cells".into());
        }
        for &(i, j) in &self.regions {
            within("regions", i, -FAR, FAR)?;
            within("regions", j, -FAR, FAR)?;
        }
        within("seam_cells", self.seam_cells, 2, 64)?;
        within("iters", self.iters, 1, 100_000)?;
        within("als_tolerance", self.als_tolerance, 1e-15, 0.5)?;
        all_within("areas", &self.areas, 1, 1 << 20, 8)
    }
}

/// Everything the study computed; the report formats it.
pub struct Computed {
    pub spec: FitSpec,
    pub preset: Preset,
    pub p: Params,
    pub result: Wang,
    /// Criterion means by bench id (results/costs.json).
    pub costs: crate::results::costs::Costs,
}

/// One compared footprint: its level, the cells it covers (with the centre's index in
/// each) and its brute-force image.
type Compared = (usize, Vec<((i64, i64), usize)>, Vec<f64>);

/// One region's explicit footprints of one level: (centre in the region, global centre).
fn centres(p: &Params, s: usize, origin: (i64, i64)) -> Vec<((usize, usize), (i64, i64))> {
    let reach = crate::tensor::pndf::window_reach(sigma_p(s, 0)) as usize;
    let size = p.region * p.side;
    let axis: Vec<usize> = (s / 2..size)
        .step_by(s)
        .filter(|&c| c >= reach && c + reach < size)
        .collect();
    let (gx, gy) = (origin.0 * p.side as i64, origin.1 * p.side as i64);
    axis.iter()
        .flat_map(|&y| axis.iter().map(move |&x| (x, y)))
        .map(|(x, y)| ((x, y), (gx + x as i64, gy + y as i64)))
        .collect()
}

/// The explicit images CP-compressed directly, one CP per group of `compared` (a level and
/// a region): ‖T − T̂‖/‖T‖ over every group together, and the values stored.
fn direct(
    compared: &[Compared],
    groups: &[usize],
    res: usize,
    t: usize,
    opts: &AlsOptions,
) -> Result<(f64, usize)> {
    let per: Vec<(f64, f64, usize)> = groups
        .windows(2)
        .collect::<Vec<_>>()
        .par_iter()
        .map(|w| {
            let imgs: Vec<&[f64]> = compared[w[0]..w[1]]
                .iter()
                .map(|c| c.2.as_slice())
                .collect();
            let Some(stack) = stack_blocks(&imgs, res, t)? else {
                return Ok((0.0, 0.0, 0));
            };
            let o = AlsOptions {
                rank: opts.rank.min(stack.tensor.data.len()),
                ..*opts
            };
            let cp = cp_als(&stack.tensor, &o)?;
            let norm2 = stack.tensor.norm().powi(2);
            Ok((cp.rel_error.powi(2) * norm2, norm2, cp.storage()))
        })
        .collect::<Result<_>>()?;
    let (d2, b2, v) = per
        .iter()
        .fold((0.0, 0.0, 0), |s, q| (s.0 + q.0, s.1 + q.1, s.2 + q.2));
    Ok(((d2 / b2).sqrt(), v))
}

/// Every footprint of every level and region: the tiles' image against the explicit map's
/// brute force. Returns the per-level checks, the compared footprints and where each
/// (level, region)'s footprints start among them.
fn compare_levels(
    p: &Params,
    set: &TileSet,
    images: &TileImages,
    colouring: &Colouring,
    levels: &[Level],
) -> Result<(Vec<LevelCheck>, Vec<Compared>, Vec<usize>)> {
    // every compared footprint: (level, cells, brute-force image)
    let mut compared: Vec<Compared> = Vec::new();
    // where each (level, region)'s footprints start in `compared`
    let mut groups = vec![0];
    let mut checks = Vec::new();
    for (l, level) in levels.iter().enumerate() {
        let mut check = LevelCheck {
            stride: level.stride,
            sigma_p: level.sigma_p,
            footprints: 0,
            by_tiles: [0; 4],
            worst: 0.0,
        };
        for &origin in &p.regions {
            let map = explicit(set, colouring, origin, (p.region, p.region))?;
            let rows: Vec<_> = centres(p, level.stride, origin)
                .par_iter()
                .map(|&((x, y), g)| {
                    let brute =
                        pndf_image(&map, x as f64, y as f64, level.sigma_p, p.sigma_r, p.res)?;
                    let tiles = images.combined(colouring, l, g)?;
                    let cells = images.cover(l, g)?;
                    let peak = brute.iter().cloned().fold(0.0, f64::max);
                    let dev = brute
                        .iter()
                        .zip(&tiles)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max);
                    Ok((cells, brute, dev / peak))
                })
                .collect::<Result<_>>()?;
            for (cells, brute, dev) in rows {
                check.footprints += 1;
                check.by_tiles[match cells.len() {
                    1 => 0,
                    2 => 1,
                    3 | 4 => 2,
                    _ => 3,
                }] += 1;
                check.worst = check.worst.max(dev);
                compared.push((l, cells, brute));
            }
            groups.push(compared.len());
        }
        checks.push(check);
    }
    Ok((checks, compared, groups))
}

pub(crate) fn compute(c: &Ctx) -> Result<Computed> {
    let p: Params = c.params()?;
    let seed = c.spec.seed;
    let example = p.example_map(seed)?;
    let set = TileSet::build(&example, p.side, p.band, seed)?;
    let straight = TileSet::build(&example, p.side, 0, seed)?;
    let colouring = Colouring { seed };
    let n = p.seam_cells;
    let cut = stats(&set, &colouring, (0, 0), (n, n))?;
    let straight_stats = stats(&straight, &colouring, (0, 0), (n, n))?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let picks: Vec<usize> = (0..n * n).map(|_| rng.random_range(0..16)).collect();
    let unmatched = layout(&set, (n, n), "unmatched".into(), &|i, j| picks[j * n + i])?;
    crate::progress::stamp("tensor-wang: tiles cut; their images next");
    let levels: Vec<Level> = p
        .strides
        .iter()
        .map(|&s| Level {
            stride: s,
            sigma_p: sigma_p(s, 0),
        })
        .collect();
    let images = TileImages::build(&set, &levels, p.res, p.sigma_r)?;
    crate::progress::stamp("tensor-wang: tile images built; explicit maps next");
    let (checks, compared, groups) = compare_levels(&p, &set, &images, &colouring, &levels)?;
    // Fig 14: the footprint across the most tiles (the first such)
    let fig14 = {
        let most = compared.iter().map(|c| c.1.len()).max().unwrap_or(0);
        let (l, cells, brute) = compared
            .iter()
            .find(|c| c.1.len() == most)
            .ok_or_else(|| Error::InvalidArgument("tensor-wang: no footprint compared".into()))?;
        let mut tiles = vec![0.0; p.res * p.res];
        for &((i, j), k) in cells {
            for (v, t) in tiles
                .iter_mut()
                .zip(&images.levels[*l].images[colouring.tile(i, j)][k])
            {
                *v += t;
            }
        }
        Fig14 {
            level: *l,
            tiles_covered: most,
            res: p.res,
            explicit: brute.clone(),
            tiles,
        }
    };
    crate::progress::stamp(&format!(
        "tensor-wang: {} footprints compared; compression next",
        compared.len()
    ));
    let ranks = p
        .ranks
        .iter()
        .map(|&rank| {
            let opts = AlsOptions {
                rank,
                tol: p.als_tolerance,
                max_iters: p.iters,
                restarts: 2,
                seed,
                nonnegative: false,
            };
            let tiles = CompressedTiles::compress(&images, p.t, &opts)?;
            let (explicit_rel_l2, explicit_values) = direct(&compared, &groups, p.res, p.t, &opts)?;
            let per: Vec<(f64, f64, f64)> = compared
                .par_iter()
                .map(|(l, cells, brute)| {
                    let img = tiles.image(&colouring, *l, cells);
                    let peak = brute.iter().cloned().fold(0.0, f64::max);
                    let (mut d2, mut b2, mut dev) = (0.0, 0.0, 0.0f64);
                    for (a, b) in img.iter().zip(brute) {
                        d2 += (a - b) * (a - b);
                        b2 += b * b;
                        dev = dev.max((a - b).abs());
                    }
                    (d2, b2, dev / peak)
                })
                .collect();
            let (d2, b2) = per.iter().fold((0.0, 0.0), |s, q| (s.0 + q.0, s.1 + q.1));
            Ok(RankCheck {
                rank,
                values: tiles.values(),
                rel_l2: (d2 / b2).sqrt(),
                worst: per.iter().map(|q| q.2).fold(0.0, f64::max),
                explicit_rel_l2,
                explicit_values,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let per_texel: f64 = levels
        .iter()
        .map(|l| (p.res * p.res) as f64 / (l.stride * l.stride) as f64)
        .sum();
    let areas = p
        .areas
        .iter()
        .map(|&a| AreaStorage {
            tiles: a,
            explicit: (a as f64 * p.side as f64).powi(2) * per_texel,
        })
        .collect();
    if checks.iter().any(|c| c.footprints == 0) {
        return Err(Error::InvalidArgument(
            "tensor-wang: a level has no footprint inside its regions".into(),
        ));
    }
    let worst = checks.iter().map(|c| c.worst).fold(0.0, f64::max);
    Ok(Computed {
        spec: c.spec.clone(),
        preset: c.preset,
        costs: crate::results::costs::read(c.results)?.unwrap_or_default(),
        result: Wang {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            example_map: match generator(&p.example) {
                Some(k) => format!("the procedural {} map, {}² texels", k.name(), example.width),
                None => format!(
                    "the normal map {}, {}×{} texels",
                    p.example, example.width, example.height
                ),
            },
            example: edge_mean(&example, 1),
            cut,
            straight: straight_stats,
            unmatched_edges: edge_mean(&unmatched, p.side),
            regions: p.regions.clone(),
            levels: checks,
            tile_values: images.values(),
            tile_texels: set.texels(),
            ranks,
            areas,
            fig14,
            verdict: {
                if worst <= c.spec.tolerance.max_rel {
                    format!("holds: every footprint's tiled image equals the explicit one to {worst:.1e} of its peak (rounding)")
                } else {
                    format!("refuted here: a tiled image differs from the explicit one by {worst:.1e} of its peak")
                }
            },
        },
        p,
    })
}

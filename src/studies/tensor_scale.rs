//! `regen --only tensor-scale`: seed 002 at its own scale (fits/tensor-scale.toml, run on
//! request only). 2K² procedural maps (flakes and brushed metal, the maps of Table 2),
//! 256² P-NDF images (Eq 2) at footprint level 0 with the paper's stride 32, t = 16 blocks
//! in the paper's 8 × 8 spatial clusters, CP-ALS at R = 16 and 32 (§4.2). Each cluster is
//! one item of a memoised map, so `--shard K/N` and `slurm` split the work by cluster.
//! Results: results/tensor-scale.md beside Table 2, results/fits/tensor-scale.json.
//! Compute ([`compute`]: the runs and their aggregates), then render ([`report`]).

use crate::error::Result;
use crate::filters::footprint::{NormalMap, Procedural};
use crate::fit::spec::FitSpec;
use crate::integrate::Figure;
use crate::integrate::Preset;
use crate::io::Outputs;
use crate::report::table::Table;
use crate::study::{Ctx, FitOutcome};
use crate::tensor::scale::{run_cluster, ClusterRun, ScalePlan};

/// Table 2 of seed 002 (geometric optics, 2K², stride 32): map, rank, NDF generation
/// (min), compression (min), storage without / with compression (MB), ratio (%). Timed on
/// 40 cores.
const TABLE2: [(&str, usize, f64, f64, f64, f64, f64); 2] = [
    ("flakes", 32, 42.80, 60.01, 1430.75, 106.86, 7.47),
    ("brushed-metal", 16, 37.39, 10.01, 1430.75, 15.19, 1.06),
];

/// What fits/tensor-scale.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Side of the two procedural maps (flakes, brushed metal).
    pub size: usize,
    /// Spatial clusters per side (the paper's 8 × 8), and how many of them run per map
    /// (spread over rows and columns; all of them when ≥ regions²).
    pub regions: usize,
    pub clusters: usize,
    /// Footprint stride at level 0 (the only level run), P-NDF image side, block side t,
    /// intrinsic roughness σ_r.
    pub stride: usize,
    pub res: usize,
    pub t: usize,
    pub sigma_r: f64,
    /// CP ranks; ALS iteration cap, stop tolerance and seeded starts per CP (best kept).
    pub ranks: Vec<usize>,
    pub max_iters: usize,
    pub als_tolerance: f64,
    pub starts: usize,
}

impl crate::fit::spec::Params for Params {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::{splits, within};
        within("size", self.size, 16, 16_384)?;
        within("regions", self.regions, 1, 64)?;
        // every region holds at least one footprint stride
        splits("size", self.size, "regions", self.regions)?;
        within("stride", self.stride, 1, self.size / self.regions)?;
        within("clusters", self.clusters, 1, 4096)?;
        crate::tensor::cluster::check_blocks(self.t, self.res, &self.ranks, self.sigma_r)?;
        within("max_iters", self.max_iters, 1, 100_000)?;
        within("als_tolerance", self.als_tolerance, 1e-15, 0.5)?;
        within("starts", self.starts, 1, 16)
    }
}

/// Map size, the clusters run of each map and the CP plan.
fn plan(p: &Params, seed: u64) -> (usize, usize, ScalePlan) {
    (
        p.size,
        p.clusters,
        ScalePlan {
            stride: p.stride,
            level: 0,
            res: p.res,
            t: p.t,
            regions: p.regions,
            sigma_r: p.sigma_r,
            ranks: p.ranks.clone(),
            tol: p.als_tolerance,
            max_iters: p.max_iters,
            seed,
            starts: p.starts,
        },
    )
}

/// `n` of the plan's clusters, spread over rows and columns (row q·R/n, a column that
/// moves with the row).
fn sample(plan: &ScalePlan, n: usize) -> Vec<usize> {
    let r = plan.regions;
    let total = r * r;
    if n >= total {
        return (0..total).collect();
    }
    (0..n)
        .map(|q| {
            let row = q * r / n;
            row * r + (3 * row + 1) % r
        })
        .collect()
}

/// results/fits/tensor-scale.json: the plan and every cluster's summary row.
#[derive(serde::Serialize)]
struct ScaleResult<'a> {
    spec: &'a FitSpec,
    command: &'static str,
    preset: &'static str,
    size: usize,
    plan: &'a ScalePlan,
    maps: [&'static str; 2],
    clusters: &'a [ClusterRun],
}

/// One (map, rank) pair, aggregated over the clusters run, and its projection beside
/// Table 2.
struct RankRow {
    map: &'static str,
    rank: usize,
    clusters: usize,
    /// Blocks per cluster, mean ± s.e.
    blocks: Figure,
    /// Non-empty share of the blocks.
    nonempty: f64,
    /// Relative reconstruction error, mean ± s.e., and its max.
    error: Figure,
    error_max: f64,
    iterations: f64,
    at_cap: usize,
    /// Stored values over all blocks' values, and over the non-empty blocks' values.
    compression_all: f64,
    compression_nonempty: f64,
    /// P-NDF and CP seconds per cluster, mean ± s.e.
    pndf_seconds: Figure,
    cp_seconds: Figure,
    /// Table 2's row for this pair, if it has one.
    paper: Option<(&'static str, usize, f64, f64, f64, f64, f64)>,
    /// Level 0's core-minutes (mean ± s.e. scaled to every cluster) and the pyramid's.
    level0_pndf_min: Figure,
    pyramid_pndf_min: f64,
    level0_cp_min: Figure,
    pyramid_cp_min: f64,
    /// Compressed storage of level 0 (MB, 4 B per value), projected from the ratio.
    level0_compressed_mb: f64,
}

/// What the study computed: the runs of every cluster and their aggregates.
pub struct Scale {
    spec: FitSpec,
    preset: Preset,
    size: usize,
    plan: ScalePlan,
    clusters: Vec<usize>,
    kinds: [Procedural; 2],
    runs: Vec<ClusterRun>,
    rows: Vec<RankRow>,
    /// Clusters per map, images at level 0 and in the pyramid, pyramid levels.
    total: usize,
    images0: usize,
    images_all: usize,
    /// Uncompressed storage of the pyramid (MB, 4 B per value).
    pyramid_mb: f64,
    level0_mb: f64,
    /// A cluster's images and its largest tensor in f64 (MB), one map's normals (MB).
    cluster_images_mb: f64,
    largest_tensor_mb: f64,
    map_mb: f64,
    worst: f64,
}

/// Run every cluster of the plan (one memoised map over clusters) and aggregate.
fn compute(c: &Ctx) -> Result<Scale> {
    let (spec, preset) = (c.spec, c.preset);
    let (size, n, plan) = plan(&c.params()?, spec.seed);
    let clusters = sample(&plan, n);
    let kinds = [Procedural::Flakes, Procedural::BrushedMetal];
    let maps: Vec<NormalMap> = kinds
        .iter()
        .map(|&k| NormalMap::procedural(k, size, 3))
        .collect::<Result<_>>()?;
    let items: Vec<(usize, usize)> = (0..kinds.len())
        .flat_map(|m| clusters.iter().map(move |&c| (m, c)))
        .collect();
    let runs: Vec<ClusterRun> =
        crate::memo::map_items("tensor-scale clusters", &items, |&(m, c)| {
            run_cluster(&maps[m], &plan, c)
        })?;
    let worst = runs
        .iter()
        .flat_map(|r| r.ranks.iter().map(|x| x.rel_error))
        .fold(0.0, f64::max);
    let total = plan.regions * plan.regions;
    let images0 = (size / plan.stride).pow(2);
    let nlev = levels(size, plan.stride);
    let images_all: usize = (0..nlev).map(|l| images0 >> (2 * l)).sum();
    let mb = |values: f64| values * 4.0 / 1e6;
    let per_image = (plan.res * plan.res) as f64;
    let pyramid_cp: f64 = (0..nlev).map(|l| 0.25f64.powi(l as i32)).sum();
    let mut rows = Vec::new();
    for (m, kind) in kinds.iter().enumerate() {
        let rs: Vec<&ClusterRun> = runs
            .iter()
            .skip(m * clusters.len())
            .take(clusters.len())
            .collect();
        let blocks = Figure::mean_of(&rs.iter().map(|r| r.blocks as f64).collect::<Vec<_>>());
        let nonempty = rs.iter().map(|r| r.blocks).sum::<usize>() as f64
            / rs.iter().map(|r| r.blocks_all).sum::<usize>().max(1) as f64;
        let pre: Vec<f64> = rs.iter().map(|r| r.pndf_seconds).collect();
        let pre = Figure::mean_of(&pre);
        for (k, &rank) in plan.ranks.iter().enumerate() {
            let of: Vec<&crate::tensor::scale::RankRun> =
                rs.iter().filter_map(|r| r.ranks.get(k)).collect();
            let errs: Vec<f64> = of.iter().map(|x| x.rel_error).collect();
            let stored = of.iter().map(|x| x.storage).sum::<usize>() as f64;
            let all_vals =
                rs.iter().map(|r| r.blocks_all).sum::<usize>() as f64 * (plan.t * plan.t) as f64;
            let nonempty_vals =
                rs.iter().map(|r| r.blocks).sum::<usize>() as f64 * (plan.t * plan.t) as f64;
            let cp = Figure::mean_of(&of.iter().map(|x| x.seconds).collect::<Vec<_>>());
            // level 0's core-minutes: the per-cluster seconds scaled to every cluster
            let minutes = |f: Figure| {
                Figure::with_se(f.value * total as f64 / 60.0, f.error * total as f64 / 60.0)
            };
            let (level0_pre, level0_cp) = (minutes(pre), minutes(cp));
            let ratio = stored / all_vals.max(1.0);
            rows.push(RankRow {
                map: kind.name(),
                rank,
                clusters: rs.len(),
                blocks,
                nonempty,
                error: Figure::mean_of(&errs),
                error_max: errs.iter().cloned().fold(0.0, f64::max),
                iterations: of.iter().map(|x| x.iterations as f64).sum::<f64>()
                    / of.len().max(1) as f64,
                at_cap: of.iter().filter(|x| x.iterations >= plan.max_iters).count(),
                compression_all: ratio,
                compression_nonempty: stored / nonempty_vals.max(1.0),
                pndf_seconds: pre,
                cp_seconds: cp,
                paper: TABLE2
                    .iter()
                    .find(|p| p.0 == kind.name() && p.1 == rank)
                    .copied(),
                level0_pndf_min: level0_pre,
                pyramid_pndf_min: level0_pre.value * nlev as f64,
                level0_cp_min: level0_cp,
                pyramid_cp_min: level0_cp.value * pyramid_cp,
                level0_compressed_mb: mb(ratio * images0 as f64 * per_image),
            });
        }
    }
    Ok(Scale {
        spec: spec.clone(),
        preset,
        size,
        total,
        images0,
        images_all,
        pyramid_mb: mb(images_all as f64 * per_image),
        level0_mb: mb(images0 as f64 * per_image),
        cluster_images_mb: (images0 / total) as f64 * per_image * 8.0 / 1e6,
        largest_tensor_mb: runs.iter().map(|r| r.blocks).max().unwrap_or(0) as f64
            * (plan.t * plan.t) as f64
            * 8.0
            / 1e6,
        map_mb: (size * size * 24) as f64 / 1e6,
        plan,
        clusters,
        kinds,
        runs,
        rows,
        worst,
    })
}

impl crate::study::Computed for Scale {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        set.put(results.join("tensor-scale.md"), report(&self));
        crate::results::put_named(
            set,
            results,
            &self.spec.name,
            &ScaleResult {
                spec: &self.spec,
                command: COMMAND,
                preset: self.preset.name(),
                size: self.size,
                plan: &self.plan,
                maps: self.kinds.map(|k| k.name()),
                clusters: &self.runs,
            },
        )?;
        Ok(())
    }
    /// Passed when every reconstruction error is finite (the study measures; it sets no
    /// bar on the error).
    fn outcome(&self) -> FitOutcome {
        FitOutcome::measured(
            &self.spec,
            self.worst,
            format!(
                "{}² maps, {} clusters each, ranks {:?}: worst relative reconstruction error {:.2} %",
                self.size,
                self.clusters.len(),
                self.plan.ranks,
                100.0 * self.worst
            ),
        )
    }
}

const COMMAND: &str = "cargo run --release -- regen --only tensor-scale";

/// Footprint levels of the full pyramid (until the stride reaches the map size, §4.1).
fn levels(size: usize, stride: usize) -> usize {
    (0..).take_while(|l| (stride << l) <= size).count().max(1)
}

/// results/tensor-scale.md (formats only).
fn report(k: &Scale) -> String {
    let (size, plan, clusters, total, preset) = (k.size, &k.plan, &k.clusters, k.total, k.preset);
    let (images0, images_all) = (k.images0, k.images_all);
    let mut md = format!(
        "# Seed 002 at the paper's scale\n\nWritten by `{COMMAND}` (preset {}) from `fits/tensor-scale.toml`. {size}² procedural maps (the flakes and brushed metal of Table 2), P-NDF images (seed 002 Eq 2) of {res}² over the projected hemisphere with σ_r = {sr}, footprint level {lv} only (stride s = {st}, σ_P = 1.5 s/√12, {images0} images per map), blocks t × t = {t}², all-zero blocks dropped, one tensor per spatial cluster of the {r} × {r} grid (§4.2), CP-ALS (tolerance {tol}, ≤ {it} iterations, {starts} seeded start(s)) at R = {ranks:?}. {ran} of the {total} clusters of each map were run{}. Each cluster's images are made and compressed on one thread (the factored-Gaussian splat, `tensor::pndf::pndf_image_separable`, equal to the brute force up to rounding); times are wall clock of one core on this machine, measured when the cluster was computed (a cached or merged cluster keeps its measured times).\n\n",
        preset.name(),
        if clusters.len() < total { format!(" ({clusters:?}, spread over rows and columns; what the others would cost is projected from them)") } else { String::new() },
        res = plan.res,
        sr = plan.sigma_r,
        lv = plan.level,
        st = plan.stride,
        t = plan.t,
        r = plan.regions,
        tol = plan.tol,
        it = plan.max_iters,
        ranks = plan.ranks,
        ran = clusters.len(),
        starts = plan.starts,
    );
    md.push_str("## Measured, per cluster\n\n");
    let mut measured = Table::new([
        "map",
        "R",
        "clusters",
        "blocks L (mean ± s.e.)",
        "non-empty blocks",
        "rel. error (mean ± s.e.)",
        "rel. error max",
        "iterations (mean)",
        "at the cap",
        "compression of all blocks",
        "of non-empty",
        "P-NDF s per cluster",
        "CP s per cluster",
    ]);
    let mut proj = String::from("## Next to Table 2\n\nThe paper's numbers (Table 2: geometric optics, 2K², stride 32, all levels, 40 cores) beside ours. Ours: level 0 measured on the clusters above (the full level 0 = their mean × the cluster count, so the sum where all were run), the full pyramid adds the levels ℓ = 1 … with their images' cost (4^−ℓ as many images, each over 4^ℓ as many texels: the same P-NDF work per level) and their blocks (4^−ℓ as many: CP work in proportion to L, the iteration counts assumed those of level 0). Core-minutes: ours are one core's, the paper's are its wall-clock minutes × 40 cores (a bound: its cores were not all busy all the time). Storage at 4 bytes per value, as Table 2's w/o-compression column is (its 1430.75 MB ≈ the ");
    proj.push_str(&format!(
        "{images_all} images × {}² × 4 B = {:.2} MB of our pyramid).\n\n",
        plan.res, k.pyramid_mb
    ));
    let mut beside = Table::new([
        "map",
        "R",
        "Table 2: Pre. core-min",
        "ours: level 0 P-NDF core-min",
        "ours: pyramid P-NDF core-min (projected)",
        "Table 2: Comp. core-min",
        "ours: level 0 CP core-min",
        "ours: pyramid CP core-min (projected)",
        "Table 2: w/o comp. MB",
        "ours: w/o comp. MB (pyramid)",
        "Table 2: w/ comp. MB",
        "ours: w/ comp. MB (level 0, projected)",
        "Table 2: ratio",
        "ours: ratio (level 0)",
    ]);
    let cell = |v: Option<f64>, d: usize| v.map_or("—".to_string(), |x| format!("{x:.d$}"));
    for r in &k.rows {
        measured.row([
            r.map.to_string(),
            r.rank.to_string(),
            r.clusters.to_string(),
            r.blocks.fixed(0),
            format!("{:.1} %", 100.0 * r.nonempty),
            format!("{} %", r.error.scaled(100.0).fixed(2)),
            format!("{:.2} %", 100.0 * r.error_max),
            format!("{:.0}", r.iterations),
            r.at_cap.to_string(),
            format!("{:.2} %", 100.0 * r.compression_all),
            format!("{:.2} %", 100.0 * r.compression_nonempty),
            r.pndf_seconds.fixed(2),
            r.cp_seconds.fixed(2),
        ]);
        let paper = r.paper;
        beside.row([
            r.map.to_string(),
            r.rank.to_string(),
            cell(paper.map(|p| p.2 * 40.0), 0),
            r.level0_pndf_min.fixed(1),
            format!("{:.0}", r.pyramid_pndf_min),
            cell(paper.map(|p| p.3 * 40.0), 0),
            r.level0_cp_min.fixed(2),
            format!("{:.2}", r.pyramid_cp_min),
            cell(paper.map(|p| p.4), 2),
            format!("{:.2}", k.pyramid_mb),
            cell(paper.map(|p| p.5), 2),
            format!("{:.2}", r.level0_compressed_mb),
            paper.map_or("—".to_string(), |p| format!("{:.2} %", p.6)),
            format!("{:.2} %", 100.0 * r.compression_all),
        ]);
    }
    md.push_str(&measured.to_string());
    proj.push_str(&beside.to_string());
    md.push('\n');
    md.push_str(&proj);
    md.push_str(&format!(
        "\nTable 2 has no reconstruction-error column (the paper judges the rank by rendered MSE, Fig. 18); the relative errors above are the tensors' own ‖T − T̂‖/‖T‖. Table 2 pairs each map with one rank (flakes R = 32, brushed metal R = 16); the other pairs have no paper row (—). Our ALS stops when the relative error changes by less than the tolerance between sweeps (the tensor study's rule, TensorLy's), which it does after the iterations above; the paper sets a maximum error of 1e-4 and 500 iterations (§4.2), which clusters whose error stays above 1e-4 (all of these) would run to the cap: at most 500 ÷ iterations × the CP time above, still a small part of the paper's compression time. Its 40-core minutes also include every level (ours projects them) and its own P-NDF method (brute force, we assume; ours the factored splat).\n\n## Where the large data goes\n\nNothing large is written. A cluster's images ({} footprints × {}² values in f64: {:.1} MB) and its tensor (L·t² values in f64: {:.1} MB at the largest L measured) live in memory while its thread runs; what a cluster leaves is its summary row (under 1 kB of JSON: in `target/ndfbench-cache/tensor-scale/` on a cached run, in the shard file of `regen --shard K/N --shard-dir DIR`, in results/fits/tensor-scale.json). The whole level 0 in f32 would be {:.0} MB per map, the pyramid {:.0} MB; neither is kept. The two {size}² maps ({:.0} MB each as f64 normals) are rebuilt from their seed in every process.\n\nSplit by cluster (every cluster one item of the study's one memoised map): `cargo run --release -- regen --only tensor-scale --shard K/N --shard-dir DIR` per machine, then `merge`, or a Slurm array: `cargo run --release -- slurm --only tensor-scale --shards 32 --out target/slurm` (README: Beyond one machine).\n",
        images0 / total,
        plan.res,
        k.cluster_images_mb,
        k.largest_tensor_mb,
        k.level0_mb,
        k.pyramid_mb,
        k.map_mb,
    ));
    md
}

crate::study::study! {
    /// The seed 002 at the paper's scale: hours at its default preset, so on request only, as
    /// the registry holds it.
    TensorScale = "tensor-scale", after [], on request true, params Params, computes compute
}

//! The tensor study's computation: P-NDF images of procedural maps, blocked, clustered and
//! CP-compressed at several ranks (seed 002 §4.1–4.2), SAT range queries against the naive
//! box average (§5), the hierarchical sampler's χ² and binning checks (§5.2), and the
//! stored inputs its report quotes (the TensorLy comparison, the criterion costs).

use crate::error::Result;
use crate::filters::footprint::{NormalMap, Procedural};
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::study::Ctx;
use crate::tensor::cluster::cluster_tensors;
use crate::tensor::cp::{cp_als, AlsOptions, Cp, Tensor3};
use crate::tensor::sample::ChiSquare;
use rayon::prelude::*;

/// What fits/tensor.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Side of the procedural maps (2×2 spatial clusters of size/2 texels).
    pub size: usize,
    /// P-NDF image side.
    pub res: usize,
    /// CP ranks tried.
    pub ranks: Vec<usize>,
    /// ALS iteration cap and stop tolerance (|Δ relative error| between sweeps).
    pub iters: usize,
    pub als_tolerance: f64,
    /// Footprint stride at level 0, in texels.
    pub stride: usize,
    /// Block side t of the t × t × L tensors.
    pub t: usize,
    /// Intrinsic roughness σ_r of the P-NDF images.
    pub sigma_r: f64,
}

impl crate::fit::spec::Params for Settings {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::within;
        within("size", self.size, 16, 1024)?;
        crate::tensor::cluster::check_blocks(self.t, self.res, &self.ranks, self.sigma_r)?;
        within("iters", self.iters, 1, 100_000)?;
        within("als_tolerance", self.als_tolerance, 1e-15, 0.5)?;
        // the footprint pyramid starts with at least two footprints per side
        within("stride", self.stride, 1, self.size / 2)
    }
}

impl Settings {
    /// Texels per side of a spatial cluster (2×2 clusters).
    pub fn region(&self) -> usize {
        self.size / 2
    }
}

/// The range-query check at the largest rank.
pub(super) struct Queries {
    pub rank: usize,
    pub n: usize,
    pub r64: f64,
    pub r32: f64,
    pub whole32: f64,
    pub b64: f64,
    pub b32: f64,
}

/// One block of the sampling check: its name and (χ², (binning MSE, expected MSE)), or
/// `None` for an empty slice.
pub(super) type Sampled = (String, Option<(ChiSquare, (f64, f64))>);

/// Everything the study computed; the report formats it.
pub struct Computed {
    pub spec: FitSpec,
    pub preset: Preset,
    pub s: Settings,
    pub rows: Vec<crate::results::tensor::Row>,
    /// Mean relative error against rank, per map kind.
    pub series: Vec<(String, Vec<(f64, f64)>)>,
    pub kinds: usize,
    pub worst: f64,
    pub queries: Queries,
    pub sampling: Vec<Sampled>,
    /// results/tensor-tensorly.json, where `tensorly-compare` has written it.
    pub tensorly: Option<crate::tensor::compare::Report>,
    /// Criterion means by bench id (results/costs.json).
    pub costs: crate::results::costs::Costs,
    /// The Table 3 bench's CP reconstruction error at each of its ranks.
    pub table3_errors: Vec<(usize, f64)>,
}

/// Compress every map kind at every rank, then run the query and sampling checks.
pub(crate) fn compute(c: &Ctx) -> Result<Computed> {
    let (spec, results, preset) = (c.spec, c.results, c.preset);
    let s: Settings = c.params()?;
    let (stride, t, sigma_r, iters) = (s.stride, s.t, s.sigma_r, s.iters);
    let ranks = &s.ranks;
    let mut rows = Vec::new();
    let mut worst = 0.0f64;
    let mut series = Vec::new();
    // kept for the query and sampling sections: every CP at the largest rank, and the
    // flakes map's CPs at the second-largest rank
    let mut top: Vec<(Tensor3, Cp)> = Vec::new();
    let mut sampled: Option<(String, usize, Tensor3, Cp, Cp)> = None;
    let rmax = *ranks.last().expect("ranks");
    let rsample = ranks[ranks.len().saturating_sub(2)];
    let kinds: Vec<Procedural> = Procedural::ALL
        .into_iter()
        .chain([Procedural::Scratches])
        .collect();
    for &kind in &kinds {
        let map = NormalMap::procedural(kind, s.size, 3)?;
        let tensors = cluster_tensors(&map, s.res, stride, t, sigma_r)?;
        let mut pts = Vec::new();
        for &r in ranks {
            let run = |nonnegative: bool| -> Result<Vec<Cp>> {
                tensors
                    .par_iter()
                    .map(|tt| {
                        let o = AlsOptions {
                            rank: r.min(tt.shape[2] * t),
                            tol: s.als_tolerance,
                            max_iters: iters,
                            restarts: 2,
                            seed: spec.seed,
                            nonnegative,
                        };
                        cp_als(tt, &o)
                    })
                    .collect()
            };
            let fits = run(false)?;
            let nn = run(true)?;
            let nn_mean = nn.iter().map(|f| f.rel_error).sum::<f64>() / nn.len() as f64;
            let nn_max = nn.iter().map(|f| f.rel_error).fold(0.0, f64::max);
            let nn_it = nn.iter().map(|f| f.iterations as f64).sum::<f64>() / nn.len() as f64;
            let n = fits.len() as f64;
            let mean = fits.iter().map(|f| f.rel_error).sum::<f64>() / n;
            let max = fits.iter().map(|f| f.rel_error).fold(0.0, f64::max);
            let comp = fits.iter().map(|f| f.storage()).sum::<usize>() as f64
                / tensors.iter().map(|t| t.data.len()).sum::<usize>() as f64;
            let it = fits.iter().map(|f| f.iterations as f64).sum::<f64>() / n;
            let capped = fits.iter().filter(|f| f.iterations >= iters).count();
            worst = worst.max(max);
            pts.push((r as f64, mean));
            rows.push(crate::results::tensor::Row {
                map: kind.name().into(),
                rank: r,
                clusters: fits.len(),
                mean_rel_error: mean,
                max_rel_error: max,
                nonnegative_mean_rel_error: nn_mean,
                nonnegative_max_rel_error: nn_max,
                compression: comp,
                mean_iterations: it,
                nonnegative_mean_iterations: nn_it,
                runs_at_cap: capped,
            });
            if r == rmax {
                top.extend(tensors.iter().cloned().zip(fits.iter().cloned()));
            }
            if r == rsample && kind == Procedural::Flakes {
                let k = (0..tensors.len())
                    .max_by_key(|&k| tensors[k].shape[2])
                    .unwrap_or(0);
                sampled = Some((
                    kind.name().to_string(),
                    r,
                    tensors[k].clone(),
                    fits[k].clone(),
                    nn[k].clone(),
                ));
            }
        }
        series.push((kind.name().to_string(), pts));
    }
    // absent: not measured; malformed or foreign: a typed error, not "absent"
    let tensorly = crate::results::read_typed::<crate::tensor::compare::Report>(
        &results.join("tensor-tensorly.json"),
        "a TensorLy comparison",
        "run `cargo run --release -- tensorly-compare`",
    )?;
    let costs = crate::results::costs::read(results)?.unwrap_or_default();
    Ok(Computed {
        spec: spec.clone(),
        preset,
        rows,
        series,
        kinds: kinds.len(),
        worst,
        queries: queries(&top, rmax),
        sampling: sampling(sampled.as_ref()),
        tensorly,
        costs,
        table3_errors: crate::tensor::brdf::table3_cp_errors()?,
        s,
    })
}

/// §5: f64 and f32 SAT queries against the naive (compensated) box average, on every
/// cluster at the largest rank: whole-range and random boxes, with the a-priori bound.
fn queries(top: &[(Tensor3, Cp)], rank: usize) -> Queries {
    use crate::tensor::query::{range, range_error_bound, range_f32, range_naive, Sat};
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12);
    let (mut n, mut r64, mut r32, mut b64, mut b32, mut whole32) =
        (0usize, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (tt, cp) in top {
        let sat = Sat::build(cp);
        let t = tt.shape[0];
        for z in 0..tt.shape[2] {
            // errors are relative to the slice's whole-block average: a small box's own
            // average can cancel to ~0 while its rounding error cannot
            let whole = range_naive(cp, (0, t - 1), (0, t - 1), z).abs();
            for q in 0..4 {
                let (x, y) = if q == 0 {
                    ((0, t - 1), (0, t - 1))
                } else {
                    let a = (rng.random_range(0..t), rng.random_range(0..t));
                    let b = (rng.random_range(0..t), rng.random_range(0..t));
                    ((a.0.min(a.1), a.0.max(a.1)), (b.0.min(b.1), b.0.max(b.1)))
                };
                let naive = range_naive(cp, x, y, z);
                let scale = whole.max(1e-300);
                let e64 = (range(cp, &sat, x, y, z) - naive).abs();
                let e32 = (range_f32(cp, &sat, x, y, z) as f64 - naive).abs();
                let bd64 = range_error_bound(cp, x, y, z, f64::EPSILON, t as f64)
                    + 8.0 * f64::EPSILON * naive.abs();
                let bd32 = range_error_bound(cp, x, y, z, f32::EPSILON as f64, 2.0)
                    + 8.0 * f32::EPSILON as f64 * naive.abs();
                if whole > 1e-6 {
                    r64 = r64.max(e64 / scale);
                    r32 = r32.max(e32 / scale);
                    if q == 0 {
                        whole32 = whole32.max(e32 / scale);
                    }
                }
                b64 = b64.max(e64 / bd64.max(1e-300));
                b32 = b32.max(e32 / bd32.max(1e-300));
                n += 1;
            }
        }
    }
    Queries {
        rank,
        n,
        r64,
        r32,
        whole32,
        b64,
        b32,
    }
}

/// §5.2: χ² and binning on a random non-negative rank-4 block and, where the run kept
/// one, on a real compressed P-NDF block (unconstrained and non-negative CP).
fn sampling(sampled: Option<&(String, usize, Tensor3, Cp, Cp)>) -> Vec<Sampled> {
    use crate::tensor::query::Sat;
    use crate::tensor::sample::{binning_mse, chi_square};
    let check = |name: String, cp: &Cp, z: usize| -> Sampled {
        let sat = Sat::build(cp);
        let r = match (
            chi_square(cp, &sat, z, 200_000, 4),
            binning_mse(cp, &sat, z, 100_000, 8),
        ) {
            (Some(c), Some(b)) => Some((c, b)),
            _ => None,
        };
        (name, r)
    };
    let rnd = crate::tensor::cp::random_cp(4, [16, 16, 2], 11);
    let mut out = vec![check(
        "random non-negative rank-4 CP, slice 1".into(),
        &rnd,
        1,
    )];
    if let Some((map, r, tt, cp, nn)) = sampled {
        // the slice with the most mass
        let z = (0..tt.shape[2])
            .max_by(|&a, &b| {
                let s = |z: usize| (0..256).map(|q| tt.at(q % 16, q / 16, z)).sum::<f64>();
                s(a).total_cmp(&s(b))
            })
            .unwrap_or(0);
        let neg = |c: &Cp| (0..256).filter(|&q| c.at(q % 16, q / 16, z) < 0.0).count();
        out.push(check(format!("{map} P-NDF, R = {r}, heaviest slice, unconstrained CP ({} of 256 reconstructed pixels < 0, clamped)", neg(cp)), cp, z));
        out.push(check(
            format!(
                "the same slice, non-negative CP ({} of 256 pixels < 0)",
                neg(nn)
            ),
            nn,
            z,
        ));
    }
    out
}

//! Tensor prefiltering (seed 002): CP-ALS, range queries, P-NDF images.

mod common;

use ndfbench::filters::footprint::{NormalMap, Procedural};
use ndfbench::tensor::cp::{cp_als, rel_error, AlsOptions, Tensor3};
use ndfbench::tensor::pndf::{pndf_image, sigma_p};
use ndfbench::tensor::query::{range, range_error_bound, range_naive, Sat};
use ndfbench::verify::tensor::random_cp;
use proptest::prelude::*;

fn dense(cp: &ndfbench::tensor::cp::Cp) -> Tensor3 {
    let [a, b, c] = cp.shape;
    let mut d = Vec::with_capacity(a * b * c);
    for k in 0..c {
        for j in 0..b {
            for i in 0..a {
                d.push(cp.at(i, j, k));
            }
        }
    }
    Tensor3::new(cp.shape, d).unwrap()
}

#[test]
fn als_recovers_an_exact_low_rank_tensor() {
    // a tensor that is exactly rank 3 is reconstructed to the tolerance by rank-3 ALS
    let truth = random_cp(3, [16, 16, 12], 5);
    let t = dense(&truth);
    let o = AlsOptions {
        rank: 3,
        tol: 1e-8,
        max_iters: 2000,
        restarts: 3,
        seed: 1,
        nonnegative: false,
    };
    let cp = cp_als(&t, &o).unwrap();
    assert!(cp.rel_error < 1e-6, "rel error {}", cp.rel_error);
    assert!((rel_error(&t, &cp) - cp.rel_error).abs() < 1e-15);
    // and rank 1 cannot represent it
    let one = cp_als(&t, &AlsOptions { rank: 1, ..o }).unwrap();
    assert!(one.rel_error > 1e-3, "rank-1 error {}", one.rel_error);
}

#[test]
fn als_is_deterministic_and_rejects_bad_input() {
    let t = dense(&random_cp(2, [8, 8, 4], 9));
    let o = AlsOptions {
        rank: 2,
        tol: 1e-6,
        max_iters: 200,
        restarts: 2,
        seed: 3,
        nonnegative: false,
    };
    let (a, b) = (cp_als(&t, &o).unwrap(), cp_als(&t, &o).unwrap());
    assert_eq!(a.rel_error.to_bits(), b.rel_error.to_bits());
    assert!(cp_als(&t, &AlsOptions { rank: 0, ..o }).is_err());
    assert!(cp_als(&t, &AlsOptions { rank: 10_000, ..o }).is_err());
    assert!(Tensor3::new([2, 2, 2], vec![0.0; 7]).is_err());
    assert!(Tensor3::new([1, 1, 1], vec![f64::NAN]).is_err());
}

proptest! {
    #![proptest_config(common::config(10_000))] // was 100

    /// The O(R) range query equals the naive average within its a-priori rounding bound,
    /// for random shapes, ranks and boxes (single cells to the whole range).
    #[test]
    fn range_query_matches_naive(
        rank in 1usize..24, t in 1usize..80, seed in 0u64..1000,
        a in 0.0f64..1.0, b in 0.0f64..1.0, c in 0.0f64..1.0, d in 0.0f64..1.0,
    ) {
        let cp = random_cp(rank, [t, t, 3], seed);
        let sat = Sat::build(&cp);
        let pick = |u: f64, v: f64| {
            let (p, q) = ((u * t as f64) as usize, (v * t as f64) as usize);
            (p.min(q).min(t - 1), p.max(q).min(t - 1))
        };
        let (x, y) = (pick(a, b), pick(c, d));
        let naive = range_naive(&cp, x, y, 1);
        let fast = range(&cp, &sat, x, y, 1);
        let bound = 2.0 * range_error_bound(&cp, x, y, 1, f64::EPSILON, t as f64) + 8.0 * f64::EPSILON * naive.abs();
        prop_assert!((fast - naive).abs() <= bound, "{fast} vs {naive} (bound {bound:e})");
    }
}

#[test]
fn pndf_image_is_a_normalised_density() {
    // ∫ D dh over the projected disk = 1 when all normals and their σ_r smear lie inside
    let map = NormalMap::procedural(Procedural::IsotropicNoise, 32, 1).unwrap();
    let res = 64;
    let img = pndf_image(&map, 16.0, 16.0, sigma_p(4, 0), 0.02, res).unwrap();
    let cell = (2.0 / res as f64).powi(2);
    let total: f64 = img.iter().sum::<f64>() * cell;
    assert!((total - 1.0).abs() < 2e-3, "∫D = {total}");
    assert!(img.iter().all(|v| v.is_finite() && *v >= 0.0));
    assert!(pndf_image(&map, 0.0, 0.0, 0.0, 0.02, 8).is_err());
    // σ_P of level ℓ doubles per level (seed 002 §4.1)
    assert!((sigma_p(32, 1) / sigma_p(32, 0) - 2.0).abs() < 1e-15);
}

#[test]
fn pndf_blocks_compress_with_bounded_error() {
    // NDF image blocks of one footprint level stacked into t×t×L and CP-compressed:
    // the error falls with the rank
    let map = NormalMap::procedural(Procedural::Flakes, 32, 2).unwrap();
    let (res, t) = (32usize, 16usize);
    let mut data = Vec::new();
    let mut l = 0;
    for (cx, cy) in [(8.0, 8.0), (24.0, 8.0), (8.0, 24.0), (24.0, 24.0)] {
        let img = pndf_image(&map, cx, cy, sigma_p(4, 0), 0.03, res).unwrap();
        for by in 0..res / t {
            for bx in 0..res / t {
                let block: Vec<f64> = (0..t * t)
                    .map(|q| img[(by * t + q / t) * res + bx * t + q % t])
                    .collect();
                if block.iter().any(|v| *v > 1e-6) {
                    data.extend(block);
                    l += 1;
                }
            }
        }
    }
    let tensor = Tensor3::new([t, t, l], data).unwrap();
    let e = |r: usize| {
        cp_als(
            &tensor,
            &AlsOptions {
                rank: r,
                tol: 1e-4,
                max_iters: 500,
                restarts: 1,
                seed: 7,
                nonnegative: false,
            },
        )
        .unwrap()
        .rel_error
    };
    let (e2, e8) = (e(2), e(8));
    assert!(e8 < e2 && e8 < 0.5, "rank 2 {e2}, rank 8 {e8}");
}

/// χ² goodness of fit of the hierarchical sampler: 8×8 bins of 2×2 pixels over a 16×16
/// block, 200 000 samples, expected counts from exact (midpoint-on-the-tent-grid)
/// integration of the returned pdf; p-value by the Wilson–Hilferty approximation with
/// 63 degrees of freedom; significance 1 %. Non-negative factors, so the reconstruction
/// is non-negative and the descent is exact.
#[test]
fn hierarchical_sampling_passes_chi_square() {
    use ndfbench::tensor::query::Sat;
    use ndfbench::tensor::sample::{pdf, sample, total};
    use rand::{Rng, SeedableRng};
    let cp = random_cp(4, [16, 16, 2], 11);
    let sat = Sat::build(&cp);
    let z = 1;
    let tot = total(&cp, z);
    // the pdf integrates to 1
    let sub = 8;
    let mut expected = vec![0.0f64; 64];
    let mut integral = 0.0;
    for j in 0..16 * sub {
        for i in 0..16 * sub {
            let (x, y) = ((i as f64 + 0.5) / sub as f64, (j as f64 + 0.5) / sub as f64);
            let p = pdf(&cp, z, tot, x, y) / (sub * sub) as f64;
            integral += p;
            expected[(y as usize / 2) * 8 + x as usize / 2] += p;
        }
    }
    assert!((integral - 1.0).abs() < 1e-12, "∫pdf = {integral}");
    let n = 200_000usize;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
    let mut counts = vec![0usize; 64];
    let mut pdf_mismatch = 0.0f64;
    for _ in 0..n {
        let s = sample(
            &cp,
            &sat,
            z,
            tot,
            [rng.random(), rng.random(), rng.random()],
        )
        .unwrap();
        counts[(s.y as usize / 2) * 8 + s.x as usize / 2] += 1;
        pdf_mismatch = pdf_mismatch.max((s.pdf - pdf(&cp, z, tot, s.x, s.y)).abs());
    }
    assert_eq!(pdf_mismatch, 0.0);
    let chi2: f64 = counts
        .iter()
        .zip(&expected)
        .map(|(&c, &e)| (c as f64 - n as f64 * e).powi(2) / (n as f64 * e))
        .sum();
    let k = 63.0;
    let zz = ((chi2 / k).powf(1.0 / 3.0) - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    let p = 0.5 * libm::erfc(zz / std::f64::consts::SQRT_2);
    assert!(p > 0.01, "χ² = {chi2:.1} (63 dof), p = {p:.4}");
    // a wrong sampler is caught: uniform samples against the same expectation
    let mut wrong = vec![0usize; 64];
    for _ in 0..n {
        let (x, y) = (rng.random::<f64>() * 16.0, rng.random::<f64>() * 16.0);
        wrong[(y as usize / 2) * 8 + x as usize / 2] += 1;
    }
    let chi2w: f64 = wrong
        .iter()
        .zip(&expected)
        .map(|(&c, &e)| (c as f64 - n as f64 * e).powi(2) / (n as f64 * e))
        .sum();
    assert!(
        chi2w > 10.0 * chi2,
        "uniform sampler χ² {chi2w:.1} vs {chi2:.1}"
    );
}

#[test]
fn range_queries_span_several_blocks() {
    use ndfbench::tensor::query::{range_naive, BlockedImage, Sat};
    // a 3×3 grid of 16×16 blocks, one dropped; the multi-block query equals the naive
    // average over the same pixels (dropped blocks count as zero)
    let cps: Vec<_> = (0..9).map(|k| random_cp(3, [16, 16, 2], 40 + k)).collect();
    let sats: Vec<_> = cps.iter().map(Sat::build).collect();
    let blocks: Vec<_> = (0..9)
        .map(|k| {
            if k == 4 {
                None
            } else {
                Some((&cps[k], 1usize, &sats[k]))
            }
        })
        .collect();
    let img = BlockedImage {
        t: 16,
        nb: 3,
        blocks,
    };
    for (x, y) in [
        ((0, 47), (0, 47)),
        ((5, 40), (12, 13)),
        ((15, 16), (15, 16)),
        ((20, 20), (33, 33)),
    ] {
        let mut s = 0.0;
        for j in y.0..=y.1 {
            for i in x.0..=x.1 {
                let k = (j / 16) * 3 + i / 16;
                if k != 4 {
                    s += range_naive(&cps[k], (i % 16, i % 16), (j % 16, j % 16), 1);
                }
            }
        }
        let naive = s / (((x.1 - x.0 + 1) * (y.1 - y.0 + 1)) as f64);
        let fast = img.range(x, y);
        assert!(
            (fast - naive).abs() <= 1e-12 * naive.abs().max(1e-12),
            "{x:?}×{y:?}: {fast} vs {naive}"
        );
    }
}

#[test]
fn scratches_map_has_scratches() {
    let m = NormalMap::procedural(Procedural::Scratches, 64, 1).unwrap();
    let tilted = m.normals.iter().filter(|n| n.z < 0.99).count();
    assert!(
        tilted > 64 && tilted < 64 * 64 / 2,
        "{tilted} tilted texels"
    );
}

/// The paper's binning comparison (§5.2): a histogram of samples per pixel, normalised,
/// against the normalised reconstructed NDF image — the MSE falls like 1/N (Monte Carlo),
/// here checked against its expected value Σ p(1 − p)/N·(pixel area)⁻² within a factor 2.
#[test]
fn sampling_histogram_matches_the_ndf_image() {
    use ndfbench::tensor::query::Sat;
    use ndfbench::tensor::sample::{descend, total};
    use rand::{Rng, SeedableRng};
    let cp = random_cp(3, [16, 16, 1], 21);
    let sat = Sat::build(&cp);
    let tot = total(&cp, 0);
    let n = 100_000usize;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(8);
    let mut hist = vec![0usize; 256];
    for _ in 0..n {
        let (i, j, p) = descend(&cp, &sat, 0, rng.random()).unwrap();
        assert!(
            (p - cp.at(i, j, 0) / tot).abs() < 1e-12,
            "descent probability = normalised value"
        );
        hist[j * 16 + i] += 1;
    }
    let (mut mse, mut expect) = (0.0, 0.0);
    for j in 0..16 {
        for i in 0..16 {
            let p = cp.at(i, j, 0) / tot;
            mse += (hist[j * 16 + i] as f64 / n as f64 - p).powi(2);
            expect += p * (1.0 - p) / n as f64;
        }
    }
    assert!(
        mse < 2.0 * expect && mse > 0.5 * expect,
        "MSE {mse:.3e} vs expected {expect:.3e}"
    );
}

/// Non-negative CP (HALS): recovers an exactly non-negative low-rank tensor, never
/// returns a negative factor entry, and on a real P-NDF block gives a reconstruction the
/// hierarchical sampler follows exactly (χ², 1 % level) — the unconstrained fit of the
/// same block has negative pixels, which the sampler cannot follow.
#[test]
fn nonnegative_cp_makes_sampling_exact_on_a_real_block() {
    use ndfbench::filters::footprint::{NormalMap, Procedural};
    use ndfbench::tensor::cluster::cluster_tensors;
    use ndfbench::tensor::query::Sat;
    use ndfbench::tensor::sample::chi_square;
    let truth = random_cp(3, [16, 16, 12], 5);
    let t = dense(&truth);
    let o = AlsOptions {
        rank: 3,
        tol: 1e-10,
        max_iters: 3000,
        restarts: 1,
        seed: 5,
        nonnegative: true,
    };
    let cp = cp_als(&t, &o).unwrap();
    assert!(cp.rel_error < 1e-6, "NN-CP error {}", cp.rel_error);
    let map = NormalMap::procedural(Procedural::Flakes, 64, 3).unwrap();
    let ts = cluster_tensors(&map, 64, 8, 16, 0.02).unwrap();
    let o = AlsOptions {
        rank: 16,
        tol: 1e-4,
        max_iters: 200,
        restarts: 1,
        seed: 5,
        nonnegative: true,
    };
    let nn = cp_als(&ts[0], &o).unwrap();
    let free = cp_als(
        &ts[0],
        &AlsOptions {
            nonnegative: false,
            ..o
        },
    )
    .unwrap();
    assert!(nn.factors.iter().flatten().all(|v| *v >= 0.0));
    assert!(nn.weights.iter().all(|v| *v >= 0.0));
    // the heaviest slice
    let z = (0..ts[0].shape[2])
        .max_by(|&a, &b| {
            let s = |z: usize| (0..256).map(|q| ts[0].at(q % 16, q / 16, z)).sum::<f64>();
            s(a).total_cmp(&s(b))
        })
        .unwrap();
    let negative = (0..256)
        .filter(|&q| free.at(q % 16, q / 16, z) < 0.0)
        .count();
    assert!(
        negative > 0,
        "the unconstrained fit has negative lobes here"
    );
    let c = chi_square(&nn, &Sat::build(&nn), z, 200_000, 4).unwrap();
    assert!(
        c.p > 0.01,
        "NN-CP χ² = {:.1} ({} dof), p = {:.4}",
        c.chi2,
        c.dof,
        c.p
    );
    assert!((c.integral - 1.0).abs() < 1e-12);
}

/// The factored-Gaussian splat that seed 002's scale runs on equals the brute force of
/// Eq 2 bin by bin (up to the rounding of exp(a)·exp(b) against exp(a + b) and the order
/// of the sums: 1e-12 of the image's peak), footprints wrapping around the map included.
#[test]
fn separable_pndf_equals_the_brute_force() {
    use ndfbench::tensor::pndf::pndf_image_separable;
    for (kind, size, res, sr, level) in [
        (Procedural::Flakes, 64, 32, 0.02, 0),
        (Procedural::BrushedMetal, 64, 64, 0.05, 1),
        (Procedural::SharpBumps, 32, 48, 0.01, 0),
    ] {
        let map = NormalMap::procedural(kind, size, 3).unwrap();
        let sp = sigma_p(8, level);
        for (cx, cy) in [(4.0, 4.0), (0.25, size as f64 - 0.5), (17.5, 30.0)] {
            let a = pndf_image(&map, cx, cy, sp, sr, res).unwrap();
            let b = pndf_image_separable(&map, cx, cy, sp, sr, res).unwrap();
            let peak = a.iter().cloned().fold(0.0, f64::max);
            let worst = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(
                worst <= 1e-12 * peak,
                "{} at ({cx}, {cy}): |Δ| {worst:e} against peak {peak:e}",
                kind.name()
            );
        }
    }
}

/// A cluster at seed 002's scale, small: its footprints are the grid points of its region,
/// its L is the number of non-empty blocks of the brute-force images, and CP at a higher
/// rank does not fit worse here (ALS from the same seed, far from the cap).
#[test]
fn a_cluster_counts_its_blocks_as_the_brute_force_does() {
    use ndfbench::tensor::scale::{run_cluster, ScalePlan};
    let map = NormalMap::procedural(Procedural::Flakes, 128, 3).unwrap();
    let plan = ScalePlan {
        stride: 8,
        level: 0,
        res: 32,
        t: 16,
        regions: 4,
        sigma_r: 0.02,
        ranks: vec![2, 8],
        tol: 1e-4,
        max_iters: 200,
        seed: 5,
        starts: 1,
    };
    for cluster in [0usize, 5, 15] {
        let r = run_cluster(&map, &plan, cluster).unwrap();
        let fps = plan.footprints(128, cluster).unwrap();
        assert_eq!(
            fps.len(),
            16,
            "a 32² region holds 4 × 4 footprints of stride 8"
        );
        let (rx, ry) = (cluster % 4, cluster / 4);
        assert!(fps
            .iter()
            .all(|&(x, y)| (x as usize) / 32 == rx && (y as usize) / 32 == ry));
        let mut blocks = 0;
        for &(cx, cy) in &fps {
            let img = pndf_image(&map, cx, cy, sigma_p(8, 0), 0.02, 32).unwrap();
            for b in 0..4 {
                let (bx, by) = (b % 2, b / 2);
                if (0..256).any(|q| img[(by * 16 + q / 16) * 32 + bx * 16 + q % 16] > 0.0) {
                    blocks += 1;
                }
            }
        }
        assert_eq!(r.blocks, blocks);
        assert_eq!(r.blocks_all, 64);
        assert_eq!(r.ranks.len(), 2);
        assert!(r
            .ranks
            .iter()
            .all(|x| x.rel_error.is_finite() && x.rel_error < 1.0));
        assert!(r.ranks[1].rel_error <= r.ranks[0].rel_error + 1e-9);
    }
    assert!(
        run_cluster(&map, &plan, 16).is_err(),
        "cluster 16 of a 4 × 4 grid"
    );
    let bad = ScalePlan {
        regions: 32,
        ..plan.clone()
    };
    assert!(
        run_cluster(&map, &bad, 0).is_err(),
        "regions narrower than the stride"
    );
}

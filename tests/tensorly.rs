//! Our CP-ALS against TensorLy's `parafac` (an independent, established
//! implementation) on the same P-NDF tensors, rank, tolerance, stop rule and start
//! (benches/tensorly_compare.py). Started from the same factors, both must walk the same
//! ALS path: the same number of sweeps and the same reconstruction error to rounding.
//! Skips with a message when python3, numpy or TensorLy is missing (`.ci/run` installs
//! them when PyPI can be reached). Times are printed, never asserted.

mod common;

use ndfbench::filters::footprint::{NormalMap, Procedural};
use ndfbench::tensor::cluster::cluster_tensors;
use ndfbench::tensor::compare::{run_ours, run_tensorly, tensorly_available};
use ndfbench::tensor::cp::{initial_factors, restart_seed, AlsOptions};

#[test]
fn ours_walks_the_same_als_path_as_tensorly() {
    if let Err(why) = tensorly_available("python3") {
        eprintln!("skipping TensorLy comparison: {why}");
        return;
    }
    let dir = common::scratch("tensorly", "tensorly");
    std::fs::create_dir_all(&dir).unwrap();
    for (kind, rank) in [(Procedural::Flakes, 8), (Procedural::BrushedMetal, 12)] {
        let map = NormalMap::procedural(kind, 32, 3).unwrap();
        let tensors = cluster_tensors(&map, 32, 4, 16, 0.02).unwrap();
        let t = &tensors[0];
        let o = AlsOptions {
            rank,
            tol: 1e-4,
            max_iters: 500,
            restarts: 1,
            seed: 1,
            nonnegative: false,
        };
        let (oe, oi, os) = run_ours(t, &o, 1).unwrap();
        let init = initial_factors(t.shape, rank, restart_seed(o.seed, 0));
        let (te, ti, ts) = run_tensorly("python3", &dir, t, &init, rank, 1e-4, 500, 1).unwrap();
        eprintln!(
            "{} {:?} R={rank}: ours {oe:.6} ({oi} sweeps, {os:.4} s), TensorLy {te:.6} ({ti} sweeps, {ts:.4} s)",
            kind.name(),
            t.shape
        );
        assert_eq!(oi, ti, "sweep counts differ");
        assert!(
            (oe - te).abs() <= 1e-6 * te.max(1e-3),
            "ours {oe} vs TensorLy {te}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

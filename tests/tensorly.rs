//! Issue 5 §3: our CP-ALS against TensorLy's `parafac` on the same P-NDF tensors, rank and
//! tolerance (benches/tensorly_compare.py). Skips with a message when Python, numpy or
//! TensorLy is missing; otherwise prints both errors and times and checks that ours is
//! no worse than TensorLy's error by more than 10 % relative.

use ndfbench::filters::footprint::{NormalMap, Procedural};
use ndfbench::tensor::cp::{cp_als, AlsOptions};
use ndfbench::tensor::regen::cluster_tensors;
use std::process::Command;

#[test]
fn ours_against_tensorly_parafac() {
    let py = Command::new("python3")
        .arg("-c")
        .arg("import numpy, tensorly")
        .output();
    match py {
        Ok(o) if o.status.success() => {}
        Ok(o) => {
            eprintln!(
                "skipping TensorLy comparison: {}",
                String::from_utf8_lossy(&o.stderr)
                    .lines()
                    .last()
                    .unwrap_or("numpy/tensorly missing")
            );
            return;
        }
        Err(e) => {
            eprintln!("skipping TensorLy comparison: no python3 ({e})");
            return;
        }
    }
    let map = NormalMap::procedural(Procedural::Flakes, 32, 3).unwrap();
    let tensors = cluster_tensors(&map, 32, 4, 16, 0.02).unwrap();
    let dir = std::env::temp_dir().join(format!("ndfbench-tensorly-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (k, t) in tensors.iter().take(2).enumerate() {
        let rank = 8;
        let start = std::time::Instant::now();
        let ours = cp_als(
            t,
            &AlsOptions {
                rank,
                tol: 1e-4,
                max_iters: 500,
                restarts: 1,
                seed: 1,
            },
        )
        .unwrap();
        let our_s = start.elapsed().as_secs_f64();
        let path = dir.join(format!("t{k}.json"));
        std::fs::write(
            &path,
            serde_json::json!({"shape": t.shape, "data": t.data}).to_string(),
        )
        .unwrap();
        let out = Command::new("python3")
            .arg("benches/tensorly_compare.py")
            .arg(&path)
            .args([rank.to_string(), "1e-4".into(), "500".into()])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let (te, ts) = (
            v["rel_error"].as_f64().unwrap(),
            v["seconds"].as_f64().unwrap(),
        );
        eprintln!("cluster {k} {:?}: ours error {:.4} in {our_s:.3} s; TensorLy error {te:.4} in {ts:.3} s", t.shape, ours.rel_error);
        assert!(
            ours.rel_error <= 1.1 * te + 1e-3,
            "ours {} vs TensorLy {te}",
            ours.rel_error
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

//! The binary: JSON from `eval`, typed errors with exit status 2, verify's exit status.

use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ndfbench"))
}

#[test]
fn eval_prints_json_with_the_closed_form() {
    let out = bin()
        .args([
            "eval",
            "lambda",
            "--ndf",
            "ggx",
            "--alpha",
            "0.5",
            "--o",
            "0.6,0,0.8",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // GGX Λ = (√(1 + α² tan²θ) − 1)/2 with tan θ = 0.75 (seed 003 Eq 16)
    let expected = ((1.0f64 + 0.25 * 0.5625).sqrt() - 1.0) / 2.0;
    let got = v["value"].as_f64().unwrap();
    assert!((got - expected).abs() < 1e-15, "{got} vs {expected}");
}

#[test]
fn eval_reports_infinite_lambda_below_the_surface_as_null() {
    let out = bin()
        .args(["eval", "lambda", "--alpha", "0.5", "--o", "0.6,0,-0.8"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["value"].is_null() && v["infinite"].as_bool() == Some(true));
}

#[test]
fn bad_input_exits_2_with_a_clear_message() {
    for args in [
        vec!["eval", "d", "--alpha", "0", "--m", "0,0,1"],
        vec!["eval", "d", "--alpha", "nan", "--m", "0,0,1"],
        vec!["eval", "d", "--matrix", "1,2,1", "--m", "0,0,1"],
        vec!["eval", "d", "--alpha", "0.1", "--m", "0,0,0"],
        vec![
            "eval", "vndf-pdf", "--alpha", "0.1", "--o", "1,0,-1", "--m", "0,0,1",
        ],
        vec!["eval", "d", "--alpha", "0.1"],
    ] {
        let out = bin().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn verify_only_runs_a_subset_and_exits_0() {
    let out = bin()
        .args([
            "verify",
            "--preset",
            "quick",
            "--only",
            "jacobian-reflection",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(s.contains("1 of 1 proofs pass"), "{s}");
}

//! The specs in fits/ configure their studies: every one names a study whose parameters
//! parse and lie within bounds at every preset, and a number changed in a spec changes
//! the run.

mod common;

use ndfbench::fit::spec::load_dir;
use std::path::Path;

#[test]
fn every_shipped_spec_checks_at_every_preset() {
    let specs = load_dir(Path::new("fits")).unwrap();
    assert_eq!(specs.len(), ndfbench::studies::STUDIES.len());
    for s in &specs {
        let study = ndfbench::studies::find(&s.name)
            .unwrap_or_else(|| panic!("fits/{}.toml names no study", s.name));
        study.check(s).unwrap();
    }
}

/// smith-lambda's held-out set is the midpoints of its training points: 600 in the shipped
/// spec, so a run with `points = 101` holds out exactly 100 (the count comes from the
/// spec, not from the code).
#[test]
fn a_number_changed_in_a_spec_changes_the_run() {
    let d = common::scratch("specs", "points");
    let fits = d.join("fits");
    std::fs::create_dir_all(&fits).unwrap();
    let text = include_str!("../fits/smith-lambda.toml");
    assert!(text.contains("points = 600"));
    std::fs::write(
        fits.join("smith-lambda.toml"),
        text.replace("points = 600", "points = 101")
            .replace("max_iters = 4000", "max_iters = 50"),
    )
    .unwrap();
    let results = d.join("results");
    let out = common::regen_in(
        &fits,
        &results,
        &["--only", "smith-lambda", "--preset", "quick"],
    )
    .arg("--no-cache")
    .output()
    .unwrap();
    // the run may miss its tolerance with 50 iterations (exit 1); it must not fail (2)
    assert!(
        out.status.code() != Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(results.join("fits/smith-lambda.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(v["held_out"]["ours"]["points"], 100);
    assert!(
        v["iterations"].as_u64().unwrap() <= 6 * 50,
        "{}",
        v["iterations"]
    );
    let _ = std::fs::remove_dir_all(&d);
}

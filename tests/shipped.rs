//! Against the shipped GGX LTC table (three.js 0.187.0's RectAreaLightTexturesLib.js, the
//! numbers of selfshadow/ltc_code's fit): `.ci/run` fetches it into target/shipped/ with
//! `npm pack`; it is never committed, and these tests skip with a message without it.
//! They check that the committed comparison (results/ltc-compare.json) is the one this
//! file and the committed table give, by recomputing a spread of its cells and squares
//! independently of the run that wrote it.

use ndfbench::ltc::compare::{cell_error, Shipped};
use std::path::Path;

const SHIPPED: &str = "target/shipped/RectAreaLightTexturesLib.js";

fn shipped() -> Option<Shipped> {
    let Ok(text) = std::fs::read_to_string(SHIPPED) else {
        eprintln!("skipped: {SHIPPED} absent (`npm pack three@0.187.0`, see .ci/run)");
        return None;
    };
    Some(Shipped::parse(&text, "LTC_MAT_1", "LTC_MAT_2").expect("the shipped file parses"))
}

#[test]
fn shipped_table_is_the_64_squared_ltc_code_fit() {
    let Some(s) = shipped() else { return };
    assert_eq!(s.n, 64);
    // ltc_code's layout: identity-like at normal incidence and α → 0, norm 1 there
    assert_eq!(s.mat[0], [1.0, 0.0, 0.0, 2e-5]);
    assert!(s.mag.iter().all(|m| (0.0..=1.0 + 1e-6).contains(&m[0])));
}

#[test]
fn committed_comparison_reproduces_from_the_shipped_file() {
    let Some(s) = shipped() else { return };
    let ours = ndfbench::ltc::compare::ours(Path::new("results")).unwrap();
    let v: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("results/ltc-compare.json").expect("results/ltc-compare.json"),
    )
    .unwrap();
    // the three.js FloatType path: both tables rounded to f32, each with its own norm
    let form = &v["forms"][0];
    assert_eq!(form["name"], "three.js FloatType");
    let cells = form["cells"].as_array().unwrap();
    assert_eq!(cells.len(), 64 * 64);
    for k in (3..64 * 64).step_by(397) {
        let (i, j) = (k % 64, k / 64);
        if (i as f64) / 63.0 < ndfbench::ltc::upload::THREE_MIN_ROUGHNESS {
            continue;
        }
        let (alpha, theta) =
            ndfbench::ltc::compare_report::alpha_theta(i as f64 / 63.0, j as f64 / 63.0);
        let q = |x: f64| x as f32 as f64;
        for (t, side) in [(&ours, "ours"), (&s, "shipped")] {
            let inv = t.mat[k].map(q);
            let e = cell_error(&inv, q(t.mag[k][0]), alpha, theta)
                .unwrap()
                .unwrap();
            let stored = &cells[k][side]["l2"];
            let (sv, se) = (
                stored["value"].as_f64().unwrap(),
                stored["error"].as_f64().unwrap(),
            );
            // a different cubature (alone, not beside the other candidates): within both bars
            assert!(
                (e.l2.value - sv).abs() <= e.l2.error + se,
                "cell ({i}, {j}) {side}: recomputed {:?}, stored {sv} ± {se}",
                e.l2
            );
        }
    }
}

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
    let ours = ndfbench::results::compare::ours(Path::new("results")).unwrap();
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
        let (alpha, theta) = ndfbench::ltc::compare::alpha_theta(i as f64 / 63.0, j as f64 / 63.0);
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

const BEVY: &str = "target/shipped/bevy_ltc.ktx2";

fn bevy() -> Option<Shipped> {
    let Ok(bytes) = std::fs::read(BEVY) else {
        eprintln!("skipped: {BEVY} absent (`cargo fetch` in engines/fetch-bevy, see .ci/run)");
        return None;
    };
    Some(ndfbench::ltc::upload::bevy_ktx2(&bytes).expect("Bevy's ltc.ktx2 decodes"))
}

/// Bevy's embedded table decodes (zstd, 2 RGBA16F layers) to the shipped numbers in
/// binary16: every value within one binary16 step of the ltc_code/three.js number, most
/// of them rounded to nearest, unlike three.js's truncating `toHalfFloat`.
#[test]
fn bevy_table_is_the_shipped_table_in_binary16() {
    let (Some(b), Some(s)) = (bevy(), shipped()) else {
        return;
    };
    assert_eq!(b.n, 64);
    let (mut nearest, mut three) = (0usize, 0usize);
    for (bm, sm) in b.mat.iter().zip(&s.mat) {
        for (x, y) in bm.iter().zip(sm) {
            let h = half::f16::from_f64(*y);
            let step =
                (half::f16::from_bits(h.to_bits().wrapping_add(1)).to_f64() - h.to_f64()).abs();
            assert!(
                (x - y).abs() <= step.max(6e-8),
                "Bevy {x} against shipped {y}"
            );
            nearest += (*x == h.to_f64()) as usize;
            three += (*x == ndfbench::ltc::upload::three_half(*y)) as usize;
        }
    }
    let total = 4 * 64 * 64;
    eprintln!("Bevy's binary16 matrix values: {nearest} of {total} to nearest, {three} equal to three.js's truncation");
    assert!(
        nearest > three,
        "Bevy's table rounds to nearest more often than it truncates"
    );
}

/// three.js's HalfFloatType table truncates: a good share of LTC_MAT_1 sits one step
/// below round-to-nearest (toward zero), none above it.
#[test]
fn three_half_table_truncates() {
    let Some(s) = shipped() else { return };
    let mut below = 0usize;
    for y in s.mat.iter().flatten() {
        let t = ndfbench::ltc::upload::three_half(*y);
        let n = half::f16::from_f64(*y).to_f64();
        assert!(
            t.abs() <= n.abs() + 1e-300,
            "{y}: three {t} beyond nearest {n}"
        );
        below += (t != n) as usize;
    }
    assert!(below > 1000, "only {below} values differ from nearest");
}

/// The committed comparison's Bevy path reproduces from the fetched file.
#[test]
fn committed_bevy_comparison_reproduces() {
    let Some(b) = bevy() else { return };
    let ours = ndfbench::results::ltc::table(Path::new("results"), "ltc-ggx").unwrap();
    let v: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("results/ltc-compare.json").expect("results/ltc-compare.json"),
    )
    .unwrap();
    let Some(form) = v["forms"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"] == "Bevy ltc.ktx2")
    else {
        panic!("results/ltc-compare.json has no Bevy path: rerun `ltc-compare --bevy`");
    };
    let cells = form["cells"].as_array().unwrap();
    for k in (0..64 * 64).step_by(509) {
        let (i, j) = (k % 64, k / 64);
        let (alpha, theta) = ndfbench::ltc::compare::alpha_theta(i as f64 / 63.0, j as f64 / 63.0);
        let h = ours.half_cell(k).map(|x| x.to_f64());
        for (inv, norm, side) in [
            ([h[0], h[1], h[2], h[3]], h[4], "ours"),
            (b.mat[k], b.mag[k][0], "shipped"),
        ] {
            let e = cell_error(&inv, norm, alpha, theta).unwrap().unwrap();
            let stored = &cells[k][side]["l2"];
            let (sv, se) = (
                stored["value"].as_f64().unwrap(),
                stored["error"].as_f64().unwrap(),
            );
            assert!(
                (e.l2.value - sv).abs() <= e.l2.error + se,
                "Bevy path cell ({i}, {j}) {side}: recomputed {:?}, stored {sv} ± {se}",
                e.l2
            );
        }
    }
}

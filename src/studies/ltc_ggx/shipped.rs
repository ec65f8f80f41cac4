//! The stored comparison with the shipped table, summarised in results/ltc.md.

use std::path::Path;

/// §2: the stored comparison with the shipped table (results/ltc-compare.json, written by
/// `ltc-compare`; the shipped file itself is never committed).
pub(super) fn section(results: &Path, our_mean_l2: f64) -> String {
    let mut md = String::from("## Against the shipped table\n\n");
    let v: Option<serde_json::Value> = crate::io::read_to_string(&results.join("ltc-compare.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    match v {
        Some(v) => {
            let cells = v["cells"].as_array().cloned().unwrap_or_default();
            // rows [i, j, alpha, theta_deg, ours_l2, shipped_l2, ours_cubic, shipped_cubic]
            let get = |c: &serde_json::Value, k: &str| {
                let col = ["i", "j", "alpha", "theta_deg", "ours_l2", "shipped_l2"]
                    .iter()
                    .position(|x| *x == k)
                    .unwrap_or(0);
                c[col].as_f64().unwrap_or(f64::NAN)
            };
            let inner: Vec<&serde_json::Value> =
                cells.iter().filter(|c| get(c, "i") > 0.0).collect();
            let m = inner.len().max(1) as f64;
            let no_worse = inner
                .iter()
                .filter(|c| get(c, "ours_l2") <= get(c, "shipped_l2") * 1.001)
                .count();
            let mut rows: Vec<u64> = inner.iter().map(|c| get(c, "j") as u64).collect();
            rows.sort();
            rows.dedup();
            let stale = (v["ours_table_mean_l2"].as_f64().unwrap_or(f64::NAN) - our_mean_l2).abs() > 1e-12;
            md.push_str(&format!(
                "From `{}` (results/ltc-compare.md, per-cell numbers in results/ltc-compare.json){}{}: {} cells (r > 0) of the θ rows {:?}; mean relative L2 ours {:.2} %, shipped {:.2} %; ours no worse (0.1 % slack) in {no_worse} of {}. Between cells (bilinear interpolation at square centres), see results/ltc-compare.md.\n\n",
                v["command"].as_str().unwrap_or("ltc-compare"),
                v["source"].as_str().map(|s| format!("; source: {s}")).unwrap_or_default(),
                if stale { " — STALE: the table was refitted after this comparison; rerun `ltc-compare`" } else { "" },
                inner.len(),
                rows,
                100.0 * inner.iter().map(|c| get(c, "ours_l2")).sum::<f64>() / m,
                100.0 * inner.iter().map(|c| get(c, "shipped_l2")).sum::<f64>() / m,
                inner.len()
            ));
        }
        None => md.push_str("Not run: `cargo run --release -- ltc-compare --shipped ltc.js --mat g_ltc_1 --mag g_ltc_2` (or three.js's RectAreaLightTexturesLib.js with the default array names) writes results/ltc-compare.md and .json.\n\n"),
    }
    md
}

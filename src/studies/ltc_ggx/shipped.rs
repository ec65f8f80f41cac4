//! The stored comparison with the shipped table, summarised in results/ltc.md.

use std::path::Path;

/// §2: the stored comparison with the shipped table (results/ltc-compare.json, written by
/// `ltc-compare`; the shipped file itself is never committed).
pub(super) fn section(results: &Path, our_mean_l2: f64) -> crate::error::Result<String> {
    let mut md = String::from("## Against the shipped table\n\n");
    let v = crate::results::read_json(&results.join("ltc-compare.json"))?;
    match v {
        Some(v) => {
            let stale = (v["ours_table_mean_l2"].as_f64().unwrap_or(f64::NAN) - our_mean_l2).abs()
                > 1e-12;
            md.push_str(&format!(
                "From `{}` (results/ltc-compare.md, per-cell and per-square numbers in results/ltc-compare.json){}{}; norms: {}. Relative L2, ours vs shipped:\n\n| where | count | ours: mean | shipped: mean | ours no worse |\n|---|---|---|---|---|\n",
                v["command"].as_str().unwrap_or("ltc-compare"),
                v["source"].as_str().map(|s| format!("; source: {s}")).unwrap_or_default(),
                if stale { " — STALE: the table was refitted after this comparison; rerun `ltc-compare`" } else { "" },
                v["norms"].as_str().unwrap_or("?"),
            ));
            for e in v["summary"].as_array().cloned().unwrap_or_default() {
                let s = &e[1];
                let f = |k: &str| s[k].as_f64().unwrap_or(f64::NAN);
                md.push_str(&format!(
                    "| {} | {} | {:.2} % | {:.2} % | {} |\n",
                    e[0].as_str().unwrap_or("?"),
                    f("count"),
                    100.0 * f("ours_mean"),
                    100.0 * f("shipped_mean"),
                    f("ours_no_worse")
                ));
            }
            md.push('\n');
        }
        None => md.push_str("Not run: `cargo run --release -- ltc-compare --shipped ltc.js --mat g_ltc_1 --mag g_ltc_2` (or three.js's RectAreaLightTexturesLib.js with the default array names) writes results/ltc-compare.md and .json.\n\n"),
    }
    Ok(md)
}

//! The stored comparison with the shipped table, summarised in results/ltc-ggx.md.

use std::path::Path;

/// §2: the stored comparison with the shipped table (results/ltc-compare.json, written by
/// `ltc-compare`; the shipped file itself is never committed).
pub(super) fn section(results: &Path, our_mean_l2: f64) -> crate::error::Result<String> {
    let mut md = String::from("## Against the shipped table\n\n");
    match crate::results::compare::read(results)? {
        Some(v) => {
            let stale = (v.ours_table_mean_l2 - our_mean_l2).abs() > 1e-12;
            md.push_str(&format!(
                "From `{}` (results/ltc-compare.md, per-cell and per-square numbers in results/ltc-compare.json){}{}; norms: {}. Relative L2 of each table against the BRDF (held-out integrals, each mean ± its error bar), and the places where ours is lower or higher by more than both error bars together:\n\n| where | count | ours: mean | shipped: mean | ours lower | ours higher |\n|---|---|---|---|---|---|\n",
                v.command,
                v.source.as_deref().map(|s| format!("; source: {s}")).unwrap_or_default(),
                if stale { " — STALE: the table was refitted after this comparison; rerun `ltc-compare`" } else { "" },
                v.norms,
            ));
            for (place, s) in &v.summary {
                md.push_str(&format!(
                    "| {place} | {} | {} | {} | {} | {} |\n",
                    s.count,
                    s.ours_l2.mean.pct(2),
                    s.shipped_l2.mean.pct(2),
                    s.ours_better,
                    s.ours_worse
                ));
            }
            md.push('\n');
        }
        None => md.push_str("Not run: `cargo run --release -- ltc-compare --shipped ltc.js --mat g_ltc_1 --mag g_ltc_2` (or three.js's RectAreaLightTexturesLib.js with the default array names) writes results/ltc-compare.md and .json.\n\n"),
    }
    Ok(md)
}

//! The stored comparison with the shipped table, summarised in results/ltc-ggx.md.

use crate::report::table::Table;
use crate::results::compare::LtcCompare;

/// §2: the stored comparison with the shipped table (results/ltc-compare.json, written by
/// `ltc-compare`; the shipped file itself is never committed), `None` where not run. It is
/// stale when it was made against another table: another fingerprint (`FittedTable::
/// fingerprint`), or, in a file without one, a mean held-out relative L2 further from
/// ours than our mean's bar — the same table judged to another tolerance moves its mean
/// within that bar.
pub(super) fn section(
    compare: Option<&LtcCompare>,
    our_mean_l2: crate::integrate::Figure<crate::integrate::Quad>,
    our_fingerprint: &str,
) -> String {
    let mut md = String::from("## Against the shipped table\n\n");
    match compare {
        Some(v) => {
            let stale = match &v.ours_table_fingerprint {
                Some(f) => f != our_fingerprint,
                None => (v.ours_table_mean_l2 - our_mean_l2.value).abs() > our_mean_l2.error,
            };
            md.push_str(&format!(
                "From `{}` (results/ltc-compare.md, per-cell and per-square numbers in results/ltc-compare.json){}{}; norms: {}. Relative L2 of each table against the BRDF (held-out integrals, each mean ± its error bar), and the places where ours is lower or higher by more than both error bars together:\n\n",
                v.command,
                v.source.as_deref().map(|s| format!("; source: {s}")).unwrap_or_default(),
                if stale { " — STALE: the table was refitted after this comparison; rerun `ltc-compare`" } else { "" },
                v.norms,
            ));
            let mut t = Table::new([
                "where",
                "count",
                "ours: mean",
                "shipped: mean",
                "ours lower",
                "ours higher",
            ]);
            for (place, s) in &v.summary {
                t.row([
                    place.clone(),
                    s.count.to_string(),
                    s.ours_l2.mean.pct(2),
                    s.shipped_l2.mean.pct(2),
                    s.ours_better.to_string(),
                    s.ours_worse.to_string(),
                ]);
            }
            md.push_str(&t.to_string());
            md.push('\n');
        }
        None => md.push_str("Not run: `cargo run --release -- ltc-compare --shipped ltc.js --mat g_ltc_1 --mag g_ltc_2` (or three.js's RectAreaLightTexturesLib.js with the default array names) writes results/ltc-compare.md and .json.\n\n"),
    }
    md
}

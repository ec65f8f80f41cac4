//! The between-cell figures in words, for the reports of the studies that measure them.
//! Formats only.

use super::{Between, BETWEEN_WORST_CELLS, VISIBLE_ALBEDO};

/// The between-cell sentence: every visible square judged (exact means), or a random
/// sample of them (means over all by the difference estimator, ± its s.e.). `absent`: what
/// the study judges when its spec gives no `between_sample`, as the sentence names it.
pub fn words(b: &Between, absent: &str) -> String {
    let left_out = if b.left_out > 0 {
        format!(" {} squares are left out: their lobe carries almost no energy (sheen seen head-on at small α), and between corners whose albedos differ by orders of magnitude the interpolated norm dwarfs it, so their relative error says nothing about the picture", b.left_out)
    } else {
        String::new()
    };
    let j = &b.judged;
    if b.all {
        return format!(
            "Between cells (what a shader sampling the table bilinearly sees): the production inverse and the norm interpolated at the centres of the squares, judged against the lobe there by the same integrals, over the {} squares whose lobe has an albedo of at least {:e}: {}.{left_out}",
            j.l2.count, VISIBLE_ALBEDO, j.words()
        );
    }
    let at =
        j.at.map_or(String::new(), |(a, t)| format!(" at ({a:.3}, {t:.1}°)"));
    let mean = |m: &crate::integrate::Figure, judged: &crate::ltc::lobe_error::Spread| {
        format!(
            "{} (s.e.; the judged figures' own integral bars average ±{:.4})",
            m.pct(4),
            100.0 * judged.mean.error
        )
    };
    format!(
        "Between cells (what a shader sampling the table bilinearly sees): the production inverse and the norm interpolated at the centres of {} of the {} squares whose lobe has an albedo of at least {:e} — {} always (those touching the {} worst cells, and those whose corners' entries jump most), and {} drawn at random from the other {} (`between_sample` in the spec, {absent}: a quarter of it goes to the jumps; as many as the other squares or more judges all, as the precise preset does) — judged against the lobe there by the same integrals. Means over all {}: the first group's sum plus the others' by the difference estimator with the mean of each square's four corner cells' held-out figures as the control, ± the sample's standard error: relative L2 {}, relative L1 {}. Largest among the judged: relative L2 {}{at}, relative L1 {}.{left_out}",
        j.l2.count,
        b.visible,
        VISIBLE_ALBEDO,
        b.census,
        BETWEEN_WORST_CELLS,
        j.l2.count.saturating_sub(b.census),
        b.rest,
        b.visible,
        mean(&b.mean_l2, &j.l2),
        mean(&b.mean_l1, &j.l1),
        j.l2.max.pct(1),
        j.l1.max.pct(1),
    )
}

//! The compact tables' report (formatting only): results/ltc-compact.md and its plot.

use crate::error::Result;
use crate::report::table::{Align, Table};
use crate::results::ltc_compact::{CompactFamily, LtcCompact};

/// three.js PR #34611's coefficient count (its figure as stated; no error is published
/// for it, and it reproduces the shipped table).
const PR_34611_COEFFICIENTS: usize = 3078;

pub fn markdown(r: &LtcCompact) -> String {
    let mut md = format!(
        "# Compact LTC tables: coefficients against the exact lobe error\n\nWritten by `{}` (preset {}) from `fits/{}.toml`, on request (the main job leaves it out). Each channel of a published table (a, b, c, d, norm, fresnel over r = √α, t = √(1 − cos θ)) is a tensor-product Chebyshev series of degree < p in r and in t (`ltc::compact`; 6·p² coefficients), fitted in one of two ways. **Least squares** fits the table's entries: on the values (`raw`), on the values over α(r) = max(r², α_min) of the channels that vanish like α (`over-α`: GGX b and d), or on the logarithm of the positive channels that span decades (`log`: sheen d and norm; `log-a`: sheen a, d and norm). The **lobe fit** (`, lobe-fit`; `ltc::compact_fit`) starts from a least-squares form and moves its five lobe channels' coefficients by Levenberg–Marquardt to lower the mean relative L2 of the lobe the shader reads — the rebuilt texels read bilinearly, against the true lobe — at every texel centre and one low-discrepancy point inside every square (nodes: the target's, the start lobe's and clamped-cosine samples; ∫D² on the lobe's own samples, so mass between nodes counts; places weighted by 1/their starting error, so the mean and not the square is what falls); the fresnel channel keeps its least-squares series. Each form is judged at the cells (texel centres) and square centres whose indices along each axis are multiples of {} against the true lobe there, by the exact held-out relative L2 (`ltc::lobe_error`, tolerance {:e} relative; mean ± the mean of the bars):\n\n- **rebuilt**: evaluated at the texel centres, stored as the nearest binary16, read bilinearly (a square centre reads the mean of its four corners): the texture an engine's start-up code would fill from the coefficients;\n- **texture-free**: evaluated per pixel in f32 at the place itself.\n\nThe full table is our stored binary16 table read the same way; the shipped table's figures at the same places come from results/ltc-compare.json (its own tolerance, 5e-4), per engine path, and a place counts as better or worse only beyond both bars. three.js PR #34611 rebuilds the shipped table from {} Chebyshev coefficients; it reproduces that table, so its error is the shipped table's (its count as stated, no figure of ours).\n\n![coefficients against error]({}.svg)\n\n",
        r.command,
        r.preset,
        r.spec.name,
        r.every,
        r.held_out_rel,
        PR_34611_COEFFICIENTS,
        r.spec.name
    );
    for f in &r.families {
        md.push_str(&family(f));
    }
    md
}

fn family(f: &CompactFamily) -> String {
    let mut md = format!(
        "## {} ({}×{} table, {} coefficients; {} cells and {} squares judged)\n\n",
        f.table, f.n, f.n, f.full_coefficients, f.full.cells.count, f.full.squares.count
    );
    let mut head = vec![
        "form".to_string(),
        "coefficients".into(),
        "rebuilt: cells".into(),
        "rebuilt: squares".into(),
        "texture-free: cells".into(),
        "texture-free: squares".into(),
        "rebuilt worse than the full table".into(),
    ];
    for s in &f.shipped {
        head.push(format!(
            "rebuilt vs shipped, {} (better / tied / worse)",
            s.path
        ));
    }
    head.push("f32 form: largest rel. error".into());
    let mut t = Table::new(head);
    for c in 1..7 {
        t = t.align(c, Align::Right);
    }
    let mut row = vec![
        "full table (binary16)".to_string(),
        f.full_coefficients.to_string(),
        f.full.cells.mean.pct(3),
        f.full.squares.mean.pct(3),
        "—".into(),
        "—".into(),
        "—".into(),
    ];
    row.extend(f.shipped.iter().map(|_| "—".to_string()));
    row.push("—".into());
    t.row(row);
    for s in &f.shipped {
        let mut row = vec![
            format!("shipped, {} (r ≥ {}; its places)", s.path, s.r_min),
            f.full_coefficients.to_string(),
            s.shipped.cells.mean.pct(3),
            s.shipped.squares.mean.pct(3),
            "—".into(),
            "—".into(),
            format!(
                "full table at its places: {} / {}",
                s.ours_full.cells.mean.pct(3),
                s.ours_full.squares.mean.pct(3)
            ),
        ];
        row.extend(f.shipped.iter().map(|_| "—".to_string()));
        row.push("—".into());
        t.row(row);
    }
    for (k, c) in f.forms.iter().enumerate() {
        let mark = if f.chosen == Some(k) { " (chosen)" } else { "" };
        let mut row = vec![
            format!("{} p = {}{mark}", c.transforms, c.p),
            c.coefficients.to_string(),
            c.rebuilt.cells.mean.pct(3),
            c.rebuilt.squares.mean.pct(3),
            c.texture_free.cells.mean.pct(3),
            c.texture_free.squares.mean.pct(3),
            c.rebuilt_worse_than_full.to_string(),
        ];
        row.extend(
            c.rebuilt_vs_shipped
                .iter()
                .map(|v| format!("{} / {} / {}", v[0], v[1], v[2])),
        );
        row.push(format!("{:.1e}", c.f32_rel_error));
        t.row(row);
    }
    md.push_str(&format!("{t}\n"));
    md.push_str(&match f.chosen {
        Some(k) => format!(
            "Chosen: {} p = {} ({} coefficients), the fewest that meet the goal.\n\n",
            f.forms[k].transforms, f.forms[k].p, f.forms[k].coefficients
        ),
        None => "No form meets the goal (at most the spec's coefficients, no reachable place worse than the shipped table, a mean within the spec's points of the full table's).\n\n".into(),
    });
    if let Some(tf) = &f.texture_free {
        let q = &f.forms[tf.form];
        md.push_str(&format!(
            "Texture-free pick (the lowest texture-free mean of cells and squares within the spec's coefficients; the form the generated texture-free code carries): {} p = {} ({} coefficients), {} (cells) / {} (squares) against the full table read as a texture, {} / {}.\n\n",
            q.transforms,
            q.p,
            q.coefficients,
            q.texture_free.cells.mean.pct(3),
            q.texture_free.squares.mean.pct(3),
            f.full.cells.mean.pct(3),
            f.full.squares.mean.pct(3)
        ));
    }
    let worst = |s: &crate::ltc::lobe_error::Spread| s.max.pct(2);
    md.push_str(&format!(
        "Largest relative L2 of the full table: {} (cells), {} (squares).\n\n",
        worst(&f.full.cells),
        worst(&f.full.squares)
    ));
    for (i, s) in f.shipped.iter().enumerate() {
        let c = s.full_vs_shipped;
        md.push_str(&format!(
            "The full table itself against the shipped one on {}'s path: better at {}, tied at {}, worse at {} of the judged places (beyond both bars).",
            s.path, c[0], c[1], c[2]
        ));
        let fewest = (0..f.forms.len()).min_by_key(|&k| f.forms[k].rebuilt_vs_shipped[i][2]);
        if let (None, Some(k), true) = (f.chosen, fewest, c[2] > 0) {
            let q = &f.forms[k];
            md.push_str(&format!(
                " So the goal's every-place condition is out of reach of any table fitted here, full or compact: its floor on this path is the full table's {} places; the compact form nearest it is {} p = {} ({} coefficients) with {}.",
                c[2],
                q.transforms,
                q.p,
                q.coefficients,
                q.rebuilt_vs_shipped[i][2]
            ));
        }
        md.push_str("\n\n");
    }
    md.push_str(&lobe_fits(f));
    md.push_str(&polygons(f));
    md
}

/// The polygon lights: per form, the mean squared difference from the Monte Carlo truth
/// (estimated without bias, ± its s.e.), rebuilt and texture-free, beside the full table.
fn polygons(f: &CompactFamily) -> String {
    let Some(p) = &f.polygons else {
        return String::new();
    };
    let cells: std::collections::BTreeSet<String> = p
        .truth
        .iter()
        .map(|(a, th, _, _)| format!("(α {a:.4}, θ {:.1}°)", th.to_degrees()))
        .collect();
    let mut md = format!(
        "### Polygon lights

The {} quad lights the table's own study checks it with (results/{}.md: {} cells {} × the four quads of `ltc::polygon::check_lights`), each with its Monte Carlo truth ± s.e.; every form shaded as norm × the exact LTC integral of the quad, with its entries at the cell's (α, θ): rebuilt (binary16, bilinear) and texture-free (f32). Each figure is the mean over the lights of (value − truth)², estimated without bias as the mean of (value − MC)² − s.e.², ± its standard error (×10⁻⁶; the lights' values: results/fits/ltc-compact.json). With truths of this accuracy, forms whose figures differ by less than about twice their bars are not told apart.\n\n",
        p.truth.len(),
        // both sheen tables are one study's, reported in results/ltc-sheen.md
        if f.table.starts_with("ltc-sheen") {
            "ltc-sheen"
        } else {
            f.table.as_str()
        },
        cells.len(),
        cells.into_iter().collect::<Vec<_>>().join(", ")
    );
    let e = |x: &crate::results::ltc_compact::PolygonFigures| x.mse.scaled(1e6).fixed(3);
    let mut t = Table::new(["form", "coefficients", "rebuilt", "texture-free"]);
    t.row([
        "full table (binary16)".to_string(),
        f.full_coefficients.to_string(),
        e(&p.full),
        "—".into(),
    ]);
    for (k, form) in f.forms.iter().enumerate() {
        if let (Some(r), Some(x)) = (p.rebuilt.get(k), p.texture_free.get(k)) {
            t.row([
                format!("{} p = {}", form.transforms, form.p),
                form.coefficients.to_string(),
                e(r),
                e(x),
            ]);
        }
    }
    md.push_str(&format!("{t}\n"));
    // the forms whose rebuild is further from the truth than the full table, beyond both
    // bars
    let full = p.full.mse;
    let worse: Vec<String> = f
        .forms
        .iter()
        .zip(&p.rebuilt)
        .filter(|(_, r)| r.mse.value - r.mse.error > full.value + full.error)
        .map(|(form, _)| format!("{} p = {}", form.transforms, form.p))
        .collect();
    md.push_str(&if worse.is_empty() {
        "No rebuilt form is further from the truth than the full table beyond both bars.\n\n"
            .to_string()
    } else {
        format!(
            "Rebuilt forms further from the truth than the full table, beyond both bars: {}.\n\n",
            worse.join("; ")
        )
    });
    md
}

/// The lobe fits' traces: training places and nodes, iterations, and per pass the mean
/// relative L2 over the training places (on that pass's nodes) at its start and end.
fn lobe_fits(f: &CompactFamily) -> String {
    let mut t = Table::new(vec![
        "form".to_string(),
        "training places".into(),
        "nodes per place".into(),
        "iterations".into(),
        "training mean rel. L2, per pass (start → end)".into(),
    ]);
    let mut any = false;
    for c in &f.forms {
        let Some(tr) = &c.lobe_fit else { continue };
        any = true;
        t.row(vec![
            format!("{} p = {}", c.transforms, c.p),
            tr.places.to_string(),
            tr.nodes_per_place.to_string(),
            tr.iterations.to_string(),
            tr.passes
                .iter()
                .map(|[a, b]| format!("{:.2} % → {:.2} %", 100.0 * a, 100.0 * b))
                .collect::<Vec<_>>()
                .join("; "),
        ]);
    }
    if !any {
        return String::new();
    }
    format!(
        "Lobe fits (training figures are Monte Carlo estimates on fixed nodes, the fit's own objective, not held-out measurements; the table above judges them):\n\n{t}\n"
    )
}

pub(super) fn plot(r: &LtcCompact) -> Result<String> {
    use crate::report::plot::{loglog_svg_legend, Panel, Series};
    let panels: Vec<Panel> = r
        .families
        .iter()
        .map(|f| {
            let mut series = Vec::new();
            let mut trs: Vec<&str> = f.forms.iter().map(|c| c.transforms.as_str()).collect();
            trs.dedup();
            for tr in trs {
                for (what, free) in [("rebuilt", false), ("texture-free", true)] {
                    series.push(Series {
                        name: format!("{tr}, {what}"),
                        points: f
                            .forms
                            .iter()
                            .filter(|c| c.transforms == tr)
                            .map(|c| {
                                let j = if free { &c.texture_free } else { &c.rebuilt };
                                (c.coefficients as f64, 100.0 * j.cells.mean.value)
                            })
                            .collect(),
                    });
                }
            }
            series.push(Series {
                name: "full table (binary16)".into(),
                points: vec![(f.full_coefficients as f64, 100.0 * f.full.cells.mean.value)],
            });
            for s in &f.shipped {
                series.push(Series {
                    name: format!("shipped, {}", s.path),
                    points: vec![(
                        f.full_coefficients as f64,
                        100.0 * s.shipped.cells.mean.value,
                    )],
                });
            }
            Panel {
                title: format!("{}: mean held-out error at the cells", f.table),
                x_label: "coefficients".into(),
                y_label: "mean relative L2 (%)".into(),
                series,
            }
        })
        .collect();
    // upper right: the small forms' curves fall to the lower left, where a legend hid them
    loglog_svg_legend(
        &panels,
        1200,
        480,
        plotters::prelude::SeriesLabelPosition::UpperRight,
    )
}

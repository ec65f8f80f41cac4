//! The deliverables' tables of results/performance.md (benches/deliverables.rs): every
//! generated shader through naga and the Khronos validators, and the prefilter tool on a
//! 2048² map next to the per-mip re-read a one-pass-per-mip tool does.

use super::criterion::{fmt_time, interval, Timed};
use crate::report::table::Table;

const SHADER_COLUMNS: [&str; 7] = [
    "naga parse + validate",
    "spv",
    "msl",
    "hlsl",
    "glsl",
    "spirv-val",
    "glslangValidator",
];

/// Module × step (criterion mean; "—" where not measured, e.g. a validator absent).
pub(super) fn shaders_table(timed: &[Timed]) -> String {
    let mut modules: Vec<&str> = timed
        .iter()
        .filter_map(|t| t.group.strip_prefix("shaders/"))
        .collect();
    modules.dedup();
    if modules.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## Shaders: translation and validation per module\n\nEach generated module with its compute harness (results/shaders.md): naga 30's WGSL front end with full validation, each back end on the validated module, and the external validators on the back end's output (process start and a temporary file included; most of glslangValidator's time is its start-up). Criterion mean per call with its 95 % confidence interval.\n\n");
    let mut table = Table::new(std::iter::once("module").chain(SHADER_COLUMNS));
    for m in modules {
        let cells = SHADER_COLUMNS.iter().map(|c| {
            timed
                .iter()
                .find(|t| t.group == format!("shaders/{m}") && t.function == *c)
                .map_or("—".to_string(), interval)
        });
        table.row(std::iter::once(m.to_string()).chain(cells));
    }
    md.push_str(&table.to_string());
    md
}

/// The prefilter tool at 2048².
pub(super) fn prefilter_table(timed: &[Timed]) -> String {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "prefilter").collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## prefilter: roughness mips of a 2048² normal map\n\nThe whole tool on an 8-bit 2048² PNG with one α (12 levels; goal < 1 s on 2 cores), its parts, and, for the complexity, the same statistics computed the way a one-pass-per-mip tool (Filament's roughness-prefilter) does: every level re-reads its 2^l × 2^l base block, O(N log N) against the pyramid's O(N).\n\n");
    let mut table = Table::new(["step", "time (95 % CI)"]);
    for t in rows {
        table.row([t.function.clone(), interval(t)]);
    }
    md.push_str(&table.to_string());
    md
}

/// Every shipped LTC table: what its study cost on this machine (`main_job::study_cost`),
/// its held-out error, and criterion's time per
/// pixel (bench `ltc-tables`: bilinear lookup of the binary16 entries + quad integral).
pub(super) fn ltc_tables_table(
    timed: &[Timed],
    results: &std::path::Path,
) -> crate::error::Result<String> {
    let mut md = String::from("\n## LTC tables: fit cost and per-pixel cost\n\nPer table: what its whole study cost on this machine (default preset: the main table and its variant, bilinear pass, binary16 storage, held-out judging, reports; not criterion): run alone in a sequential uncached `regen` where that profile is kept, with its own CPU seconds, else its wall clock in the last cold main job, where studies overlap; its held-out relative L2, and criterion's mean per pixel (95 % CI) for the lookup of the binary16 table at (α, cos θ) plus norm × the quad integral (rational edges, f64 on the CPU): every table has the same layout, so each lobe an area light shades with costs one more lookup and one more polygon integral.\n\n");
    let mut table = Table::new([
        "table",
        "study cost",
        "held-out rel. L2 mean / max",
        "per pixel (95 % CI)",
    ]);
    for kind in &crate::codegen::textures::TABLES {
        let Some(v) =
            crate::results::read_named::<crate::results::ltc::Summary>(results, kind.fit)?
        else {
            continue;
        };
        let study = if kind.fit.starts_with("ltc-sheen") {
            "ltc-sheen"
        } else if kind.fit.starts_with("ltc-diffuse") {
            "ltc-diffuse"
        } else {
            kind.fit
        };
        let fit = super::main_job::study_cost(study)
            .map_or("—".into(), |c| format!("{} ({study})", c.describe()));
        let h = &v.held_out.l2;
        let err = format!("{} / {}", h.mean.pct(2), h.max.pct(1));
        let px = timed
            .iter()
            .find(|t| {
                t.group == "ltc-tables" && t.function == format!("{}: 1024 pixels", kind.stem)
            })
            .map_or("—".to_string(), per_pixel);
        table.row([format!("{} ({})", kind.stem, kind.fit), fit, err, px]);
    }
    if let Some(v) = crate::results::read::<crate::results::ltc_aniso::Aniso>(results)? {
        let s = &v.summary;
        let px = timed
            .iter()
            .find(|t| t.group == "ltc-tables" && t.function == "ltc_ggx_aniso: 1024 pixels")
            .map_or("—".to_string(), per_pixel);
        table.row([
            "ltc_ggx_aniso (ltc-aniso; 4D, 12 fetches, between cells)".to_string(),
            format!(
                "{} for {} cells",
                super::main_job::study_cost("ltc-aniso").map_or("—".into(), |c| c.describe()),
                s.cells_fitted
            ),
            format!(
                "{} (s.e., {} random cases) / {:.1} %",
                s.between_table.mean.pct(2),
                s.between_table.count,
                100.0 * s.between_table.max
            ),
            px,
        ]);
    }
    md.push_str(&table.to_string());
    Ok(md)
}

/// A 1024-pixel bench's time per pixel with its interval.
fn per_pixel(t: &Timed) -> String {
    format!(
        "{} ({} – {})",
        fmt_time(t.mean_ns / 1024.0),
        fmt_time(t.lo_ns / 1024.0),
        fmt_time(t.hi_ns / 1024.0)
    )
}

/// Each render method's cost per pixel (criterion, one core, 64² of the example scene)
/// beside its error in results/render.md (relative MSE over the views of the default
/// render: best – worst).
pub(super) fn render_table(
    timed: &[Timed],
    results: &std::path::Path,
) -> crate::error::Result<String> {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "render").collect();
    if rows.is_empty() {
        return Ok(String::new());
    }
    let v: Option<crate::results::render::Render> = crate::results::read(results)?;
    let err = |scene: &str, key: &str| -> String {
        let Some(v) = &v else { return "—".into() };
        let r: Vec<f64> = v
            .renders
            .iter()
            .filter(|rd| rd.scene.name == scene)
            .flat_map(|rd| &rd.views)
            .flat_map(|view| &view.methods)
            .filter(|m| m.key == key)
            .map(|m| m.measures.rel_mse.value)
            .filter(|x| x.is_finite())
            .collect();
        if r.is_empty() {
            return "—".into();
        }
        let lo = r.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = r.iter().cloned().fold(0.0, f64::max);
        format!("{:.1} % – {:.1} %", 100.0 * lo, 100.0 * hi)
    };
    let mut md = String::from("\n## Render methods: cost per pixel beside their error\n\nCriterion's mean per pixel (95 % CI) on one core: the G-buffer over each example scene's whole 256² image, each method over its 64² centre pixels (`cargo bench --bench deliverables -- render`; the bench's CP models are built from the quick preset's P-NDF grid, 32² images, so their query cost is that of 32² images) beside the method's relative MSE against the truth over the views of results/render.md (best – worst view).\n\n");
    let mut table = Table::new([
        "scene: method",
        "per pixel (95 % CI)",
        "relative MSE (results/render.md)",
    ]);
    for t in rows {
        let Some((scene, rest)) = t.function.split_once(": ") else {
            continue;
        };
        let Some((key, count)) = rest.split_once(", ") else {
            continue;
        };
        let n: f64 = count.trim_end_matches(" pixels").parse().unwrap_or(1.0);
        let px = format!(
            "{} ({} – {})",
            fmt_time(t.mean_ns / n),
            fmt_time(t.lo_ns / n),
            fmt_time(t.hi_ns / n)
        );
        let e = if key == "G-buffer" {
            "—".into()
        } else {
            err(scene, key)
        };
        table.row([format!("{scene}: {key}"), px, e]);
    }
    md.push_str(&table.to_string());
    Ok(md)
}

/// The survey's representations: criterion's ns per lobe evaluation (f64, the shading
/// rule included) beside the parameters per texel and the mean L2 error of results/filters-survey.md.
pub(super) fn survey_table(
    timed: &[Timed],
    results: &std::path::Path,
) -> crate::error::Result<String> {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "survey").collect();
    if rows.is_empty() {
        return Ok(String::new());
    }
    // the rows' names, parameter counts and errors from results/fits/filters.json (the
    // survey's rows follow the filters' twelve)
    let v: Option<crate::results::filters::Filters> = crate::results::read(results)?;
    let first = crate::filters::registry::MAP.len();
    let row = |i: usize| -> Option<(String, String, String)> {
        let r = v.as_ref()?.survey.rows.get(first + i)?;
        let params = r.params.map_or("all texels".into(), |p| p.to_string());
        let err = r.ggx.l2.pct(1);
        Some((r.name.clone(), params, err))
    };
    let mut md = String::from("\n## Survey representations: cost per evaluation beside their error\n\nCriterion's mean per lobe evaluation (95 % CI, one core, f64: the reconstruction q̂(h) and the shared Eq 12 shading rule, `cargo bench --bench deliverables -- survey`) on one flakes footprint (8×8 texels, GGX α 0.05), next to the representation's parameters per texel and its mean relative L2 lobe error over the GGX cases of results/filters-survey.md. The plain isotropic GGX lobe (what every mean-normal rule shades) is the scale.\n\n");
    let mut table = Table::new([
        "representation",
        "params",
        "per evaluation (95 % CI)",
        "L2, GGX (results/filters-survey.md)",
    ]);
    for t in rows {
        let per = |x: f64| fmt_time(x / 1024.0);
        let time = format!("{} ({} – {})", per(t.mean_ns), per(t.lo_ns), per(t.hi_ns));
        let idx = t
            .function
            .strip_prefix("row ")
            .and_then(|s| s.split(':').next())
            .and_then(|s| s.parse::<usize>().ok());
        match idx.and_then(row) {
            Some((name, p, e)) => table.row([name, p, time, e]),
            None => table.row([
                t.function.trim_end_matches(": 1024 lobes").to_string(),
                "3".into(),
                time,
                "—".into(),
            ]),
        };
    }
    md.push_str(&table.to_string());
    Ok(md)
}

/// Visibility lookups: criterion's ns per lookup of each horizon and shadow method.
pub(super) fn visibility_table(timed: &[Timed]) -> String {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "visibility").collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## Visibility lookups: cost per lookup\n\nCriterion's mean per lookup (95 % CI, one core, f64) from the footprint's filtered parameters (`cargo bench --bench deliverables -- visibility`): the horizon forms from an 8×8 bumps footprint's stored moments, the shadow methods from a layered-scene footprint. Their errors are in results/visibility.md.\n\n");
    let mut table = Table::new(["method", "per lookup (95 % CI)"]);
    for t in rows {
        let per = |x: f64| fmt_time(x / 1024.0);
        table.row([
            t.function.trim_end_matches(", 1024 lookups").to_string(),
            format!("{} ({} – {})", per(t.mean_ns), per(t.lo_ns), per(t.hi_ns)),
        ]);
    }
    md.push_str(&table.to_string());
    md
}

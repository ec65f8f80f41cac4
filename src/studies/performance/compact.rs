//! The compact LTC tables' cost beside their error: the texture-free series at each degree
//! against the bilinear lookup of a table, per pixel, as SPIR-V instructions (naga's
//! output of the generated WGSL, each function counted at every call: the code is
//! loop-free) and as CPU time (bench `ltc-compact`: the f32 kernels of `kernels`), next to
//! the held-out lobe errors of results/fits/ltc-compact.json.

use super::criterion::{fmt_time, Timed};
use crate::error::Result;
use crate::report::table::Table;
use crate::results::ltc_compact::{Judged, LtcCompact};
use std::path::Path;

/// Instructions one pixel's lookup executes: `ndfb_ltc_lut_matrix` and
/// `ndfb_ltc_lut_weights` of results/wgsl/ltc_lut.wgsl (two filtered fetches and the uv of
/// (α, cos θ) each).
fn lookup_instructions(results: &Path) -> Result<usize> {
    let p = results.join("wgsl/ltc_lut.wgsl");
    let src = std::fs::read_to_string(&p).map_err(|e| crate::error::Error::Io {
        path: p.display().to_string(),
        msg: e.to_string(),
    })?;
    let v = crate::codegen::backends::executed_instructions(
        &src,
        "ltc_lut.wgsl",
        &["ndfb_ltc_lut_matrix", "ndfb_ltc_lut_weights"],
    )?;
    Ok(v.iter().sum())
}

/// Instructions one pixel's texture-free form executes: `ltc_compact_mat` and
/// `ltc_compact_mag` of the WGSL `codegen::compact` writes for this series.
fn series_instructions(c: &crate::ltc::compact::Compact, n: usize) -> Result<usize> {
    let src = crate::codegen::compact::render_wgsl(c, n, "bench-report");
    let v = crate::codegen::backends::executed_instructions(
        &src,
        "compact series",
        &["ltc_compact_mat", "ltc_compact_mag"],
    )?;
    Ok(v.iter().sum())
}

/// For a sheen family with a texture-free pick: what its generated shader executes per
/// pixel (`ltc_sheen_<key>_mat` + `ltc_sheen_<key>_norm` of results/wgsl/ltc_sheen.wgsl:
/// five channels, no Fresnel), beside the six-channel count the table shows at that degree.
fn sheen_shader(f: &crate::results::ltc_compact::CompactFamily) -> Result<Option<String>> {
    let (Some(fam), Some(tf)) = (
        crate::codegen::sheen::FAMILIES
            .iter()
            .find(|x| x.table == f.table),
        &f.texture_free,
    ) else {
        return Ok(None);
    };
    let q = f.forms.get(tf.form).ok_or_else(|| {
        crate::error::Error::InvalidArgument(format!(
            "results/fits/ltc-compact.json: {}'s texture-free pick names form {} of {}",
            f.table,
            tf.form,
            f.forms.len()
        ))
    })?;
    let src = crate::codegen::sheen::render_family(
        crate::codegen::sheen::Lang::Wgsl,
        fam,
        &tf.series,
        "bench-report",
    );
    let names = [
        format!("ltc_sheen_{}_mat", fam.key),
        format!("ltc_sheen_{}_norm", fam.key),
    ];
    let v = crate::codegen::backends::executed_instructions(
        &src,
        "sheen series",
        &[names[0].as_str(), names[1].as_str()],
    )?;
    Ok(Some(format!(
        "{}: its texture-free pick ({} p = {}) as the generated sheen shader runs it (`{}` + `{}`, results/wgsl/ltc_sheen.wgsl; five channels, the sheen has no Fresnel): {} SPIR-V instructions per pixel, against {} for the six-channel form above.",
        f.table,
        q.transforms,
        q.p,
        names[0],
        names[1],
        v.iter().sum::<usize>(),
        series_instructions(&tf.series, f.n)?
    )))
}

/// ns per pixel (4096-pixel batches) of one bench function on one backend.
fn per_pixel(timed: &[Timed], function: &str, backend: &str) -> Option<f64> {
    timed
        .iter()
        .find(|t| t.group == "ltc-compact" && t.function == function && t.param == backend)
        .map(|t| t.mean_ns / 4096.0)
}

fn pct(j: &Judged) -> String {
    format!("{} / {}", j.cells.mean.pct(2), j.squares.mean.pct(2))
}

/// The heading of the section.
pub(super) const HEAD: &str = "\n## Compact LTC tables: texture-free against the texture";

/// The section of results/performance.md and its plot (results/ltc-compact-cost.svg), or
/// nothing without the study's file or the bench.
pub(super) fn ltc_compact_table(
    set: &mut crate::io::Outputs,
    timed: &[Timed],
    results: &Path,
) -> Result<String> {
    let Some(file) = crate::results::read::<LtcCompact>(results)? else {
        return Ok(String::new());
    };
    if !timed.iter().any(|t| t.group == "ltc-compact") {
        return Ok(String::new());
    }
    let lookup = lookup_instructions(results)?;
    let mut md = String::from(HEAD);
    md.push_str("\n\nPer pixel, the six channels of the LTC table (M⁻¹'s a, b, c, d; norm; fresnel) at (α, cos θ): read bilinearly from a 64×64 binary16 table (two filtered fetches), or evaluated from the compact Chebyshev series (results/ltc-compact.md) in f32 with no texture. **SPIR-V**: the instructions a pixel executes in naga's SPIR-V of the generated WGSL (the lookup: `ndfb_ltc_lut_matrix` + `ndfb_ltc_lut_weights` of results/wgsl/ltc_lut.wgsl, each fetch one instruction; the series: `ltc_compact_mat` + `ltc_compact_mag` as results/wgsl/ltc_compact.wgsl writes them at that degree; both loop-free, every function counted at each call). **CPU**: criterion's mean per pixel over 4096 pixels for the f32 kernels (`kernels::ltc_compact_lookup`, `ltc_compact_series`; the series at each degree is the stored one resized, its cost depends on the degree alone): AVX2 (8 pixels at a time, gathers for the fetches), and the scalar form one pixel per call. **Error**: mean held-out relative L2 of the lobe at the judged cells / squares (results/ltc-compact.md, ± the mean of the bars there); for a degree, the most accurate texture-free form the study fitted at it.\n\n");
    let mut table = Table::new([
        "table",
        "form",
        "coefficients",
        "SPIR-V instructions",
        "CPU AVX2 (ns/pixel)",
        "CPU per pixel call (ns/pixel)",
        "error: cells / squares",
    ]);
    let mut panels = Vec::new();
    let mut verdicts = Vec::new();
    for f in &file.families {
        let name = f.table.trim_start_matches("ltc-");
        let cpu = |func: &str| {
            (
                per_pixel(timed, func, "avx2").map_or("—".into(), fmt_time),
                per_pixel(timed, func, "per-pixel").map_or("—".into(), fmt_time),
            )
        };
        let (la, lp) = cpu(&format!("{name} lookup"));
        table.row([
            f.table.clone(),
            "lookup: full table (binary16)".into(),
            f.full_coefficients.to_string(),
            lookup.to_string(),
            la.clone(),
            lp.clone(),
            pct(&f.full),
        ]);
        let mut lookup_pts = vec![(lookup as f64, 100.0 * f.full.cells.mean.value)];
        if let Some(k) = crate::results::ltc_compact::series_form(&f.forms, f.chosen) {
            let s = &f.forms[k];
            table.row([
                f.table.clone(),
                format!("lookup: compact rebuild ({}, p = {})", s.transforms, s.p),
                s.coefficients.to_string(),
                lookup.to_string(),
                la,
                lp,
                pct(&s.rebuilt),
            ]);
            lookup_pts.push((lookup as f64, 100.0 * s.rebuilt.cells.mean.value));
        }
        let mut degrees: Vec<usize> = f.forms.iter().map(|x| x.p).collect();
        degrees.sort();
        degrees.dedup();
        let mut free_pts = Vec::new();
        let mut verdict = None;
        for p in degrees {
            let Some(best) = f.forms.iter().filter(|x| x.p == p).min_by(|a, b| {
                a.texture_free
                    .cells
                    .mean
                    .value
                    .total_cmp(&b.texture_free.cells.mean.value)
            }) else {
                continue;
            };
            let count = series_instructions(&f.series.resized(p)?, f.n)?;
            let (a, pp) = cpu(&format!("{name} series p{p}"));
            table.row([
                f.table.clone(),
                format!("texture-free p = {p} ({})", best.transforms),
                best.coefficients.to_string(),
                count.to_string(),
                a,
                pp,
                pct(&best.texture_free),
            ]);
            free_pts.push((count as f64, 100.0 * best.texture_free.cells.mean.value));
            // the cheapest degree whose texture-free form beats the full table's lookup at
            // the cells and at the squares, beyond both bars
            let below = |a: &crate::ltc::lobe_error::Spread, b: &crate::ltc::lobe_error::Spread| {
                a.mean.value + a.mean.error < b.mean.value - b.mean.error
            };
            if verdict.is_none()
                && below(&best.texture_free.cells, &f.full.cells)
                && below(&best.texture_free.squares, &f.full.squares)
            {
                let ratio = |func: &str| match (
                    per_pixel(timed, func, "avx2"),
                    per_pixel(timed, &format!("{name} lookup"), "avx2"),
                ) {
                    (Some(a), Some(b)) => format!("{:.1}×", a / b),
                    _ => "—".into(),
                };
                verdict = Some(format!(
                    "{}: at p = {p}, the lowest degree where it is, the texture-free series is more accurate than the full table read as a texture, at the cells and at the squares ({} against {}), for {:.0}× the lookup's SPIR-V instructions and {} its AVX2 time.",
                    f.table,
                    pct(&best.texture_free),
                    pct(&f.full),
                    count as f64 / lookup as f64,
                    ratio(&format!("{name} series p{p}"))
                ));
            }
        }
        verdicts.push(verdict.unwrap_or_else(|| {
            format!(
                "{}: no texture-free form the study fitted is more accurate than the full table read as a texture at both the cells and the squares.",
                f.table
            )
        }));
        if let Some(v) = sheen_shader(f)? {
            verdicts.push(v);
        }
        panels.push(crate::report::plot::Panel {
            title: format!("{}: error against cost per pixel", f.table),
            x_label: "SPIR-V instructions per pixel".into(),
            y_label: "mean held-out relative L2 at the cells (%)".into(),
            series: vec![
                crate::report::plot::Series {
                    name: "texture-free series, p = 6 … 24".into(),
                    points: free_pts,
                },
                crate::report::plot::Series {
                    name: "lookup (full table; compact rebuild)".into(),
                    points: lookup_pts,
                },
            ],
        });
    }
    md.push_str(&table.to_string());
    let svg = crate::report::plot::loglog_svg(&panels, 1100, 480)?;
    set.put(&results.join("ltc-compact-cost.svg"), svg.as_bytes());
    md.push_str("\n![error against cost](ltc-compact-cost.svg)\n\nWhere each is the better trade. The lookup costs the same few instructions and two texture fetches whatever the table's accuracy; the series' cost grows as p² (the series takes r = √α and t = √(1 − cos θ): a caller starting from (α, cos θ) adds the two square roots the lookup's count already holds).\n\n");
    for v in verdicts {
        md.push_str(&format!("- {v}\n"));
    }
    md.push_str("\nSo per pixel the texture is the cheap form; the texture-free form pays where accuracy is worth thousands of instructions, or where a shader has no sampler or texture slot left. Where it is the texture's download or memory that is scarce, rebuild the texture at start-up (results/textures/three/ltc_compact.js, results/wgsl/ltc_compact_rebuild.wgsl): the series is paid once per texel, not per pixel.\n");
    Ok(md)
}

//! What storing the table in f32 or f16 costs, cell by cell, against the f64 table.

use crate::error::Result;
use crate::ltc::fit::{Cell, Table};

/// §5: what storing the table in f32 or f16 costs, cell by cell, against the f64 table
/// (relative L2 against the BRDF on the held-out sample sets; the f16 numbers are exactly
/// those of results/wgsl/ltc_table_f16.wgsl and src/generated/ltc_table.rs).
pub(super) fn section(main: &Table, n_samples: usize) -> Result<String> {
    use crate::codegen::table::rounded;
    use crate::ltc::compare::cell_error;
    let cells: Vec<&Cell> = main.cells.iter().flatten().collect();
    // [f64, f32, f16 to nearest, f16 as stored] relative L2, or None where the rounded
    // matrix is singular
    let errs: Vec<[Option<f64>; 4]> = crate::memo::map_items("storage precision", &cells, |c| {
        let full = [c.inv[0], c.inv[1], c.inv[2], c.inv[3], c.norm, c.fresnel];
        let e = |v: [f64; 6]| {
            cell_error(&[v[0], v[1], v[2], v[3]], v[4], c.alpha, c.theta, n_samples)
                .ok()
                .map(|x| x.0)
        };
        Ok([
            e(full),
            e(rounded(&full, false)),
            e(rounded(&full, true)),
            e(c.half),
        ])
    })?;
    let mut md = String::from("## Storage precision\n\nThe table goes through the code generator as Rust constants (src/generated/ltc_table.rs: f32, and binary16 pairs packed in u32), WGSL data (results/wgsl/ltc_table.wgsl: f32; results/wgsl/ltc_table_f16.wgsl: binary16 read with `unpack2x16float`) and the engine files of results/textures/ (f16: KTX2, DDS, raw; f32: raw and the ES module). Every f16 file holds the stored binary16 table (`table_f16`): per cell, the f16 neighbours of a, b, c, d (up to 4 ulps from nearest) that minimise the training relative L2, judged here on the held-out set. What each precision costs, per cell, as the change of the held-out relative L2 error against the BRDF from the f64 table:\n\n| storage | mean change | largest change | where (α, θ) | cells changed by > 1 point | singular cells |\n|---|---|---|---|---|---|\n");
    for (k, name) in [
        (1usize, "f32"),
        (2, "f16, each entry rounded to nearest"),
        (3, "f16 as stored (neighbours chosen by the training L2)"),
    ] {
        let (mut sum, mut cnt, mut worst, mut at, mut big, mut sing) =
            (0.0, 0usize, 0.0f64, (0.0, 0.0), 0usize, 0usize);
        for (c, e) in cells.iter().zip(&errs) {
            match (e[0], e[k]) {
                (Some(a), Some(b)) => {
                    let d = b - a;
                    sum += d;
                    cnt += 1;
                    if d.abs() > worst.abs() {
                        worst = d;
                        at = (c.alpha, c.theta.to_degrees());
                    }
                    if d.abs() > 0.01 {
                        big += 1;
                    }
                }
                (Some(_), None) => sing += 1,
                _ => {}
            }
        }
        md.push_str(&format!(
            "| {name} | {:+.2e} | {:+.2e} | ({:.2e}, {:.1}°) | {big} | {sing} |\n",
            sum / cnt.max(1) as f64,
            worst,
            at.0,
            at.1
        ));
    }
    // the f16 hazard: entries that leave the normal range
    let sub = main
        .cells
        .iter()
        .flatten()
        .filter(|c| c.inv.iter().any(|v| *v != 0.0 && v.abs() < 6.104e-5))
        .count();
    md.push_str(&format!("\nbinary16 keeps 11 significant bits down to 6.1e-5 and flushes below 6e-8: {sub} cells hold an entry below 6.1e-5 (the smallest-α rows near grazing, where a, b and d of M⁻¹ shrink like α²); there the f16 table loses most of those entries' digits. Changes are in absolute relative-L2 (0.01 = one percentage point).\n\n"));
    Ok(md)
}

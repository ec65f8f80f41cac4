//! What storing the table in f32 or f16 costs, cell by cell, against the f64 table:
//! `measure` computes, `section` formats.

use crate::integrate::{Figure, Quad};
use crate::ltc::fit::{Cell, Table};
use crate::ltc::lobe_error::Change;
use crate::report::table::Table as MdTable;

/// What one storage precision costs over the table.
pub(super) struct Row {
    name: &'static str,
    /// Mean change of the held-out relative L2 and the mean of its bars.
    mean: Figure<Quad>,
    /// The largest change with its bar, and where (α, θ°).
    worst: Figure<Quad>,
    at: (f64, f64),
    /// Cells changed by more than one point.
    big: usize,
    /// Cells whose stored determinant is not positive.
    mirrored: usize,
}

/// §5: what storing the table in f32 or f16 costs, cell by cell, against the f64 table
/// (the held-out relative L2 against the BRDF, `Cell::held`; the f16 numbers are exactly
/// those of results/wgsl/ltc_table_f16.wgsl and src/generated/ltc_table.rs).
pub(super) struct Precision {
    rows: Vec<Row>,
    /// Cells holding an entry below binary16's normal range.
    subnormal: usize,
}

pub(super) fn measure(main: &Table) -> Precision {
    use crate::ltc::lobe_error::Held;
    use crate::ltc::lobe_error::LobeError;
    let cells: Vec<&Cell> = main.cells.iter().flatten().collect();
    // [f64, f32, f16 to nearest, f16 as stored], None where singular (or not judged)
    let errs: Vec<[Option<LobeError>; 4]> = cells
        .iter()
        .map(|c| match c.held {
            Some(Held {
                f64: a,
                f32: b,
                f16_nearest: d,
                f16: e,
            }) => [a, b, d, e],
            None => [None; 4],
        })
        .collect();
    let mut rows = Vec::new();
    for (k, name) in [
        (1usize, "f32"),
        (2, "f16, each entry rounded to nearest"),
        (3, "f16 as stored (neighbours chosen by the training L2)"),
    ] {
        let change = Change::of(
            errs.iter()
                .map(|e| e[0].zip(e[k]).map(|(a, b)| (a.l2, b.l2))),
            0.01,
        );
        let at = change.argmax.map_or((0.0, 0.0), |i| {
            (cells[i].alpha, cells[i].theta.to_degrees())
        });
        let mirrored = cells
            .iter()
            .filter(|c| {
                let v = stored_entries(c, k);
                !(v[0] * v[3] - v[1] * v[2] > 0.0)
            })
            .count();
        rows.push(Row {
            name,
            mean: change.mean,
            worst: change.largest,
            at,
            big: change.big,
            mirrored,
        });
    }
    // the f16 hazard: entries that leave the normal range
    let subnormal = cells
        .iter()
        .filter(|c| c.inv.iter().any(|v| *v != 0.0 && v.abs() < 6.104e-5))
        .count();
    Precision { rows, subnormal }
}

pub(super) fn section(p: &Precision) -> String {
    let mut md = String::from("## Storage precision\n\nThe table goes through the code generator as Rust constants (src/generated/ltc_table.rs: f32, and binary16 pairs packed in u32), WGSL data (results/wgsl/ltc_table.wgsl: f32; results/wgsl/ltc_table_f16.wgsl: binary16 read with `unpack2x16float`) and the engine files of results/textures/ (f16: KTX2, DDS, raw; f32: raw and the ES module). Every f16 file holds the stored binary16 table (`table_f16`): per cell, the f16 neighbours of a, b, c, d (up to 4 ulps from nearest) that minimise the training relative L2, judged here by the held-out integrals. What each precision costs, per cell, as the change of the held-out relative L2 error against the BRDF from the f64 table; each change ± the sum of the two figures' error bars (an upper bound: both come from the same panels, so their errors are largely shared):\n\n");
    let mut t = MdTable::new([
        "storage",
        "mean change",
        "largest change",
        "where (α, θ)",
        "cells changed by > 1 point",
        "cells with a non-positive determinant (a mirrored lobe)",
    ]);
    for r in &p.rows {
        t.row([
            r.name.to_string(),
            r.mean.sci_signed(2, 1),
            r.worst.sci_signed(2, 1),
            format!("({:.2e}, {:.1}°)", r.at.0, r.at.1),
            r.big.to_string(),
            r.mirrored.to_string(),
        ]);
    }
    md.push_str(&t.to_string());
    let sub = p.subnormal;
    md.push_str(&format!("\nbinary16 keeps 11 significant bits down to 6.1e-5 and flushes below 6e-8: {sub} cells hold an entry below 6.1e-5 (the smallest-α rows near grazing, where a, b and d of M⁻¹ shrink like α²); there the f16 table loses most of those entries' digits. Rounded to nearest, such a cell's determinant ad − bc can change sign, which mirrors the lobe across the view plane; the stored binary16 table is searched only among neighbours that keep the determinant positive and b's sign (`ltc::storage`). Changes are in absolute relative-L2 (0.01 = one percentage point).\n\n"));
    md
}

/// (a, b, c, d) of a cell in storage precision k (0 f64, 1 f32, 2 f16 to nearest, 3 f16
/// as stored).
fn stored_entries(c: &Cell, k: usize) -> [f64; 4] {
    match k {
        0 => c.inv,
        1 => c.inv.map(|x| x as f32 as f64),
        2 => c.inv.map(|x| half::f16::from_f64(x).to_f64()),
        _ => [c.half[0], c.half[1], c.half[2], c.half[3]],
    }
}

//! results/tensor-wang.md: formats what [`super::compute`] measured.

use super::compute::Computed;
use crate::error::Result;
use crate::report::plot::{heatmap_svg, HeatPanel};
use crate::report::table::Table;
use crate::tensor::wang::seams::PairMean;
use crate::tensor::wang::TILES;

/// The bench ids of the query costs (benches/engines.rs, group `tensor-wang`).
pub const BENCHES: [(&str, &str); 6] = [
    (
        "tensor-wang/tiles-rank8/1",
        "tiles, rank 8, stride 4, footprint inside one tile",
    ),
    (
        "tensor-wang/tiles-rank8/2",
        "tiles, rank 8, stride 4, footprint across 2 tiles",
    ),
    (
        "tensor-wang/tiles-rank8/4",
        "tiles, rank 8, stride 4, footprint across 4 tiles",
    ),
    (
        "tensor-wang/explicit-brute-force/4",
        "explicit map, Eq 2 over the window's 15² texels (stride 4)",
    ),
    (
        "tensor-wang/tiles-rank8-stride8/4",
        "tiles, rank 8, stride 8, footprint across 4 tiles",
    ),
    (
        "tensor-wang/explicit-brute-force-stride8/4",
        "explicit map, Eq 2 over the window's 29² texels (stride 8)",
    ),
];

/// Fig 14: one footprint's image from the explicit map and summed from its tiles, and
/// their difference, over h_xy ∈ [−1, 1]².
pub(super) fn svg(c: &Computed) -> Result<String> {
    let f = &c.result.fig14;
    let n = f.res;
    let axis: Vec<f64> = (0..n)
        .map(|k| -1.0 + (k as f64 + 0.5) * 2.0 / n as f64)
        .collect();
    let grid =
        |v: &[f64]| -> Vec<Vec<f64>> { (0..n).map(|j| v[j * n..(j + 1) * n].to_vec()).collect() };
    let peak = f
        .explicit
        .iter()
        .cloned()
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let diff: Vec<f64> = f
        .explicit
        .iter()
        .zip(&f.tiles)
        .map(|(a, b)| (a - b).abs())
        .collect();
    let panel = |title: String, v: &[f64], range: (f64, f64), label: &str| HeatPanel {
        title,
        x: axis.clone(),
        y: axis.clone(),
        values: grid(v),
        log_range: range,
        x_label: "h_x".into(),
        y_label: "h_y".into(),
        log_axes: false,
        y_down: false,
        colour_label: label.into(),
    };
    let top = peak.log10();
    heatmap_svg(
        &[
            panel(
                "explicit map, brute force (Eq 2)".into(),
                &f.explicit,
                (top - 4.0, top),
                "log10 D",
            ),
            panel(
                format!("summed from its {} tiles", f.tiles_covered),
                &f.tiles,
                (top - 4.0, top),
                "log10 D",
            ),
            panel(
                "|difference| (grey: exactly equal)".into(),
                &diff,
                (top - 17.0, top - 13.0),
                "log10 |Δ D|",
            ),
        ],
        1500,
        470,
    )
}

fn pair_row(t: &mut Table, what: &str, m: &PairMean) {
    t.row([
        what.to_string(),
        m.pairs.to_string(),
        format!("{:.3e}", m.mean),
        String::new(),
    ]);
}

pub(super) fn markdown(c: &Computed) -> String {
    let (r, p) = (&c.result, &c.p);
    let mut md = format!(
        "# Seed 002 §5.5: constant storage by Wang tiles\n\nWritten by `{}` (preset {}) from `fits/tensor-wang.toml`, on request (the main job leaves it out). Model: `tensor::wang`. Example: {}; {TILES} tiles of {}² texels (the paper: 16 of 512² from a 2K² example), two colours per edge direction, every colouring a tile.\n\n",
        r.command,
        c.preset.name(),
        r.example_map,
        p.side
    );
    md.push_str(&format!(
        "## Seams\n\nEach edge colour owns a patch of the example; a tile is four triangles, one per edge, filled from its edge's patch centred on the edge (Cohen et al. 2003's diamonds), so the texels on both sides of every tile edge are consecutive texels of one patch. The seams lie inside the tiles, between triangles, and follow a minimum-error cut within {} texels of each diagonal. Mean squared difference of neighbouring normals |Δn|² over every adjacent pair of a {n}×{n}-tile map synthesised by the implicit colouring (exact sums over that map):\n\n",
        p.band,
        n = p.seam_cells
    ));
    let mut t = Table::new(["pairs", "count", "mean |Δn|²", "continuous"]);
    pair_row(&mut t, "the example's own neighbours", &r.example);
    for (name, s) in [
        ("minimum-error cut", &r.cut),
        ("straight diagonals", &r.straight),
    ] {
        pair_row(&mut t, &format!("{name}: inside a triangle"), &s.continuous);
        pair_row(&mut t, &format!("{name}: across a triangle seam"), &s.cuts);
        t.row([
            format!("{name}: across a tile edge"),
            s.edges.pairs.to_string(),
            format!("{:.3e}", s.edges.mean),
            format!("{} of {}", s.edges_continuous, s.edges.pairs),
        ]);
    }
    pair_row(
        &mut t,
        "the same tiles laid out at random (colours ignored): across a tile edge",
        &r.unmatched_edges,
    );
    md.push_str(&t.to_string());
    md.push_str("\nAcross a tile edge only the pairs at a tile's corner texels are not continuous; a layout that ignores the colours puts unrelated patches side by side at every edge.\n\n");
    md.push_str(&format!(
        "## Implicit = explicit (Fig 14)\n\nEach tile stores, per level, the NDF image term (Eq 2, σ_r = {}, {}² images over h_xy ∈ [−1, 1]²) of every footprint centre of the stride grid whose window reaches it, centres outside the tile included (Fig 12); a footprint anywhere on the unbounded map is the sum of the terms of the tiles it covers, which the per-vertex hash names with no index map (Fig 13). Checked against the brute-force P-NDF of the explicitly synthesised map at every grid centre whose window lies inside a {}²-tile region, for regions starting at cells {}:\n\n",
        p.sigma_r,
        p.res,
        p.region,
        r.regions
            .iter()
            .map(|(i, j)| format!("({i}, {j})"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    let mut t = Table::new([
        "stride",
        "σ_P (texels)",
        "footprints",
        "in 1 tile",
        "across 2",
        "across 3–4",
        "more",
        "largest |tiles − explicit| / peak",
    ]);
    for l in &r.levels {
        t.row([
            l.stride.to_string(),
            format!("{:.3}", l.sigma_p),
            l.footprints.to_string(),
            l.by_tiles[0].to_string(),
            l.by_tiles[1].to_string(),
            l.by_tiles[2].to_string(),
            l.by_tiles[3].to_string(),
            format!("{:.1e}", l.worst),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\nThe two differ by rounding only (the spec's tolerance: {:.0e} of the peak): the tiles' terms are splatted, the explicit image summed texel by texel, and the sum over tiles is a different order of the same additions. **Verdict on Fig 14's claim** (implicit and explicit synthesis give identical NDFs): {}. The footprint across the most tiles, as Fig 14 shows it:\n\n![explicit and tiled NDF images of one footprint and their difference](tensor-wang.svg)\n\n",
        c.spec.tolerance.max_rel,
        r.verdict
    ));
    md.push_str(&format!(
        "## Compressed tiles\n\nEach tile's images of each level CP-compressed in {}² blocks (CP-ALS, 2 seeded starts, ≤ {} sweeps, tolerance {:e}; seed 002 §4.2), each footprint's image rebuilt by one point query (Eq 6) per covered tile and pixel, against the same brute force over every footprint above (the L2 sums run over all their pixels; exact over that set):\n\n",
        p.t, p.iters, p.als_tolerance
    ));
    let mut t = Table::new([
        "R",
        "tiles: values stored",
        "tiles: ‖Δ‖ / ‖explicit‖",
        "tiles: largest |Δ| / peak",
        "explicit images compressed directly: values",
        "directly: ‖Δ‖ / ‖explicit‖",
    ]);
    for x in &r.ranks {
        t.row([
            x.rank.to_string(),
            x.values.to_string(),
            format!("{:.2} %", 100.0 * x.rel_l2),
            format!("{:.3}", x.worst),
            x.explicit_values.to_string(),
            format!("{:.2} %", 100.0 * x.explicit_rel_l2),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("
The last two columns compress the compared footprints' explicit images themselves, one CP per level and region (as the tensor study clusters a map), at the same rank: the error a rank costs either way. The tiles' images are partial (a tile's share of each footprint), centres outside the tile included, so they hold more, sparser images than the footprints they add up to.\n");
    md.push_str(&format!(
        "\n## Storage\n\nThe tiles hold {} normals and {} image values (all levels, uncompressed) whatever area they synthesise. An explicit map needs its images per footprint centre, (tiles × {})² / stride² centres per level:\n\n",
        r.tile_texels, r.tile_values, p.side
    ));
    let mut t = Table::new([
        "synthesised area",
        "texels",
        "explicit map's image values",
        "tiles' values / explicit",
    ]);
    for a in &r.areas {
        t.row([
            format!("{}² tiles", a.tiles),
            format!("{:.3e}", (a.tiles as f64 * p.side as f64).powi(2)),
            format!("{:.3e}", a.explicit),
            format!("{:.2e}", r.tile_values as f64 / a.explicit),
        ]);
    }
    md.push_str(&t.to_string());
    md.push_str("\n## Query cost\n\n");
    let rows: Vec<_> = BENCHES
        .iter()
        .filter_map(|(k, what)| c.costs.get(k).map(|ns| (what, ns)))
        .collect();
    if rows.is_empty() {
        md.push_str("No criterion figures in results/costs.json yet (`cargo bench --bench engines -- tensor-wang`, then `ndfbench bench-report`).\n");
    } else {
        md.push_str(&format!("One NDF value at one h per footprint (criterion means from results/costs.json; intervals in results/performance.md), tiles compressed at rank 8, the tile colours hashed per query:\n\n"));
        let mut t = Table::new(["query", "time"]);
        for (what, ns) in rows {
            t.row([what.to_string(), format!("{ns:.1} ns")]);
        }
        md.push_str(&t.to_string());
        md.push_str("\nThe tiled query costs one colour hash (three ChaCha8 blocks, one per vertex it reads) and one point query per covered tile, whatever the footprint's width; Eq 2 over the explicit map costs one term per texel of its window and grows with σ_P². Only the tiles keep the storage constant.\n");
    }
    md
}

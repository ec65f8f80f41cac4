//! Writing one render: the PNG grid (truth in the first column, each method's tile with
//! its ꟻLIP map under it, one pair of rows per view), the frame strip of a camera path,
//! the markdown tables (error ± s.e., ꟻLIP, flicker) and the typed JSON. No wall clock:
//! the cost of each method per pixel is criterion's, in results/performance.md.

use crate::error::Result;
use crate::render::measure::{Measured, Scored};
use crate::render::picture::{colour_bar, labelled_grid, Rgb};
use crate::render::Render;
use crate::report::table::Table;
use crate::results::render::{FlickerRun, MethodRun, SceneRun, ViewRun};
use std::path::Path;

/// Pixels of a grid tile's side (centre crop of the full image).
pub const TILE: usize = 96;

/// Which views the grid shows: four frames of a path, else every other scale (the
/// tables list every view).
fn shown(r: &Render) -> Vec<usize> {
    let n = r.views.len();
    let mut v = if r.scene.frames() > 1 {
        vec![0, n / 3, 2 * n / 3, n - 1]
    } else {
        (0..n).step_by(2).collect()
    };
    v.dedup();
    v
}

/// Methods × views: the relative MSE ± s.e. and ꟻLIP of every view at a glance.
fn summary(r: &Render, m: &Measured) -> String {
    let views: Vec<usize> = if r.scene.frames() > 1 {
        shown(r)
    } else {
        (0..r.views.len()).collect()
    };
    let mut t = Table::new(
        std::iter::once("method".to_string()).chain(views.iter().map(|&k| view_name(r, k))),
    );
    for (i, mi) in r.views[0].methods.iter().enumerate() {
        t.row(
            std::iter::once(mi.label.clone()).chain(views.iter().map(|&k| {
                let s = &m.views[k][i].m;
                format!("{} · ꟻLIP {:.3}", s.rel_mse.pct(2), s.flip.value)
            })),
        );
    }
    t.to_string()
}

fn view_name(r: &Render, k: usize) -> String {
    let v = &r.views[k];
    if r.scene.frames() > 1 {
        format!("frame {}", v.frame)
    } else {
        format!("scale ×{}", v.scale)
    }
}

/// The grid: per shown view a row of images (truth, methods) and a row of ꟻLIP maps
/// (the colour bar under the truth), the methods named above their columns and the views
/// to the left of their rows.
pub fn grid_png(r: &Render, m: &Measured, tile: usize) -> Result<Rgb> {
    let exp = r.scene.render.exposure;
    let mut rows = Vec::new();
    let mut names = Vec::new();
    for k in shown(r) {
        let v = &r.views[k];
        let t: Vec<f64> = v.truth.iter().map(|p| p.value).collect();
        let mut imgs = vec![Rgb::from_linear(&t, r.width, r.height, exp).crop(tile, tile)];
        let mut errs = vec![colour_bar(tile, tile / 8)];
        for (mi, s) in v.methods.iter().zip(&m.views[k]) {
            let p: Vec<f64> = mi.pixels.iter().map(|&x| x as f64).collect();
            imgs.push(Rgb::from_linear(&p, r.width, r.height, exp).crop(tile, tile));
            errs.push(Rgb::magma(&s.flip_map, r.width, r.height).crop(tile, tile));
        }
        rows.push(imgs);
        rows.push(errs);
        names.push(view_name(r, k));
        names.push(format!("{}: ꟻLIP 0 → 1", view_name(r, k)));
    }
    let cols: Vec<String> = std::iter::once("truth".to_string())
        .chain(r.views[0].methods.iter().map(|mi| mi.label.clone()))
        .collect();
    labelled_grid(&rows, 4, &cols, &names, 6, tile)
}

/// A strip of consecutive frames (rows: truth, then each method, named to their left;
/// columns named by frame) of a path, cropped around the image centre.
pub fn strip_png(r: &Render, frames: usize, tile: usize) -> Result<Rgb> {
    let exp = r.scene.render.exposure;
    let n = r.views.len().min(frames);
    let start = (r.views.len() - n) / 2;
    let mut rows = Vec::new();
    let truth_row: Vec<Rgb> = (start..start + n)
        .map(|k| {
            let t: Vec<f64> = r.views[k].truth.iter().map(|p| p.value).collect();
            Rgb::from_linear(&t, r.width, r.height, exp).crop(tile, tile)
        })
        .collect();
    rows.push(truth_row);
    for i in 0..r.views[0].methods.len() {
        rows.push(
            (start..start + n)
                .map(|k| {
                    let p: Vec<f64> = r.views[k].methods[i]
                        .pixels
                        .iter()
                        .map(|&x| x as f64)
                        .collect();
                    Rgb::from_linear(&p, r.width, r.height, exp).crop(tile, tile)
                })
                .collect(),
        );
    }
    let cols: Vec<String> = (start..start + n)
        .map(|k| format!("frame {}", r.views[k].frame))
        .collect();
    let names: Vec<String> = std::iter::once("truth".to_string())
        .chain(r.views[0].methods.iter().map(|mi| mi.label.clone()))
        .collect();
    labelled_grid(&rows, 2, &cols, &names, 2, 3 * tile)
}

fn row(s: &Scored) -> [String; 4] {
    [
        s.label.to_string(),
        s.m.mse.sci(3, 1),
        s.m.rel_mse.pct(2),
        s.m.flip.fixed(4),
    ]
}

/// The markdown of one render (tables per view, flicker), image links relative to the
/// report at `rel`.
pub fn markdown(r: &Render, m: &Measured, rel: &str) -> String {
    let sc = &r.scene;
    let draws = sc.render.truth_draws.map_or(String::new(), |m| {
        format!("; footprints of more than {m} texels draw {m} per replicate in proportion to their overlap")
    });
    let mut md = format!(
        "{}. {}×{} pixels, {} truth samples per pixel (two independent replicates{draws}), tone map: exposure {} → Reinhard → sRGB.\n\n![grid: truth in the first column, each method's ꟻLIP map under it (magma, 0 → 1, the bar under the truth)]({rel}/{}-grid.png)\n\n",
        sc.description, r.width, r.height, sc.render.truth_samples, sc.render.exposure, sc.name
    );
    if sc.frames() > 1 {
        md.push_str(&format!(
            "![frames {}–{} of the dolly (rows: truth, then the methods in table order)]({rel}/{}-strip.png)\n\n",
            (r.views.len() - r.views.len().min(8)) / 2,
            (r.views.len() - r.views.len().min(8)) / 2 + r.views.len().min(8) - 1,
            sc.name
        ));
    }
    for note in &r.notes {
        md.push_str(&format!("- {note}\n"));
    }
    md.push_str(&format!(
        "\nRelative MSE Σ(m − t)²/Σt² per view, each pixel's (m − t)² and t² estimated without bias from the truth's two replicates r₁, r₂ as (m − r₁)(m − r₂) and r₁r₂, ± the standard error the truth's noise leaves (with the ratio's bias bound); and the mean ꟻLIP against the truth image as rendered (tables per view below):\n\n{}",
        summary(r, m)
    ));
    let every: Vec<usize> = if r.scene.frames() > 1 {
        shown(r)
    } else {
        (0..r.views.len()).collect()
    };
    for k in every {
        let v = &r.views[k];
        let noise = m.views[k].first().map_or(0.0, |s| s.m.truth_noise);
        let on = v.truth.iter().filter(|p| p.covered);
        let count = on.clone().count().max(1) as f64;
        let mean_t = on.map(|p| p.value).sum::<f64>() / count;
        md.push_str(&format!(
            "\n### {}: {} — mean radiance {mean_t:.3e}, truth noise floor √mean(s.e.²) = {noise:.2e}, removed from every method’s MSE ({} covered pixels)\n\n",
            sc.name,
            view_name(r, k),
            m.views[k].first().map_or(0, |s| s.m.pixels)
        ));
        let mut t = Table::new(["method", "MSE ± s.e.", "relative MSE ± s.e.", "ꟻLIP ± s.e."]);
        for s in &m.views[k] {
            t.row(row(s));
        }
        md.push_str(&t.to_string());
    }
    if let Some(tc) = &m.truth_change {
        md.push_str(&format!(
            "\n### {}: flicker over {} frames — the truth's own mean squared Δ = {} (Δ of the displayed value between frames; squared changes and differences from the truth's two independent replicates, Δt_a·Δt_b and (Δm − Δt_a)(Δm − Δt_b), so the truth's noise does not bias them; ± s.e. over frame pairs)\n\n",
            sc.name,
            r.views.len(),
            tc.sci(3, 1)
        ));
        let mut t = Table::new([
            "method",
            "mean |Δ|",
            "mean Δ², excess over the truth",
            "temporal MSE (Δm − Δt)²",
        ]);
        for (_, label, f) in &m.flicker {
            t.row([
                label.to_string(),
                f.change.sci(3, 1),
                f.excess.sci_signed(3, 1),
                f.temporal_mse.sci(3, 1),
            ]);
        }
        md.push_str(&t.to_string());
    }
    md
}

/// One render's measures as the result file holds them.
pub fn json(r: &Render, m: &Measured) -> SceneRun {
    SceneRun {
        scene: r.scene.clone(),
        views: r
            .views
            .iter()
            .zip(&m.views)
            .map(|(v, s)| ViewRun {
                scale: v.scale,
                frame: v.frame,
                methods: s
                    .iter()
                    .map(|x| MethodRun {
                        key: x.key.clone(),
                        label: x.label.clone(),
                        measures: x.m,
                    })
                    .collect(),
            })
            .collect(),
        flicker: m
            .flicker
            .iter()
            .map(|(k, l, f)| FlickerRun {
                key: k.clone(),
                label: l.clone(),
                flicker: *f,
            })
            .collect(),
        truth_change: m.truth_change,
        notes: r.notes.clone(),
    }
}

/// Add a render's pictures under `dir` to `set` (grid, and strip for a path); returns
/// their paths.
pub fn put_pictures(
    set: &mut crate::io::Outputs,
    dir: &Path,
    r: &Render,
    m: &Measured,
    tile: usize,
) -> Result<Vec<std::path::PathBuf>> {
    let mut out = Vec::new();
    let g = dir.join(format!("{}-grid.png", r.scene.name));
    set.put(&g, grid_png(r, m, tile)?.png()?);
    out.push(g);
    if r.scene.frames() > 1 {
        let s = dir.join(format!("{}-strip.png", r.scene.name));
        set.put(&s, strip_png(r, 8, tile / 2)?.png()?);
        out.push(s);
    }
    Ok(out)
}

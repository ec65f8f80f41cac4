//! results/engines.md and results/engines.svg from an [`EnginesResult`]: the tables,
//! and a labelled figure (truth, both tables' images, their error maps, with a colour bar)
//! of a few scenes. Formats only.

use super::compute::{EngineResult, EnginesResult, Errors, PathResult, SceneResult};
use super::summary::{PathSummary, Summary};
use crate::error::Result;
use crate::render::picture::Rgb;
use crate::report::table::Table;

fn cell(e: &Errors) -> String {
    format!("{} (mean {})", e.rel_rmse.pct(2), e.mean_rel.pct(1))
}

/// The markdown report.
pub fn markdown(r: &EnginesResult, sum: &Summary, command: &str) -> String {
    let mut md = format!(
        "# LTC tables in the engines, against the truth\n\nWritten by `{command}`. Each engine rendered the scenes of engines/three/scenes.json ({}×{} pixels each: a metallic white GGX plane, F0 = 1, under one rectangular light of unit radiance, an orthographic camera, a linear float render target, no tone mapping) twice (three.js a third time where the compact drop-in's run is given): with the LTC table it ships, and with ours put in the way a user would.\n\n- **three.js** (engines/three, headless Chromium with SwiftShader, WebGL2): the page's import map sends `RectAreaLightTexturesLib.js` to ours (results/textures/three/RectAreaLightTexturesLib.js); where a third run is given, the **compact** table, to the compact drop-in (results/textures/three/RectAreaLightTexturesLib.compact.js), whose `init()` rebuilds the four textures from the series of results/fits/ltc-compact.json (results/ltc-compact.md) in f32 and as their nearest binary16. Each run renders with WebGLRenderer the float path (LTC_FLOAT textures) and the half-float path (LTC_HALF textures, as on a device without OES_texture_float_linear), and with WebGPURenderer (WebGPU on SwiftShader, where Chromium offers an adapter; ours through `RectAreaLightNode.setLTC` and the import map's entry for the bare specifier) the `webgpu-float` or `webgpu-half` path, as three binds them.\n- **Bevy** (engines/bevy-check, headless wgpu): its embedded `ltc.ktx2`, and ours (results/textures/ltc_ggx_zstd.ktx2) through the `AreaLightLuts` resource; one path, its RGBA16F texture array.\n\nEvery covered pixel is judged against the truth: the exact GGX BRDF (height-correlated Smith G2) integrated over the light by adaptive cubature, each pixel's value ± its error bar (largest relative bar over all pixels: {:.1e}).\n\nEach cell: relative RMSE √(Σ(x − truth)²/Σ truth²) (and in parentheses the mean relative error (x − truth)/truth over the pixels brighter than 1 % of the scene's peak), each ± what the truth's error bars allow. The engine's error splits into the **table's share** (the table's lookup with the exact edge integral, clipped in the LTC's space, against the truth) and the **shader's share** (the engine's image against that value: the engine's rational fit of θ/sin θ, its horizon handling, f16 filtering, f32 arithmetic).\n\n",
        r.width,
        r.height,
        sum.truth_bar
    );
    for (e, paths) in r.engines.iter().zip(&sum.paths) {
        engine_section(&mut md, e, paths);
    }
    godot_section(&mut md, r, sum);
    md.push_str("![scenes](engines.svg)\n\nThe figure: for four scenes and each engine, the truth, the engine with its shipped table and with ours (its first path, the same exposure per row), and their relative errors |engine − truth|/truth on the colour bar's scale (0 to 25 %; pixels darker than 10⁻³ of the peak are black). Rows are labelled with the engine and the scene (roughness, view angle), columns with what they show.\n");
    md
}

fn godot_section(md: &mut String, r: &EnginesResult, sum: &Summary) {
    let Some((formulas, share)) = sum.godot_means else {
        return;
    };
    md.push_str("## Godot 4 (formulas in f64; not rendered)\n\nNo Godot binary runs here, and Godot's own LTC files could not be fetched (its repository is over this machine's fetch limit), so Godot is judged by its shader's formulas transcribed in f64 (`engines::godot`, read from area_lights_inc.glsl): its bilinear lookup of our `results/textures/godot/ltc_lut{1,2}.dds` (f32, its θ-linear view axis through `acos_approx`), its matrix form, horizon clip and Hill's edge fit, at the first engine's pixel points. **Formulas**: that value against the truth; **table's share**: the same texels with the exact edge integral against the truth.\n\n");
    let mut t = Table::new(["scene", "formulas", "table's share"]);
    for s in &r.godot {
        t.row([s.name.clone(), cell(&s.formulas), cell(&s.table_share)]);
    }
    md.push_str(&t.to_string());
    md.push_str(&format!(
        "\nMean relative RMSE over the scenes (± the mean of their bars): formulas {}, table's share {}.\n\n",
        formulas.pct(2),
        share.pct(2)
    ));
}

fn engine_section(md: &mut String, e: &EngineResult, sums: &[PathSummary]) {
    let paths = &e.paths;
    md.push_str(&format!(
        "## {} ({}, on {})\n\n### The engine against the truth\n\n",
        e.engine.name(),
        e.version,
        e.adapter
    ));
    let mut t = Table::new(
        ["scene".to_string(), "pixels".to_string()]
            .into_iter()
            .chain(
                paths
                    .iter()
                    .flat_map(|p| e.tables.iter().map(move |tb| format!("{tb}, {p}"))),
            ),
    );
    for s in &e.scenes {
        t.row(
            [s.name.clone(), s.pixels.to_string()]
                .into_iter()
                .chain(paths.iter().flat_map(|p| {
                    e.tables.iter().map(move |tb| {
                        EngineResult::find(s, tb, p).map_or("—".into(), |x| cell(&x.engine))
                    })
                })),
        );
    }
    md.push_str(&t.to_string());
    let p0 = paths[0];
    md.push_str(&format!("\n### Where the error comes from ({p0} path)\n\n"));
    let mut t = Table::new(
        std::iter::once("scene".to_string()).chain(e.tables.iter().flat_map(|tb| {
            [
                format!("{tb}: table's share"),
                format!("{tb}: shader's share"),
            ]
        })),
    );
    for s in &e.scenes {
        let c = |t: &str, f: &dyn Fn(&PathResult) -> String| {
            EngineResult::find(s, t, p0).map_or("—".into(), |x| f(&x))
        };
        t.row(
            std::iter::once(s.name.clone()).chain(e.tables.iter().flat_map(|tb| {
                [
                    c(tb, &|x| cell(&x.table_share)),
                    c(tb, &|x| cell(&x.shader_share)),
                ]
            })),
        );
    }
    md.push_str(&t.to_string());
    for p in sums {
        let worse: Vec<String> = p
            .worse
            .iter()
            .map(|w| {
                let cause = if w.table_is_cause() {
                    "the table: its own share is larger"
                } else {
                    "the engine's shader: the table's own share is smaller"
                };
                format!(
                    "{} ({} against {}; tables' shares {} against {}: {cause})",
                    w.scene,
                    w.ours.pct(2),
                    w.shipped.pct(2),
                    w.ours_table.pct(2),
                    w.shipped_table.pct(2)
                )
            })
            .collect();
        md.push_str(&format!(
            "\nOn the {} path, ours renders closer to the truth (relative RMSE, beyond both error bars) in {} of {} scenes and further from it in {}{}. Mean relative RMSE over the scenes (± the mean of their bars): shipped {}, ours {}; the tables' own share: shipped {}, ours {}; the engine's formulas in f64 against its image (f32 arithmetic, filtering): at most {:.2e}.\n",
            p.path,
            p.better.len(),
            p.scenes,
            worse.len(),
            if worse.is_empty() { String::new() } else { format!(": {}", worse.join("; ")) },
            p.shipped_mean.pct(2),
            p.ours_mean.pct(2),
            p.shipped_table_mean.pct(2),
            p.ours_table_mean.pct(2),
            p.gpu_max
        ));
        for o in &p.others {
            md.push_str(&format!(
                "The {} table on the {} path: mean relative RMSE {}, its own share {}; closer to the truth than the shipped table in {} of {} scenes, further in {}{}.\n",
                o.table,
                p.path,
                o.mean.pct(2),
                o.table_mean.pct(2),
                o.better_than_shipped.len(),
                p.scenes,
                o.worse_than_shipped.len(),
                if o.worse_than_shipped.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", o.worse_than_shipped.join(", "))
                }
            ));
        }
    }
    md.push('\n');
}

fn b64_png(img: &Rgb) -> Result<String> {
    use base64::Engine;
    Ok(base64::engine::general_purpose::STANDARD.encode(img.png()?))
}

/// The labelled figure: rows = scenes, columns = truth, shipped, ours, |shipped − truth|,
/// |ours − truth|; PNG tiles (flipped to image order) in an SVG with text labels.
pub fn figure(r: &EnginesResult, picks: &[&str]) -> Result<String> {
    let (w, h) = (r.width, r.height);
    let scale = 6usize;
    let (tw, th) = (w * scale, h * scale);
    let (left, top, gap) = (190usize, 40usize, 10usize);
    let cols = [
        "truth",
        "engine + shipped table",
        "engine + ours",
        "|shipped − truth|/truth",
        "|ours − truth|/truth",
    ];
    let rows: Vec<(&EngineResult, &SceneResult)> = picks
        .iter()
        .flat_map(|p| {
            r.engines
                .iter()
                .filter_map(move |e| e.scenes.iter().find(|s| s.name == *p).map(|s| (e, s)))
        })
        .collect();
    let width = left + cols.len() * (tw + gap) + 20;
    let height = top + rows.len() * (th + gap) + 80;
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"13\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for (c, name) in cols.iter().enumerate() {
        svg.push_str(&format!(
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{name}</text>\n",
            left + c * (tw + gap) + tw / 2,
            top - 12
        ));
    }
    // image rows come bottom-up from the GL read-back
    let flip =
        |v: &[f64]| -> Vec<f64> { (0..w * h).map(|k| v[(h - 1 - k / w) * w + k % w]).collect() };
    for (ri, (e, s)) in rows.iter().enumerate() {
        let get = |name: &str| s.images.iter().find(|x| x.0 == name).map(|x| flip(&x.1));
        let p0 = e.engine.paths()[0];
        let (Some(truth), Some(sh), Some(ou)) = (
            get("truth"),
            get(&format!("shipped ({p0})")),
            get(&format!("ours ({p0})")),
        ) else {
            continue;
        };
        let peak = truth.iter().cloned().fold(0.0, f64::max).max(1e-300);
        let exposure = 1.0 / peak;
        let err = |x: &[f64]| -> Vec<f32> {
            x.iter()
                .zip(&truth)
                .map(|(a, t)| {
                    if *t > 1e-3 * peak {
                        ((a - t).abs() / t / 0.25) as f32
                    } else {
                        0.0
                    }
                })
                .collect()
        };
        let tiles = [
            Rgb::from_linear(&truth, w, h, exposure),
            Rgb::from_linear(&sh, w, h, exposure),
            Rgb::from_linear(&ou, w, h, exposure),
            Rgb::magma(&err(&sh), w, h),
            Rgb::magma(&err(&ou), w, h),
        ];
        let y = top + ri * (th + gap);
        svg.push_str(&format!(
            "<text x=\"10\" y=\"{}\">{} ({p0})</text>\n<text x=\"10\" y=\"{}\">{}</text>\n<text x=\"10\" y=\"{}\" fill=\"#555\">r = {}, view {}°</text>\n",
            y + th / 2 - 24,
            e.engine.name(),
            y + th / 2 - 6,
            s.name,
            y + th / 2 + 12,
            s.roughness,
            s.view_deg
        ));
        for (c, t) in tiles.iter().enumerate() {
            svg.push_str(&format!(
                "<image x=\"{}\" y=\"{y}\" width=\"{tw}\" height=\"{th}\" style=\"image-rendering:pixelated\" href=\"data:image/png;base64,{}\"/>\n",
                left + c * (tw + gap),
                b64_png(t)?
            ));
        }
    }
    // the colour bar of the error columns
    let bar = crate::render::picture::colour_bar(2 * tw + gap, 14);
    let by = top + rows.len() * (th + gap) + 8;
    let bx = left + 3 * (tw + gap);
    svg.push_str(&format!(
        "<image x=\"{bx}\" y=\"{by}\" width=\"{}\" height=\"14\" href=\"data:image/png;base64,{}\"/>\n<text x=\"{bx}\" y=\"{}\">0 %</text>\n<text x=\"{}\" y=\"{}\" text-anchor=\"end\">25 % relative error</text>\n<text x=\"{left}\" y=\"{}\" fill=\"#555\">tone-mapped, exposure 1/peak of the row's truth</text>\n",
        2 * tw + gap,
        b64_png(&bar)?,
        by + 30,
        bx + 2 * tw + gap,
        by + 30,
        by + 30
    ));
    svg.push_str("</svg>\n");
    Ok(svg)
}

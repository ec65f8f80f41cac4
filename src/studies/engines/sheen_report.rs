//! The sheen check's report (results/engines-sheen.{md,json}) and the step that reads the
//! harness's run, judges it and publishes it.

use super::sheen::{
    judge, SheenErrors, SheenResult, SheenRun, SheenScene, TABLE, THREE_MIN_SHEEN_ROUGHNESS,
};
use crate::engines::EngineScenes;
use crate::error::{Error, Result};
use crate::integrate::{Figure, Quad};
use crate::report::table::{Align, Table};

/// The mean of per-scene figures, within the mean of their bars.
pub fn mean_of(v: &[Figure<Quad>]) -> Figure<Quad> {
    Figure::<Quad>::mean_bounded(v)
}

/// Scenes where `a` exceeds `b` beyond both bars.
pub fn worse_count(a: &[Figure<Quad>], b: &[Figure<Quad>]) -> usize {
    a.iter()
        .zip(b)
        .filter(|(a, b)| a.value > b.value + a.error + b.error)
        .count()
}

/// Per scene, the RMS error over the albedo of one column.
pub fn over_albedo(r: &SheenResult, f: fn(&SheenScene) -> &SheenErrors) -> Vec<Figure<Quad>> {
    r.scenes.iter().map(|s| f(s).rms_over_albedo).collect()
}

/// The report: what is judged and how, then one section per run.
pub fn markdown(checks: &[SheenResult], command: &str) -> String {
    let Some(first) = checks.first() else {
        return String::new();
    };
    let r = first;
    let mut md = format!(
        "# Sheen under RectAreaLight in three.js: the texture-free recipe against the truth\n\nWritten by `{command}`.\n\nthree.js r187 (WebGLRenderer in headless Chromium, {}) renders each scene file below ({}×{} pixels a scene) with a MeshPhysicalMaterial that is sheen alone: a black dielectric base with specularIntensity 0 under a white sheen (sheen 1) whose sheenRoughness is the scene's roughness (three clamps it to ≥ {THREE_MIN_SHEEN_ROUGHNESS}). Once as three is, and once after `RectAreaLightSheen.init()` (results/textures/three/RectAreaLightSheen.js), which adds the Charlie sheen LTC with Neubelt's visibility — three's own BRDF_Sheen — to RE_Direct_RectArea_Physical, its M⁻¹ and norm evaluated per pixel from the {TABLE} table's texture-free series ({}; results/ltc-compact.md): no texture, no sampler.\n\nThe truth per pixel is ∫_P f(l) dω over the light (unit radiance), f the Charlie sheen BRDF with Neubelt's visibility 1/(4(l_z + v_z − l_z v_z)) times the cosine (without three's half-precision clamps), by adaptive cubature to 1e-5 relative (± its bar). A sheen of small roughness reflects only where the half-vector is near grazing (a grazing view, a light low on the horizon); where a scene's light sits elsewhere its truth is orders of magnitude below the sheen's albedo, and an error relative to the truth says nothing about the picture (results/engines-sheen.json holds it). Each column is therefore the RMS error over the scene's covered pixels divided by the lobe's directional albedo at the scene's view — the error's share of what the sheen can reflect at all, as results/ltc-sheen.md's polygon lights report it — ± the half-width the truth's bars allow (printed to 0.001 points; results/engines-sheen.json holds every digit):\n\n- **three as shipped**: three's render without the recipe;\n- **recipe (three.js)**: three's render with the recipe;\n- **series, exact**: the recipe's f32 entries with the exact edge integral of the LTC (the series' own share);\n- **sampled table, exact**: our {TABLE} table as a texture would hold it (binary16, bilinear) with the exact edge integral — what a second texture pair would buy;\n- **GPU share**: the recipe's render against three's LTC_Evaluate in f64 with the series' entries, relative RMSE (f32 arithmetic, the GPU's `exp`).\n\n",
        r.adapter,
        r.width,
        r.height,
        r.series
    );
    for r in checks {
        md.push_str(&section(r));
    }
    md
}

/// One run's section: per scene and the means.
fn section(r: &SheenResult) -> String {
    let (shipped, recipe, series, table) = (
        over_albedo(r, |s| &s.shipped),
        over_albedo(r, |s| &s.recipe),
        over_albedo(r, |s| &s.series_share),
        over_albedo(r, |s| &s.table_share),
    );
    let gpu: Vec<Figure<Quad>> = r.scenes.iter().map(|s| s.gpu_share.rel_rmse).collect();
    let mut md = format!("## {} ({} scenes)\n\n", r.scenes_file, r.scenes.len());
    let mut t = Table::new([
        "scene",
        "sheenRoughness",
        "view",
        "albedo",
        "truth's peak / albedo",
        "three as shipped",
        "recipe (three.js)",
        "series, exact",
        "sampled table, exact",
        "GPU share",
    ]);
    for c in 1..10 {
        t = t.align(c, Align::Right);
    }
    for (k, s) in r.scenes.iter().enumerate() {
        t.row([
            s.name.clone(),
            s.roughness.to_string(),
            format!("{}°", s.view_deg),
            format!("{:.3e} ± {:.0e}", s.albedo, s.albedo_error),
            format!("{:.2e}", s.truth_peak / s.albedo),
            shipped[k].pct_fixed(3),
            recipe[k].pct_fixed(3),
            series[k].pct_fixed(3),
            table[k].pct_fixed(3),
            gpu[k].pct_fixed(3),
        ]);
    }
    t.row([
        "**mean**".to_string(),
        String::new(),
        String::new(),
        String::new(),
        String::new(),
        mean_of(&shipped).pct_fixed(3),
        mean_of(&recipe).pct_fixed(3),
        mean_of(&series).pct_fixed(3),
        mean_of(&table).pct_fixed(3),
        mean_of(&gpu).pct_fixed(3),
    ]);
    md.push_str(&format!("{t}\n"));
    let wg: Vec<&super::sheen::WebGpuSheen> =
        r.scenes.iter().filter_map(|s| s.webgpu.as_ref()).collect();
    if wg.len() == r.scenes.len() && !wg.is_empty() {
        let rec: Vec<Figure<Quad>> = wg.iter().map(|w| w.recipe.rms_over_albedo).collect();
        let share = wg
            .iter()
            .map(|w| w.gpu_share.rel_rmse.value)
            .fold(0.0, f64::max);
        md.push_str(&format!(
            "WebGPURenderer (WebGPU on SwiftShader), as three is and with `RectAreaLightSheenNode.init()` (results/textures/three/RectAreaLightSheenNode.js: the same series as `wgslFn` nodes in PhysicalLightingModel.directRectArea): as shipped {} of {} scenes have any pixel above 0; with the recipe the mean RMS error over the albedo is {}, and its image is three's formula in f64 with the series' entries to at most {:.1e} relative RMSE per scene.\n\n",
            wg.iter().filter(|w| w.shipped_max > 0.0).count(),
            wg.len(),
            mean_of(&rec).pct_fixed(3),
            share
        ));
    } else {
        md.push_str("WebGPURenderer: not in this run (Chromium offered no WebGPU adapter).\n\n");
    }
    let lit = r.scenes.iter().filter(|s| s.shipped_max > 0.0).count();
    md.push_str(&format!(
        "three as shipped renders no sheen under RectAreaLight: {} of {} scenes have any pixel above 0. With the recipe, three's image is further from the truth than the sampled table would be (beyond both bars) in {} of {} scenes, and closer in {}. ",
        lit,
        r.scenes.len(),
        worse_count(&recipe, &table),
        r.scenes.len(),
        worse_count(&table, &recipe)
    ));
    let darker: Vec<&str> = r
        .scenes
        .iter()
        .zip(recipe.iter().zip(&shipped))
        .filter(|(_, (a, b))| a.value > b.value + a.error + b.error)
        .map(|(s, _)| s.name.as_str())
        .collect();
    md.push_str(&format!(
        "Scenes where the recipe is further from the truth than no sheen at all (beyond both bars): {}; where the sampled table would be: {} of {}.\n\n",
        if darker.is_empty() {
            "none".to_string()
        } else {
            darker.join(", ")
        },
        worse_count(&table, &shipped),
        r.scenes.len()
    ));
    md
}

/// Read each run (its scene file named in it), judge it with the series and table of
/// `results`, and put results/engines-sheen.{md,json} into `set`. Returns the summary line.
pub fn run(
    set: &mut crate::io::Outputs,
    runs: &[std::path::PathBuf],
    results: &std::path::Path,
    out: &std::path::Path,
    command: &str,
) -> Result<String> {
    if runs.is_empty() {
        return Err(Error::InvalidArgument("engines-sheen: no run given".into()));
    }
    let mut checks = Vec::new();
    for p in runs {
        let run = SheenRun::from_json(&super::files::read_text(p)?).map_err(|_| {
            Error::InvalidArgument(format!(
                "engines-sheen: {} is not a sheen run, or names no scene file (render.mjs --table sheen writes one)",
                crate::error::quoted(&p.display().to_string())
            ))
        })?;
        let sc = EngineScenes::read(std::path::Path::new(&run.scenes))?;
        run.check(&sc)?;
        checks.push(judge(&sc, &run, results)?);
    }
    set.put(
        &out.join("engines-sheen.md"),
        markdown(&checks, command).as_bytes(),
    );
    #[derive(serde::Serialize)]
    struct File<'a> {
        checks: &'a [SheenResult],
        /// What the runs loaded and the judge read, with their digests when judged.
        inputs: Vec<super::inputs::InputDigest>,
    }
    // what the runs load (the recipe) and the judge reads (the series it was made from,
    // the table it is set beside)
    let table = format!("fits/{}.json", super::sheen::TABLE);
    let inputs = super::inputs::digests(
        results,
        &[
            "fits/ltc-compact.json",
            &table,
            "textures/three/RectAreaLightSheen.js",
        ],
    )?;
    set.put(
        &out.join("engines-sheen.json"),
        serde_json::to_string_pretty(&File {
            checks: &checks,
            inputs,
        })
        .map_err(|e| Error::InvalidArgument(format!("engines-sheen: json: {e}")))?
        .as_bytes(),
    );
    let line: Vec<String> = checks
        .iter()
        .map(|r| {
            format!(
                "{}: recipe {}, sampled table {}",
                r.scenes_file,
                mean_of(&over_albedo(r, |s| &s.recipe)).pct(3),
                mean_of(&over_albedo(r, |s| &s.table_share)).pct(3)
            )
        })
        .collect();
    Ok(format!(
        "wrote {}: mean RMS error over the albedo: {}",
        out.join("engines-sheen.md").display(),
        line.join("; ")
    ))
}

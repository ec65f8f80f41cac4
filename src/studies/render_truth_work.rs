//! `regen --only render-truth-work` (on request): the render truth's accuracy against its
//! work, the curve each scene's `truth_draws` (fits/render/<scene>.toml) is chosen from.
//!
//! The truth shades every texel a pixel covers (render/truth.rs). Under a quad light or an
//! SG environment each texel takes at least one light sample per replicate, so once a
//! footprint holds more than n/2 texels (n the scene's truth samples) a pixel's work grows
//! with its footprint: up to 2 × 4096 texel shadings where the scene asks for n. The draw
//! scale d bounds it: each replicate draws ⌈d · n/2⌉ texels in proportion to their overlap
//! instead (`render::truth::Work::Drawn`), an unbiased estimate of the same
//! overlap-weighted mean whose noise grows as d falls.
//!
//! Each scene of `scenes` (at the render study's size and truth samples for the preset) is
//! rendered with the truth that shades every texel, the reference, then at each draw scale
//! of `draws` with the next seed, so that each truth's noise is independent of the
//! reference's. Per view and truth:
//!
//! - the work: texel shadings per pixel (`Work::shadings`, counted, not timed);
//! - the truth's variance, the mean s.e.² of a covered pixel ± its s.e.;
//! - the excess mean((t − t_ref)² − s.e.² − s.e._ref²) over the pixels that drew, ± its s.e.:
//!   0 when both truths estimate the same value and state their errors honestly;
//! - each method's relative MSE and ꟻLIP against it, as the render study reports them.
//!
//! A draw scale passes a scene when, in every view: (a) the excess is within 3 s.e. of 0;
//! (b) every method's relative MSE is within 3 s.e. of the reference's (the two bars in
//! quadrature); (c) every method's relative MSE keeps two significant digits: its bar at
//! most 1 % of its value, or (where the reference's own bar is wider) at most 1.1 × the
//! reference's. The relative MSE is unbiased whatever the truth's noise (render::measure),
//! so the draws change its bar, not its value; ꟻLIP is computed against the truth as
//! rendered, so a noisier truth raises it: it is shown, not judged (render.md says so).
//! Each scene file's `truth_draws` is its choice: supported when it draws at least the
//! smallest passing scale's texels, or every texel (absent). The run fails on a scene whose
//! choice the curve does not support.
//!
//! Writes results/render-truth-work.{md,svg} and results/fits/render-truth-work.json.

use super::render::{builtin_params, Params as RenderParams, SCENES};
use crate::error::{Error, Result};
use crate::integrate::Figure;
use crate::io::Outputs;
use crate::render::geometry::{Camera, Surface};
use crate::render::measure::{self, Measured};
use crate::render::scene::Scene;
use crate::render::truth::{footprint_texels, Budget, PixelTruth, Shader, Work};
use crate::render::{light, normal_map, texture::Texture, Render};
use crate::report::table::Table;
use crate::results::render::{
    TruthWork, TruthWorkMethod, TruthWorkPoint, TruthWorkScene, TruthWorkView,
};
use crate::study::{Ctx, FitOutcome};
use std::path::Path;

/// The texels each truth replicate draws at `scale` × (n/2), n truth samples: at least 1,
/// at most the 4096 of an exact footprint.
fn draws(n: usize, scale: f64) -> usize {
    ((scale * (n / 2) as f64).ceil() as usize).clamp(1, crate::render::truth::MAX_EXACT_TEXELS)
}

/// What fits/render-truth-work.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Scenes of fits/render/ by name.
    pub scenes: Vec<String>,
    /// Draw scales (× n/2 texels per replicate), strictly increasing.
    pub draws: Vec<f64>,
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        crate::fit::spec::within("scenes (its length)", self.scenes.len(), 1, SCENES.len())?;
        crate::fit::spec::within("draws (its length)", self.draws.len(), 1, 16)?;
        for s in &self.scenes {
            if !SCENES.iter().any(|(n, _)| n == s) {
                return Err(format!("scenes: no scene {s:?} in fits/render/"));
            }
        }
        for &d in &self.draws {
            crate::fit::spec::within("draws", d, 1.0 / 64.0, 64.0)?;
        }
        if !self.draws.windows(2).all(|w| w[0] < w[1]) {
            return Err(format!("draws = {:?} must increase strictly", self.draws));
        }
        Ok(())
    }
}

/// The study's result.
pub struct Computed {
    pub result: TruthWork,
}

/// Each view's work census: the texels of every pixel's exact footprint (`None`: none).
fn census(scene: &Scene) -> Result<Vec<Vec<Option<usize>>>> {
    let tex = Texture::new(normal_map(scene, Path::new("fits/render"))?);
    let lights = light::resolve(&scene.lights);
    let m = &scene.material;
    let sh = Shader::new(m.lobe, m.alpha, m.sigma_r, &lights, &tex)?;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let frames = scene.frames();
    crate::memo::map(
        &format!("render-truth-work census {}", scene.name),
        scene.render.scales.len() * frames,
        |v| -> Result<Vec<Option<usize>>> {
            let surf = Surface::new(&scene.surface, scene.render.scales[v / frames]);
            let cam = Camera::at_frame(&scene.camera, v % frames);
            Ok((0..w * h)
                .map(|k| footprint_texels(&cam, &surf, &sh, k % w, k / w))
                .collect())
        },
    )
}

/// A rendered truth's figures per view, against the reference's where it is not one.
fn point(
    budget: Budget,
    sampled: bool,
    census: &[Vec<Option<usize>>],
    (r, m): (&Render, &Measured),
    reference: Option<&Render>,
) -> Vec<TruthWorkView> {
    r.views
        .iter()
        .zip(census)
        .enumerate()
        .map(|(v, (view, texels))| {
            let work: Vec<Work> = texels.iter().map(|&t| budget.work(t, sampled)).collect();
            let covered = |t: &&PixelTruth| t.covered;
            let se2: Vec<f64> = view
                .truth
                .iter()
                .filter(covered)
                .map(|t| t.se().powi(2))
                .collect();
            let excess = reference.map(|rf| {
                let d: Vec<f64> = view
                    .truth
                    .iter()
                    .zip(&rf.views[v].truth)
                    .zip(&work)
                    .filter(|((t, _), w)| t.covered && matches!(w, Work::Drawn { .. }))
                    .map(|((t, q), _)| {
                        (t.value - q.value).powi(2) - t.se().powi(2) - q.se().powi(2)
                    })
                    .collect();
                Figure::mean_of(&d)
            });
            // no pixel drew: the two truths are the same numbers
            let excess = excess.filter(|e| e.value.is_finite());
            TruthWorkView {
                scale: view.scale,
                frame: view.frame,
                shadings_per_pixel: mean(work.iter().map(Work::shadings)),
                drawn_pixels: view
                    .truth
                    .iter()
                    .zip(&work)
                    .filter(|(t, w)| t.covered && matches!(w, Work::Drawn { .. }))
                    .count(),
                pixels: se2.len(),
                truth_variance: Figure::mean_of(&se2),
                excess,
                methods: m.views[v]
                    .iter()
                    .map(|s| TruthWorkMethod {
                        key: s.key.clone(),
                        rel_mse: s.m.rel_mse,
                        flip: s.m.flip,
                    })
                    .collect(),
            }
        })
        .collect()
}

fn mean(v: impl Iterator<Item = usize>) -> f64 {
    let (s, n) = v.fold((0usize, 0usize), |(s, n), x| (s + x, n + 1));
    s as f64 / n.max(1) as f64
}

/// |a − b| in units of their bars in quadrature (0 where the values are equal, ∞ where
/// both are exact and differ).
fn apart(a: Figure, b: Figure) -> f64 {
    if a.value == b.value {
        return 0.0;
    }
    (a.value - b.value).abs() / a.error.hypot(b.error)
}

/// Checks (a)–(c) of the module doc for one view against the reference's: what failed.
fn view_failures(v: &TruthWorkView, r: &TruthWorkView) -> Vec<String> {
    let at = format!("×{} frame {}", v.scale, v.frame);
    let mut out = Vec::new();
    if let Some(e) = v.excess.filter(|e| !(e.value.abs() <= 3.0 * e.error)) {
        out.push(format!(
            "{at}: excess {:.1e} ± {:.1e} (a)",
            e.value, e.error
        ));
    }
    for (a, b) in v.methods.iter().zip(&r.methods) {
        let (f, g) = (a.rel_mse, b.rel_mse);
        if !(apart(f, g) <= 3.0) {
            out.push(format!(
                "{at}: {} {:.1} s.e. from the reference's (b)",
                a.key,
                apart(f, g)
            ));
        }
        if !(f.error <= (0.01 * f.value.abs()).max(1.1 * g.error)) {
            out.push(format!(
                "{at}: {} bar {:.2} % of its value (c)",
                a.key,
                100.0 * f.error / f.value.abs()
            ));
        }
    }
    out
}

fn scene_run(
    scene: &Scene,
    plan: &Plan,
    pa: &RenderParams,
    c: &crate::render::methods::Constants,
) -> Result<TruthWorkScene> {
    let mut base = super::render::sized(scene.clone(), pa);
    let chosen = base.render.truth_draws.take();
    let n = base.render.truth_samples;
    let census = census(&base)?;
    let sampled = light::resolve(&base.lights)
        .iter()
        .any(|l| matches!(l, light::Light::Quad { .. } | light::Light::Sg(_)));
    let render = |s: &Scene| -> Result<(Render, Measured)> {
        crate::report::stage(&format!(
            "render-truth-work {}: truth draws {:?}",
            s.name, s.render.truth_draws
        ));
        let r = crate::render::render(s, Path::new("fits/render"), c, &pa.glints)?;
        let m = measure::measure_render(&r);
        Ok((r, m))
    };
    let every = Budget { n, draws: None };
    let (rr, rm) = render(&base)?;
    let ref_views = point(every, sampled, &census, (&rr, &rm), None);
    let mut points = vec![TruthWorkPoint {
        draw_scale: None,
        draws: None,
        shadings_per_pixel: mean_views(&ref_views),
        views: ref_views.clone(),
        passes: true,
        failures: Vec::new(),
    }];
    for &d in &plan.draws {
        let mut s = base.clone();
        let m = draws(n, d);
        s.render.truth_draws = Some(m);
        let (r, me) = render(&s)?;
        let views = point(
            Budget { n, draws: Some(m) },
            sampled,
            &census,
            (&r, &me),
            Some(&rr),
        );
        let failures: Vec<String> = views
            .iter()
            .zip(&ref_views)
            .flat_map(|(v, r)| view_failures(v, r))
            .collect();
        points.push(TruthWorkPoint {
            draw_scale: Some(d),
            draws: Some(m),
            shadings_per_pixel: mean_views(&views),
            views,
            passes: failures.is_empty(),
            failures,
        });
    }
    let smallest_passing = points
        .iter()
        .find(|p| p.draw_scale.is_some() && p.passes)
        .and_then(|p| p.draw_scale);
    let supported = match (chosen, smallest_passing) {
        (None, _) => true,
        (Some(m), Some(d)) => m >= draws(n, d),
        (Some(_), None) => false,
    };
    Ok(TruthWorkScene {
        scene: base.name.clone(),
        samples: n,
        chosen,
        smallest_passing,
        supported,
        points,
    })
}

fn mean_views(v: &[TruthWorkView]) -> f64 {
    v.iter().map(|x| x.shadings_per_pixel).sum::<f64>() / v.len().max(1) as f64
}

pub fn compute(c: &Ctx) -> Result<Computed> {
    let plan: Plan = c.params()?;
    let pa: RenderParams = match c
        .specs
        .iter()
        .find(|s| s.name == crate::results::names::RENDER)
    {
        Some(s) => s.params(c.preset)?,
        None => builtin_params(c.preset)?,
    };
    let constants = crate::results::render::constants(c.results)?;
    let mut scenes = Vec::new();
    for name in &plan.scenes {
        let (_, text) = SCENES.iter().find(|(n, _)| n == name).ok_or_else(|| {
            Error::InvalidArgument(format!("render-truth-work: no scene {name:?}"))
        })?;
        scenes.push(scene_run(
            &Scene::parse(text, name)?,
            &plan,
            &pa,
            &constants,
        )?);
    }
    Ok(Computed {
        result: TruthWork {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            scenes,
        },
    })
}

fn label(p: &TruthWorkPoint) -> String {
    match (p.draw_scale, p.draws) {
        (Some(d), Some(m)) => format!("{d} × n/2 = {m}"),
        _ => "every texel (reference)".into(),
    }
}

fn markdown(r: &TruthWork) -> String {
    let mut md = format!(
        "# The render truth: accuracy against work\n\nWritten by `{}` (preset {}). Each scene's truth shades every texel a pixel covers (the reference), then, where a quad light or an SG environment shines on a footprint of more texels than the draws, draws ⌈d · n/2⌉ texels per replicate in proportion to their overlap (n the scene's truth samples; src/studies/render_truth_work.rs, render/truth/texels.rs). Work is texel shadings per pixel, counted. The truth's variance is the mean s.e.² of a covered pixel; the excess is mean((t − t_ref)² − s.e.² − s.e._ref²) over the pixels that drew, 0 when both truths estimate the same value with honest errors. A pixel's drawn truth takes other numbers of its random stream than its every-texel truth, so their noise is independent; the methods' images are the same. A draw scale passes when in every view the excess is within 3 s.e. of 0, every method's relative MSE is within 3 s.e. of the reference's (bars in quadrature), and its bar is at most 1 % of its value (or, where the reference's is wider, at most 1.1 × the reference's). The relative MSE is unbiased whatever the truth's noise, so the draws move its bar, not its value. ꟻLIP is computed against the truth as rendered, so a noisier truth raises it; it is shown, not judged.\n\n",
        r.command, r.preset
    );
    let mut t = Table::new([
        "scene",
        "truth samples n",
        "smallest passing draw scale",
        "the scene file's truth_draws",
        "shadings per pixel: chosen / every texel",
        "supported",
    ]);
    for s in &r.scenes {
        let chosen = s
            .chosen
            .and_then(|m| s.points.iter().find(|p| p.draws == Some(m)));
        let every = s.points[0].shadings_per_pixel;
        t.row([
            s.scene.clone(),
            s.samples.to_string(),
            s.smallest_passing
                .map_or("none".to_string(), |d| format!("{d} × n/2")),
            s.chosen
                .map_or("absent: every texel".to_string(), |m| m.to_string()),
            match (s.chosen, chosen) {
                (None, _) => format!("{every:.0} / {every:.0}"),
                (Some(_), Some(p)) => format!("{:.0} / {every:.0}", p.shadings_per_pixel),
                (Some(_), None) => format!("— (not on the curve) / {every:.0}"),
            },
            if s.supported { "yes" } else { "no" }.to_string(),
        ]);
    }
    md.push_str("Each scene's choice (`[render] truth_draws` in fits/render/<scene>.toml) is supported when it draws at least as many texels as the smallest passing scale, or shades every texel:\n\n");
    md.push_str(&t.to_string());
    md.push('\n');
    for s in &r.scenes {
        md.push_str(&format!(
            "## {} ({} truth samples per pixel)\n\n",
            s.scene, s.samples
        ));
        let mut head = vec![
            "truth (texels drawn per replicate)".to_string(),
            "shadings per pixel".into(),
        ];
        let views = &s.points[0].views;
        head.extend(
            views
                .iter()
                .map(|v| format!("×{} frame {}: variance · excess", v.scale, v.frame)),
        );
        head.push("passes".into());
        let mut t = Table::new(head);
        for p in &s.points {
            let mut row = vec![label(p), format!("{:.0}", p.shadings_per_pixel)];
            row.extend(p.views.iter().map(|v| {
                let ex = v.excess.map_or("—".to_string(), |e| e.sci_signed(1, 1));
                format!(
                    "{} · {} ({} drew)",
                    v.truth_variance.sci(2, 1),
                    ex,
                    v.drawn_pixels
                )
            }));
            row.push(match p.failures.split_first() {
                None => "yes".to_string(),
                Some((first, [])) => format!("no: {first}"),
                Some((first, rest)) => format!("no: {first}, and {} more", rest.len()),
            });
            t.row(row);
        }
        md.push_str(&t.to_string());
        md.push('\n');
        if !s.points[0].views[0].methods.is_empty() {
            md.push_str("Relative MSE and ꟻLIP per method, at the largest view scale and the truth's figures beside the reference's:\n\n");
            let last = views.len() - 1;
            let mut head = vec!["truth".to_string()];
            head.extend(
                s.points[0].views[last]
                    .methods
                    .iter()
                    .map(|m| m.key.clone()),
            );
            let mut t = Table::new(head);
            for p in &s.points {
                let mut row = vec![label(p)];
                row.extend(
                    p.views[last]
                        .methods
                        .iter()
                        .map(|m| format!("{} · ꟻLIP {}", m.rel_mse.pct(2), m.flip.fixed(4))),
                );
                t.row(row);
            }
            md.push_str(&t.to_string());
            md.push('\n');
        }
    }
    md
}

fn plot(r: &TruthWork) -> Result<String> {
    use crate::report::plot::{loglog_svg, Panel, Series};
    let series = r
        .scenes
        .iter()
        .flat_map(|s| {
            let nv = s.points[0].views.len();
            (0..nv).map(move |v| Series {
                name: format!("{} ×{}", s.scene, s.points[0].views[v].scale),
                points: s
                    .points
                    .iter()
                    .map(|p| {
                        (
                            p.views[v].shadings_per_pixel,
                            p.views[v].truth_variance.value,
                        )
                    })
                    .collect(),
            })
        })
        .collect();
    loglog_svg(
        &[Panel {
            title: "The truth's variance against its work, per view".into(),
            x_label: "texel shadings per pixel".into(),
            y_label: "mean s.e.² of a pixel".into(),
            series,
        }],
        900,
        560,
    )
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &Path) -> Result<()> {
        let (md, svg) = (markdown(&self.result), plot(&self.result)?);
        crate::results::put_report(set, results, &md, &svg, &self.result)
    }

    fn outcome(&self) -> FitOutcome {
        let r = &self.result;
        let unsupported = r.scenes.iter().filter(|s| !s.supported).count();
        FitOutcome::judged(
            &r.spec,
            unsupported as f64,
            r.scenes
                .iter()
                .map(|s| {
                    format!(
                        "{}: smallest passing {}, truth_draws {} ({})",
                        s.scene,
                        s.smallest_passing
                            .map_or("none".to_string(), |d| format!("{d} × n/2")),
                        s.chosen.map_or("absent".to_string(), |m| m.to_string()),
                        if s.supported {
                            "supported"
                        } else {
                            "not supported"
                        }
                    )
                })
                .collect::<Vec<_>>()
                .join("; "),
        )
    }
}

crate::study::study! {
    /// The render truth's accuracy against its work, as the registry holds it.
    RenderTruthWork = "render-truth-work", after ["filters"], on request true, params Plan, computes compute
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view(excess: Option<Figure>, rel: &[(f64, f64)]) -> TruthWorkView {
        TruthWorkView {
            scale: 1.0,
            frame: 0,
            shadings_per_pixel: 1.0,
            drawn_pixels: 1,
            pixels: 1,
            truth_variance: Figure::with_se(1.0, 0.1),
            excess,
            methods: rel
                .iter()
                .map(|&(v, e)| TruthWorkMethod {
                    key: "m".into(),
                    rel_mse: Figure::with_se(v, e),
                    flip: Figure::with_se(0.1, 0.001),
                })
                .collect(),
        }
    }

    /// The rule's three checks, each at and across its edge, and an exact view (no noise,
    /// no draws) against itself.
    #[test]
    fn the_rule_fails_each_check_at_its_edge() {
        let r = view(None, &[(10.0, 0.03)]);
        let fails = |v: &TruthWorkView| view_failures(v, &r).len();
        // (a) the excess: 2.9 s.e. passes, 3.1 fails
        assert_eq!(
            fails(&view(Some(Figure::with_se(2.9, 1.0)), &[(10.0, 0.03)])),
            0
        );
        assert_eq!(
            fails(&view(Some(Figure::with_se(-3.1, 1.0)), &[(10.0, 0.03)])),
            1
        );
        // (b) 0.15 apart with bars 0.04 and 0.03 (0.05 in quadrature): 3 s.e. passes
        assert_eq!(fails(&view(None, &[(10.149, 0.04)])), 0);
        assert_eq!(fails(&view(None, &[(10.151, 0.04)])), 1);
        // (c) a bar of 1 % of the value passes, more fails (the reference's 0.03 is narrower)
        assert_eq!(fails(&view(None, &[(10.0, 0.0999)])), 0);
        assert_eq!(fails(&view(None, &[(10.0, 0.11)])), 1);
        // (c) where the reference's bar is already wider than 1 %: up to 1.1 × it
        let wide = view(None, &[(1.0, 0.05)]);
        assert!(view_failures(&view(None, &[(1.0, 0.0549)]), &wide).is_empty());
        assert_eq!(view_failures(&view(None, &[(1.0, 0.0551)]), &wide).len(), 1);
        // an exact view: equal values with zero bars agree
        let exact = view(None, &[(0.5, 0.0)]);
        assert!(view_failures(&exact, &exact).is_empty());
    }
}

//! `regen --only tensor-wave`: seed 002's wave-optics NDF images (§3.1, Eq 3–4; the model
//! in `tensor::wave`) checked and compressed, run on request (fits/tensor-wave.toml).
//!
//! - **Checks:** the FFT against the direct sum of Eq 3; the energy ∫ D* dψ against the
//!   window's (Parseval) and against 1; the geometric limit, the total-variation distance
//!   of the footprint's image (Eq 4) to the distribution of −∇h as λ shrinks, with the
//!   reference's own quadrature bar and the fitted rate; colour tending to neutral as the
//!   same surface is magnified (= λ divided).
//! - **Images:** RGB NDF images (8 spectral samples) of a grid of footprints over an
//!   isotropic-noise surface, each footprint one item of a memoised map (so `--shard` and
//!   `slurm` split them).
//! - **Compression:** CP-ALS of the RGB images' t × t blocks with colour folded into the
//!   third mode (seed 002 §4.2), error and storage ratio against rank beside Table 2's
//!   wave row.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::io::Outputs;
use crate::report::plot::{loglog_svg, Panel, Series};
use crate::report::table::Table;
use crate::results::tensor::{LimitPoint, RankRow, WaveResult};
use crate::study::{Ctx, FitOutcome};
use crate::tensor::cluster::stack_blocks;
use crate::tensor::cp::{cp_als, AlsOptions};
use crate::tensor::wave::{
    bin, energy, field_side, gndf_direct, gndf_fft, patch_for, sampled_for, slope_image, to_rgb,
    tv_distance, wave_image, Footprint, Waves, TABLE2_WAVE, WAVELENGTHS,
};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What fits/tensor-wave.toml sets (lengths in µm).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// The surfaces' period (one tile) and RMS slope.
    pub period: f64,
    pub rms_slope: f64,
    /// The geometric-limit surface: cosines and their largest wave number per period.
    pub components: usize,
    pub kmax: u32,
    /// The isotropic-noise surface of the colour images.
    pub noise_components: usize,
    pub noise_kmax: u32,
    /// Coherence window σ_c, footprint σ_P and the step of the window centres.
    pub sigma_c: f64,
    pub sigma_p: f64,
    pub step: f64,
    /// NDF image side (over ψ ∈ [−1, 1]²).
    pub res: usize,
    /// The geometric-limit wavelengths, and the slope image's quadrature spacing (its bar
    /// is the distance to the image at twice the spacing).
    pub lambdas: Vec<f64>,
    pub ds: f64,
    /// Footprints per side of the colour images' grid.
    pub footprints: usize,
    /// Magnifications of the neutral-colour check.
    pub magnifications: Vec<f64>,
    /// Blocks and CP.
    pub t: usize,
    pub ranks: Vec<usize>,
    pub iters: usize,
    pub als_tolerance: f64,
}

impl crate::fit::spec::Params for Params {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::within;
        within("period", self.period, 4.0, 512.0)?;
        within("rms_slope", self.rms_slope, 1e-3, 0.5)?;
        within("components", self.components, 1, 1024)?;
        within("kmax", self.kmax, 1, 64)?;
        within("noise_components", self.noise_components, 1, 4096)?;
        within("noise_kmax", self.noise_kmax, 1, 256)?;
        within("sigma_c", self.sigma_c, 0.1, self.period / 16.0)?;
        within("sigma_p", self.sigma_p, 0.1, self.period / 8.0)?;
        within("step", self.step, self.sigma_p / 8.0, 4.0 * self.sigma_p)?;
        crate::tensor::cluster::check_blocks(self.t, self.res, &self.ranks, 0.02)?;
        if self.lambdas.is_empty() || self.lambdas.len() > 8 {
            return Err("lambdas: 1 to 8 wavelengths".into());
        }
        for l in &self.lambdas {
            within("lambdas", *l, 0.05, 1.0)?;
        }
        within("ds", self.ds, 1e-3, self.sigma_c / 4.0)?;
        within("footprints", self.footprints, 1, 16)?;
        if self.magnifications.len() < 2 {
            return Err("magnifications: at least two".into());
        }
        for f in &self.magnifications {
            within("magnifications", *f, 1.0, 8.0)?;
        }
        within("iters", self.iters, 1, 100_000)?;
        within("als_tolerance", self.als_tolerance, 1e-15, 0.5)?;
        // the height fields the sweep samples stay within tensor::wave::MAX_SIDE
        let widest = self.magnifications.iter().cloned().fold(1.0, f64::max);
        let shortest = self.lambdas.iter().cloned().fold(WAVELENGTHS[0], f64::min);
        field_side(self.period * widest, WAVELENGTHS[0])
            .and(field_side(self.period, shortest))
            .map(|_| ())
            .map_err(|e| format!("period, lambdas and magnifications: {e}"))
    }
}

fn checks(p: &Params, w: &Waves) -> Result<(f64, f64, f64)> {
    let (mut fft_dev, mut parseval, mut vs_one) = (0.0f64, 0.0f64, 0.0f64);
    let u = (0.3 * p.period, 0.6 * p.period);
    for &lambda in &p.lambdas {
        let (hf, _) = sampled_for(w, lambda, p.sigma_c)?;
        for f in [0.5, 1.0, 2.0] {
            let sc = f * p.sigma_c;
            let m = patch_for(hf.dx, sc);
            if m > hf.n {
                continue;
            }
            let g = gndf_fft(&hf, u, sc, lambda, m)?;
            let (e, ew) = energy(&g, &hf, sc, u)?;
            parseval = parseval.max((e - ew).abs() / ew);
            vs_one = vs_one.max((e - 1.0).abs());
            if f == 1.0 {
                let peak = g.values.iter().cloned().fold(0.0, f64::max);
                let h = (m / 2) as i64;
                let nodes = [(0i64, 0i64), (3, -5), (-h, h - 1), (h / 3, 2), (-9, -h / 2)];
                let psi: Vec<(f64, f64)> = nodes
                    .iter()
                    .map(|&(a, b)| (a as f64 * g.dpsi, b as f64 * g.dpsi))
                    .collect();
                for (&(a, b), d) in nodes.iter().zip(gndf_direct(&hf, u, sc, lambda, m, &psi)?) {
                    let v = g.values[((b + h) * m as i64 + a + h) as usize];
                    fft_dev = fft_dev.max((v - d).abs() / peak);
                }
            }
        }
    }
    Ok((fft_dev, parseval, vs_one))
}

fn limit(p: &Params, w: &Waves) -> Result<(Vec<LimitPoint>, f64, f64)> {
    let fp = Footprint {
        x: (0.3 * p.period, 0.2 * p.period),
        sigma_p: p.sigma_p,
        step: p.step,
    };
    let geo = slope_image(w, &fp, p.sigma_c, p.ds, p.res)?;
    let bar = tv_distance(
        &geo,
        &slope_image(w, &fp, p.sigma_c, 2.0 * p.ds, p.res)?,
        p.res,
    );
    let mut pts = Vec::new();
    for &lambda in &p.lambdas {
        crate::progress::stamp(&format!("tensor-wave: geometric limit at λ = {lambda} µm"));
        let (hf, m) = sampled_for(w, lambda, p.sigma_c)?;
        let img = wave_image(&hf, &fp, p.sigma_c, lambda, m, p.res)?;
        pts.push(LimitPoint {
            lambda,
            dx: hf.dx,
            patch: m,
            tv: tv_distance(&img, &geo, p.res),
        });
    }
    let xy: Vec<(f64, f64)> = pts.iter().map(|q| (q.lambda.ln(), q.tv.ln())).collect();
    let n = xy.len() as f64;
    let (mx, my) = (
        xy.iter().map(|v| v.0).sum::<f64>() / n,
        xy.iter().map(|v| v.1).sum::<f64>() / n,
    );
    let sxx: f64 = xy.iter().map(|v| (v.0 - mx).powi(2)).sum();
    let rate = if sxx > 0.0 {
        xy.iter().map(|v| (v.0 - mx) * (v.1 - my)).sum::<f64>() / sxx
    } else {
        f64::NAN
    };
    Ok((pts, bar, rate))
}

/// Chroma of one window's RGB image (Eq 3) of the surface magnified by f (σ_c with it).
fn chroma(p: &Params, w: &Waves, f: f64) -> Result<f64> {
    let wf = w.magnified(f);
    let sc = p.sigma_c * f;
    let (hf, m) = sampled_for(&wf, WAVELENGTHS[0], sc)?;
    let u = (0.25 * wf.period, 0.25 * wf.period);
    let spectral: Vec<Vec<f64>> = WAVELENGTHS
        .iter()
        .map(|&l| bin(&gndf_fft(&hf, u, sc, l, m)?, p.res))
        .collect::<Result<_>>()?;
    let [r, g, b] = to_rgb(&spectral)?;
    let (mut spread, mut mean) = (0.0, 0.0);
    for q in 0..r.len() {
        spread += r[q].max(g[q]).max(b[q]) - r[q].min(g[q]).min(b[q]);
        mean += (r[q] + g[q] + b[q]) / 3.0;
    }
    Ok(spread / mean)
}

/// What the study computed.
pub struct Computed {
    spec: FitSpec,
    preset: Preset,
    p: Params,
    result: WaveResult,
}

fn compute(c: &Ctx) -> Result<Computed> {
    let p: Params = c.params()?;
    let seed = c.spec.seed;
    let w = Waves::new(p.components, p.kmax, p.period, p.rms_slope, seed)?;
    let (fft_vs_direct, parseval, energy_vs_one) = checks(&p, &w)?;
    let (limit, limit_bar, limit_rate) = limit(&p, &w)?;
    let chroma = p
        .magnifications
        .iter()
        .map(|&f| Ok((f, chroma(&p, &w, f)?)))
        .collect::<Result<Vec<_>>>()?;
    // RGB images of a grid of footprints over the isotropic-noise surface
    let noise = Waves::new(
        p.noise_components,
        p.noise_kmax,
        p.period,
        p.rms_slope,
        seed + 1,
    )?;
    let (hf, m) = sampled_for(&noise, WAVELENGTHS[0], p.sigma_c)?;
    let spacing = p.period / p.footprints as f64;
    let items: Vec<(usize, usize)> = (0..p.footprints * p.footprints)
        .map(|q| (q % p.footprints, q / p.footprints))
        .collect();
    let images: Vec<Vec<Vec<f64>>> =
        crate::memo::map_items("tensor-wave footprints", &items, |&(i, j)| {
            let fp = Footprint {
                x: ((i as f64 + 0.5) * spacing, (j as f64 + 0.5) * spacing),
                sigma_p: p.sigma_p,
                step: p.step,
            };
            let spectral: Vec<Vec<f64>> = WAVELENGTHS
                .iter()
                .map(|&l| wave_image(&hf, &fp, p.sigma_c, l, m, p.res))
                .collect::<Result<_>>()?;
            Ok(to_rgb(&spectral)?.to_vec())
        })?;
    let flat: Vec<&[f64]> = images.iter().flatten().map(|v| v.as_slice()).collect();
    let stack = stack_blocks(&flat, p.res, p.t)?.ok_or_else(|| {
        crate::error::Error::InvalidArgument("tensor-wave: every RGB block is zero".into())
    })?;
    let blocks = stack.tensor.shape[2];
    let blocks_all = flat.len() * (p.res / p.t).pow(2);
    let total = (flat.len() * p.res * p.res) as f64;
    let ranks = p
        .ranks
        .iter()
        .map(|&r| {
            let cp = cp_als(
                &stack.tensor,
                &AlsOptions {
                    rank: r,
                    tol: p.als_tolerance,
                    max_iters: p.iters,
                    restarts: 2,
                    seed,
                    nonnegative: false,
                },
            )?;
            Ok(RankRow {
                rank: r,
                rel_error: cp.rel_error,
                iterations: cp.iterations,
                ratio_all: cp.storage() as f64 / total,
                ratio_nonempty: cp.storage() as f64 / stack.tensor.data.len() as f64,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Computed {
        spec: c.spec.clone(),
        preset: c.preset,
        result: WaveResult {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            fft_vs_direct,
            parseval,
            energy_vs_one,
            limit,
            limit_bar,
            limit_rate,
            chroma,
            images: images.len(),
            blocks,
            blocks_all,
            ranks,
        },
        p,
    })
}

impl crate::study::Computed for Computed {
    fn outcome(&self) -> FitOutcome {
        let r = &self.result;
        let worst = r.ranks.iter().map(|x| x.rel_error).fold(0.0, f64::max);
        FitOutcome::measured(
            &self.spec,
            worst,
            format!(
                "wave optics: FFT = direct to {:.1e}, energy 1 ± {:.1e}, TV to the geometric limit {:.3} at λ = {} µm",
                r.fft_vs_direct,
                r.energy_vs_one,
                r.limit.last().map_or(f64::NAN, |q| q.tv),
                r.limit.last().map_or(f64::NAN, |q| q.lambda)
            ),
        )
    }

    fn render(&self, set: &mut Outputs, results: &Path) -> Result<()> {
        let r = &self.result;
        let panel = Panel {
            title: "Wave-optics NDF image against its geometric limit".into(),
            x_label: "wavelength λ (µm)".into(),
            y_label: "total-variation distance to the slope image".into(),
            series: vec![Series {
                name: format!("σ_c = {} µm, σ_P = {} µm", self.p.sigma_c, self.p.sigma_p),
                points: r.limit.iter().map(|q| (q.lambda, q.tv)).collect(),
            }],
        };
        set.put(
            results.join("tensor-wave.svg"),
            loglog_svg(&[panel], 720, 480)?,
        );
        set.put(results.join("tensor-wave.md"), self.markdown());
        crate::results::put(set, results, r)
    }
}

impl Computed {
    fn markdown(&self) -> String {
        let (r, p) = (&self.result, &self.p);
        let mut md = format!(
            "# Seed 002 §3.1: wave-optics NDF images\n\nWritten by `{}` (preset {}) from `fits/tensor-wave.toml`, on request (the main job leaves it out). Model: `tensor::wave` (Eq 3 by 2D FFT, Eq 4 over window centres every {} µm within 3σ_P, 8 wavelengths 420–700 nm to white-balanced linear sRGB through the CIE 1931 2° colour matching functions). Lengths in µm; σ_c = {} µm (the paper's coherence windows are 5–10 µm: smaller here to keep the sweep on one machine), σ_P = {} µm, images {}² over ψ ∈ [−1, 1]², A_c = πσ_c² (so ∫D* dψ = 1 over the ψ plane).\n\n",
            r.command, self.preset.name(), p.step, p.sigma_c, p.sigma_p, p.res
        );
        md.push_str(&format!(
            "## Checks\n\n- **FFT = direct sum of Eq 3:** largest difference {:.1e} of the image's peak, over 5 nodes per wavelength (the centre, interior nodes and the grid's corner).\n- **Energy (Parseval):** Σ D*·dψ² equals the sampled window's Σ G_c² dx²/A_c to {:.1e} (relative), and 1 to {:.1e}, over σ_c × {{0.5, 1, 2}} and every λ below (the ±4σ_c patch leaves ~3e-8 of the window out).\n",
            r.fft_vs_direct, r.parseval, r.energy_vs_one
        ));
        md.push_str(&format!(
            "- **Geometric limit:** the footprint's image (Eq 4) against the distribution of −∇h under Σ_u G_P(u) G_c(s − u)²/A_c (stationary phase), on a surface of {} cosines (wave numbers ≤ {} per {} µm period, RMS slope {}). Total-variation distance (½ Σ |a − b| cell², in [0, 1]); the reference's quadrature bar is its own distance to the same image at twice the spacing: {:.1e}.\n\n",
            p.components, p.kmax, p.period, p.rms_slope, r.limit_bar
        ));
        let mut t = Table::new(["λ (µm)", "dx (µm)", "FFT patch", "TV distance"]);
        for q in &r.limit {
            t.row([
                format!("{}", q.lambda),
                format!("{:.4}", q.dx),
                format!("{}²", q.patch),
                format!("{:.4}", q.tv),
            ]);
        }
        md.push_str(&t.to_string());
        md.push_str(&format!(
            "\nFitted rate: TV ∝ λ^{:.2} over these wavelengths (diffraction widens each slope's spike by ~λ/σ_c in ψ).\n\n![TV distance against λ](tensor-wave.svg)\n\n",
            r.limit_rate
        ));
        md.push_str("- **Colour tends to neutral:** the same surface magnified by f (heights, period and σ_c; optically λ/f), one window, chroma = Σ (max − min channel)/Σ mean channel of the RGB image: ");
        md.push_str(
            &r.chroma
                .iter()
                .map(|(f, c)| format!("f = {f}: {c:.4}"))
                .collect::<Vec<_>>()
                .join(", "),
        );
        md.push_str(". A flat spectrum gives R = G = B exactly (each channel's weights are normalised to sum to 1).\n\n");
        let (pre, comp, wo, w, ratio) = TABLE2_WAVE;
        md.push_str(&format!(
            "## Compression of the RGB images (§4.2)\n\n{} footprints on a {}×{} grid over an isotropic-noise surface ({} cosines, wave numbers ≤ {}), 3 channels each, cut into {}² blocks with colour folded into the third mode: {} non-empty of {} blocks. CP-ALS (2 seeded starts, ≤ {} sweeps, tolerance {:e}); relative error ‖T − T̂‖/‖T‖ of the stacked blocks.\n\n",
            r.images, p.footprints, p.footprints, p.noise_components, p.noise_kmax, p.t, r.blocks, r.blocks_all, p.iters, p.als_tolerance
        ));
        let mut t = Table::new([
            "R",
            "rel. error",
            "ALS sweeps",
            "stored / all values",
            "stored / non-empty blocks' values",
        ]);
        for x in &r.ranks {
            t.row([
                x.rank.to_string(),
                format!("{:.2} %", 100.0 * x.rel_error),
                x.iterations.to_string(),
                format!("{:.2} %", 100.0 * x.ratio_all),
                format!("{:.2} %", 100.0 * x.ratio_nonempty),
            ]);
        }
        md.push_str(&t.to_string());
        md.push_str(&format!(
            "\nTable 2's wave row (isotropic noise, 8K², RGB, R = 16, 40 cores): {pre:.2} min of NDF generation, {comp:.2} min of compression, {wo:.2} MB without and {w:.2} MB with compression, a ratio of {ratio:.2} %. A CP of rank R stores R·(2t + L + 1) values for t²·L, so for the long tensors of a large map the ratio tends to R/t² = {:.2} % at R = 16, t = {}: the ratios above sit at that floor already, and Table 2's 8.21 % lies above it by what its MB count holds besides the factors (the summed-area tables, at least; it does not itemise them). The reconstruction errors are this surface's at this image size. results/performance.md (section \"Seed 002 Table 2's wave row, projected\") projects Table 2's compression minutes from the measured cost of an ALS sweep per slice, and bounds its generation minutes by the measured cost of one coherence window (the paper does not state its windows per footprint or its sampling).\n",
            100.0 * 16.0 / (p.t * p.t) as f64,
            p.t
        ));
        md
    }
}

crate::study::study! {
    /// Seed 002's wave optics: minutes at its default preset (FFTs up to 1024² per window
    /// centre), so on request only.
    TensorWave = "tensor-wave", after [], on request true, params Params, computes compute
}

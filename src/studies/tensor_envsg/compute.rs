//! The tensor-envsg study's computation: the SG fit of a procedural environment, two
//! footprints' compressed NDF images, and per (footprint, lighting) the quadrature truth,
//! the point-query estimator and the prefiltered one over the (ε, scale) grid.

use crate::error::{Error, Result};
use crate::filters::footprint::{NormalMap, Procedural};
use crate::fit::spec::FitSpec;
use crate::integrate::{Figure, Preset, Quad};
use crate::results::envsg::{Case, EnvSg, Fig11, Picture, Row, SgFit, Trade};
use crate::study::Ctx;
use crate::tensor::brdf::CompressedNdf;
use crate::tensor::cluster::stack_blocks;
use crate::tensor::cp::AlsOptions;
use crate::tensor::envsg::{fit, query_side, Env, Read, Sg, SgEnv, Shading};
use crate::tensor::pndf::{pndf_image, pndf_image_separable, sigma_p};
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// What fits/tensor-envsg.toml sets.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// The glinty map, its side, the footprint stride and the levels shown (σ_P =
    /// 1.5·stride·2^level/√12), the images' side and σ_r, the CP's block and rank.
    pub map: Procedural,
    pub map_size: usize,
    pub stride: usize,
    pub levels: Vec<usize>,
    pub res: usize,
    pub sigma_r: f64,
    pub t: usize,
    pub rank: usize,
    /// The view's angle from the normal (degrees).
    pub view_deg: f64,
    /// Single-SG lightings (amplitude 1, on the mirror direction): their bandwidths.
    pub lambdas: Vec<f64>,
    /// The environment: "procedural" (equirectangular, w × h, a sun of this radiance), or
    /// a user's equirectangular PNG (a path; its radiance is the decoded linear luminance
    /// times `env_scale`).
    pub environment: String,
    pub env_size: (usize, usize),
    pub sun: f64,
    pub env_scale: f64,
    pub lobes: usize,
    pub axes: usize,
    pub fit_lambdas: Vec<f64>,
    /// The prefilter grid: ε of Eq 8 and the scale of Eq 9's side.
    pub eps: Vec<f64>,
    pub scales: Vec<f64>,
    /// Samples per estimator per case.
    pub samples: usize,
    /// The picture: footprints every `picture_stride` texels over the map, `spp` samples
    /// per pixel, under the fitted sky.
    pub picture_stride: usize,
    pub spp: usize,
}

impl crate::fit::spec::Params for Params {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::{all_within, power_of_two, within};
        power_of_two("map_size", self.map_size, 16, 1024)?;
        within("stride", self.stride, 1, self.map_size / 2)?;
        all_within("levels", &self.levels, 0, 8, 4)?;
        crate::tensor::cluster::check_blocks(self.t, self.res, &[self.rank], self.sigma_r)?;
        power_of_two("t", self.t, 2, 64)?;
        within("view_deg", self.view_deg, 0.0, 89.0)?;
        all_within("lambdas", &self.lambdas, 0.1, 1e5, 8)?;
        within("env_size.0", self.env_size.0, 8, 1024)?;
        within("env_size.1", self.env_size.1, 4, 512)?;
        within("sun", self.sun, 0.0, 1e6)?;
        within("env_scale", self.env_scale, 1e-9, 1e9)?;
        if self.environment != PROCEDURAL && !std::path::Path::new(&self.environment).is_file() {
            return Err(format!(
                "environment = {:?} is neither \"{PROCEDURAL}\" nor a PNG file",
                self.environment
            ));
        }
        within("lobes", self.lobes, 1, 16)?;
        within("axes", self.axes, 4, 512)?;
        all_within("fit_lambdas", &self.fit_lambdas, 0.1, 1e5, 8)?;
        all_within("eps", &self.eps, 1e-6, 0.99, 8)?;
        all_within("scales", &self.scales, 0.01, 8.0, 8)?;
        within("samples", self.samples, 64, 1 << 22)?;
        within("picture_stride", self.picture_stride, 2, self.map_size / 4)?;
        within("spp", self.spp, 1, 1024)
    }
}

/// Everything the study computed; the report formats it.
pub struct Computed {
    pub spec: FitSpec,
    pub preset: Preset,
    pub p: Params,
    pub result: EnvSg,
}

/// Mean, unbiased variance and their standard errors of `f` over `n` draws of `rng`.
fn moments(
    n: usize,
    seed: u64,
    mut f: impl FnMut([f64; 3]) -> Result<f64>,
) -> Result<(Figure, Figure)> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let v: Vec<f64> = (0..n).map(|_| f(rng.random())).collect::<Result<_>>()?;
    let nf = n as f64;
    let m = v.iter().sum::<f64>() / nf;
    let m2 = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / nf;
    let m4 = v.iter().map(|x| (x - m).powi(4)).sum::<f64>() / nf;
    let var = m2 * nf / (nf - 1.0);
    // the sample variance's standard error (its fourth-moment form)
    let se_var = ((m4 - m2 * m2 * (nf - 3.0) / (nf - 1.0)).max(0.0) / nf).sqrt();
    Ok((Figure::new(m, (var / nf).sqrt()), Figure::new(var, se_var)))
}

/// The relative bias and the unbiased relative MSE of a 16-sample pixel, from a mean and
/// variance against the truth `i`.
fn judged(mean: Figure, var: Figure, i: f64) -> (Figure, Figure) {
    let b = mean.value - i;
    let mse = (b * b - mean.error * mean.error + var.value / 16.0) / (i * i);
    let err = ((2.0 * b * mean.error).powi(2) + (var.error / 16.0).powi(2)).sqrt() / (i * i);
    (Figure::new(b / i, mean.error / i), Figure::new(mse, err))
}

fn case(
    p: &Params,
    ndf: &CompressedNdf,
    image: usize,
    env: &SgEnv,
    names: (String, String),
    seed: u64,
) -> Result<Case> {
    let v = p.view_deg.to_radians();
    let sh = Shading {
        ndf,
        image,
        o: Vector3::new(v.sin(), 0.0, v.cos()),
    };
    let (r4, r8) = (sh.reference(env, 8), sh.reference(env, 16));
    if !(r8 > 0.0) {
        return Err(Error::InvalidArgument(format!(
            "tensor-envsg: {} under {} reflects no light",
            names.0, names.1
        )));
    }
    let reference = Figure::<Quad>::new(r8, (r8 - r4).abs());
    let (pm, pv) = moments(p.samples, seed, |u| sh.sample(env, Read::Point, u))?;
    let (point_bias, point_mse16) = judged(pm, pv, r8);
    let mut rows = Vec::new();
    for (a, &eps) in p.eps.iter().enumerate() {
        for (b, &scale) in p.scales.iter().enumerate() {
            let s = seed + 1 + (a * p.scales.len() + b) as u64;
            let (m, var) = moments(p.samples, s, |u| {
                sh.sample(env, Read::Prefiltered { eps, scale }, u)
            })?;
            let (bias, mse16) = judged(m, var, r8);
            let r = pv.value / var.value;
            let sides: Vec<usize> = env
                .lobes
                .iter()
                .map(|g| query_side(g.support(eps), p.res, scale))
                .collect();
            rows.push(Row {
                eps,
                scale,
                q: (
                    sides.iter().copied().min().unwrap_or(1),
                    sides.iter().copied().max().unwrap_or(1),
                ),
                bias,
                var_ratio: Figure::new(
                    r,
                    r * ((pv.error / pv.value).powi(2) + (var.error / var.value).powi(2)).sqrt(),
                ),
                mse16,
            });
        }
    }
    Ok(Case {
        footprint: names.0,
        lighting: names.1,
        reference,
        point_bias,
        point_mse16,
        rows,
    })
}

/// The images stacked in t × t blocks and CP-compressed together at the spec's rank.
fn compress(p: &Params, images: &[Vec<f64>], seed: u64, what: &str) -> Result<CompressedNdf> {
    let refs: Vec<&[f64]> = images.iter().map(|v| v.as_slice()).collect();
    let stack = stack_blocks(&refs, p.res, p.t)?.ok_or_else(|| {
        Error::InvalidArgument(format!("tensor-envsg: every {what} image is zero"))
    })?;
    let opts = AlsOptions {
        rank: p.rank,
        tol: 1e-6,
        max_iters: 500,
        restarts: 2,
        seed,
        nonnegative: false,
    };
    CompressedNdf::compress(&stack, p.res, &opts)
}

/// Seed 002 Fig 11 on a flat patch: one pixel per footprint of a grid over `map` (the
/// images compressed together as the cases' are), the truth by quadrature and both
/// estimators at `spp` samples, under `sky`, with the paper's (ε, scale).
fn picture(p: &Params, map: &NormalMap, sky: &SgEnv, seed: u64) -> Result<Picture> {
    let s = p.picture_stride;
    let side = p.map_size / s;
    let sp = sigma_p(s, 0);
    let images: Vec<Vec<f64>> = (0..side * side)
        .into_par_iter()
        .map(|k| {
            let (x, y) = (
                (s / 2 + (k % side) * s) as f64,
                (s / 2 + (k / side) * s) as f64,
            );
            pndf_image_separable(map, x, y, sp, p.sigma_r, p.res)
        })
        .collect::<Result<_>>()?;
    let ndf = compress(p, &images, seed, "picture footprint")?;
    let v = p.view_deg.to_radians();
    let o = Vector3::new(v.sin(), 0.0, v.cos());
    let (eps, scale) = (0.3, 0.5);
    let pixels: Vec<(f64, f64, f64)> = (0..side * side)
        .into_par_iter()
        .map(|k| {
            let sh = Shading {
                ndf: &ndf,
                image: k,
                o,
            };
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed.wrapping_add(k as u64));
            let (mut a, mut b) = (0.0, 0.0);
            for _ in 0..p.spp {
                a += sh.sample(sky, Read::Point, rng.random())?;
                b += sh.sample(sky, Read::Prefiltered { eps, scale }, rng.random())?;
            }
            Ok((sh.reference(sky, 8), a / p.spp as f64, b / p.spp as f64))
        })
        .collect::<Result<_>>()?;
    // the mean over pixels of (image − truth)² over the truth's mean square, ± the s.e.
    // of that mean (the pixels' samples are independent; the denominator is the truth's)
    let t2 = pixels.iter().map(|q| q.0 * q.0).sum::<f64>() / pixels.len() as f64;
    let rel = |f: &dyn Fn(&(f64, f64, f64)) -> f64| {
        let v: Vec<f64> = pixels.iter().map(|q| (f(q) - q.0).powi(2) / t2).collect();
        Figure::mean_of(&v)
    };
    Ok(Picture {
        side,
        stride: s,
        spp: p.spp,
        eps,
        scale,
        rel_mse_point: rel(&|q| q.1),
        rel_mse_prefiltered: rel(&|q| q.2),
        reference: pixels.iter().map(|q| q.0).collect(),
        point: pixels.iter().map(|q| q.1).collect(),
        prefiltered: pixels.iter().map(|q| q.2).collect(),
    })
}

/// Fig 11's verdict from the rows at the paper's (ε 0.3, scale 0.5), where the grid has them.
fn fig11(cases: &[Case]) -> Fig11 {
    let rows: Vec<&Row> = cases
        .iter()
        .filter_map(|c| c.rows.iter().find(|r| r.eps == 0.3 && r.scale == 0.5))
        .collect();
    let acting: Vec<f64> = rows
        .iter()
        .filter(|r| r.q.1 > 1)
        .map(|r| r.var_ratio.value)
        .collect();
    let range = |v: &mut dyn Iterator<Item = f64>| {
        v.fold((f64::INFINITY, f64::NEG_INFINITY), |a, x| {
            (a.0.min(x), a.1.max(x))
        })
    };
    let var_ratio = range(&mut acting.iter().copied());
    let bias = range(&mut rows.iter().map(|r| r.bias.value));
    let visible_bias = rows
        .iter()
        .filter(|r| r.bias.value.abs() > 0.02 && r.bias.value.abs() > 3.0 * r.bias.error)
        .count();
    let lower = !acting.is_empty() && var_ratio.0 > 2.0;
    let verdict = match (rows.is_empty(), lower, visible_bias) {
        (true, _, _) => "not judged: the grid lacks the paper's (ε 0.3, scale 0.5)".to_string(),
        (false, false, _) => "refuted: prefiltering does not lower the variance by 2× in every case it acts in".to_string(),
        (false, true, 0) => "holds: the variance falls and no bias exceeds 2 % beyond 3 s.e.".to_string(),
        (false, true, k) => format!(
            "holds with a caveat: the variance falls {:.1}–{:.1}× where the square exceeds a pixel, but {k} of {} cases carry a bias beyond 2 % and 3 s.e. ({:+.1} % to {:+.1} %)",
            var_ratio.0,
            var_ratio.1,
            rows.len(),
            100.0 * bias.0,
            100.0 * bias.1
        ),
    };
    Fig11 {
        var_ratio,
        bias,
        visible_bias,
        verdict,
    }
}

/// The `environment` that names the generated sky.
const PROCEDURAL: &str = "procedural";

pub(crate) fn compute(c: &Ctx) -> Result<Computed> {
    let p: Params = c.params()?;
    let seed = c.spec.seed;
    // the environment and its SG fit, its error at two samplings of the environment
    // the procedural sky's second sampling is twice as fine; a user's map's is its 2×2 average
    let (env, second, environment) = if p.environment == PROCEDURAL {
        let (w, h) = p.env_size;
        (
            Env::procedural(w, h, p.sun)?,
            Env::procedural(2 * w, 2 * h, p.sun)?,
            format!("A procedural sky ({w}×{h} equirectangular, z up: a sun of radiance {} within 3° of 40° from the zenith, sky 0.6 + 0.4 z, ground 0.2)", p.sun),
        )
    } else {
        let env = Env::from_png(std::path::Path::new(&p.environment), p.env_scale)?;
        let second = env.halved()?;
        let text = format!("The environment map {} ({}×{} equirectangular, z up, row 0 at the zenith; sRGB decoded to linear luminance × {})", p.environment, env.width, env.height, p.env_scale);
        (env, second, text)
    };
    let sgs = fit(&env, p.lobes, p.axes, &p.fit_lambdas)?;
    let fitted = SgFit {
        environment,
        lobes: sgs.lobes.clone(),
        rel_error: [env.rel_error(&sgs), second.rel_error(&sgs)],
        resolutions: [(env.width, env.height), (second.width, second.height)],
    };
    crate::progress::stamp("tensor-envsg: environment fitted; footprints next");
    // the footprints' images, compressed together
    let map = NormalMap::procedural(p.map, p.map_size, seed)?;
    let centre = (p.map_size / 2) as f64;
    let images: Vec<Vec<f64>> = p
        .levels
        .iter()
        .map(|&l| pndf_image(&map, centre, centre, sigma_p(p.stride, l), p.sigma_r, p.res))
        .collect::<Result<_>>()?;
    let ndf = compress(&p, &images, seed, "footprint")?;
    // the lightings: single SGs on the mirror direction, then the fitted environment
    let v = p.view_deg.to_radians();
    let mirror = Vector3::new(-v.sin(), 0.0, v.cos());
    let mut lightings: Vec<(String, SgEnv)> = p
        .lambdas
        .iter()
        .map(|&l| {
            Ok((
                format!("one SG, λ = {l}"),
                SgEnv {
                    lobes: vec![Sg::new(mirror, l, 1.0)?],
                },
            ))
        })
        .collect::<Result<_>>()?;
    crate::progress::stamp("tensor-envsg: footprints compressed; the picture next");
    let picture = picture(&p, &map, &sgs, seed)?;
    crate::progress::stamp("tensor-envsg: picture drawn; the cases next");
    lightings.push((format!("the fitted sky ({} SGs)", sgs.lobes.len()), sgs));
    let jobs: Vec<(usize, usize)> = (0..p.levels.len())
        .flat_map(|f| (0..lightings.len()).map(move |l| (f, l)))
        .collect();
    let cases: Vec<Case> = jobs
        .par_iter()
        .map(|&(f, l)| {
            let name = format!(
                "level {} (σ_P = {:.1} texels)",
                p.levels[f],
                sigma_p(p.stride, p.levels[f])
            );
            let s = seed.wrapping_mul(1000) + 100 * (f * lightings.len() + l) as u64;
            case(
                &p,
                &ndf,
                f,
                &lightings[l].1,
                (name, lightings[l].0.clone()),
                s,
            )
        })
        .collect::<Result<_>>()?;
    let mean = |v: Vec<Figure>| {
        let n = v.len() as f64;
        Figure::new(
            v.iter().map(|x| x.value).sum::<f64>() / n,
            v.iter().map(|x| x.error * x.error).sum::<f64>().sqrt() / n,
        )
    };
    let trade = (0..p.eps.len() * p.scales.len())
        .map(|k| Trade {
            eps: cases[0].rows[k].eps,
            scale: cases[0].rows[k].scale,
            mse16: mean(cases.iter().map(|c| c.rows[k].mse16).collect()),
        })
        .collect();
    Ok(Computed {
        spec: c.spec.clone(),
        preset: c.preset,
        result: EnvSg {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            fit: fitted,
            cp_rel_error: ndf.cp().rel_error,
            samples: p.samples,
            point_mse16: mean(cases.iter().map(|c| c.point_mse16).collect()),
            fig11: fig11(&cases),
            cases,
            trade,
            picture,
        },
        p,
    })
}

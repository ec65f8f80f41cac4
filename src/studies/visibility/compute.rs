//! The visibility study's computation: the plan per preset, horizon cases on two height
//! fields, shadow footprints, and the procedural colour, grid, spectral, normal and
//! correlation rows.

use crate::error::Result;
use crate::filters::truth::{compare, Candidate, Footprint, Frame, Truth};
use crate::integrate::Figure;
use crate::microfacet::{Microsurface, NdfKind};
use crate::visibility::horizon::{self, Dir, HdfMoments, LegendreHorizon};
use crate::visibility::procedural::{self, Spectral, Waves};
use crate::visibility::shadow::{self, Method, Occluders, Precision, Receiver, Scene};
use crate::visibility::{correlation, HeightField, Relief};
use nalgebra::{Matrix2, Vector2, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::PI;

/// What fits/visibility.toml sets: the sizes of every measurement.
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Side of the two procedural height fields of the horizon study (a power of two).
    pub height_size: usize,
    /// Footprint levels (2^L texels) of the horizon study.
    pub levels: Vec<usize>,
    /// Footprints per level.
    pub footprints: usize,
    /// Side of the shadow study's occluder maps, its levels and footprints per level.
    pub shadow_size: usize,
    pub shadow_levels: Vec<usize>,
    pub shadow_footprints: usize,
    /// Filter widths of the procedural-colour study.
    pub widths: usize,
    /// Cases per procedural normal map.
    pub normal_cases: usize,
    /// Light samples per lobe.
    pub samples: usize,
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        use crate::fit::spec::{all_within, power_of_two, within};
        power_of_two("height_size", self.height_size, 16, 4096)?;
        power_of_two("shadow_size", self.shadow_size, 16, 4096)?;
        let top = |n: usize| n.trailing_zeros() as usize - 1;
        all_within("levels", &self.levels, 1, top(self.height_size), 16)?;
        all_within(
            "shadow_levels",
            &self.shadow_levels,
            1,
            top(self.shadow_size),
            16,
        )?;
        within("footprints", self.footprints, 1, 10_000)?;
        within("shadow_footprints", self.shadow_footprints, 1, 10_000)?;
        within("widths", self.widths, 2, 100_000)?;
        within("normal_cases", self.normal_cases, 1, 1_000)?;
        within("samples", self.samples, 16, 1 << 20)
    }
}

/// fits/visibility.toml as this build compiled it in: the plan of the commands that run
/// the study's measurements on a user's input (`horizon`).
const SPEC: &str = include_str!("../../../fits/visibility.toml");

/// The study's plan at `preset`, from the compiled-in spec.
pub fn builtin_plan(preset: crate::integrate::Preset) -> crate::error::Result<Plan> {
    crate::fit::spec::FitSpec::compiled_params(SPEC, "fits/visibility.toml", preset)
}

/// Legendre orders of the horizon study.
pub const LEGENDRE_K: [usize; 5] = [2, 4, 8, 16, 32];

/// β's width (radians) in Ashikhmin et al.'s joint form.
pub const ASHIKHMIN_WIDTH: f64 = 0.25;

/// One horizon case: a footprint, a view, a light, the truth and every method.
#[derive(Clone, Debug, Serialize)]
pub struct HorizonCase {
    pub map: String,
    pub level: usize,
    pub hotspot: bool,
    pub v: Dir,
    pub l: Dir,
    pub truth_v: f64,
    pub truth_lv: f64,
    /// V_A(v): Fournier, Tan (erf), Legendre at each order of [`LEGENDRE_K`], then Tan and
    /// Legendre 32 from horizons at v's exact azimuth (diagnostics).
    pub single: Vec<f64>,
    /// V_A(l, v): Fournier's product, Tan + product, Tan + Eq 28, Tan + Ashikhmin,
    /// Legendre (K = 16) + Eq 28.
    pub joint: Vec<f64>,
}

pub(super) fn hash_index(k: usize, n: usize, salt: usize) -> usize {
    (k.wrapping_mul(2654435761)
        .wrapping_add(salt.wrapping_mul(40503))
        + 12345)
        % n.max(1)
}

pub(super) fn horizon_cases(
    maps: &[HeightField],
    plan: &Plan,
    seed: u64,
) -> Result<Vec<HorizonCase>> {
    let mut descs = Vec::new();
    for m in 0..maps.len() {
        for &level in &plan.levels {
            for f in 0..plan.footprints {
                descs.push((m, level, f));
            }
        }
    }
    let out: Vec<Vec<HorizonCase>> = descs
        .par_iter()
        .enumerate()
        .map(|(ci, &(m, level, f))| {
            let hf = &maps[m];
            let nb = hf.size >> level;
            let b = hash_index(f, nb * nb, level);
            let texels = hf.block(level, b % nb, b / nb);
            let thetas = horizon::stored_horizons(hf, &texels);
            let mom = HdfMoments::new(&thetas);
            let leg: Vec<LegendreHorizon> = LEGENDRE_K
                .iter()
                .map(|&k| LegendreHorizon::new(&thetas, k))
                .collect();
            let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (ci as u64).wrapping_mul(0x9E37_79B9));
            let mut cases = Vec::new();
            for &e in &[10f64, 25.0, 45.0] {
                let v = Dir {
                    elev: e.to_radians(),
                    azim: 2.0 * PI * rng.random::<f64>(),
                };
                let lights = [
                    (true, v),
                    (
                        false,
                        Dir {
                            elev: v.elev + 0.08,
                            azim: v.azim + 0.1,
                        },
                    ),
                    (
                        false,
                        Dir {
                            elev: (10.0 + 40.0 * rng.random::<f64>()).to_radians(),
                            azim: 2.0 * PI * rng.random::<f64>(),
                        },
                    ),
                ];
                for (hot, l) in lights {
                    let (tv, tlv) = horizon::exact(hf, &texels, &v, &l);
                    let Some(tlv) = tlv else { continue };
                    let (fv, fl) = (horizon::fournier(&mom, &v), horizon::fournier(&mom, &l));
                    let (gv, gl) = (horizon::tan_erf(&mom, &v), horizon::tan_erf(&mom, &l));
                    let c = v.cos_between(&l);
                    let (lv16, ll16) = (leg[3].eval(&v), leg[3].eval(&l));
                    let mut single = vec![fv, gv];
                    single.extend(leg.iter().map(|lg| lg.eval(&v)));
                    // diagnostics: the same forms with every texel's horizon at v's own
                    // azimuth (what four stored azimuths lose to interpolation)
                    let at_v: Vec<[f64; 4]> = texels
                        .iter()
                        .map(|&(i, j)| [horizon::horizon(hf, i, j, v.azim); 4])
                        .collect();
                    single.push(horizon::tan_erf(&HdfMoments::new(&at_v), &v));
                    single.push(LegendreHorizon::new(&at_v, 32).eval(&v));
                    cases.push(HorizonCase {
                        map: hf.name.clone(),
                        level,
                        hotspot: hot,
                        v,
                        l,
                        truth_v: tv,
                        truth_lv: tlv,
                        single,
                        joint: vec![
                            horizon::joint_product(fl, fv),
                            horizon::joint_product(gl, gv),
                            horizon::joint_eq28(gl, gv, c),
                            horizon::joint_ashikhmin(gl, gv, c, ASHIKHMIN_WIDTH),
                            horizon::joint_eq28(ll16, lv16, c),
                        ],
                    });
                }
            }
            cases
        })
        .collect();
    Ok(out.into_iter().flatten().collect())
}

/// The shadow methods measured, in report order.
pub fn shadow_methods() -> Vec<Method> {
    let mut m = vec![Method::Vsm];
    for t in [4, 8, 16, 32] {
        m.push(Method::Csm {
            terms: t,
            fixed: false,
        });
        m.push(Method::Csm {
            terms: t,
            fixed: true,
        });
    }
    for c in [5.0, 11.0, 20.0, 40.0, 80.0] {
        m.push(Method::Esm { c });
    }
    for c in [2.0, 5.5, 10.0, 20.0, 40.0] {
        m.push(Method::Evsm { c });
    }
    m
}

/// One shadow footprint: PCF truth, Eq 33's version, and each method at f32 and f16.
#[derive(Clone, Debug, Serialize)]
pub struct ShadowCase {
    pub scene: Scene,
    pub level: usize,
    pub pcf: f64,
    pub pcf_mean_depth: f64,
    /// Some texel of the footprint is deeper than d̄ (ESM's divergence region d < Z).
    pub diverging: bool,
    pub f32: Vec<f64>,
    pub f16: Vec<f64>,
}

pub(super) fn shadow_cases(plan: &Plan) -> Vec<ShadowCase> {
    let mut scenes = Vec::new();
    for o in [
        Occluders::Plane,
        Occluders::Layers,
        Occluders::Fence,
        Occluders::Sphere,
    ] {
        for r in [Receiver::Parallel, Receiver::Tilted] {
            scenes.push(Scene {
                occluders: o,
                receiver: r,
                size: plan.shadow_size,
            });
        }
    }
    let methods = shadow_methods();
    let out: Vec<Vec<ShadowCase>> = scenes
        .par_iter()
        .map(|sc| {
            let z = sc.depth_map();
            let hf = HeightField {
                name: String::new(),
                size: sc.size,
                h: vec![0.0; sc.size * sc.size],
            };
            let mut cases = Vec::new();
            for &level in &plan.shadow_levels {
                let nb = sc.size >> level;
                for f in 0..plan.shadow_footprints {
                    let b = hash_index(f, nb * nb, level + 7);
                    let texels = hf.block(level, b % nb, b / nb);
                    let (own, avg, dbar) = shadow::pcf(sc, &z, &texels);
                    let diverging = texels
                        .iter()
                        .any(|&(i, j)| z[j * sc.size + i] > dbar + 1e-9);
                    let eval = |p: Precision| -> Vec<f64> {
                        methods
                            .iter()
                            .map(|m| m.lookup(&m.filter(&z, sc.size, &texels, p), dbar))
                            .collect()
                    };
                    cases.push(ShadowCase {
                        scene: *sc,
                        level,
                        pcf: own,
                        pcf_mean_depth: avg,
                        diverging,
                        f32: eval(Precision::F32),
                        f16: eval(Precision::F16),
                    });
                }
            }
            cases
        })
        .collect();
    out.into_iter().flatten().collect()
}

/// Procedural colour: per width, mean |error| of the point sample, global fading and the
/// analytic box average (1D pulse train) and of the clamped spectral sums.
#[derive(Clone, Debug, Serialize)]
pub struct ColourRow {
    pub width: f64,
    /// (mean, s.e.) of |error|: point sample, faded, analytic.
    pub pulse: Vec<Figure>,
}

pub(super) fn colour_rows(plan: &Plan, seed: u64) -> Vec<ColourRow> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    [0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 5.0]
        .iter()
        .map(|&w| {
            let mut e = vec![Vec::new(), Vec::new(), Vec::new()];
            for _ in 0..plan.widths {
                let x = 100.0 * rng.random::<f64>();
                let t = procedural::pulse_integral_by_cells(x - 0.5 * w, x + 0.5 * w) / w;
                e[0].push((procedural::pulse(x) - t).abs());
                e[1].push((procedural::faded(x, w) - t).abs());
                e[2].push((procedural::box_average(x - 0.5 * w, x + 0.5 * w) - t).abs());
            }
            ColourRow {
                width: w,
                pulse: e.iter().map(|v| Figure::mean_of(v)).collect(),
            }
        })
        .collect()
}

/// The sheared 2D grid: (scale, rotation°, anisotropy, mean |separable − exact| ± s.e.).
pub(super) fn grid_rows(plan: &Plan, seed: u64) -> Vec<(f64, f64, f64, Figure)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x61);
    let mut out = Vec::new();
    for &s in &[0.5, 1.0, 2.0, 4.0] {
        for &rot in &[0.0f64, 15.0, 45.0] {
            for &an in &[1.0, 4.0] {
                let th = rot.to_radians();
                let e1 = Vector2::new(th.cos(), th.sin()) * s;
                let e2 = Vector2::new(-th.sin(), th.cos()) * (s / an);
                let errs: Vec<f64> = (0..plan.widths / 4)
                    .map(|_| {
                        let c =
                            Vector2::new(50.0 * rng.random::<f64>(), 50.0 * rng.random::<f64>());
                        (procedural::grid_average_separable(c, e1, e2)
                            - procedural::grid_average_exact(c, e1, e2))
                        .abs()
                    })
                    .collect();
                out.push((s, rot, an, Figure::mean_of(&errs)));
            }
        }
    }
    out
}

/// Frequency clamping: (clamp threshold c or 0 for no filtering, mean |error| ± s.e.) over
/// widths 2^−8…2^−1 and seeded positions.
pub(super) fn spectral_rows(plan: &Plan, seed: u64) -> Vec<(f64, Figure)> {
    let f = Spectral::octaves(8, seed);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5C);
    let pts: Vec<(f64, f64)> = (0..plan.widths)
        .map(|_| {
            (
                rng.random::<f64>(),
                2f64.powf(-8.0 + 7.0 * rng.random::<f64>()),
            )
        })
        .collect();
    [0.0, 0.25, 0.5, 1.0, 2.0]
        .iter()
        .map(|&c| {
            let e: Vec<f64> = pts
                .iter()
                .map(|&(x, w)| {
                    let approx = if c == 0.0 {
                        f.clamped(x, 0.0, 1.0)
                    } else {
                        f.clamped(x, w, c)
                    };
                    (approx - f.box_average(x, w)).abs()
                })
                .collect();
            (c, Figure::mean_of(&e))
        })
        .collect()
}

/// Procedural normals (§6.2): per footprint width, the relative L2 lobe error of the clamped
/// normal alone, Bruneton et al.'s clamped-variance lobe and the box-averaged normal with
/// the vMF 2/κ rule, against the footprint truth.
#[derive(Clone, Debug, Serialize)]
pub struct NormalRow {
    pub width: f64,
    pub l2: Vec<Figure>,
}

pub(super) fn normal_rows(plan: &Plan, seed: u64) -> Result<Vec<NormalRow>> {
    let waves = Waves::new(seed, 0.3);
    let alpha = 0.1;
    let kind = NdfKind::Ggx;
    let widths = [2.0, 4.0, 8.0, 16.0];
    widths
        .par_iter()
        .map(|&w| {
            let mut errs = vec![Vec::new(), Vec::new(), Vec::new()];
            let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (w as u64));
            for case in 0..plan.normal_cases {
                let c = Vector2::new(100.0 * rng.random::<f64>(), 100.0 * rng.random::<f64>());
                let n = ((4.0 * w) as usize).clamp(16, 32);
                let normals: Vec<Vector3<f64>> = (0..n * n)
                    .map(|k| {
                        let p = c + Vector2::new(
                            ((k % n) as f64 + 0.5) / n as f64 - 0.5,
                            ((k / n) as f64 + 0.5) / n as f64 - 0.5,
                        ) * w;
                        waves.normal(p, f64::INFINITY)
                    })
                    .collect();
                let fp = Footprint::uniform(normals);
                let truth = Truth::new(kind, alpha, &fp)?;
                let kc = PI / w; // wavelengths below 2w are clamped
                let n0 = waves.normal(c, kc);
                let cov = waves.clamped_covariance(kc);
                let mean = fp.mean();
                let r = mean.norm().min(1.0);
                let a_vmf = crate::filters::rules::vmf(alpha, r, 2.0);
                let a = Matrix2::identity() * (alpha * alpha) + cov * 2.0;
                let bruneton = Microsurface::new(kind, crate::microfacet::Roughness::matrix(a)?);
                let cands = vec![
                    Candidate::iso("clamped normal", kind, n0, alpha)?,
                    Candidate::surface("Bruneton et al.", bruneton, Frame::around(n0)),
                    Candidate::iso(
                        "box-averaged normal + vMF 2/κ",
                        kind,
                        mean.normalize(),
                        a_vmf.max(1e-4),
                    )?,
                ];
                for (vi, th) in [0.0f64, 60.0].iter().enumerate() {
                    let t = th.to_radians();
                    let v = Vector3::new(t.sin(), 0.0, t.cos());
                    let res = compare(
                        &truth,
                        &v,
                        &cands,
                        plan.samples,
                        seed ^ ((case * 2 + vi) as u64),
                    )?;
                    for (e, r) in errs.iter_mut().zip(&res) {
                        e.push(r.l2.value);
                    }
                }
            }
            Ok(NormalRow {
                width: w,
                l2: errs.iter().map(|e| Figure::mean_of(e)).collect(),
            })
        })
        .collect()
}

/// The cost of separating correlated maps (§8.1): per (level, view elevation), mean ± s.e.
/// of the colour–slope and visibility–normal relative L2.
pub(super) fn correlation_rows(
    plan: &Plan,
    seed: u64,
) -> Result<Vec<(usize, f64, Figure, Figure)>> {
    let hf = HeightField::procedural(Relief::Bumps, plan.height_size.min(128), seed + 1)?;
    let mut descs = Vec::new();
    for &level in &[2usize, 3] {
        for &e in &[20.0f64, 45.0, 70.0] {
            descs.push((level, e));
        }
    }
    descs
        .par_iter()
        .map(|&(level, e)| {
            let nb = hf.size >> level;
            let (mut c, mut v) = (Vec::new(), Vec::new());
            for f in 0..plan.normal_cases {
                let b = hash_index(f, nb * nb, level + 3);
                let texels = hf.block(level, b % nb, b / nb);
                let dir = Dir {
                    elev: e.to_radians(),
                    azim: 0.3 + f as f64,
                };
                let (a, b2) =
                    correlation::separation_cost(&hf, &texels, NdfKind::Ggx, 0.3, &dir, 24)?;
                if a.is_finite() {
                    c.push(a);
                }
                if b2.is_finite() {
                    v.push(b2);
                }
            }
            Ok((level, e, Figure::mean_of(&c), Figure::mean_of(&v)))
        })
        .collect()
}

/// Everything the study measured.
#[derive(Serialize)]
pub struct Measured {
    pub plan: Plan,
    pub horizon: Vec<HorizonCase>,
    pub shadow: Vec<ShadowCase>,
    pub colour: Vec<ColourRow>,
    pub grid: Vec<(f64, f64, f64, Figure)>,
    pub spectral: Vec<(f64, Figure)>,
    pub normals: Vec<NormalRow>,
    pub correlation: Vec<(usize, f64, Figure, Figure)>,
}

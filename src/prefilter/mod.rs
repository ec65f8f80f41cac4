//! `prefilter`: a normal map's variance turned into a roughness mip chain that an engine
//! loads as it is (KTX2 with every level, one PNG per level), with the normal map's own
//! mips. The rule that turns a footprint's mean normal length r = ‖μ‖ into roughness is
//! one of the footprint filters measured in results/filters.md (seed 004 §3.2.1; vMF
//! after Banerjee et al. as in Neubelt & Pettineo and Karis), or one of the engines'
//! tools as they ship (Filament's roughness-prefilter, Godot's import-time limiter); by
//! default the one the measurements rank best. Pipeline: inputs (`input`) → statistics
//! pyramid (`chain`) → rule per texel ([`texel_alpha`], the registry's rule) → files (`output`).

pub mod chain;
pub mod input;
pub mod output;

use crate::error::{Error, Result};
use crate::filters::registry::{Domain, Filter, MapRule, Rule};
use std::path::{Path, PathBuf};

/// The rule the tool applies: the measured best, or one filter of the registry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Choice {
    /// the rule with the smallest measured mean lobe error (results/fits/filters.json)
    Best,
    Filter(Filter),
}

impl Choice {
    /// The choice of a key: "best" or an [`eligible`] filter's key (typed error otherwise).
    pub fn parse(key: &str) -> Result<Choice> {
        if key == "best" {
            return Ok(Choice::Best);
        }
        eligible()
            .find(|f| f.key() == key)
            .map(Choice::Filter)
            .ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "--filter {}: not a map filter with an isotropic α′; valid: best, {}",
                    crate::error::quoted(key),
                    eligible().map(|f| f.key()).collect::<Vec<_>>().join(", ")
                ))
            })
    }

    /// The keys the CLI accepts, each with its label as help.
    pub fn keys() -> clap::builder::PossibleValuesParser {
        use clap::builder::PossibleValue;
        clap::builder::PossibleValuesParser::new(
            std::iter::once(PossibleValue::new("best").help(
                "the measured rule with the smallest mean lobe error (results/fits/filters.json)",
            ))
            .chain(eligible().map(|f| PossibleValue::new(f.key()).help(f.label()))),
        )
    }
}

/// The filters a roughness chain can carry: every map filter of the registry with an
/// isotropic α′ that returns the base roughness where the footprint does not vary
/// (r = 1), refitted ones included. Not LEAN (a matrix), and not seed 000's Eq 5 + Eq 7
/// as printed (0.07α² + 0.94α at r = 1, not α: it is measured, not shipped).
pub fn eligible() -> impl Iterator<Item = Filter> {
    Filter::all().filter(|f| {
        f.domain() == Domain::Map
            && !matches!(f.rule(), Rule::Map(MapRule::Lean | MapRule::Seed000Paper))
    })
}

/// α′ of a footprint with mean-normal length r, mean α² and mean perceptual roughness p
/// under `rule` (f64; r = 1 gives the base). The engines' tools work on the box-filtered
/// perceptual roughness (α = p²), the others on √⟨α²⟩. The moment rule's
/// ρ⁻¹(rρ(α)) takes rρ and 1 − rρ = (1 − ρ) + (1 − r)ρ, each without cancellation, and
/// the inverse of [`crate::multiscale::mrl::alpha_from_pair`] (NaN where it fails, which
/// the caller reports).
pub fn texel_alpha(rule: MapRule, r: f64, mean_a2: f64, mean_p: f64) -> f64 {
    let a = if rule.on_perceptual() {
        mean_p * mean_p
    } else {
        mean_a2.max(0.0).sqrt()
    };
    let moment = || {
        let r = crate::filters::rules::clamp_r(r);
        let (rho, one_minus) = if a > 0.0 {
            crate::multiscale::mrl::mrl_pair(a)
        } else {
            (1.0, 0.0)
        };
        // (‖b̄‖, 1 − ‖b̄‖) of the footprint, each without cancellation
        let (b, y) = (r * rho, one_minus + (1.0 - r) * rho);
        if y <= 0.0 {
            return a;
        }
        crate::multiscale::mrl::alpha_from_pair(b.min(1.0), y.min(1.0)).unwrap_or(f64::NAN)
    };
    rule.alpha(a, r, moment).unwrap_or(f64::NAN)
}

/// A filter's measured error: mean lobe L2 over the footprint study's cases ± s.e.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Measured {
    pub filter: Filter,
    pub l2: crate::integrate::Figure,
    pub what: String,
}

/// What results/fits/filters.json says about the eligible filters: every measured error,
/// and the refitted constants by family (GGX). Empty when the study has not been run; a
/// malformed file is an error.
#[derive(Debug)]
pub struct Evidence {
    pub measured: Vec<Measured>,
    pub fitted: Vec<(String, f64)>,
}

impl Evidence {
    /// The GGX constant of a refitted family.
    pub fn constant(&self, family: &str) -> Option<f64> {
        self.fitted.iter().find(|f| f.0 == family).map(|f| f.1)
    }
}

/// Read the evidence from `results`/fits/filters.json.
pub fn measured(results: &Path) -> Result<Evidence> {
    let Some(j) = crate::results::read::<crate::results::filters::Filters>(results)? else {
        return Ok(Evidence {
            measured: Vec::new(),
            fitted: Vec::new(),
        });
    };
    let mut out = Vec::new();
    for f in eligible() {
        if let Some(e) = f.uses().summary.and_then(|k| j.summary.get(k)) {
            out.push(Measured {
                filter: f,
                l2: e.l2,
                what: "GGX, every map, level and view of the footprint study".into(),
            });
        } else if let Some(x) = f.family().and_then(|fam| j.fitted(fam, "GGX")) {
            out.push(Measured {
                filter: f,
                l2: x.held_out.l2,
                what: "GGX, the held-out footprints and views only (not comparable with the all-case means)".into(),
            });
        }
    }
    let fitted = j
        .fitted
        .iter()
        .filter(|f| f.ndf == "GGX")
        .map(|f| (f.family.clone(), f.constant))
        .collect();
    Ok(Evidence {
        measured: out,
        fitted,
    })
}

/// How a stored roughness value relates to α.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
pub enum Store {
    /// perceptual roughness p = √α (glTF, Bevy, three.js, Godot, Filament)
    Perceptual,
    /// α itself
    Alpha,
}

/// The texel format of the roughness chain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
pub enum Format {
    R8,
    R16,
    R16f,
}

/// How the roughness chain is laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
pub enum Layout {
    /// one channel (Godot's roughness_texture with its channel set to R; Filament; any
    /// engine that reads a single-channel roughness map)
    R,
    /// a glTF metallicRoughness / ORM texture: R occlusion, G roughness, B metallic, A 1
    /// (Bevy's metallic_roughness_texture, three.js roughnessMap/metalnessMap, glTF);
    /// R and B carried from an RGB(A) roughness input (box mips), else 1 and 0
    Gltf,
}

/// Whether the normal mips are renormalised.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
pub enum NormalMips {
    /// unit normals (the roughness mips carry the variance)
    Renormalised,
    /// the mean normal as it is (‖μ‖ < 1), for shaders that read its length
    Raw,
}

/// Everything the tool is asked to do.
#[derive(Clone, Debug)]
pub struct Options {
    pub input: PathBuf,
    pub roughness: Option<PathBuf>,
    pub alpha: Option<f64>,
    pub channel: input::Channel,
    pub filter: Choice,
    pub store: Store,
    pub format: Format,
    pub layout: Layout,
    pub normals: NormalMips,
    pub reconstruct_z: bool,
    /// Where results/fits/filters.json is read from (the measured errors).
    pub results: PathBuf,
}

/// What the tool computed: the chain and the rule with its evidence.
pub struct Outcome {
    pub options: Options,
    /// The filter applied ([`Choice::Best`] resolved) and its rule (a refitted one's
    /// with its constant).
    pub filter: Filter,
    pub rule: MapRule,
    pub evidence: Evidence,
    pub width: usize,
    pub height: usize,
    pub input_bits: u8,
    pub roughness_size: Option<(usize, usize, u8)>,
    pub levels: Vec<chain::Level>,
    /// Per level, the stored roughness value (perceptual or α, in [0, 1]) of each texel.
    pub stored: Vec<Vec<f32>>,
    /// Per level, texels whose α′ exceeded 1 and were clamped.
    pub clamped: Vec<usize>,
    /// The glTF layout's other channels: (texels per roughness texel at level 0, their
    /// box mips at the roughness map's resolution); None without an RGB(A) input.
    pub others: Option<(usize, Vec<(usize, usize, Vec<[f32; 2]>)>)>,
}

impl Outcome {
    /// A filter's label, a refitted one's with its constant.
    pub fn label(&self, f: Filter) -> String {
        f.label_with(f.family().and_then(|family| self.evidence.constant(family)))
    }

    /// (occlusion, metallic) under texel k of level l (glTF layout): the roughness map's
    /// own mip where it has one of that size, else its base read nearest; (1, 0) without one.
    pub fn others_at(&self, l: usize, k: usize) -> [f32; 2] {
        let Some((scale, mips)) = &self.others else {
            return [1.0, 0.0];
        };
        let lv = &self.levels[l];
        let (x, y) = (k % lv.width, k / lv.width);
        let shift = scale.trailing_zeros() as usize;
        if l >= shift {
            let (w, _, v) = &mips[(l - shift).min(mips.len() - 1)];
            v[y.min(v.len() / w - 1) * w + x.min(w - 1)]
        } else {
            let s = 1usize << (shift - l);
            let (w, _, v) = &mips[0];
            v[(y / s) * w + x / s]
        }
    }
}

/// The smallest accepted constant α: the pyramid holds ⟨α²⟩ in f32, whose normal range
/// ends near 1e-38 (a 16-bit map's smallest step, 1/65535 in perceptual roughness, is
/// α ≈ 2.3e-10, above it).
pub const MIN_ALPHA: f64 = 1e-12;

/// Decode, check and compute (no file is touched).
pub fn run(options: Options) -> Result<Outcome> {
    match (options.roughness.is_some(), options.alpha) {
        (true, Some(_)) | (false, None) => {
            return Err(Error::InvalidArgument(
                "give exactly one of --roughness ROUGH.png and --alpha A".into(),
            ))
        }
        // ⟨α²⟩ is held in f32: α below 1e-12 would lose its square to underflow
        (_, Some(a)) if !(a.is_finite() && (MIN_ALPHA..=1.0).contains(&a)) => {
            return Err(Error::InvalidArgument(format!(
                "--alpha {a:e}: the base α must lie in [{MIN_ALPHA:e}, 1]"
            )))
        }
        _ => {}
    }
    let normals = input::normals(&options.input, options.reconstruct_z)?;
    let (w, h, bits) = (normals.width, normals.height, normals.bits);
    let rough = match (&options.roughness, options.alpha) {
        (Some(p), _) => input::roughness(p, options.channel, w, h)?,
        (None, Some(a)) => input::Roughness::Constant(a),
        _ => unreachable!("checked above"),
    };
    let roughness_size = match &rough {
        input::Roughness::Map {
            width,
            height,
            bits,
            ..
        } => Some((*width, *height, *bits)),
        input::Roughness::Constant(_) => None,
    };
    let evidence = measured(&options.results)?;
    let filter = match options.filter {
        // the all-case means only: a refit's held-out mean is not comparable with them
        Choice::Best => evidence
            .measured
            .iter()
            .filter(|m| m.filter.family().is_none())
            .min_by(|a, b| a.l2.value.total_cmp(&b.l2.value))
            .map_or(Filter::of("vmf-2"), |m| m.filter),
        Choice::Filter(f) => f,
    };
    let Rule::Map(rule) = filter.rule_with(|family| evidence.constant(family))? else {
        unreachable!("every eligible filter is a map filter")
    };
    let others = match (&rough, options.layout) {
        (
            input::Roughness::Map {
                width,
                height,
                scale,
                others: Some(o),
                ..
            },
            Layout::Gltf,
        ) => Some((*scale, chain::box_mips(*width, *height, o.clone()))),
        _ => None,
    };
    let levels = chain::pyramid(normals, &rough);
    let mut stored = Vec::with_capacity(levels.len());
    let mut clamped = Vec::with_capacity(levels.len());
    let mut nonfinite = 0usize;
    for lv in &levels {
        let mut over = 0;
        let values: Vec<f32> = (0..lv.width * lv.height)
            .map(|k| {
                let a = texel_alpha(rule, lv.r(k), lv.mean_a2[k] as f64, lv.mean_p[k] as f64);
                if !a.is_finite() {
                    nonfinite += 1;
                }
                if a > 1.0 {
                    over += 1;
                }
                let a = a.clamp(0.0, 1.0);
                (match options.store {
                    Store::Perceptual => a.sqrt(),
                    Store::Alpha => a,
                }) as f32
            })
            .collect();
        stored.push(values);
        clamped.push(over);
    }
    if nonfinite > 0 {
        return Err(Error::InvalidArgument(format!(
            "--filter {}: α′ is not finite at {nonfinite} texels (no chain written)",
            filter.key()
        )));
    }
    Ok(Outcome {
        options,
        filter,
        rule,
        evidence,
        width: w,
        height: h,
        input_bits: bits,
        roughness_size,
        levels,
        stored,
        clamped,
        others,
    })
}

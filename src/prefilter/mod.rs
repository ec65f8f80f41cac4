//! `prefilter`: a normal map's variance turned into a roughness mip chain that an engine
//! loads as it is (KTX2 with every level, one PNG per level), with the normal map's own
//! mips. The rule that turns a footprint's mean normal length r = ‖μ‖ into roughness is
//! one of the footprint filters measured in results/filters.md (seed 004 §3.2.1; vMF
//! after Banerjee et al. as in Neubelt & Pettineo and Karis), or one of the engines'
//! tools as they ship (Filament's roughness-prefilter, Godot's import-time limiter); by
//! default the one the measurements rank best. Pipeline: inputs (`input`) → statistics
//! pyramid (`chain`) → rule per texel (`Filter::alpha`) → files (`output`).

pub mod chain;
pub mod input;
pub mod output;

use crate::error::{Error, Result};
use crate::filters::rules;
use std::path::{Path, PathBuf};

/// A rule from (r, mean α², mean perceptual roughness) of a footprint to its α′.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
pub enum Filter {
    /// the measured rule with the smallest mean lobe error (results/fits/filters.json)
    Best,
    /// no normal-variance term: α′² = ⟨α²⟩ (the mip of α² alone)
    None,
    /// Toksvig, Blinn–Phong form
    ToksvigBp,
    /// Toksvig α′² = ⟨α²⟩ + 2σ², σ² = (1 − r)/r
    Toksvig,
    /// vMF α′² = ⟨α²⟩ + 2/κ, κ = (3r − r³)/(1 − r²)
    Vmf,
    /// vMF with the constant refitted against the footprint-averaged GGX BRDF
    VmfFitted,
    /// Filament's roughness-prefilter: p′² = ⟨p⟩² + 2/κ on perceptual roughness
    Filament,
    /// Godot's import roughness limiter: p′² = ⟨p⟩² + min(0.75/κ, 0.16) on perceptual roughness
    Godot,
}

impl Filter {
    /// Every concrete rule.
    pub const ALL: [Filter; 7] = [
        Filter::None,
        Filter::ToksvigBp,
        Filter::Toksvig,
        Filter::Vmf,
        Filter::VmfFitted,
        Filter::Filament,
        Filter::Godot,
    ];

    /// The CLI name.
    pub fn name(self) -> &'static str {
        match self {
            Filter::Best => "best",
            Filter::None => "none",
            Filter::ToksvigBp => "toksvig-bp",
            Filter::Toksvig => "toksvig",
            Filter::Vmf => "vmf",
            Filter::VmfFitted => "vmf-fitted",
            Filter::Filament => "filament",
            Filter::Godot => "godot",
        }
    }

    /// The rule in words.
    pub fn formula(self, fitted_c: f64) -> String {
        match self {
            Filter::Best => "the best measured rule".into(),
            Filter::None => "α′² = ⟨α²⟩ (no normal-variance term)".into(),
            Filter::ToksvigBp => "Toksvig, Blinn–Phong form: s = 2/⟨α²⟩ − 2, s′ = s/(1 + sσ²), α′ = √(2/(s′ + 2)), σ² = (1 − r)/r".into(),
            Filter::Toksvig => "α′² = ⟨α²⟩ + 2σ², σ² = (1 − r)/r".into(),
            Filter::Vmf => "α′² = ⟨α²⟩ + 2/κ, κ = (3r − r³)/(1 − r²)".into(),
            Filter::VmfFitted => format!("α′² = ⟨α²⟩ + c/κ, c = {fitted_c:.4} (refitted, GGX)"),
            Filter::Filament => "p′² = ⟨p⟩² + 2/κ on perceptual roughness p (α = p²), as Filament's roughness-prefilter".into(),
            Filter::Godot => "p′² = ⟨p⟩² + min(0.75/κ, 0.16) on perceptual roughness p, as Godot's Image::generate_mipmap_roughness".into(),
        }
    }

    /// Its entry in results/fits/filters.json `summary` (GGX, all maps), if measured.
    pub fn summary_key(self) -> Option<&'static str> {
        match self {
            Filter::None => Some("none-map"),
            Filter::ToksvigBp => Some("toksvig-bp"),
            Filter::Toksvig => Some("toksvig"),
            Filter::Vmf => Some("vmf"),
            Filter::Filament => Some("filament"),
            Filter::Godot => Some("godot"),
            _ => None,
        }
    }

    /// α′ of a footprint with mean-normal length r, mean α² and mean perceptual
    /// roughness p (f64; r is clamped as in the shading forms, r = 1 gives the base).
    pub fn alpha(self, r: f64, mean_a2: f64, mean_p: f64, fitted_c: f64) -> f64 {
        let a = mean_a2.max(0.0).sqrt();
        match self {
            Filter::Best | Filter::Vmf => rules::vmf(a, r, 2.0),
            Filter::None => a,
            Filter::ToksvigBp => rules::toksvig_bp(a, r),
            Filter::Toksvig => rules::toksvig_alpha2(a, r, 2.0),
            Filter::VmfFitted => rules::vmf(a, r, fitted_c),
            // α′ = p′² with p′² as the engines compute it, on their box-filtered p
            Filter::Filament => rules::filament_prefilter(mean_p * mean_p, r),
            Filter::Godot => rules::godot_limiter(mean_p * mean_p, r),
        }
    }
}

/// A filter's measured error: mean lobe L2 over the footprint study's cases ± s.e.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Measured {
    pub filter: Filter,
    pub l2_mean: f64,
    pub l2_se: f64,
    pub what: String,
}

/// Every measured error of the concrete rules, read from `results`/fits/filters.json
/// (empty when the study has not been run; a malformed file is an error).
pub fn measured(results: &Path) -> Result<(Vec<Measured>, f64)> {
    let Some(j) = crate::results::read::<crate::results::filters::Filters>(results)? else {
        return Ok((Vec::new(), 2.0));
    };
    let fitted = j
        .fitted
        .iter()
        .find(|f| f.ndf == "GGX" && f.family.starts_with("vMF"));
    let c = fitted.map_or(2.0, |f| f.constant);
    let mut out = Vec::new();
    for f in Filter::ALL {
        if let Some(e) = f.summary_key().and_then(|k| j.summary.get(k)) {
            out.push(Measured {
                filter: f,
                l2_mean: e.l2_mean,
                l2_se: e.l2_se,
                what: "GGX, every map, level and view of the footprint study".into(),
            });
        }
    }
    if let Some(f) = fitted {
        out.push(Measured {
            filter: Filter::VmfFitted,
            l2_mean: f.held_out.l2_mean,
            l2_se: f.held_out.l2_se,
            what: "GGX, the held-out footprints and views only (not comparable with the all-case means)".into(),
        });
    }
    Ok((out, c))
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
    pub filter: Filter,
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
    pub filter: Filter,
    pub fitted_c: f64,
    pub measured: Vec<Measured>,
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
    let (measured, fitted_c) = measured(&options.results)?;
    let filter = match options.filter {
        Filter::Best => measured
            .iter()
            .filter(|m| m.filter != Filter::VmfFitted)
            .min_by(|a, b| a.l2_mean.total_cmp(&b.l2_mean))
            .map_or(Filter::Vmf, |m| m.filter),
        f => f,
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
    for lv in &levels {
        let mut over = 0;
        let values: Vec<f32> = (0..lv.width * lv.height)
            .map(|k| {
                let a = filter.alpha(lv.r(k), lv.mean_a2[k] as f64, lv.mean_p[k] as f64, fitted_c);
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
    Ok(Outcome {
        options,
        filter,
        fitted_c,
        measured,
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

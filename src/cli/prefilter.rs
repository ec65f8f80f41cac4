//! The `prefilter` subcommand's arguments.

use crate::integrate::Preset;
use std::path::{Path, PathBuf};

/// Roughness mips from a normal map; or, with --study, the footprint-filter study on it;
/// or, with --rank, its P-NDF compression (seed 002).
#[derive(clap::Args, Debug, Clone)]
pub struct PrefilterArgs {
    /// tangent-space normal map, 8/16-bit RGB(A) PNG, power-of-two sides ≤ 8192
    #[arg(long, conflicts_with = "generator")]
    pub input: Option<PathBuf>,
    /// a procedural map instead of a PNG (with --rank): isotropic-noise, brushed-metal,
    /// flakes, sharp-bumps, scratches (64×64)
    #[arg(long)]
    pub generator: Option<String>,
    /// perceptual-roughness map (glTF: α = value²), 8/16-bit PNG, the normal map's size
    /// or smaller by a power of two (each texel then covers that block)
    #[arg(long, conflicts_with = "alpha")]
    pub roughness: Option<PathBuf>,
    /// the roughness map's channel: auto = grey, or G of RGB(A) (glTF metallicRoughness)
    #[arg(long, value_enum, default_value_t = crate::prefilter::input::Channel::Auto)]
    pub channel: crate::prefilter::input::Channel,
    /// one base α for the whole map (the study's base roughness with --study; default 0.1 there)
    #[arg(long)]
    pub alpha: Option<f64>,
    /// the rule: best = the measured one with the smallest error (results/fits/filters.json),
    /// or a map filter's key (results/filters.md)
    #[arg(long, default_value = "best", value_parser = crate::prefilter::Choice::keys())]
    pub filter: String,
    /// what the roughness texels hold
    #[arg(long, value_enum, default_value_t = crate::prefilter::Store::Perceptual)]
    pub store: crate::prefilter::Store,
    /// the roughness chain's texel format
    #[arg(long, value_enum, default_value_t = crate::prefilter::Format::R8)]
    pub format: crate::prefilter::Format,
    /// one channel, or glTF metallicRoughness (G roughness; R, B carried from an RGB(A) input)
    #[arg(long, value_enum, default_value_t = crate::prefilter::Layout::R)]
    pub layout: crate::prefilter::Layout,
    /// the normal mips: renormalised, or the mean normal as it is
    #[arg(long, value_enum, default_value_t = crate::prefilter::NormalMips::Renormalised)]
    pub normals: crate::prefilter::NormalMips,
    /// ignore the blue channel and rebuild n_z = √(1 − x² − y²) (two-channel maps)
    #[arg(long)]
    pub reconstruct_z: bool,
    /// run the footprint-filter study on the map instead (report, JSON, α′ maps)
    #[arg(long)]
    pub study: bool,
    /// output directory
    #[arg(long, default_value = "prefilter-out")]
    pub out: PathBuf,
    /// compress the map's P-NDF blocks at this CP rank (seed 002) instead
    #[arg(long)]
    pub rank: Option<usize>,
    #[arg(long, value_enum, default_value_t = Preset::Default)]
    pub preset: Preset,
}

impl PrefilterArgs {
    /// The mip-chain tool's options (None without --input; a typed error for a filter key
    /// that is not a chain's rule).
    pub fn options(
        &self,
        results: &Path,
    ) -> crate::error::Result<Option<crate::prefilter::Options>> {
        let filter = crate::prefilter::Choice::parse(&self.filter)?;
        Ok(self.input.clone().map(|input| crate::prefilter::Options {
            input,
            roughness: self.roughness.clone(),
            alpha: self.alpha,
            channel: self.channel,
            filter,
            store: self.store,
            format: self.format,
            layout: self.layout,
            normals: self.normals,
            reconstruct_z: self.reconstruct_z,
            results: PathBuf::from(results),
        }))
    }
}

/// `prefilter`: one output set (atomically published) per call.
pub fn run(a: PrefilterArgs, results: &std::path::Path) -> Result<bool, crate::Error> {
    let dir = a.out.clone();
    crate::io::in_set("prefilter", &dir.join(".manifest.json"), |set| {
        prefilter_set(set, a, &dir, results)
    })
}

fn prefilter_set(
    set: &mut crate::io::Outputs,
    a: PrefilterArgs,
    dir: &std::path::Path,
    results: &std::path::Path,
) -> Result<bool, crate::Error> {
    use crate::filters::footprint::{NormalMap, Procedural};
    let tool = a.options(results)?;
    let PrefilterArgs {
        input,
        generator,
        alpha,
        study,
        rank,
        preset,
        filter: a_filter,
        ..
    } = a;
    let msg = match (input, generator, rank) {
        (Some(p), None, None) if study => {
            crate::studies::filters::prefilter(set, &p, dir, alpha.unwrap_or(0.1), preset)?
        }
        (Some(_), None, None) => {
            let options = tool.expect("tool options with --input");
            let command = format!(
                "ndfbench prefilter --input {} {} --filter {}",
                options.input.display(),
                match (&options.roughness, options.alpha) {
                    (Some(r), _) => format!("--roughness {}", r.display()),
                    (None, Some(x)) => format!("--alpha {x}"),
                    _ => String::new(),
                },
                a_filter
            );
            let outcome = crate::prefilter::run(options)?;
            let files = crate::prefilter::output::render(&outcome, &command)?;
            for (name, bytes) in &files {
                set.put(&dir.join(name), bytes);
            }
            format!(
                "wrote {} files to {} ({} levels, rule {})",
                files.len(),
                dir.display(),
                outcome.levels.len(),
                outcome.filter.key()
            )
        }
        (Some(p), None, Some(r)) => {
            let map = NormalMap::from_png(&p)?;
            crate::studies::tensor::prefilter_tensor(set, &map, dir, r, preset)?
        }
        (None, Some(g), r) => {
            let kind = Procedural::ALL
                .into_iter()
                .chain([Procedural::Scratches])
                .find(|k| k.name() == g)
                .ok_or_else(|| crate::Error::InvalidArgument(format!("--generator '{g}': one of isotropic-noise, brushed-metal, flakes, sharp-bumps, scratches")))?;
            let map = NormalMap::procedural(kind, 64, 1)?;
            match r {
                Some(r) => crate::studies::tensor::prefilter_tensor(set, &map, dir, r, preset)?,
                None => {
                    return Err(crate::Error::InvalidArgument(
                        "--generator needs --rank (the footprint-filter study takes --input PNG)"
                            .into(),
                    ))
                }
            }
        }
        _ => {
            return Err(crate::Error::InvalidArgument(
                "give --input MAP.png or --generator NAME".into(),
            ))
        }
    };
    println!("{msg}");
    Ok(true)
}

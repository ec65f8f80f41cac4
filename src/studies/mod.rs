//! The registry of studies (one per fits/*.toml) and the `regen` driver. Only the CLI
//! (and tests) use it; the studies themselves live with their topics and never import it.
//!
//! Each entry adapts a topic's entry point to [`Study`]; an unknown spec name is a typed
//! error. Order: studies without `after` first, then those with, each group by name.

use crate::error::{Error, Result};
use crate::fit::spec::{self, FitSpec};
use crate::integrate::Preset;
use crate::study::{Ctx, FitOutcome, Study};
use std::path::Path;

pub mod filters;
pub mod leadr_grids;
pub mod ltc_aniso;
pub mod ltc_ggx;
pub mod ltc_lobes;
pub mod multiscale_alpha_me;
pub mod multiscale_convolution;
pub mod render;
pub mod smith_lambda;
pub mod tensor;
pub mod visibility;

/// A study given as its name, the studies it follows and its entry point.
struct Entry {
    name: &'static str,
    after: &'static [&'static str],
    run: fn(&Ctx) -> Result<FitOutcome>,
}

impl Study for Entry {
    fn name(&self) -> &'static str {
        self.name
    }
    fn after(&self) -> &'static [&'static str] {
        self.after
    }
    fn run(&self, ctx: &Ctx) -> Result<FitOutcome> {
        (self.run)(ctx)
    }
}

fn leadr_grids(c: &Ctx) -> Result<FitOutcome> {
    leadr_grids::regen(c.spec, c.results)
}
fn smith_lambda(c: &Ctx) -> Result<FitOutcome> {
    smith_lambda::regen(c.spec, c.results)
}
fn filters(c: &Ctx) -> Result<FitOutcome> {
    filters::run(c.spec, c.results, c.preset)
}
fn ltc_ggx(c: &Ctx) -> Result<FitOutcome> {
    ltc_ggx::run(c.spec, c.results, c.preset)
}
fn ltc_lobes(c: &Ctx) -> Result<FitOutcome> {
    ltc_lobes::run(c.spec, c.results, c.preset)
}
fn ltc_aniso(c: &Ctx) -> Result<FitOutcome> {
    ltc_aniso::run(c.spec, c.results, c.preset)
}
fn tensor(c: &Ctx) -> Result<FitOutcome> {
    tensor::run(c.spec, c.results, c.preset)
}
fn visibility(c: &Ctx) -> Result<FitOutcome> {
    visibility::run(c.spec, c.results, c.preset)
}
fn render(c: &Ctx) -> Result<FitOutcome> {
    render::run(c.spec, c.results, c.preset)
}
fn multiscale_alpha_me(c: &Ctx) -> Result<FitOutcome> {
    multiscale_alpha_me::run(c.spec, c.results, c.preset)
}
fn multiscale_convolution(c: &Ctx) -> Result<FitOutcome> {
    multiscale_convolution::run(c.spec, c.specs, c.results, c.preset)
}

/// Every study, as data.
pub static STUDIES: &[&dyn Study] = &[
    &Entry {
        name: "leadr-grids",
        after: &[],
        run: leadr_grids,
    },
    &Entry {
        name: "ltc-diffuse",
        after: &[],
        run: ltc_lobes,
    },
    &Entry {
        name: "ltc-ggx",
        after: &[],
        run: ltc_ggx,
    },
    &Entry {
        name: "ltc-sheen",
        after: &[],
        run: ltc_lobes,
    },
    &Entry {
        name: "multiscale-alpha-me",
        after: &[],
        run: multiscale_alpha_me,
    },
    &Entry {
        name: "multiscale-convolution",
        after: &[],
        run: multiscale_convolution,
    },
    &Entry {
        name: "smith-lambda",
        after: &[],
        run: smith_lambda,
    },
    &Entry {
        name: "tensor",
        after: &[],
        run: tensor,
    },
    &Entry {
        name: "visibility",
        after: &[],
        run: visibility,
    },
    // the anisotropic fits start from the isotropic GGX table
    &Entry {
        name: "ltc-aniso",
        after: &["ltc-ggx"],
        run: ltc_aniso,
    },
    // the renders read the footprint study's refitted constants
    &Entry {
        name: "render",
        after: &["filters"],
        run: render,
    },
    // results/filters.md embeds the LEADR and Λ reports
    &Entry {
        name: "filters",
        after: &["leadr-grids", "smith-lambda"],
        run: filters,
    },
];

/// The study named `name`.
pub fn find(name: &str) -> Option<&'static dyn Study> {
    STUDIES.iter().copied().find(|s| s.name() == name)
}

/// Run the studies whose spec name contains `only` (all when None; an exact name also
/// runs the studies it follows), each published as one output set.
pub fn regen(
    fits_dir: &Path,
    results: &Path,
    only: Option<&str>,
    preset: Preset,
) -> Result<Vec<FitOutcome>> {
    regen_timed(fits_dir, results, only, preset).map(|(o, _)| o)
}

/// [`regen`], with each study's wall-clock seconds (in run order).
pub fn regen_timed(
    fits_dir: &Path,
    results: &Path,
    only: Option<&str>,
    preset: Preset,
) -> Result<(Vec<FitOutcome>, Vec<(String, f64)>)> {
    let specs = spec::load_dir(fits_dir)?;
    // every spec must name a study: a typo is an error, not some other fit
    for s in &specs {
        if find(&s.name).is_none() {
            return Err(Error::InvalidArgument(format!(
                "{}: spec '{}' names no study (known: {})",
                fits_dir.display(),
                s.name,
                STUDIES
                    .iter()
                    .map(|s| s.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    // an exact name of a study that follows others runs those first (filters embeds the
    // LEADR and Λ reports); any other text selects the specs whose names contain it
    let group: Option<Vec<&str>> = only
        .and_then(find)
        .filter(|e| !e.after().is_empty())
        .map(|e| {
            let mut g = e.after().to_vec();
            g.push(e.name());
            g
        });
    let mut selected: Vec<&FitSpec> = specs
        .iter()
        .filter(|s| match &group {
            Some(g) => g.contains(&s.name.as_str()),
            None => only.is_none_or(|o| s.name.contains(o)),
        })
        .collect();
    selected.sort_by_key(|s| {
        let follows = find(&s.name).is_some_and(|x| !x.after().is_empty());
        (follows, s.name.clone())
    });
    let mut out = Vec::new();
    let mut times = Vec::new();
    for s in selected {
        let study = find(&s.name)
            .ok_or_else(|| Error::InvalidArgument(format!("spec '{}' names no study", s.name)))?;
        // one study = one output set, published in one step (crate::io)
        let set = crate::io::begin_set(&s.name, &crate::io::results_manifest(results, &s.name))?;
        crate::report::stage(&format!("regen {}: started", s.name));
        let t = std::time::Instant::now();
        let o = study.run(&Ctx {
            spec: s,
            specs: &specs,
            results,
            preset,
        })?;
        set.commit()?;
        let secs = t.elapsed().as_secs_f64();
        crate::report::stage(&format!("regen {}: done in {secs:.1} s", s.name));
        times.push((s.name.clone(), secs));
        out.push(o);
    }
    if out.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "no fit spec in '{}' matches {:?}",
            fits_dir.display(),
            only
        )));
    }
    Ok((out, times))
}

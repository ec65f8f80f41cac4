//! The registry of studies (one per fits/*.toml) and the `regen` driver. Only the CLI
//! (and tests) use it; the studies themselves live with their topics and never import it.
//!
//! Each entry adapts a topic's entry point to [`Study`]; an unknown spec name is a typed
//! error. Order: studies without `after` first, then those with, each group by name.

use crate::error::Result;
use crate::study::{Ctx, FitOutcome, Study};

pub mod engines;
pub mod filters;
pub mod leadr_grids;
pub mod ltc_aniso;
pub mod ltc_ggx;
pub mod ltc_lobes;
pub mod multiscale_alpha_me;
pub mod multiscale_convolution;
pub mod render;
mod run;
pub mod smith_lambda;
pub mod tensor;
pub mod tensor_scale;
pub mod visibility;

/// A study given as its name, the studies it follows and its entry point.
struct Entry {
    name: &'static str,
    after: &'static [&'static str],
    run: fn(&Ctx) -> Result<FitOutcome>,
}

/// A study the main job leaves out: run only when named (seed 002 at the paper's scale).
struct OnRequest(Entry);

impl Study for OnRequest {
    fn name(&self) -> &'static str {
        self.0.name
    }
    fn on_request(&self) -> bool {
        true
    }
    fn run(&self, ctx: &Ctx) -> Result<FitOutcome> {
        (self.0.run)(ctx)
    }
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
fn tensor_scale(c: &Ctx) -> Result<FitOutcome> {
    tensor_scale::run(c.spec, c.results, c.preset)
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
    // seed 002 at the paper's scale: hours at its default preset, so on request only
    &OnRequest(Entry {
        name: "tensor-scale",
        after: &[],
        run: tensor_scale,
    }),
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

pub use run::{check_sharded, merge, regen, regen_timed, regen_with, shard, RunOptions, StudyTime};

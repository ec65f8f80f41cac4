//! The registry of studies, as data: one entry per fits/*.toml with the studies it follows
//! and its entry point.

use crate::error::Result;
use crate::study::{Ctx, FitOutcome, Study};

use super::{
    filters, leadr_grids, ltc_aniso, ltc_ggx, ltc_lobes, multiscale_alpha_me,
    multiscale_convolution, render, smith_lambda, tensor, tensor_scale, visibility,
};

/// A study given as its name, the studies it follows and its entry point.
pub(super) struct Entry {
    name: &'static str,
    after: &'static [&'static str],
    run: fn(&Ctx) -> Result<FitOutcome>,
}

/// A study the main job leaves out: run only when named (seed 002 at the paper's scale).
pub(super) struct OnRequest(Entry);

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

pub(super) fn leadr_grids(c: &Ctx) -> Result<FitOutcome> {
    leadr_grids::regen(c.spec, c.results)
}

pub(super) fn smith_lambda(c: &Ctx) -> Result<FitOutcome> {
    smith_lambda::regen(c.spec, c.results)
}

pub(super) fn filters(c: &Ctx) -> Result<FitOutcome> {
    filters::run(c.spec, c.results, c.preset)
}

pub(super) fn ltc_ggx(c: &Ctx) -> Result<FitOutcome> {
    ltc_ggx::run(c.spec, c.results, c.preset)
}

pub(super) fn ltc_lobes(c: &Ctx) -> Result<FitOutcome> {
    ltc_lobes::run(c.spec, c.results, c.preset)
}

pub(super) fn ltc_aniso(c: &Ctx) -> Result<FitOutcome> {
    ltc_aniso::run(c.spec, c.results, c.preset)
}

pub(super) fn tensor(c: &Ctx) -> Result<FitOutcome> {
    tensor::run(c.spec, c.results, c.preset)
}

pub(super) fn tensor_scale(c: &Ctx) -> Result<FitOutcome> {
    tensor_scale::run(c.spec, c.results, c.preset)
}

pub(super) fn visibility(c: &Ctx) -> Result<FitOutcome> {
    visibility::run(c.spec, c.results, c.preset)
}

pub(super) fn render(c: &Ctx) -> Result<FitOutcome> {
    render::run(c.spec, c.results, c.preset)
}

pub(super) fn multiscale_alpha_me(c: &Ctx) -> Result<FitOutcome> {
    multiscale_alpha_me::run(c.spec, c.results, c.preset)
}

pub(super) fn multiscale_convolution(c: &Ctx) -> Result<FitOutcome> {
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

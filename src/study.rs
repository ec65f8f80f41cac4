//! What a study is, apart from any particular one: the context it runs in, what it
//! computes, what it reports back, and the trait each study implements and the registry
//! (`studies`) holds. A study imports this, never the driver that runs it.
//!
//! A study runs in two steps: `compute` returns its typed result (nothing formatted, no
//! file written), then [`Computed::render`] turns that result into its output files as
//! data (markdown, SVG, PNG, the typed JSON), which the driver publishes as one set. The
//! driver reads the run's outcome off the result ([`Computed::outcome`]).

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::io::Outputs;
use std::path::Path;

/// What one study produced.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FitOutcome {
    pub name: String,
    pub held_out_max_rel: f64,
    pub tolerance: f64,
    pub passed: bool,
    pub summary: String,
}

impl FitOutcome {
    /// The outcome of the study specified by `spec` whose held-out figure is
    /// `held_out_max_rel`, judged against the spec's tolerance.
    pub fn judged(spec: &FitSpec, held_out_max_rel: f64, summary: String) -> FitOutcome {
        let tolerance = spec.tolerance.max_rel;
        FitOutcome {
            name: spec.name.clone(),
            held_out_max_rel,
            tolerance,
            passed: held_out_max_rel <= tolerance,
            summary,
        }
    }
}

impl FitOutcome {
    /// The outcome of a study that measures without a bar on its figure (tolerance 1):
    /// passed when the figure `worst` is finite.
    pub fn measured(spec: &FitSpec, worst: f64, summary: String) -> FitOutcome {
        FitOutcome {
            name: spec.name.clone(),
            held_out_max_rel: worst,
            tolerance: 1.0,
            passed: worst.is_finite(),
            summary,
        }
    }
}

/// Everything a study may read: its spec, every spec of the run (a study may read
/// another's settings), where results go, and the preset.
#[derive(Clone, Copy)]
pub struct Ctx<'a> {
    pub spec: &'a FitSpec,
    pub specs: &'a [FitSpec],
    pub results: &'a Path,
    pub preset: Preset,
}

impl Ctx<'_> {
    /// The study's parameters at the run's preset ([`FitSpec::params`]).
    pub fn params<P: crate::fit::spec::Params>(&self) -> Result<P> {
        self.spec.params(self.preset)
    }
}

/// A study's computed result: everything its reports show, already measured.
pub trait Computed: Send {
    /// The run's outcome, read off the result.
    fn outcome(&self) -> FitOutcome;
    /// The study's output files under `results`, as data put into `set` (formats only:
    /// no number is computed here that the result does not hold); the driver publishes
    /// the set.
    fn render(&self, set: &mut Outputs, results: &Path) -> Result<()>;
}

/// One study: named as its fits/*.toml, ordered after the studies whose reports it embeds.
pub trait Study: Sync {
    /// The spec name it runs (fits/<name>.toml).
    fn name(&self) -> &'static str;
    /// Its module, as `module_path!()` gives it: its cache entries are keyed by the code
    /// this module reaches (`memo::deps`), not by every source file.
    fn module(&self) -> &'static str;
    /// Studies that must run first because this one embeds their reports; `regen --only
    /// NAME` with this exact name runs them too.
    fn after(&self) -> &'static [&'static str] {
        &[]
    }
    /// Run only when named exactly (`regen --only NAME`, shards, Slurm), never by the main
    /// job: a study whose default preset is a batch job.
    fn on_request(&self) -> bool {
        false
    }
    /// Its spec's parameters parse and lie within bounds at every preset (the driver
    /// checks every spec before anything runs).
    fn check(&self, spec: &FitSpec) -> Result<()>;
    /// Compute the typed result (the driver renders and publishes it).
    fn compute(&self, ctx: &Ctx) -> Result<Box<dyn Computed>>;
}

/// Declare a study in the module that runs it: a unit struct implementing [`Study`],
/// named as its spec, following `after`, main job or `on request`, reading its spec's
/// `[params]` as the type `params` names (a [`crate::fit::spec::Params`]). Its entry point is
/// `computes f` with `f: fn(&Ctx) -> Result<R>`, `R: Computed`: the study computes, then
/// renders. Its cache is keyed by the code of the module the macro is invoked in
/// (`module_path!()` there).
///
/// ```ignore
/// crate::study::study! {
///     /// The Λ refit.
///     SmithLambda = "smith-lambda", after [], on request false, params Params, computes compute
/// }
/// ```
macro_rules! study {
    (
        $(#[$doc:meta])*
        $ty:ident = $name:literal,
        after [$($after:literal),*],
        on request $on_request:literal,
        params $params:ty,
        computes $run:path
    ) => {
        $(#[$doc])*
        pub struct $ty;

        impl $crate::study::Study for $ty {
            fn name(&self) -> &'static str {
                $name
            }
            fn module(&self) -> &'static str {
                module_path!()
            }
            fn after(&self) -> &'static [&'static str] {
                &[$($after),*]
            }
            fn on_request(&self) -> bool {
                $on_request
            }
            fn check(&self, spec: &$crate::fit::spec::FitSpec) -> $crate::error::Result<()> {
                for p in $crate::integrate::Preset::ALL {
                    spec.params::<$params>(p)?;
                }
                Ok(())
            }
            fn compute(
                &self,
                c: &$crate::study::Ctx,
            ) -> $crate::error::Result<Box<dyn $crate::study::Computed>> {
                Ok(Box::new($run(c)?))
            }
        }
    };
}
pub(crate) use study;

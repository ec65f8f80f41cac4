//! What a study is, apart from any particular one: the context it runs in, what it
//! reports back, and the trait each study implements and the registry (`studies`) holds.
//! A study imports this, never the driver that runs it.

use crate::error::Result;
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
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

/// Everything a study may read: its spec, every spec of the run (a study may read
/// another's settings), where results go, and the preset.
#[derive(Clone, Copy)]
pub struct Ctx<'a> {
    pub spec: &'a FitSpec,
    pub specs: &'a [FitSpec],
    pub results: &'a Path,
    pub preset: Preset,
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
    /// Compute and report; every file goes into `set`, which the driver publishes (a
    /// study writes nothing itself).
    fn run(&self, ctx: &Ctx, set: &mut crate::io::Outputs) -> Result<FitOutcome>;
}

/// Declare a study in the module that runs it: a unit struct implementing [`Study`],
/// named as its spec, following `after`, main job or `on request`, whose `run` is the
/// module's `fn(&mut Outputs, &Ctx) -> Result<FitOutcome>`. Its cache is keyed by the
/// code of the module the macro is invoked in (`module_path!()` there).
///
/// ```ignore
/// crate::study::study! {
///     /// The Λ refit.
///     SmithLambda = "smith-lambda", after [], on request false, runs regen
/// }
/// ```
macro_rules! study {
    (
        $(#[$doc:meta])*
        $ty:ident = $name:literal,
        after [$($after:literal),*],
        on request $on_request:literal,
        runs $run:path
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
            fn run(
                &self,
                c: &$crate::study::Ctx,
                set: &mut $crate::io::Outputs,
            ) -> $crate::error::Result<$crate::study::FitOutcome> {
                $run(set, c)
            }
        }
    };
}
pub(crate) use study;

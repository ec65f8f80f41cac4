//! What a study is, apart from any particular one: the context it runs in, what it
//! reports back, and the trait the registry (`studies`) holds. Studies implement nothing
//! here themselves; the registry adapts their entry points, so no study imports the
//! driver that runs it.

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
    /// Compute, report and write (into the open output set).
    fn run(&self, ctx: &Ctx) -> Result<FitOutcome>;
}

//! Numerical proofs: each identity in proofs/*.md has a check here that evaluates it by
//! independent methods (closed form vs adaptive quadrature vs Monte Carlo) over a stated
//! parameter set, and reports its worst error against a stated tolerance.
//!
//! `cargo run --release -- verify` runs them all, writes results/proofs.md and exits
//! non-zero if any fails. tests/proofs.rs runs the same checks at the quick preset.

pub mod cases;
pub mod envsg;
pub mod furnace;
pub mod jacobians;
pub mod multiscale;
pub mod ndf;
mod outcome;
pub mod sggx;
pub mod survey;
pub mod tensor;
pub mod tokuyoshi;
pub mod visibility;
pub mod wang;
pub mod wave;

pub use outcome::{Outcome, Worst};

use crate::error::Result;
use crate::integrate::Preset;
use std::time::Instant;

/// A registered check.
pub struct Check {
    pub id: &'static str,
    pub run: fn(Preset) -> Outcome,
}

/// Every check, in report order.
pub fn all() -> Vec<Check> {
    vec![
        Check {
            id: "ndf-normalization",
            run: ndf::normalization,
        },
        Check {
            id: "smith-projected-area",
            run: ndf::smith_projected_area,
        },
        Check {
            id: "sggx-projected-area",
            run: sggx::projected_area,
        },
        Check {
            id: "weak-white-furnace",
            run: furnace::weak_white_furnace,
        },
        Check {
            id: "weak-white-furnace-walter",
            run: furnace::weak_white_furnace_walter,
        },
        Check {
            id: "smith-lambda-closed-forms",
            run: ndf::lambda_closed_forms,
        },
        Check {
            id: "walter-lambda-error",
            run: ndf::walter_error,
        },
        Check {
            id: "vndf-sampling",
            run: ndf::vndf_sampling,
        },
        Check {
            id: "jacobian-normal-to-slope",
            run: jacobians::normal_to_slope,
        },
        Check {
            id: "jacobian-reflection",
            run: jacobians::reflection,
        },
        Check {
            id: "jacobian-half-vector",
            run: jacobians::half_vector,
        },
        Check {
            id: "jacobian-slope-parallel",
            run: jacobians::slope_parallel,
        },
        Check {
            id: "jacobian-projected-disk",
            run: jacobians::projected_disk,
        },
        Check {
            id: "jacobian-ltc",
            run: jacobians::ltc,
        },
        Check {
            id: "tokuyoshi-eigenvalue-bound",
            run: tokuyoshi::eigenvalue_bound,
        },
        Check {
            id: "tokuyoshi-eq12-gap",
            run: tokuyoshi::eq12_gap,
        },
        Check {
            id: "mrl-closed-form",
            run: multiscale::mrl_closed_form,
        },
        Check {
            id: "mrl-product",
            run: multiscale::mrl_product,
        },
        Check {
            id: "tensor-rank1-box",
            run: tensor::rank1_box,
        },
        Check {
            id: "wave-fft-direct",
            run: wave::fft_direct,
        },
        Check {
            id: "wave-parseval",
            run: wave::parseval,
        },
        Check {
            id: "wave-geometric-limit",
            run: wave::geometric_limit,
        },
        Check {
            id: "sg-compact-support",
            run: envsg::compact_support,
        },
        Check {
            id: "wang-implicit-explicit",
            run: wang::implicit_explicit,
        },
        Check {
            id: "wang-constant-storage",
            run: wang::constant_storage,
        },
        Check {
            id: "gaussian-moment-matching",
            run: survey::moment_matching,
        },
        Check {
            id: "vmf-mixture-moments",
            run: survey::vmf_mixture_moments,
        },
        Check {
            id: "sh-convolution",
            run: survey::sh_convolution,
        },
        Check {
            id: "horizon-joint-limits",
            run: visibility::horizon_joint_limits,
        },
        Check {
            id: "legendre-horizon-linearity",
            run: visibility::legendre_horizon_linearity,
        },
        Check {
            id: "vsm-single-plane",
            run: visibility::vsm_single_plane,
        },
        Check {
            id: "box-filter-analytic-integration",
            run: visibility::box_filter_analytic,
        },
    ]
}

/// The checks `only` names (exact ids, comma-separated; every check when None), in
/// report order. An id that is no check is an error listing the valid ones.
pub fn select(only: Option<&str>) -> crate::error::Result<Vec<Check>> {
    let every = all();
    let Some(list) = only else { return Ok(every) };
    let ids: Vec<&str> = list.split(',').map(str::trim).collect();
    if let Some(bad) = ids.iter().find(|id| !every.iter().any(|c| c.id == **id)) {
        // the whole list is long: name the ids that contain the text, if any
        let near: Vec<&str> = every
            .iter()
            .map(|c| c.id)
            .filter(|id| !bad.is_empty() && id.contains(bad))
            .take(6)
            .collect();
        let hint = if near.is_empty() {
            String::new()
        } else {
            format!("; did you mean {}?", near.join(", "))
        };
        return Err(crate::error::Error::InvalidArgument(format!(
            "verify --only {}: not a check id{hint} (the {} valid ids are the stems of proofs/*.md)",
            crate::error::quoted(bad),
            every.len()
        )));
    }
    Ok(every.into_iter().filter(|c| ids.contains(&c.id)).collect())
}

/// Run `checks`, several at a time on the rayon pool (each check's outcome depends on
/// nothing but its own inputs, so the same bits in any order); `progress` is called after
/// each one, in the order they end. The outcomes come back in the order of `checks`.
pub fn run(preset: Preset, checks: Vec<Check>, progress: impl Fn(&Outcome) + Sync) -> Vec<Outcome> {
    use rayon::prelude::*;
    checks
        .into_par_iter()
        .map(|c| {
            let t0 = Instant::now();
            let mut o = (c.run)(preset);
            o.seconds = t0.elapsed().as_secs_f64();
            progress(&o);
            o
        })
        .collect()
}

/// Markdown report of a verify run.
pub fn report_markdown(outcomes: &[Outcome], preset: Preset) -> String {
    let mut s = String::new();
    s.push_str("# Numerical proofs\n\n");
    s.push_str(&format!(
        "Written by `cargo run --release -- verify --preset {}` (or the no-argument main job). \
Each row checks one identity of proofs/ by independent methods; `worst error` is the largest \
error over all cases tried, in the unit of the `kind` column.\n\n",
        preset.name()
    ));
    let mut t = crate::report::table::Table::new([
        "identity",
        "source",
        "ranges tried",
        "cases",
        "worst error",
        "kind",
        "worst case",
        "tolerance",
        "result",
    ]);
    for o in outcomes {
        t.row([
            format!("[{}](../proofs/{}.md)", o.title, o.id),
            o.source.to_string(),
            o.ranges.to_string(),
            o.cases.to_string(),
            format!("{:.3e}", o.worst_error),
            o.error_kind.to_string(),
            o.worst_case.to_string(),
            format!("{:.1e}", o.tolerance),
            (if o.passed { "pass" } else { "**FAIL**" }).to_string(),
        ]);
    }
    s.push_str(&t.to_string());
    s.push_str("\n## Findings\n\n");
    for o in outcomes {
        if o.notes.is_empty() {
            continue;
        }
        s.push_str(&format!("### {}\n\n", o.title));
        for n in &o.notes {
            s.push_str(&format!("- {n}\n"));
        }
        s.push('\n');
    }
    s
}

/// Write results/proofs.md and results/proofs.json atomically.
pub fn write_results(
    set: &mut crate::io::Outputs,
    outcomes: &[Outcome],
    preset: Preset,
    dir: &std::path::Path,
) -> Result<()> {
    set.put(
        &dir.join("proofs.md"),
        report_markdown(outcomes, preset).as_bytes(),
    );
    let json = serde_json::to_string_pretty(outcomes).expect("outcomes serialise");
    set.put(&dir.join("proofs.json"), json.as_bytes());
    Ok(())
}

//! The anisotropic table's accuracy-against-work study (`regen --only ltc-aniso-work`, on
//! request): its reference route at the published offset is the published table, a
//! fixed-node route evaluates fewer targets, a published table it cannot judge is refused,
//! and the committed file is of the committed table.

mod common;

use ndfbench::results::{self, ltc_aniso};
use std::path::Path;

/// `regen --only STUDY --preset quick --no-cache` on the specs of `fits`, into `results`.
fn quick(fits: &Path, results: &Path, study: &str) -> std::process::Output {
    let args = ["--only", study, "--preset", "quick", "--no-cache"];
    common::regen_in(fits, results, &args).output().unwrap()
}

/// At the quick preset, in a scratch results folder: the GGX and anisotropic studies
/// publish their tables, then the work study refits. Its first draw (the reference route
/// at the published offset) goes through the work study's own code path and must give
/// the anisotropic study's published figures: the same mean between cells bit for bit
/// (same cases, same estimator) and the same mean over the fitted cells; the route at the
/// published settings on moving samples is that draw again (no cell above or below the
/// envelopes that hold it), and the fixed-node route evaluates the lobe less.
#[test]
fn the_reference_at_the_published_offset_is_the_published_table() {
    let d = common::scratch("ltc-aniso-work", "quick");
    common::assert_success(&quick(Path::new("fits"), &d, "ltc-aniso-work"));
    let w = results::read::<ltc_aniso::AnisoWork>(&d)
        .unwrap()
        .expect("ltc-aniso-work.json");
    let a = results::read::<ltc_aniso::Aniso>(&d)
        .unwrap()
        .expect("ltc-aniso.json");
    let w = &w.work;
    assert_eq!(
        w.table_fingerprint,
        ltc_aniso::aniso_table(&d).unwrap().fingerprint()
    );
    let d0 = &w.draws[0];
    assert_eq!(d0.offset, 0.5);
    let between = d0
        .between_l2
        .expect("a refitted draw is judged between cells");
    assert_eq!(
        between.value.to_bits(),
        a.summary.between_table.mean.value.to_bits()
    );
    assert_eq!(
        between.error.to_bits(),
        a.summary.between_table.mean.error.to_bits()
    );
    let cells = a.summary.cells.ours.mean.value;
    assert!(
        (d0.mean.value - cells).abs() <= 1e-12 * cells,
        "{} against {cells}",
        d0.mean.value
    );
    // the quick plan's first route: the reference's own settings on moving samples
    let (check, v) = &w.routes[0];
    assert_eq!(check.nodes(), ndfbench::ltc::fit::Nodes::Moving);
    assert_eq!((check.samples, check.max_iters), (d0.samples, d0.max_iters));
    assert_eq!(check.mean.value.to_bits(), d0.mean.value.to_bits());
    assert_eq!(v.candidate[0], v.reference[0]);
    for e in &v.candidate[1..] {
        assert_eq!((e.above, e.below), (0, 0), "{e:?}");
    }
    // the fixed-node route: trials on nodes drawn once, so fewer target evaluations
    let (fixed, _) = &w.routes[1];
    assert_eq!(fixed.nodes(), ndfbench::ltc::fit::Nodes::Fixed);
    let (e_fixed, e_ref) = (
        fixed.target_evals_per_cell.unwrap(),
        d0.target_evals_per_cell.unwrap(),
    );
    assert!(e_fixed < 0.75 * e_ref, "{e_fixed} against {e_ref}");
    let _ = std::fs::remove_dir_all(&d);
}

/// A table published on fixed nodes must be among the routes the study judges: with
/// fits/ltc-aniso.toml on `nodes = "fixed"` and a plan without a fixed route, the study
/// refuses before fitting (exit 2, one line); `nodes = "fixed-all"` (one stage: no such
/// route) is refused by the anisotropic study itself.
#[test]
fn an_unjudged_published_route_and_a_route_that_does_not_exist_are_refused() {
    let d = common::scratch("ltc-aniso-work-refuse", "quick");
    let fits = d.join("fits-in");
    common::copy_dir(Path::new("fits"), &fits);
    let spec = std::fs::read_to_string("fits/ltc-aniso.toml").unwrap();
    let with_nodes = |nodes: &str| {
        let s = spec.replace("[params]\n", &format!("[params]\nnodes = \"{nodes}\"\n"));
        std::fs::write(fits.join("ltc-aniso.toml"), s).unwrap();
    };
    let results = d.join("results");
    std::fs::create_dir_all(&results).unwrap();
    with_nodes("fixed-all");
    let out = quick(&fits, &results, "ltc-aniso");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let last = err.trim_end().lines().last().unwrap_or_default();
    assert!(last.contains("one stage"), "{err}");
    with_nodes("fixed");
    let plan = std::fs::read_to_string("fits/ltc-aniso-work.toml").unwrap();
    let moving_only: String = plan
        .lines()
        .filter(|l| !l.contains("nodes = \"fixed\" }"))
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(fits.join("ltc-aniso-work.toml"), moving_only).unwrap();
    let out = quick(&fits, &results, "ltc-aniso-work");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let last = err.trim_end().lines().last().unwrap_or_default();
    assert!(
        last.contains("results/fits/ltc-aniso.json") && last.contains("would go unjudged"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// The committed work study ran on the committed table: a refit without rerunning it
/// leaves it describing another table.
#[test]
fn the_work_study_is_of_the_published_table() {
    let r = Path::new("results");
    let w = results::read::<ltc_aniso::AnisoWork>(r)
        .unwrap()
        .expect("results/fits/ltc-aniso-work.json");
    assert_eq!(
        w.work.table_fingerprint,
        ltc_aniso::aniso_table(r).unwrap().fingerprint(),
        "results/fits/ltc-aniso-work.json was computed on another table than results/fits/ltc-aniso.json (regen --only ltc-aniso-work)"
    );
}

//! Every numerical proof of proofs/ at the quick preset. Each proof file names its test
//! here. The default/precise presets run through `cargo run --release -- verify`.

use ndfbench::integrate::Preset;
use ndfbench::verify::{all, Outcome};

fn check(id: &str) -> Outcome {
    let c = all()
        .into_iter()
        .find(|c| c.id == id)
        .unwrap_or_else(|| panic!("no check named {id}"));
    let o = (c.run)(Preset::Quick);
    assert!(
        o.passed,
        "{id}: worst {:.3e} ({}) at {} > tol {:.1e}\nnotes: {:#?}",
        o.worst_error, o.error_kind, o.worst_case, o.tolerance, o.notes
    );
    assert!(o.cases > 0, "{id} ran no case");
    o
}

#[test]
fn ndf_normalization() {
    check("ndf-normalization");
}
#[test]
fn smith_projected_area() {
    check("smith-projected-area");
}
#[test]
fn sggx_projected_area() {
    check("sggx-projected-area");
}
#[test]
fn weak_white_furnace() {
    check("weak-white-furnace");
}
#[test]
fn weak_white_furnace_walter() {
    let o = check("weak-white-furnace-walter");
    // the approximation must visibly break the furnace (it is not an identity)
    assert!(o.notes.iter().any(|n| n.contains("worst |furnace − 1|")));
}
#[test]
fn smith_lambda_closed_forms() {
    check("smith-lambda-closed-forms");
}
#[test]
fn walter_lambda_error() {
    let o = check("walter-lambda-error");
    // published behaviour of the rational (seed 001 §3.2): its G1 error is of order 1e-3
    assert!(
        o.worst_error > 1e-4 && o.worst_error < 1e-2,
        "{}",
        o.worst_error
    );
}
#[test]
fn vndf_sampling() {
    check("vndf-sampling");
}
#[test]
fn jacobian_normal_to_slope() {
    check("jacobian-normal-to-slope");
}
#[test]
fn jacobian_reflection() {
    check("jacobian-reflection");
}
#[test]
fn jacobian_half_vector() {
    check("jacobian-half-vector");
}
#[test]
fn jacobian_slope_parallel() {
    check("jacobian-slope-parallel");
}
#[test]
fn jacobian_projected_disk() {
    check("jacobian-projected-disk");
}
#[test]
fn jacobian_ltc() {
    check("jacobian-ltc");
}
#[test]
fn tokuyoshi_eigenvalue_bound() {
    check("tokuyoshi-eigenvalue-bound");
}
#[test]
fn tokuyoshi_eq12_gap() {
    check("tokuyoshi-eq12-gap");
}

#[test]
fn mrl_closed_form() {
    check("mrl-closed-form");
}

#[test]
fn mrl_product() {
    check("mrl-product");
}

#[test]
fn every_check_has_a_proof_file_that_names_its_test() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for c in all() {
        let p = root.join("proofs").join(format!("{}.md", c.id));
        let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        let test = format!("tests/proofs.rs::{}", c.id.replace('-', "_"));
        assert!(
            text.contains(&test),
            "{} must name its test {test}",
            p.display()
        );
        for section in [
            "## Statement",
            "## Source",
            "## Derivation",
            "## Assumptions",
            "## Test",
        ] {
            assert!(
                text.contains(section),
                "{} lacks section {section}",
                p.display()
            );
        }
    }
}

#[test]
fn tensor_rank1_box() {
    check("tensor-rank1-box");
}
#[test]
fn gaussian_moment_matching() {
    check("gaussian-moment-matching");
}
#[test]
fn vmf_mixture_moments() {
    let o = check("vmf-mixture-moments");
    // the counter-example must show: κ and μ themselves do not interpolate
    assert!(o
        .notes
        .iter()
        .any(|n| n.contains("interpolating κ_k and μ_k")));
}
#[test]
fn sh_convolution() {
    check("sh-convolution");
}
#[test]
fn horizon_joint_limits() {
    let o = check("horizon-joint-limits");
    // the counter-example: the plain product misses the hotspot
    assert!(o.notes.iter().any(|n| n.contains("misses the hotspot")));
}
#[test]
fn legendre_horizon_linearity() {
    check("legendre-horizon-linearity");
}
#[test]
fn vsm_single_plane() {
    let o = check("vsm-single-plane");
    assert!(o.notes.iter().any(|n| n.contains("light bleeding")));
}
#[test]
fn box_filter_analytic_integration() {
    check("box-filter-analytic-integration");
}
#[test]
fn wave_fft_direct() {
    check("wave-fft-direct");
}
#[test]
fn wave_parseval() {
    check("wave-parseval");
}
#[test]
fn sg_compact_support() {
    check("sg-compact-support");
}
#[test]
fn wang_implicit_explicit() {
    check("wang-implicit-explicit");
}
#[test]
fn wang_constant_storage() {
    let o = check("wang-constant-storage");
    assert!(o.notes.iter().any(|n| n.contains("χ²")));
}
#[test]
fn wave_geometric_limit() {
    check("wave-geometric-limit");
}

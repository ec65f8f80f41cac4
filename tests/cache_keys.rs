//! A study's cache entries are keyed by the code it reaches (`memo::deps`), so an edit
//! it cannot reach keeps them warm and an edit to anything it reaches invalidates them.
//! The expectations are read off the sources' own imports (e.g. studies/ltc_ggx names
//! `crate::ltc::…`, and ltc names `crate::microfacet::…`), never off the resolver.

use ndfbench::memo::deps::{reach, unit_hashes, unit_of};
use std::collections::BTreeMap;
use std::path::Path;

/// The files build.rs hashes: src/, fits/render/, Cargo.toml, Cargo.lock.
fn tree() -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![
        Path::new("src").to_path_buf(),
        Path::new("fits/render").to_path_buf(),
    ];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .is_some_and(|x| x == "rs" || x == "wgsl" || x == "toml")
            {
                out.push((p.display().to_string(), std::fs::read(&p).unwrap()));
            }
        }
    }
    for f in ["Cargo.toml", "Cargo.lock"] {
        out.push((f.to_string(), std::fs::read(f).unwrap()));
    }
    out.sort();
    out
}

/// `files` with a line appended to `path` (which must exist).
fn edited(files: &[(String, Vec<u8>)], path: &str) -> Vec<(String, Vec<u8>)> {
    let mut out = files.to_vec();
    let f = out.iter_mut().find(|(p, _)| p == path).expect(path);
    f.1.extend_from_slice(b"\n// an edit\n");
    out
}

fn changed(a: &BTreeMap<String, String>, b: &BTreeMap<String, String>, unit: &str) -> bool {
    a[unit] != b[unit]
}

#[test]
fn an_unrelated_edit_keeps_a_study_warm_and_a_dependency_edit_does_not() {
    let files = tree();
    let before = unit_hashes(&files);
    // another study's report: ltc-ggx and smith-lambda stay warm, filters does not
    let after = unit_hashes(&edited(&files, "src/studies/filters/report.rs"));
    assert!(!changed(&before, &after, "studies::ltc_ggx"));
    assert!(!changed(&before, &after, "studies::smith_lambda"));
    assert!(changed(&before, &after, "studies::filters"));
    // the driver and the CLI: no study reaches them
    for f in ["src/studies/run.rs", "src/cli/command.rs", "src/main.rs"] {
        let after = unit_hashes(&edited(&files, f));
        for s in ["studies::ltc_ggx", "studies::filters", "studies::render"] {
            assert!(!changed(&before, &after, s), "{f} invalidated {s}");
        }
    }
    // the LTC fitter: the GGX study (`crate::ltc::…`) and the lobe tables go cold, the
    // Λ refit (which names no ltc path) stays warm
    let after = unit_hashes(&edited(&files, "src/ltc/fit.rs"));
    assert!(changed(&before, &after, "studies::ltc_ggx"));
    assert!(changed(&before, &after, "studies::ltc_lobes"));
    assert!(!changed(&before, &after, "studies::smith_lambda"));
    // a dependency of a dependency: ltc names `crate::microfacet::…`
    let after = unit_hashes(&edited(&files, "src/microfacet/mod.rs"));
    assert!(changed(&before, &after, "studies::ltc_ggx"));
    // how entries are stored, and the dependencies' versions: every study
    for f in ["src/memo/cache.rs", "Cargo.lock"] {
        let after = unit_hashes(&edited(&files, f));
        for s in [
            "studies::ltc_ggx",
            "studies::smith_lambda",
            "studies::tensor",
        ] {
            assert!(changed(&before, &after, s), "{f} left {s} warm");
        }
    }
    // an example scene the render study compiles in (include_str!)
    let after = unit_hashes(&edited(&files, "fits/render/glints-plane.toml"));
    assert!(changed(&before, &after, "studies::render"));
    assert!(!changed(&before, &after, "studies::ltc_ggx"));
}

#[test]
fn every_study_is_keyed_by_its_own_unit_as_compiled() {
    let files = tree();
    let hashes = unit_hashes(&files);
    // build.rs ran the same resolver on the same files
    let compiled: BTreeMap<String, String> = ndfbench::memo::UNIT_HASHES
        .iter()
        .map(|(u, h)| (u.to_string(), h.to_string()))
        .collect();
    assert_eq!(
        compiled, hashes,
        "rebuild: the compiled unit hashes are stale"
    );
    let mut seen = std::collections::BTreeSet::new();
    for s in ndfbench::studies::STUDIES {
        let code = ndfbench::memo::code_hash_of(s.module());
        assert_ne!(
            code,
            ndfbench::memo::CODE_HASH,
            "{} falls back to the whole build",
            s.name()
        );
        let unit = format!("studies::{}", s.module().rsplit("::").next().unwrap());
        assert_eq!(code, hashes[&unit], "{}", s.name());
        seen.insert(code);
    }
    // one unit per study module (ltc-diffuse and ltc-sheen share one, and so do
    // ltc-aniso and ltc-aniso-work)
    assert_eq!(seen.len(), ndfbench::studies::STUDIES.len() - 2);
}

fn mini(files: &[(&str, &str)]) -> Vec<(String, Vec<u8>)> {
    files
        .iter()
        .map(|(p, t)| (p.to_string(), t.as_bytes().to_vec()))
        .collect()
}

#[test]
fn the_resolver_follows_groups_super_impls_and_includes_but_not_comments() {
    let files = mini(&[
        (
            "src/lib.rs",
            "pub mod a; pub mod b; pub mod c; pub mod d; pub mod studies;",
        ),
        ("src/a/mod.rs", "pub mod inner;\npub struct T;\n"),
        ("src/a/inner.rs", "pub fn f() {}\n"),
        // an inherent impl of a's type lives in b: a's users reach b
        (
            "src/b.rs",
            "impl crate::a::T {\n    pub fn g(&self) {}\n}\n",
        ),
        ("src/c.rs", "pub fn h() {}\n"),
        ("src/d.rs", "pub trait Tr { fn m(&self); }\n"),
        ("src/studies/mod.rs", "pub mod x;\npub mod y;\n"),
        // a nested group, and c only in a comment
        (
            "src/studies/x.rs",
            "use crate::{a::{self, inner::f}, d::Tr};\n// crate::c::h\npub struct X;\n",
        ),
        // super:: names the sibling study, and an included file
        (
            "src/studies/y/mod.rs",
            "use super::x::X;\nconst S: &str = include_str!(\"../../../fits/s.toml\");\n",
        ),
        ("fits/s.toml", "s = 1\n"),
    ]);
    assert_eq!(
        unit_of("src/studies/y/mod.rs").as_deref(),
        Some("studies::y")
    );
    assert_eq!(unit_of("src/a/inner.rs").as_deref(), Some("a"));
    assert_eq!(unit_of("src/main.rs"), None);
    let r = reach(&files);
    let x = &r["studies::x"];
    for f in [
        "src/studies/x.rs",
        "src/a/mod.rs",
        "src/a/inner.rs",
        "src/b.rs",
        "src/d.rs",
    ] {
        assert!(x.contains(f), "studies::x misses {f}: {x:?}");
    }
    assert!(!x.contains("src/c.rs"), "a comment made an arrow");
    assert!(!x.contains("src/studies/y/mod.rs"));
    let y = &r["studies::y"];
    for f in ["src/studies/x.rs", "src/b.rs", "fits/s.toml", "Cargo.lock"] {
        assert!(y.contains(f), "studies::y misses {f}: {y:?}");
    }
}

/// Two studies that each declare a type of the same name in one file and implement a
/// trait for it in another (`compute.rs` declares `Computed`, `mod.rs` implements
/// `study::Computed` for it) do not reach each other: a bare name belongs to the unit that
/// declares it in any of its files.
#[test]
fn a_name_declared_in_another_file_of_the_same_unit_is_its_own() {
    let files = mini(&[
        ("src/lib.rs", "pub mod study; pub mod studies;"),
        ("src/study.rs", "pub trait Computed { fn f(&self); }\n"),
        ("src/studies/mod.rs", "pub mod p;\npub mod q;\n"),
        ("src/studies/p/mod.rs", "mod compute;\nuse compute::Computed;\nimpl crate::study::Computed for Computed {\n    fn f(&self) {}\n}\n"),
        ("src/studies/p/compute.rs", "pub struct Computed;\n"),
        ("src/studies/q/mod.rs", "mod compute;\nuse compute::Computed;\nimpl crate::study::Computed for Computed {\n    fn f(&self) {}\n}\n"),
        ("src/studies/q/compute.rs", "pub struct Computed;\n"),
    ]);
    let r = reach(&files);
    assert!(
        !r["studies::p"].contains("src/studies/q/compute.rs"),
        "{:?}",
        r["studies::p"]
    );
    assert!(!r["studies::q"].contains("src/studies/p/mod.rs"));
    assert!(r["studies::p"].contains("src/studies/p/compute.rs"));
}

/// The study → study arrows the sources have, each with its reason. Any other arrow from
/// one study to another fails: shared measures and drawing go beside the studies
/// (`studies::ltc_between`, `studies::ltc_error_map`, `studies::ltc_work_tables`), so a study's cache never reaches
/// another study's files.
const STUDY_ARROWS: &[(&str, &str, &str)] = &[
    (
        "studies::performance",
        "studies::convergence",
        "performance.md times the convergence study's engines on its integrands",
    ),
    (
        "studies::render_truth_work",
        "studies::render",
        "the curve is of the render study's own scenes, at the size and truth samples its spec sets",
    ),
];

#[test]
fn no_study_imports_another_study() {
    let g = ndfbench::memo::deps::graph(&tree());
    // the driver (run, registry) and the shared measures and drawing are not studies
    let study = |u: &str| {
        u.starts_with("studies::")
            && ![
                "studies::run",
                "studies::registry",
                "studies::ltc_between",
                "studies::ltc_error_map",
                "studies::ltc_work_tables",
            ]
            .contains(&u)
    };
    let mut found: Vec<(String, String)> = Vec::new();
    for (from, to) in &g.arrows {
        for t in to {
            if study(from) && study(t) && t != from {
                found.push((from.clone(), t.clone()));
            }
        }
    }
    let listed: Vec<(String, String)> = STUDY_ARROWS
        .iter()
        .map(|(a, b, _)| (a.to_string(), b.to_string()))
        .collect();
    let extra: Vec<_> = found.iter().filter(|a| !listed.contains(a)).collect();
    assert!(extra.is_empty(), "studies importing studies: {extra:?}");
    let gone: Vec<_> = listed.iter().filter(|a| !found.contains(a)).collect();
    assert!(
        gone.is_empty(),
        "listed arrows that are gone (remove them): {gone:?}"
    );
}

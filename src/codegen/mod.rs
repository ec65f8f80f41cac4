//! Code generation: fitted constants and f32 shading functions emitted as
//! WGSL (results/wgsl/) and as Rust twins (src/generated/), both from one description.
//!
//! Each function is written once in a neutral subset that is valid WGSL and valid Rust
//! at the same time: scalar `f32`/`bool` parameters, `let x: f32 = …;`, `if (…) { return …; }`,
//! `return …;`, and the calls sqrt/exp/log/abs/min/max/clamp/select, which the Rust file
//! defines as inline helpers with WGSL's semantics. Constants are `const NAME: f32 = …;`
//! in both. Floats are printed as the shortest decimal that round-trips to the f32, so
//! generation is byte-for-byte deterministic.
//!
//! Sources: results/fits/{multiscale-alpha-me, smith-lambda, filters, leadr-grids, ltc-ggx}.json.
//! tests/codegen.rs re-renders from those files and fails when a committed generated file
//! differs (stale), validates every WGSL module with naga, and compares each Rust twin
//! with its f64 reference.

pub mod audit;
pub mod desc;
pub mod table;

use crate::error::{Error, Result};
use desc::{FnDesc, FUNCTIONS};
use std::path::Path;

/// Coefficients of the two branches of the generated `alpha_me_pair`
/// (fits/multiscale-alpha-me.toml `terms` and `terms_large`).
pub const ALPHA_ME_SMALL_TERMS: usize = 7;
pub const ALPHA_ME_LARGE_TERMS: usize = 8;

/// The command that (re)generates the files, named in their headers.
pub const COMMAND: &str = "cargo run --release -- regen";

/// A named f32 constant with its provenance.
#[derive(Clone, Debug, PartialEq)]
pub struct Const {
    pub name: String,
    pub value: f32,
    pub doc: String,
}

fn lit(x: f32) -> String {
    // `{:?}` is the shortest round-trip form and always has a '.' or an exponent
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') || s.contains("inf") || s.contains("NaN") {
        s
    } else {
        format!("{s}.0")
    }
}

fn num(v: &serde_json::Value, path: &[&str], file: &str) -> Result<f64> {
    let mut cur = v;
    for p in path {
        cur = match p.parse::<usize>() {
            Ok(i) => &cur[i],
            Err(_) => &cur[*p],
        };
    }
    cur.as_f64().ok_or_else(|| {
        Error::InvalidArgument(format!(
            "codegen: results/fits/{file}.json has no number at {} (run `{COMMAND}`)",
            path.join(".")
        ))
    })
}

/// Read every constant from the fit results in `results`.
pub fn constants(results: &Path) -> Result<Vec<Const>> {
    let read = |name: &str| {
        crate::results::read_result(results, name).ok_or_else(|| {
            Error::InvalidArgument(format!(
                "codegen: missing or malformed {}/fits/{name}.json (run `{COMMAND}`)",
                results.display()
            ))
        })
    };
    let mut out = vec![Const {
        name: "PI".into(),
        value: std::f32::consts::PI,
        doc: "π".into(),
    }];
    let am = read("multiscale-alpha-me")?;
    let held = num(&am, &["ours", "held_out", "max_rel"], "multiscale-alpha-me")?;
    // both branches of the fit: (JSON key, constant prefix, generated count, what k means)
    for (key, prefix, want, power) in [
        (
            "coefficients",
            "ALPHA_ME_C",
            ALPHA_ME_SMALL_TERMS,
            "α ≤ 1 branch, coefficient of s^-",
        ),
        (
            "coefficients_large",
            "ALPHA_ME_D",
            ALPHA_ME_LARGE_TERMS,
            "α > 1 branch, coefficient of ‖b̄‖^",
        ),
    ] {
        let n = am["ours"][key].as_array().map_or(0, |a| a.len());
        if n != want {
            return Err(Error::InvalidArgument(format!(
                "codegen: multiscale-alpha-me has {n} {key}; the generated α_me form has {want}"
            )));
        }
        for k in 0..n {
            out.push(Const {
                name: format!("{prefix}{}", k + 1),
                value: num(&am, &["ours", key, &k.to_string()], "multiscale-alpha-me")? as f32,
                doc: format!(
                    "α_me(‖b̄‖) fit, {power}{} (held-out max rel. error {held:.2e})",
                    k + 1
                ),
            });
        }
    }
    let sl = read("smith-lambda")?;
    let dg = num(&sl, &["held_out", "ours", "max_dg1"], "smith-lambda")?;
    for (key, name) in [
        ("a1", "A1"),
        ("a2", "A2"),
        ("b1", "B1"),
        ("b2", "B2"),
        ("b3", "B3"),
        ("nu_c", "NU_C"),
    ] {
        out.push(Const {
            name: format!("BECKMANN_LAMBDA_{name}"),
            value: num(&sl, &["parameters", key], "smith-lambda")? as f32,
            doc: format!("refitted Beckmann Λ(ν), parameter {key} (held-out max |ΔG1| {dg:.2e})"),
        });
    }
    let fl = read("filters")?;
    let fitted = fl["fitted"].as_array().cloned().unwrap_or_default();
    let find = |fam: &str, ndf: &str| -> Result<(f32, f64)> {
        fitted
            .iter()
            .find(|f| f["family"] == fam && f["ndf"] == ndf)
            .and_then(|f| {
                Some((
                    f["constant"].as_f64()? as f32,
                    f["held_out"]["l2_mean"].as_f64()?,
                ))
            })
            .ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "codegen: filters.json has no fit '{fam}' ({ndf}) (run `{COMMAND}`)"
                ))
            })
    };
    for (fam, ndf, name) in [
        ("vMF α² + c/κ", "GGX", "FILTER_VMF_C_GGX"),
        ("vMF α² + c/κ", "Beckmann", "FILTER_VMF_C_BECKMANN"),
        (
            "Eq 13 σ² (Gaussian pixel)",
            "GGX",
            "FILTER_EQ13_SIGMA2_GAUSSIAN_PIXEL",
        ),
        (
            "Eq 13 σ² (box pixel)",
            "GGX",
            "FILTER_EQ13_SIGMA2_BOX_PIXEL",
        ),
    ] {
        let (c, l2) = find(fam, ndf)?;
        out.push(Const {
            name: name.into(),
            value: c,
            doc: format!("{fam}, {ndf}: fitted constant (held-out mean lobe L2 error {:.1} %, results/filters.md)", 100.0 * l2),
        });
    }
    out.push(Const {
        name: "FILTER_DELTA_MAX".into(),
        value: 0.18,
        doc: "clamp δ_max of seed 003 Eq 10/13".into(),
    });
    let lg = read("leadr-grids")?;
    let h = num(&lg, &["fitted_h_n5"], "leadr-grids")?;
    out.push(Const {
        name: "LEADR_SPACING_N5".into(),
        value: h as f32,
        doc: "fitted uniform slope-grid spacing for N = 5 (results/leadr.md; the paper uses 0.9)"
            .into(),
    });
    // weights ∝ φ(k h), k = 0, ±1, ±2, normalised (the paper's construction, seed 001 §3.4)
    let phi: Vec<f64> = (0..3)
        .map(|k| (-0.5 * (k as f64 * h).powi(2)).exp())
        .collect();
    let sum = phi[0] + 2.0 * (phi[1] + phi[2]);
    for (k, p) in phi.iter().enumerate() {
        out.push(Const {
            name: format!("LEADR_W{k}"),
            value: (p / sum) as f32,
            doc: format!("5-point slope-grid weight of node ±{k}·h (φ(kh)/Σφ with the fitted h)"),
        });
    }
    let lt = read("ltc-ggx")?;
    let n = lt["table"].as_array().map_or(0, |t| t.len());
    if n < 2 {
        return Err(Error::InvalidArgument(format!(
            "codegen: results/fits/ltc-ggx.json has no table (run `{COMMAND}`)"
        )));
    }
    out.push(Const {
        name: "LTC_LUT_SIZE".into(),
        value: n as f32,
        doc: "side of the GGX LTC table (results/fits/ltc-ggx.json: [a, b, c, d] → ltc_1, [norm, fresnel] → ltc_2)".into(),
    });
    Ok(out)
}

/// The functions `names` need, dependencies included, in FUNCTIONS order (which lists
/// dependencies before their users).
pub fn closure(names: &[&str]) -> Result<Vec<&'static FnDesc>> {
    fn add(n: &str, want: &mut Vec<&'static str>) -> Result<()> {
        let f = FUNCTIONS
            .iter()
            .find(|f| f.name == n)
            .ok_or_else(|| Error::InvalidArgument(format!("codegen: unknown function '{n}'")))?;
        for d in f.deps {
            add(d, want)?;
        }
        if !want.contains(&f.name) {
            want.push(f.name);
        }
        Ok(())
    }
    let mut want: Vec<&'static str> = Vec::new();
    for n in names {
        add(n, &mut want)?;
    }
    Ok(FUNCTIONS
        .iter()
        .filter(|f| want.contains(&f.name))
        .collect())
}

/// Constants used by a set of functions (by name occurrence in their bodies).
fn used_consts<'a>(fns: &[&FnDesc], consts: &'a [Const]) -> Vec<&'a Const> {
    consts
        .iter()
        .filter(|c| {
            fns.iter().any(|f| {
                let body = f.body.text();
                body.match_indices(c.name.as_str()).any(|(i, _)| {
                    let after = body[i + c.name.len()..].chars().next();
                    !after.is_some_and(|ch| ch.is_alphanumeric() || ch == '_')
                })
            })
        })
        .collect()
}

/// Render a WGSL module with the given functions (and their dependencies).
pub fn render_wgsl(title: &str, names: &[&str], consts: &[Const], command: &str) -> Result<String> {
    let fns = closure(names)?;
    let mut s = format!("// Generated by `{command}` (src/codegen); do not edit.\n// {title}\n\n");
    for c in used_consts(&fns, consts) {
        s.push_str(&format!(
            "// {}\nconst {}: f32 = {};\n",
            c.doc,
            c.name,
            lit(c.value)
        ));
    }
    for f in fns {
        s.push_str(&format!(
            "\n// {}\nfn {}({}) -> {} {{\n{}}}\n",
            f.doc,
            f.name,
            f.params,
            f.ret,
            f.body.text()
        ));
    }
    Ok(s)
}

/// Render the Rust twin module with the given functions.
pub fn render_rust(names: &[&str], consts: &[Const], command: &str) -> Result<String> {
    let fns = closure(names)?;
    let mut s = format!(
        "// @generated by `{command}` (src/codegen); do not edit.\n//! f32 twins of the generated WGSL functions (same source text), with the fitted constants.\n#![allow(unused_parens, clippy::all, dead_code)]\n\n"
    );
    s.push_str(RUST_PRELUDE);
    for c in used_consts(&fns, consts) {
        s.push_str(&format!(
            "/// {}\npub const {}: f32 = {};\n",
            c.doc,
            c.name,
            lit(c.value)
        ));
    }
    for f in fns {
        s.push_str(&format!(
            "\n/// {}\npub fn {}({}) -> {} {{\n{}}}\n",
            f.doc,
            f.name,
            f.params,
            f.ret,
            f.body.text()
        ));
    }
    Ok(s)
}

const RUST_PRELUDE: &str = "// WGSL built-ins with WGSL semantics\n#[inline]\nfn sqrt(x: f32) -> f32 {\n    x.sqrt()\n}\n#[inline]\nfn exp(x: f32) -> f32 {\n    x.exp()\n}\n#[inline]\nfn log(x: f32) -> f32 {\n    x.ln()\n}\n#[inline]\nfn abs(x: f32) -> f32 {\n    x.abs()\n}\n#[inline]\nfn min(a: f32, b: f32) -> f32 {\n    a.min(b)\n}\n#[inline]\nfn max(a: f32, b: f32) -> f32 {\n    a.max(b)\n}\n#[inline]\nfn clamp(x: f32, lo: f32, hi: f32) -> f32 {\n    x.max(lo).min(hi)\n}\n#[inline]\nfn select(f: f32, t: f32, c: bool) -> f32 {\n    if c {\n        t\n    } else {\n        f\n    }\n}\n\n";

/// The WGSL modules of results/wgsl/: (file name, title, functions).
pub const MODULES: [(&str, &str, &[&str]); 5] = [
    (
        "ndf.wgsl",
        "NDFs, Smith Λ and G2, point-light specular (GGX and Beckmann; tangent space, F = 1)",
        &["ggx_d", "ggx_d_aniso", "ggx_d_matrix", "ggx_lambda", "ggx_g2", "ggx_specular", "beckmann_d", "beckmann_lambda", "beckmann_g2"],
    ),
    (
        "filters.wgsl",
        "Footprint roughness filters (results/filters.md)",
        &["filter_sqrt_sum", "filter_toksvig", "filter_vmf", "filter_vmf_fitted", "filter_deferred", "filter_deferred_fitted", "filter_eq10", "filter_projected"],
    ),
    (
        "ltc.wgsl",
        "LTC polygon lights: table coordinates, edge integral and the quad integral with the clipped-sphere horizon (results/ltc.md); the table itself is data (results/fits/ltc-ggx.json), sampled as two textures",
        &["ltc_lut_u", "ltc_lut_v", "ltc_quad"],
    ),
    (
        "leadr.wgsl",
        "LEADR 5×5 slope-grid integration (seed 001 §3.4–3.5) with the fitted spacing, for an analytic sky + sun environment",
        &["leadr5_env"],
    ),
    (
        "multiscale.wgsl",
        "Multi-scale LTC roughness: ‖b̄‖ → α_me and the overall α by the product identity (results/multiscale*.md)",
        &["alpha_me_pair", "alpha_me", "multiscale_alpha"],
    ),
];

/// Every generated file: (path relative to the repository root, contents). Rust goes to
/// src/generated/ only when `rust` is set (i.e. when regenerating the canonical results/).
pub fn render_all(results: &Path, rust: bool) -> Result<Vec<(String, String)>> {
    let consts = constants(results)?;
    let mut out = Vec::new();
    for (file, title, names) in MODULES {
        out.push((
            format!("wgsl/{file}"),
            render_wgsl(title, names, &consts, COMMAND)?,
        ));
    }
    let table = table::read(results)?;
    out.push((
        "wgsl/ltc_table.wgsl".into(),
        table::render_wgsl(&table, false, COMMAND),
    ));
    out.push((
        "wgsl/ltc_table_f16.wgsl".into(),
        table::render_wgsl(&table, true, COMMAND),
    ));
    if rust {
        let all: Vec<&str> = FUNCTIONS.iter().map(|f| f.name).collect();
        out.push((
            "src/generated/shading.rs".into(),
            render_rust(&all, &consts, COMMAND)?,
        ));
        out.push((
            "src/generated/ltc_table.rs".into(),
            table::render_rust(&table, COMMAND),
        ));
    }
    Ok(out)
}

/// Write the generated files: WGSL under `results`/wgsl, Rust under src/generated when
/// `results` is the canonical `results` directory (so a redirected --results never
/// rewrites the crate's sources). Returns the paths written.
pub fn write_all(results: &Path) -> Result<Vec<String>> {
    let canonical = results == Path::new("results");
    let mut written = Vec::new();
    for (rel, text) in render_all(results, canonical)? {
        let path = if let Some(w) = rel.strip_prefix("wgsl/") {
            // a module that naga rejects is never written
            crate::scene::validate_wgsl(&text, &rel)?;
            results.join("wgsl").join(w)
        } else {
            Path::new(&rel).to_path_buf()
        };
        crate::io::write_atomic(&path, text.as_bytes())?;
        written.push(path.display().to_string());
    }
    if canonical {
        // the audit runs the compiled twins: only meaningful when they are the text just
        // rendered (after a refit, rebuild and rerun `regen` to audit the new twins)
        let rendered = render_rust(
            &FUNCTIONS.iter().map(|f| f.name).collect::<Vec<_>>(),
            &constants(results)?,
            COMMAND,
        )?;
        if rendered == COMPILED_TWINS {
            let md = audit::markdown(&audit::run(), COMMAND);
            let p = results.join("generated-range.md");
            crate::io::write_atomic(&p, md.as_bytes())?;
            written.push(p.display().to_string());
        } else {
            crate::report::stage(
                "codegen: the twins changed; rebuild and rerun `regen` to refresh results/generated-range.md",
            );
        }
    }
    Ok(written)
}

/// The twins this binary was compiled with.
pub const COMPILED_TWINS: &str = include_str!("../generated/shading.rs");

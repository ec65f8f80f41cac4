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
//! Sources: results/fits/{multiscale-alpha-me, smith-lambda, filters, leadr-grids, ltc-ggx}.json,
//! and results/fits/ltc-compact.json where the on-request study has written it (`compact`,
//! and the texture-free sheen forms: `sheen`).
//! tests/codegen.rs re-renders from those files and fails when a committed generated file
//! differs (stale), validates every WGSL module with naga, and compares each Rust twin
//! with its f64 reference.

pub mod aniso;
pub mod audit;
pub mod backends;
pub mod compact;
pub mod desc;
pub mod forms;
pub mod lut;
pub mod namespace;
pub mod shaders;
pub mod sheen;
pub mod table;
mod text;
pub mod textures;
pub mod validate;
pub mod validators;

pub use text::{
    closure, constants, header, render_items, render_rust, render_wgsl, Const,
    ALPHA_ME_LARGE_TERMS, ALPHA_ME_SMALL_TERMS, COMMAND, COMPILED_TWINS, MODULES,
};

use crate::error::Result;
use desc::FUNCTIONS;
use std::path::Path;

/// Every generated file: (path relative to the repository root, contents). Rust goes to
/// src/generated/ only when `rust` is set (i.e. when regenerating the canonical results/).
pub fn render_all(results: &Path, rust: bool) -> Result<Vec<(String, String)>> {
    let consts = constants(results)?;
    let mut out = Vec::new();
    for form in [forms::Form::Plain, forms::Form::NagaOil, forms::Form::Wesl] {
        for (file, title, names) in MODULES {
            out.push((
                form.path(forms::stem(file)),
                forms::render_module(file, title, names, &consts, COMMAND, form)?,
            ));
        }
    }
    let table = table::read(results)?;
    for (stem, half) in [("ltc_table", false), ("ltc_table_f16", true)] {
        let plain = table::render_wgsl(&table, half, COMMAND);
        for form in [forms::Form::NagaOil, forms::Form::Wesl] {
            out.push((form.path(stem), forms::render_data(stem, &plain, form)));
        }
        out.push((forms::Form::Plain.path(stem), plain));
    }
    let lut = lut::render_wgsl(COMMAND);
    for form in [forms::Form::NagaOil, forms::Form::Wesl] {
        out.push((
            form.path("ltc_lut"),
            forms::render_data("ltc_lut", &lut, form),
        ));
    }
    out.push((forms::Form::Plain.path("ltc_lut"), lut));
    let an = aniso::render_wgsl(COMMAND);
    for form in [forms::Form::NagaOil, forms::Form::Wesl] {
        out.push((
            form.path("ltc_aniso"),
            forms::render_data("ltc_aniso", &an, form),
        ));
    }
    out.push((forms::Form::Plain.path("ltc_aniso"), an));
    out.extend(compact::render_all(results, rust, COMMAND)?);
    out.extend(sheen::render_all(results, rust, COMMAND)?);
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
pub fn write_all(set: &mut crate::io::Outputs, results: &Path) -> Result<Vec<String>> {
    let canonical = results == Path::new("results");
    let mut written = Vec::new();
    for (rel, text) in render_all(results, canonical)? {
        let path = if rel.starts_with("wgsl/")
            || rel.starts_with("glsl/")
            || rel.starts_with("shaders/")
            || rel.starts_with("textures/")
        {
            // a module that naga rejects is never written
            if rel.starts_with("wgsl/") {
                validate::validate_wgsl(&text, &rel)?;
            }
            results.join(&rel)
        } else {
            Path::new(&rel).to_path_buf()
        };
        set.put(&path, text.as_bytes());
        written.push(path.display().to_string());
    }
    for kind in &textures::TABLES {
        // the GGX table is required; a table of another lobe only once its study has run
        let t = match crate::results::ltc::table(results, kind.fit) {
            Ok(t) => t,
            Err(_) if *kind != textures::GGX => continue,
            Err(e) => return Err(e),
        };
        for (rel, bytes) in textures::render(&t, kind, COMMAND) {
            let path = results.join(rel);
            set.put(&path, &bytes);
            written.push(path.display().to_string());
        }
    }
    // the anisotropic table once its study has run
    if let Ok(t) = crate::results::ltc_aniso::aniso_table(results) {
        for (rel, bytes) in aniso::render(&t, COMMAND) {
            let path = results.join(rel);
            set.put(&path, &bytes);
            written.push(path.display().to_string());
        }
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
            set.put(&p, md.as_bytes());
            written.push(p.display().to_string());
        } else {
            crate::report::stage(
                "codegen: the twins changed; rebuild and rerun `regen` to refresh results/generated-range.md",
            );
        }
    }
    Ok(written)
}

//! results/shaders.md and results/shaders/spv/: every generated module (results/wgsl/)
//! and every scene shader (results/scenes/*/scene.wgsl), with its harness, through each
//! naga back end (`backends`), and each translation through its validator
//! (`validators`). Compute (`measure`) → markdown (`markdown`) → files (`write`).

use super::backends::{self, Backend, BACKENDS};
use super::validators::{self, Verdict};
use crate::error::{Error, Result};
use std::path::Path;

/// One shader and what became of it.
#[derive(Clone, Debug)]
pub struct Entry {
    /// Its name in the report and in results/shaders/spv/<name>.spv.
    pub name: String,
    /// Where its library text lives, relative to results/.
    pub source: String,
    pub functions: usize,
    pub wgsl_bytes: usize,
    /// Per back end: the output (or naga's error) and the validator's verdict.
    pub outputs: Vec<(backends::Output, Verdict)>,
}

/// The shaders to translate: (name, path relative to `results`), modules first (the
/// compact table's once its on-request study has written it), then the scenes present
/// under `results`/scenes, in name order.
pub fn sources(results: &Path) -> Vec<(String, String)> {
    let compact = results.join("wgsl/ltc_compact.wgsl").is_file();
    let mut out: Vec<(String, String)> = super::text::MODULES
        .iter()
        .map(|(f, _, _)| super::forms::stem(f).to_string())
        .chain(["ltc_table", "ltc_table_f16", "ltc_lut", "ltc_aniso"].map(String::from))
        .chain(compact.then(|| "ltc_compact".to_string()))
        .map(|s| (s.clone(), format!("wgsl/{s}.wgsl")))
        .collect();
    let mut scenes: Vec<String> = std::fs::read_dir(results.join("scenes"))
        .map(|d| {
            d.filter_map(|e| e.ok())
                .filter(|e| e.path().join("scene.wgsl").is_file())
                .filter_map(|e| e.file_name().to_str().map(String::from))
                .collect()
        })
        .unwrap_or_default();
    scenes.sort();
    out.extend(
        scenes
            .into_iter()
            .map(|s| (format!("scene-{s}"), format!("scenes/{s}/scene.wgsl"))),
    );
    out
}

/// Translate and validate every shader of `results` (`validate`: run the external
/// validators; without it every verdict is "not run").
pub fn measure(results: &Path, validate: bool) -> Result<Vec<Entry>> {
    let mut entries = Vec::new();
    for (name, rel) in sources(results) {
        let path = results.join(&rel);
        let src = std::fs::read_to_string(&path).map_err(|e| Error::Io {
            path: path.display().to_string(),
            msg: e.to_string(),
        })?;
        let calls = backends::calls(&src, &rel)?;
        let shader = format!("{src}{}", backends::harness(&calls));
        let outputs = backends::translate(&shader, &rel)?
            .into_iter()
            .map(|o| {
                let v = match (&o.result, validate) {
                    (Ok(bytes), true) => validators::validate(o.backend, bytes),
                    (Ok(_), false) if validators::tool(o.backend).is_none() => Verdict::NoValidator,
                    (Ok(_), false) => Verdict::ToolAbsent,
                    (Err(_), _) => Verdict::NoValidator,
                };
                (o, v)
            })
            .collect();
        entries.push(Entry {
            name,
            source: rel,
            functions: calls.len(),
            wgsl_bytes: src.len(),
            outputs,
        });
    }
    Ok(entries)
}

fn kib(n: usize) -> String {
    format!("{:.1} KiB", n as f64 / 1024.0)
}

/// The report's line naming the validators (a test masks it where they are absent).
pub const VALIDATORS_LINE: &str = "Validators:";

/// results/shaders.md.
pub fn markdown(entries: &[Entry], command: &str) -> String {
    let mut s = super::text::header(
        "<!--",
        command,
        "results/wgsl/*.wgsl and results/scenes/*/scene.wgsl",
    );
    s.push_str("# Generated shaders through every naga back end\n\n");
    s.push_str(&format!(
        "Each library module (no entry point, no bindings) is completed by a generated harness — two storage buffers and one compute entry point `{}` that calls every function of the module — parsed and validated by naga {}, and written by naga's four back ends. The SPIR-V is kept in results/shaders/spv/<module>.spv so that anyone can re-validate it (`spirv-val --target-env vulkan1.0 FILE`). Importable forms of the same modules: results/shaders/naga_oil/ (`#define_import_path ndfbench::<module>`) and results/shaders/wesl/ (package `ndfbench`); tests/shaders.rs composes both with the real composers (naga_oil, wesl-rs) into a shader that calls every function and validates it.\n\n",
        backends::ENTRY,
        naga_version()
    ));
    let tools: Vec<String> = BACKENDS
        .iter()
        .filter_map(|&b| validators::tool(b))
        .map(|(p, args, _)| {
            format!(
                "`{p}{}{}` ({})",
                if args.is_empty() { "" } else { " " },
                args.join(" "),
                validators::version(p).unwrap_or_else(|| "absent".into())
            )
        })
        .collect();
    s.push_str(&format!(
        "{VALIDATORS_LINE} {}. MSL and HLSL have no validator on Linux (Apple's `metal` and Microsoft's `dxc` are not packaged); they are reported as translated only.\n\n",
        tools.join(", ")
    ));
    let mut ok = 0;
    let mut valid = 0;
    let mut total = 0;
    use crate::report::table::{Align, Table};
    let mut t = Table::new([
        "shader",
        "source",
        "functions",
        "WGSL",
        "back end",
        "translated",
        "size",
        "validator",
    ])
    .align(2, Align::Right)
    .align(3, Align::Right)
    .align(6, Align::Right);
    for e in entries {
        for (o, v) in &e.outputs {
            total += 1;
            let tool = validators::tool(o.backend).map_or("", |t| t.0);
            let (tr, size) = match &o.result {
                Ok(b) => {
                    ok += 1;
                    ("yes".to_string(), kib(b.len()))
                }
                Err(m) => (
                    format!("NO: {}", m.lines().next().unwrap_or("")),
                    "—".into(),
                ),
            };
            if *v == Verdict::Valid {
                valid += 1;
            }
            t.row([
                e.name.to_string(),
                e.source.to_string(),
                e.functions.to_string(),
                kib(e.wgsl_bytes),
                o.backend.target().to_string(),
                tr,
                size,
                v.cell(tool).to_string(),
            ]);
        }
    }
    s.push_str(&t.to_string());
    let validated = entries.len()
        * BACKENDS
            .iter()
            .filter(|b| validators::tool(**b).is_some())
            .count();
    s.push_str(&format!(
        "\n{ok} of {total} translations succeeded; {valid} of the {validated} that have a validator passed it.\n"
    ));
    // what the SPIR-V copies into function memory per invocation (dynamically indexed
    // const arrays), counted from the words of each module
    let copies: Vec<String> = entries
        .iter()
        .filter_map(|e| {
            let spv = e.outputs.iter().find(|(o, _)| o.backend == Backend::Spv)?;
            let n = backends::function_array_copies(spv.0.result.as_ref().ok()?);
            let big: Vec<String> = n
                .iter()
                .filter(|&&k| k >= 256)
                .map(|k| k.to_string())
                .collect();
            (!big.is_empty()).then(|| format!("{} (arrays of {} elements)", e.name, big.join(", ")))
        })
        .collect();
    if !copies.is_empty() {
        s.push_str(&format!(
            "\nFunction-memory copies in the SPIR-V (`OpVariable … Function` of an array type, counted from the module's words): {}. naga indexes a `const` array with a dynamic index through a per-invocation copy of the whole array; drivers have to compile and run that copy (tests/gpu.rs measured lavapipe, Mesa 22.3.6, not finishing the f32 table's pipeline in 15 min). Renderers should sample the tables as textures (results/textures/); the const-array modules serve compute passes and tests.\n",
            copies.join("; ")
        ));
    }
    s.push_str("\nThe time each translation and validation takes: results/performance.md (criterion, `shaders/…`).\n");
    s
}

/// The naga version the crate is built with (Cargo.lock).
pub fn naga_version() -> &'static str {
    "30.0.2"
}

/// Every file of the shader report: (path relative to `results`, bytes).
pub fn render(entries: &[Entry], command: &str) -> Vec<(String, Vec<u8>)> {
    let mut out = vec![(
        "shaders.md".to_string(),
        markdown(entries, command).into_bytes(),
    )];
    for e in entries {
        for (o, _) in &e.outputs {
            if let (Backend::Spv, Ok(bytes)) = (o.backend, &o.result) {
                out.push((format!("shaders/spv/{}.spv", e.name), bytes.clone()));
            }
        }
    }
    out
}

/// Measure and write results/shaders.md and the SPIR-V files; returns the paths.
pub fn write(set: &mut crate::io::Outputs, results: &Path) -> Result<Vec<String>> {
    let entries = measure(results, true)?;
    let mut written = Vec::new();
    for (rel, bytes) in render(&entries, super::text::COMMAND) {
        let p = results.join(rel);
        set.put(&p, &bytes);
        written.push(p.display().to_string());
    }
    Ok(written)
}

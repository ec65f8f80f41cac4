//! The generated shader modules as engines take them: importable (naga_oil and WESL,
//! composed by the real composer crates into one shader that calls every function),
//! free of bindings and entry points, namespaced; every module and scene shader
//! translated by naga's four back ends, the SPIR-V and GLSL accepted by the Khronos
//! validators where they are installed, and results/shaders.md fresh.

mod common;

use ndfbench::codegen::{self, backends, forms, shaders, validators};
use std::path::Path;

/// The library modules (stem, plain text, naga_oil text, WESL text).
fn modules() -> Vec<(String, String, String, String)> {
    let read = |p: String| {
        std::fs::read_to_string(Path::new("results").join(&p))
            .unwrap_or_else(|e| panic!("results/{p}: {e}"))
    };
    codegen::MODULES
        .iter()
        .map(|(f, _, _)| forms::stem(f).to_string())
        .chain([
            "ltc_table".into(),
            "ltc_table_f16".into(),
            "ltc_lut".into(),
            "ltc_aniso".into(),
        ])
        .map(|s| {
            (
                s.clone(),
                read(forms::Form::Plain.path(&s)),
                read(forms::Form::NagaOil.path(&s)),
                read(forms::Form::Wesl.path(&s)),
            )
        })
        .collect()
}

/// Every function of every module, called by module-qualified name (`ndf::ndfb_ggx_d`),
/// so that two modules may hold functions of the same name (the two table precisions).
fn qualified_calls() -> Vec<backends::Call> {
    let mut calls = Vec::new();
    for (stem, plain, _, _) in modules() {
        for mut c in backends::calls(&plain, &stem).unwrap() {
            c.name = format!("{stem}::{}", c.name);
            calls.push(c);
        }
    }
    calls
}

fn validate(module: &naga::Module, what: &str) -> naga::valid::ModuleInfo {
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), backends::CAPABILITIES)
        .validate(module)
        .unwrap_or_else(|e| panic!("{what}: {e:?}"))
}

/// The composed shader reaches every function of every module: after composition each
/// one is present (by its namespaced name, possibly decorated by the composer).
fn assert_calls_every_function(module: &naga::Module, what: &str) {
    let names: Vec<String> = module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.clone())
        .collect();
    for (stem, plain, _, _) in modules() {
        for c in backends::calls(&plain, &stem).unwrap() {
            assert!(
                names.iter().any(|n| n.contains(&c.name)),
                "{what}: {stem}::{} missing after composition",
                c.name
            );
        }
    }
    assert_eq!(module.entry_points.len(), 1, "{what}");
}

#[test]
fn library_modules_have_no_bindings_no_entry_points_and_namespaced_names() {
    for (stem, plain, oil, wesl) in modules() {
        for (form, text) in [("plain", &plain), ("naga_oil", &oil), ("wesl", &wesl)] {
            for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
                for bad in [
                    "@group",
                    "@binding",
                    "@compute",
                    "@vertex",
                    "@fragment",
                    "var<",
                ] {
                    assert!(
                        !line.contains(bad),
                        "{stem} ({form}) declares {bad}: {line}"
                    );
                }
            }
        }
        let m = naga::front::wgsl::parse_str(&plain).unwrap();
        assert!(
            m.entry_points.is_empty() && m.global_variables.is_empty(),
            "{stem}"
        );
        for (_, f) in m.functions.iter() {
            let n = f.name.as_deref().unwrap();
            assert!(n.starts_with(codegen::namespace::FN_PREFIX), "{stem}: {n}");
        }
        for (_, c) in m.constants.iter() {
            let n = c.name.as_deref().unwrap();
            assert!(
                n.starts_with(codegen::namespace::CONST_PREFIX),
                "{stem}: {n}"
            );
        }
        // every function states its input convention where it takes α
        let doc_lines: Vec<&str> = plain.lines().collect();
        for (k, l) in doc_lines.iter().enumerate() {
            if l.starts_with("fn ") && l.contains("alpha: f32") {
                assert!(
                    doc_lines[k - 1].contains("perceptual roughness")
                        || doc_lines[k - 1].contains("perceptual_roughness"),
                    "{stem}: {l} lacks the α convention"
                );
            }
        }
        assert!(
            oil.contains(&format!("#define_import_path ndfbench::{stem}\n")),
            "{stem}: naga_oil import path"
        );
    }
}

#[test]
fn naga_oil_composes_every_module_into_one_validating_shader() {
    use naga_oil::compose::{
        ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderLanguage, ShaderType,
    };
    let mut composer = Composer::default().with_capabilities(backends::CAPABILITIES);
    let mods = modules();
    for (stem, _, oil, _) in &mods {
        let r = composer.add_composable_module(ComposableModuleDescriptor {
            source: oil,
            file_path: &format!("ndfbench/{stem}.wgsl"),
            language: ShaderLanguage::Wgsl,
            ..Default::default()
        });
        if let Err(e) = r {
            panic!("{stem}: {}", e.emit_to_string(&composer));
        }
    }
    let imports: String = mods
        .iter()
        .map(|(s, _, _, _)| format!("#import ndfbench::{s}\n"))
        .collect();
    let shader = format!("{imports}{}", backends::harness(&qualified_calls()));
    let module = composer
        .make_naga_module(NagaModuleDescriptor {
            source: &shader,
            file_path: "harness.wgsl",
            shader_type: ShaderType::Wgsl,
            ..Default::default()
        })
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&composer)));
    let info = validate(&module, "naga_oil composition");
    assert_calls_every_function(&module, "naga_oil");
    for b in backends::BACKENDS {
        let out = backends::write(b, &module, &info);
        assert!(out.is_ok(), "naga_oil composition → {b:?}: {out:?}");
    }
}

#[test]
fn wesl_composes_every_module_as_the_package_ndfbench() {
    // the user's layout: their shader root holds main.wesl; our modules are the package
    // `ndfbench` (Bevy main registers them under that name), imported as ndfbench::<module>
    use wesl::syntax::{ModulePath, PathOrigin};
    let dir = common::scratch("shaders", "wesl");
    let pkg = dir.join("ndfbench");
    std::fs::create_dir_all(&pkg).unwrap();
    let mods = modules();
    for (stem, _, _, wesl) in &mods {
        std::fs::write(pkg.join(format!("{stem}.wesl")), wesl).unwrap();
    }
    let imports: String = mods
        .iter()
        .map(|(s, _, _, _)| format!("import ndfbench::{s};\n"))
        .collect();
    std::fs::write(
        dir.join("main.wesl"),
        format!("{imports}{}", backends::harness(&qualified_calls())),
    )
    .unwrap();
    let mut router = wesl::Router::new();
    router.mount_resolver(
        ModulePath::new(PathOrigin::Package("ndfbench".into()), vec![]),
        wesl::FileResolver::new(&pkg),
    );
    router.mount_fallback_resolver(wesl::FileResolver::new(&dir));
    let compiler = wesl::Wesl::new(&dir).set_custom_resolver(router);
    let root = ModulePath::new(PathOrigin::Absolute, vec!["main".into()]);
    let compiled = compiler
        .compile(&root)
        .unwrap_or_else(|e| panic!("wesl: {e}"));
    let wgsl = compiled.to_string();
    let _ = std::fs::remove_dir_all(&dir);
    let module = naga::front::wgsl::parse_str(&wgsl)
        .unwrap_or_else(|e| panic!("wesl output: {}", e.emit_to_string(&wgsl)));
    let info = validate(&module, "wesl composition");
    assert_calls_every_function(&module, "wesl");
    for b in backends::BACKENDS {
        let out = backends::write(b, &module, &info);
        assert!(out.is_ok(), "wesl composition → {b:?}: {out:?}");
    }
}

/// results/shaders.md without the validators' versions (which differ between
/// distributions) and, with `verdicts`, without their verdicts too (for machines that
/// lack the tools).
fn mask(md: &str, verdicts: bool) -> String {
    md.lines()
        .filter(|l| !l.starts_with(shaders::VALIDATORS_LINE))
        .map(
            |l| match (verdicts && l.starts_with("| "), l.rfind(" | ")) {
                (true, Some(i)) => l[..i].to_string(),
                _ => l.to_string(),
            },
        )
        .filter(|l| !verdicts || !l.contains(" that have a validator passed it"))
        .collect::<Vec<_>>()
        .join("\n")
}

fn tools_present() -> bool {
    backends::BACKENDS
        .iter()
        .filter_map(|&b| validators::tool(b))
        .all(|(p, _, _)| validators::version(p).is_some())
}

#[test]
fn shaders_report_and_spirv_files_are_fresh() {
    let results = Path::new("results");
    let present = tools_present();
    if !present {
        eprintln!("spirv-val or glslangValidator absent: comparing results/shaders.md without its verdict column");
    }
    let entries = shaders::measure(results, present).unwrap();
    for (rel, bytes) in shaders::render(&entries, codegen::COMMAND) {
        let path = results.join(&rel);
        let committed = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let stale = format!("{} is stale: run `{}`", path.display(), codegen::COMMAND);
        if rel.ends_with(".md") {
            let (a, b) = (
                String::from_utf8(committed).unwrap(),
                String::from_utf8(bytes).unwrap(),
            );
            assert!(mask(&a, !present) == mask(&b, !present), "{stale}");
            assert!(a.lines().next().unwrap().contains(codegen::COMMAND));
        } else {
            assert!(committed == bytes, "{stale}");
        }
    }
    // every shader translated by every back end
    for e in &entries {
        for (o, _) in &e.outputs {
            assert!(
                o.result.is_ok(),
                "{} → {:?}: {:?}",
                e.name,
                o.backend,
                o.result
            );
        }
    }
    assert!(entries.iter().any(|e| e.name.starts_with("scene-")));
}

#[test]
fn committed_spirv_and_fresh_glsl_pass_the_khronos_validators() {
    for (b, program) in [
        (backends::Backend::Spv, "spirv-val"),
        (backends::Backend::Glsl, "glslangValidator"),
    ] {
        if validators::version(program).is_none() {
            eprintln!("skipping {program}: not installed (Debian spirv-tools / glslang-tools; .ci/run installs them)");
            continue;
        }
        let entries = shaders::measure(Path::new("results"), false).unwrap();
        let mut n = 0;
        for e in &entries {
            let bytes = if b == backends::Backend::Spv {
                std::fs::read(Path::new("results/shaders/spv").join(format!("{}.spv", e.name)))
                    .unwrap()
            } else {
                e.outputs
                    .iter()
                    .find(|(o, _)| o.backend == b)
                    .unwrap()
                    .0
                    .result
                    .clone()
                    .unwrap()
            };
            let v = validators::validate(b, &bytes);
            assert_eq!(v, validators::Verdict::Valid, "{program} on {}", e.name);
            n += 1;
        }
        eprintln!("{program}: {n} shaders valid");
    }
}

#[test]
fn a_broken_shader_is_an_invalid_verdict_not_a_pass() {
    // the validators are not rubber stamps: a truncated SPIR-V module and GLSL with a type
    // error are rejected
    if validators::version("spirv-val").is_some() {
        let good = std::fs::read("results/shaders/spv/ndf.spv").unwrap();
        let v = validators::validate(backends::Backend::Spv, &good[..good.len() / 2]);
        assert!(matches!(v, validators::Verdict::Invalid(_)), "{v:?}");
    } else {
        eprintln!("skipping: spirv-val not installed");
    }
    if validators::version("glslangValidator").is_some() {
        let bad = b"#version 450 core\nlayout(local_size_x = 1) in;\nvoid main() { float x = vec2(1.0); }\n";
        let v = validators::validate(backends::Backend::Glsl, bad);
        assert!(matches!(v, validators::Verdict::Invalid(_)), "{v:?}");
    } else {
        eprintln!("skipping: glslangValidator not installed");
    }
}

#[test]
fn the_reported_naga_version_is_the_locked_one() {
    let lock = std::fs::read_to_string("Cargo.lock").unwrap();
    let i = lock.find("name = \"naga\"\n").expect("naga in Cargo.lock");
    let version = lock[i..].lines().nth(1).unwrap();
    assert_eq!(
        version,
        format!("version = \"{}\"", shaders::naga_version())
    );
}

#[test]
fn the_harness_rejects_what_it_cannot_call() {
    let e = backends::calls("fn f(v: vec3<f32>) -> f32 { return v.x; }", "t").unwrap_err();
    assert!(e.to_string().contains("f has a signature"), "{e}");
    assert!(backends::calls("fn f(", "t").is_err());
}

#[test]
fn the_const_array_tables_are_copied_into_function_memory_and_the_modules_are_not() {
    // the counter reads what spirv-dis shows for ltc_table.spv: two Function-class
    // variables of 4096-element arrays (LTC_1 and LTC_2), none for the function modules
    let copies = |name: &str| {
        backends::function_array_copies(
            &std::fs::read(format!("results/shaders/spv/{name}.spv")).unwrap(),
        )
    };
    assert_eq!(copies("ltc_table"), vec![4096, 4096]);
    assert_eq!(copies("ltc_table_f16"), vec![4096, 4096]);
    for m in ["ndf", "filters", "ltc", "multiscale"] {
        assert!(copies(m).iter().all(|&n| n < 256), "{m}: {:?}", copies(m));
    }
    // and against SPIRV-Tools' disassembler, where installed
    if validators::version("spirv-dis").is_none() {
        eprintln!("spirv-dis absent: the word counter checked against fixed expectations only");
        return;
    }
    for (name, _) in shaders::sources(Path::new("results")) {
        let path = format!("results/shaders/spv/{name}.spv");
        let out = std::process::Command::new("spirv-dis")
            .arg(&path)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        let dis = text
            .lines()
            .filter(|l| l.contains("= OpVariable %_ptr_Function__arr_"))
            .count();
        assert_eq!(dis, copies(&name).len(), "{name}");
    }
}

/// The executed-instruction counter of results/performance.md's compact-LTC section: a
/// function's own instructions, each call adding its callee's; loops and unknown names
/// are typed errors. What spirv-dis shows naga 30 emitting for these two functions: g is
/// OpBranch (into its body block), OpFMul, OpReturnValue; f is OpBranch, OpFunctionCall,
/// OpFAdd (x + 1), OpFunctionCall, OpFAdd, OpReturnValue.
#[test]
fn executed_instructions_count_calls_and_refuse_loops() {
    let src = "fn g(x: f32) -> f32 {\n    return x * 2.0;\n}\n\nfn f(x: f32) -> f32 {\n    return g(x) + g(x + 1.0);\n}\n";
    let v = backends::executed_instructions(src, "t", &["g", "f"]).unwrap();
    assert_eq!(v[0], 3, "g");
    assert_eq!(v[1], 6 + 2 * 3, "f: its own six, and g twice");
    let looped = "fn h(x: f32) -> f32 {\n    var s = 0.0;\n    for (var i = 0; i < 4; i++) {\n        s += x;\n    }\n    return s;\n}\n";
    let e = backends::executed_instructions(looped, "t", &["h"]).unwrap_err();
    assert!(e.to_string().contains("loops"), "{e}");
    let e = backends::executed_instructions(src, "t", &["nope"]).unwrap_err();
    assert!(e.to_string().contains("no function nope"), "{e}");
}

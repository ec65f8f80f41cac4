//! The three forms of every generated module, from one description:
//! - plain WGSL (results/wgsl/): self-contained, every dependency inlined — paste it;
//! - naga_oil (results/shaders/naga_oil/): `#define_import_path ndfbench::<module>` and
//!   `#import` of what another module owns (Bevy ≤ 0.19, any naga_oil `Composer`);
//! - WESL (results/shaders/wesl/, the root of the package `ndfbench`): `import package::…`
//!   (Bevy main, wesl-rs, wesl-js). WESL is a superset of WGSL: the body is the same text.
//!
//! Library modules hold no `@group`/`@binding` globals (the engine owns its bind groups)
//! and no entry points; every function and constant is namespaced (`namespace`).

use super::desc::FnDesc;
use super::text::{closure, header, render_items, Const, MODULES};
use crate::error::Result;

/// The package name of the importable forms: `ndfbench::ndf`, `ndfbench::ltc`, ….
pub const PACKAGE: &str = "ndfbench";

/// How a module is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// Self-contained WGSL.
    Plain,
    /// WGSL with naga_oil's `#define_import_path` / `#import` directives.
    NagaOil,
    /// WESL with `import package::…;` declarations.
    Wesl,
}

impl Form {
    /// Where the form lives under results/, and its file extension.
    pub fn path(self, stem: &str) -> String {
        match self {
            Form::Plain => format!("wgsl/{stem}.wgsl"),
            Form::NagaOil => format!("shaders/naga_oil/{stem}.wgsl"),
            Form::Wesl => format!("shaders/wesl/{stem}.wesl"),
        }
    }
}

/// The module stem of a MODULES file name (`ndf.wgsl` → `ndf`).
pub fn stem(file: &str) -> &str {
    file.strip_suffix(".wgsl").unwrap_or(file)
}

/// The module that owns a function: the first of MODULES whose functions (with their
/// dependencies) include it. Other modules import it from there.
pub fn owner(name: &str) -> Option<&'static str> {
    MODULES.iter().find_map(|(file, _, names)| {
        closure(names)
            .ok()?
            .iter()
            .any(|f| f.name == name)
            .then(|| stem(file))
    })
}

/// The directive lines of a module in `form`: its own import path and its imports
/// (module stem → WGSL names).
fn directives(form: Form, stem: &str, imports: &[(&str, Vec<String>)]) -> String {
    let mut s = String::new();
    match form {
        Form::Plain => {}
        Form::NagaOil => {
            s.push_str(&format!("#define_import_path {PACKAGE}::{stem}\n"));
            for (m, names) in imports {
                s.push_str(&format!(
                    "#import {PACKAGE}::{m}::{{{}}}\n",
                    names.join(", ")
                ));
            }
        }
        Form::Wesl => {
            for (m, names) in imports {
                s.push_str(&format!("import package::{m}::{{{}}};\n", names.join(", ")));
            }
        }
    }
    if !s.is_empty() {
        s.push('\n');
    }
    s
}

/// A function module (one of MODULES) in `form`. The plain form inlines every
/// dependency; the importable forms hold only the module's own functions and import
/// the others' from their owner.
pub fn render_module(
    file: &str,
    title: &str,
    names: &[&str],
    consts: &[Const],
    command: &str,
    form: Form,
) -> Result<String> {
    if form == Form::Plain {
        return super::text::render_wgsl(title, names, consts, command);
    }
    let st = stem(file);
    let all = closure(names)?;
    let own: Vec<&FnDesc> = all
        .iter()
        .copied()
        .filter(|f| owner(f.name) == Some(st))
        .collect();
    let mut imports: Vec<(&str, Vec<String>)> = Vec::new();
    for f in &own {
        for d in f.deps {
            let o = owner(d).unwrap_or(st);
            if o == st {
                continue;
            }
            let name = super::namespace::wgsl_name(d);
            match imports.iter_mut().find(|(m, _)| *m == o) {
                Some((_, v)) if !v.contains(&name) => v.push(name),
                Some(_) => {}
                None => imports.push((o, vec![name])),
            }
        }
    }
    Ok(format!(
        "{}// {title}\n\n{}{}",
        header("//", command, "src/codegen/desc.rs and results/fits/*.json"),
        directives(form, st, &imports),
        render_items(&own, consts)
    ))
}

/// A data module (the LTC tables, no imports) in `form`: its plain text with the
/// directive placed after the leading comment lines.
pub fn render_data(stem: &str, plain: &str, form: Form) -> String {
    let d = directives(form, stem, &[]);
    if d.is_empty() {
        return plain.to_string();
    }
    let cut = plain
        .split_inclusive('\n')
        .take_while(|l| l.starts_with("//") || l.trim().is_empty())
        .map(str::len)
        .sum::<usize>();
    format!("{}{d}{}", &plain[..cut], &plain[cut..])
}

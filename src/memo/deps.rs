//! What a study's cached maps depend on: the source files its code can reach, found from
//! the sources themselves. The build script runs this (through `#[path]`, so it uses only
//! std and sha2) and compiles in one hash per *unit*; a study's cache key takes its own
//! unit's hash instead of a hash of every source, so an edit to a report, a test or
//! another study leaves its entries warm, and an edit to anything it reaches invalidates
//! them.
//!
//! A unit is a top-level module (`ltc`, `microfacet`, `scene`, … with every file under its
//! folder), except under `studies/` and `results/`, where every child folder or file is a
//! unit of its own (`studies::ltc_ggx`, `results::smith_lambda`) and the folder's `mod.rs`
//! is the unit `studies` or `results`. The reach is the
//! closure of unit-to-unit arrows, taken generously, because a missed arrow would let a
//! stale entry give stale bits:
//!
//! - every `crate::a::…` path in any file of a unit (comments included, `super::` chains
//!   resolved to absolute paths, nested `use` groups expanded) names `a`, or `studies::x`
//!   for a path into a study; the `mod.rs` of a split folder also names every child it
//!   names bare in a path (its re-exports);
//! - an `impl` in unit A of a trait or for a type that another unit B defines is an arrow
//!   B → A as well: B's users may call methods they never import;
//! - `include_str!`/`include_bytes!` add the file they include;
//! - every unit reaches `lib`, `memo` (how entries are stored), `Cargo.toml` and
//!   `Cargo.lock` (the dependencies' versions).

use sha2::{Digest, Sha256};
use std::collections::{BTreeMap, BTreeSet};

/// The unit of the source file `path` (relative to the crate root, `/`-separated), or
/// `None` for a file outside the library (`src/main.rs`, anything not under src/).
pub fn unit_of(path: &str) -> Option<String> {
    let rel = path.strip_prefix("src/")?;
    if rel == "main.rs" {
        return None;
    }
    let mut segs: Vec<&str> = rel.split('/').collect();
    let last = segs.pop()?;
    let stem = last.rsplit_once('.').map_or(last, |(s, _)| s).to_string();
    let mut module: Vec<String> = segs.iter().map(|s| s.to_string()).collect();
    if stem != "mod" {
        module.push(stem);
    }
    Some(match module.as_slice() {
        [] => "lib".to_string(),
        [one] if one == "lib" => "lib".to_string(),
        [top, sub, ..] if SPLIT.contains(&top.as_str()) => format!("{top}::{sub}"),
        [top, ..] => top.clone(),
    })
}

/// The folders whose children are units of their own (their `mod.rs` is the folder's
/// unit): every study, and every result file's type.
const SPLIT: [&str; 2] = ["studies", "results"];

/// The module path of a source file (`src/ltc/fit.rs` → `ltc::fit`, `src/ltc/mod.rs` →
/// `ltc`, `src/lib.rs` → ``).
fn module_of(path: &str) -> Vec<String> {
    let rel = path.strip_prefix("src/").unwrap_or(path);
    let mut segs: Vec<String> = rel.split('/').map(str::to_string).collect();
    let last = segs.pop().unwrap_or_default();
    let stem = last.rsplit_once('.').map_or(last.as_str(), |(s, _)| s);
    if stem != "mod" && stem != "lib" {
        segs.push(stem.to_string());
    }
    segs
}

// the path roots, spelled so that a scan of this file's own text finds no path in them
const CRATE: &str = concat!("crate", "::");
const SUPER: &str = concat!("super", "::");

/// `super::` chains rewritten as absolute `crate::` paths for a file of module `m`.
fn absolute(m: &[String], text: &str) -> String {
    let mut code = text.to_string();
    while let Some(at) = code.find(SUPER) {
        let mut parent = m.to_vec();
        let mut end = at;
        while code[end..].starts_with(SUPER) {
            parent.pop();
            end += SUPER.len();
        }
        let abs = if parent.is_empty() {
            CRATE.to_string()
        } else {
            format!("{CRATE}{}::", parent.join("::"))
        };
        code.replace_range(at..end, &abs);
    }
    code
}

fn ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Every path a `crate::` occurrence names, with `use` groups expanded:
/// `crate::a::{b, c::{d, e}}` gives `a::b`, `a::c::d`, `a::c::e` (and `a` itself).
fn crate_paths(code: &str) -> Vec<Vec<String>> {
    fn walk(s: &[char], mut i: usize, prefix: &[String], out: &mut Vec<Vec<String>>) -> usize {
        let mut path = prefix.to_vec();
        if i >= 2 && s.get(i) == Some(&'{') {
            // `crate::{a, b}`: read the group from its `::`
            i -= 2;
        }
        loop {
            let start = i;
            while i < s.len() && ident(s[i]) {
                i += 1;
            }
            if i > start {
                path.push(s[start..i].iter().collect());
            }
            if i + 2 < s.len() && s[i] == ':' && s[i + 1] == ':' && s[i + 2] == '{' {
                out.push(path.clone());
                i += 3;
                loop {
                    while i < s.len() && (s[i].is_whitespace() || s[i] == ',') {
                        i += 1;
                    }
                    if i >= s.len() || s[i] == '}' {
                        return i + 1;
                    }
                    let before = i;
                    i = walk(s, i, &path, out);
                    // skip `as x`, `self`, `*` and anything else up to the next item
                    while i < s.len() && s[i] != ',' && s[i] != '}' {
                        i += 1;
                    }
                    if i == before {
                        i += 1;
                    }
                }
            }
            if i + 1 < s.len() && s[i] == ':' && s[i + 1] == ':' {
                i += 2;
                continue;
            }
            out.push(path);
            return i;
        }
    }
    let chars: Vec<char> = code.chars().collect();
    let text: String = chars.iter().collect();
    let mut out = Vec::new();
    for (byte_at, _) in text.match_indices(CRATE) {
        let at = text[..byte_at].chars().count();
        if at > 0 && ident(chars[at - 1]) {
            continue;
        }
        walk(&chars, at + CRATE.len(), &[], &mut out);
    }
    out
}

/// The unit a module path names (`["ltc", "fit", "Table"]` → `ltc`, `["studies",
/// "ltc_ggx", …]` → `studies::ltc_ggx`), given the units that exist.
fn unit_of_path(p: &[String], units: &BTreeSet<String>) -> Option<String> {
    let top = p.first()?;
    if SPLIT.contains(&top.as_str()) {
        if let Some(s) = p.get(1) {
            let u = format!("{top}::{s}");
            if units.contains(&u) {
                return Some(u);
            }
        }
    }
    Some(top.clone())
}

/// The names a file declares as types or traits: a line that starts (after `pub`,
/// `pub(crate)`, `pub(super)`) with `struct X`, `enum X`, `trait X` or `union X`, or a
/// module-level `type X` (column 0; an associated type is indented).
fn declared(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in code.lines() {
        let top = !line.starts_with(char::is_whitespace);
        let mut l = line.trim_start();
        for vis in ["pub(crate) ", "pub(super) ", "pub "] {
            l = l.strip_prefix(vis).unwrap_or(l);
        }
        for kw in ["struct ", "enum ", "trait ", "union ", "type "] {
            if kw == "type " && !top {
                continue;
            }
            if let Some(rest) = l.strip_prefix(kw) {
                let name: String = rest.chars().take_while(|c| ident(*c)).collect();
                if !name.is_empty() {
                    out.insert(name);
                }
            }
        }
    }
    out
}

/// A path as written and its last name (`crate::a::Tr` → (`crate::a::Tr`, `Tr`)).
type Named = (String, String);

/// Each `impl` header's trait (if any) and self type:
/// `impl<T: X> crate::a::Tr<T> for Foo<T> where … {` → (Some(crate::a::Tr), Foo).
fn impls(code: &str) -> Vec<(Option<Named>, Named)> {
    fn skip_generics(h: &str) -> &str {
        let h = h.trim_start();
        if !h.starts_with('<') {
            return h;
        }
        let mut depth = 0;
        for (k, c) in h.char_indices() {
            match c {
                '<' => depth += 1,
                '>' => {
                    depth -= 1;
                    if depth == 0 {
                        return &h[k + 1..];
                    }
                }
                _ => {}
            }
        }
        ""
    }
    fn named(t: &str) -> Named {
        let t = t.trim().trim_start_matches('!').trim_start_matches('&');
        let t = t.strip_prefix("dyn ").unwrap_or(t).trim();
        let path: String = t.chars().take_while(|c| ident(*c) || *c == ':').collect();
        let last = path.rsplit("::").next().unwrap_or("").to_string();
        (path, last)
    }
    let mut out = Vec::new();
    for line in code.lines() {
        let l = line.trim_start();
        let l = l.strip_prefix("unsafe ").unwrap_or(l);
        let Some(rest) = l.strip_prefix("impl") else {
            continue;
        };
        if rest.chars().next().is_some_and(ident) {
            continue;
        }
        let header = skip_generics(rest);
        let header = header.split(" where").next().unwrap_or(header);
        let header = header.split('{').next().unwrap_or(header);
        match header.split_once(" for ") {
            Some((tr, ty)) => out.push((Some(named(tr)), named(ty))),
            None => out.push((None, named(header))),
        }
    }
    out
}

/// `include_str!("…")` and `include_bytes!("…")` targets of the file `path`, as paths
/// relative to the crate root.
fn includes(path: &str, code: &str) -> Vec<String> {
    let dir: Vec<&str> = path
        .rsplit_once('/')
        .map_or(vec![], |(d, _)| d.split('/').collect());
    let mut out = Vec::new();
    for mac in ["include_str!(\"", "include_bytes!(\""] {
        for (at, _) in code.match_indices(mac) {
            let rel: String = code[at + mac.len()..]
                .chars()
                .take_while(|c| *c != '"')
                .collect();
            let mut parts: Vec<&str> = dir.clone();
            for seg in rel.split('/') {
                match seg {
                    ".." => {
                        parts.pop();
                    }
                    "." | "" => {}
                    s => parts.push(s),
                }
            }
            out.push(parts.join("/"));
        }
    }
    out
}

/// The text without lines that are only a comment (a comment after code stays: cutting
/// at `//` could cut a string such as a URL, and a path in a comment only adds an arrow).
fn code(text: &str) -> String {
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Each unit's own files and its direct arrows to other units (see the module doc).
pub struct Graph {
    pub own: BTreeMap<String, BTreeSet<String>>,
    pub arrows: BTreeMap<String, BTreeSet<String>>,
}

/// The unit graph of `files` ((path relative to the crate root, bytes)).
pub fn graph(files: &[(String, Vec<u8>)]) -> Graph {
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    let sources: Vec<(&str, String, String)> = files
        .iter()
        .filter(|(p, _)| p.ends_with(".rs"))
        .filter_map(|(p, b)| {
            unit_of(p).map(|u| (p.as_str(), u, absolute(&module_of(p), &code(&text(b)))))
        })
        .collect();
    let units: BTreeSet<String> = sources.iter().map(|s| s.1.clone()).collect();
    let mut own: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut arrows: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut defines: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (p, u, code) in &sources {
        own.entry(u.clone()).or_default().insert(p.to_string());
        own.get_mut(u).unwrap().extend(includes(p, code));
        for name in declared(code) {
            defines.entry(name).or_default().insert(u.clone());
        }
        let a = arrows.entry(u.clone()).or_default();
        for path in crate_paths(code) {
            if let Some(v) = unit_of_path(&path, &units) {
                a.insert(v);
            }
        }
    }
    // a split folder's mod.rs names its children bare in paths (`pub use registry::{…}`)
    for top in SPLIT {
        let Some((_, _, code)) = sources.iter().find(|s| s.0 == format!("src/{top}/mod.rs")) else {
            continue;
        };
        let a = arrows.entry(top.to_string()).or_default();
        let prefix = format!("{top}::");
        for s in units.iter().filter(|u| u.starts_with(&prefix)) {
            let bare = format!("{}::", &s[prefix.len()..]);
            if code.match_indices(&bare).any(|(at, _)| {
                !code[..at]
                    .chars()
                    .next_back()
                    .is_some_and(|c| ident(c) || c == ':')
            }) {
                a.insert(s.clone());
            }
        }
    }
    // an impl in A for another unit's type (or, for a type of no unit, of another unit's
    // trait): that unit reaches A. A type named by a `crate::` path is that path's unit; a
    // bare name A declares itself (in any of its files) is A's own
    let mut declared_in: BTreeMap<&str, BTreeSet<String>> = BTreeMap::new();
    for (_, u, code) in &sources {
        declared_in
            .entry(u.as_str())
            .or_default()
            .extend(declared(code));
    }
    for (_, u, code) in &sources {
        // what the unit declares in any of its files (a study's mod.rs implements a trait
        // for the type its compute.rs declares)
        let mine = &declared_in[u.as_str()];
        for (tr, (ty_path, ty)) in impls(code) {
            let owners = |path: &str, name: &str| -> BTreeSet<String> {
                if let Some(p) = path.strip_prefix(CRATE) {
                    let segs: Vec<String> = p.split("::").map(str::to_string).collect();
                    return unit_of_path(&segs, &units).into_iter().collect();
                }
                if mine.contains(name) {
                    return BTreeSet::new();
                }
                defines.get(name).cloned().unwrap_or_default()
            };
            let mut from = owners(&ty_path, &ty);
            if from.is_empty() && !mine.contains(&ty) {
                if let Some((tp, t)) = &tr {
                    from = owners(tp, t);
                }
            }
            for d in from {
                if d != *u {
                    arrows.entry(d).or_default().insert(u.clone());
                }
            }
        }
    }
    Graph { own, arrows }
}

/// For every unit of `files` ((path relative to the crate root, bytes); the library's
/// sources, the files they include, Cargo.toml and Cargo.lock), the sorted paths of the
/// files it reaches (see the module doc).
pub fn reach(files: &[(String, Vec<u8>)]) -> BTreeMap<String, BTreeSet<String>> {
    let Graph { own, arrows } = graph(files);
    let always: Vec<&str> = ["lib", "memo"].to_vec();
    let mut out = BTreeMap::new();
    for u in own.keys() {
        let mut seen: BTreeSet<String> = BTreeSet::new();
        let mut stack: Vec<String> = vec![u.clone()];
        stack.extend(always.iter().map(|s| s.to_string()));
        while let Some(v) = stack.pop() {
            if !own.contains_key(&v) || !seen.insert(v.clone()) {
                continue;
            }
            stack.extend(arrows.get(&v).into_iter().flatten().cloned());
        }
        let mut reached: BTreeSet<String> =
            seen.iter().flat_map(|v| own[v].iter().cloned()).collect();
        reached.insert("Cargo.toml".into());
        reached.insert("Cargo.lock".into());
        out.insert(u.clone(), reached);
    }
    out
}

/// The hash of each unit: SHA-256 over the files it reaches (path and length frame each
/// file; a reached path absent from `files` hashes as absent).
pub fn unit_hashes(files: &[(String, Vec<u8>)]) -> BTreeMap<String, String> {
    let bytes: BTreeMap<&str, &[u8]> = files
        .iter()
        .map(|(p, b)| (p.as_str(), b.as_slice()))
        .collect();
    reach(files)
        .into_iter()
        .map(|(u, paths)| {
            let mut h = Sha256::new();
            for p in &paths {
                h.update(p.as_bytes());
                match bytes.get(p.as_str()) {
                    Some(b) => {
                        h.update((b.len() as u64).to_le_bytes());
                        h.update(b);
                    }
                    None => h.update(b"absent"),
                }
            }
            let hex: String = h.finalize().iter().map(|b| format!("{b:02x}")).collect();
            (u, hex)
        })
        .collect()
}

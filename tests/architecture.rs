//! ARCHITECTURE.md stays true (every folder under src/ is named in it) and the layers point
//! one way: no import circle between files or folders, models never reach the driver,
//! results/, memo/ or report/, and report/ knows no model.

use std::path::Path;

/// Backtick tokens of a line, with `dir/{a,b}.rs` expanded; a bare `x.rs` takes the
/// directory of the first token of the same line that has one.
fn names(line: &str) -> Vec<String> {
    let toks: Vec<&str> = line.split('`').skip(1).step_by(2).collect();
    let mut out = Vec::new();
    let mut dir = String::new();
    for t in toks {
        let expanded: Vec<String> = match (t.find('{'), t.find('}')) {
            (Some(a), Some(b)) if a < b => t[a + 1..b]
                .split(',')
                .map(|x| format!("{}{}{}", &t[..a], x.trim(), &t[b + 1..]))
                .collect(),
            _ => vec![t.to_string()],
        };
        for e in expanded {
            if let Some(k) = e.rfind('/') {
                if dir.is_empty() {
                    dir = e[..=k].to_string();
                }
                out.push(e);
            } else {
                out.push(format!("{dir}{e}"));
                out.push(e);
            }
        }
    }
    out
}

#[test]
fn every_folder_is_named_in_architecture_md() {
    let arch = std::fs::read_to_string("ARCHITECTURE.md").unwrap();
    let named: std::collections::HashSet<String> = arch.lines().flat_map(names).collect();
    // every folder under src/ as `dir/`, and every file directly in src/
    let mut missing = Vec::new();
    let mut stack = vec![Path::new("src").to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            let rel = p.strip_prefix("src").unwrap().display().to_string();
            if p.is_dir() {
                stack.push(p.clone());
                if !named.contains(&format!("{rel}/")) {
                    missing.push(format!("{rel}/"));
                }
            } else if d == Path::new("src")
                && p.extension().is_some_and(|x| x == "rs")
                && !named.contains(&rel)
            {
                missing.push(rel);
            }
        }
    }
    missing.sort();
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md does not name: {missing:?}"
    );
}

/// Every hand-written source file as (module path, text), e.g. ("ltc::fit", …).
fn sources() -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut stack = vec![Path::new("src").to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                if !p.ends_with("generated") {
                    stack.push(p);
                }
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p.strip_prefix("src").unwrap().with_extension("");
                let m = rel.display().to_string().replace('/', "::");
                let m = m.strip_suffix("::mod").unwrap_or(&m).to_string();
                out.push((m, std::fs::read_to_string(&p).unwrap()));
            }
        }
    }
    out
}

/// The modules the file of module `m` names through `crate::…` and `super::…` paths
/// (longest known prefix), comments and `#[cfg(test)]` modules stripped;
/// `use crate::a::{b, c::d}` names a::b and a::c, and `super::x` in `a::b` names `a::x`.
fn imports(m: &str, text: &str, known: &std::collections::HashSet<String>) -> Vec<String> {
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    let mut code: String = text
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
    // super:: chains → absolute crate:: paths (a module's super is its parent module)
    while let Some(at) = code.find("super::") {
        let mut parent: Vec<&str> = m.split("::").collect();
        let mut end = at;
        while code[end..].starts_with("super::") {
            parent.pop();
            end += 7;
        }
        let abs = if parent.is_empty() {
            "crate::".to_string()
        } else {
            format!("crate::{}::", parent.join("::"))
        };
        code.replace_range(at..end, &abs);
    }
    // a module's own children, named bare (`mod cases;` then `cases::x`) or by `self::`
    let children: Vec<String> = code
        .lines()
        .filter_map(|l| {
            let l = l.trim();
            let l = l.strip_prefix("pub ").unwrap_or(l);
            let l = l.strip_prefix("pub(crate) ").unwrap_or(l);
            let l = l.strip_prefix("pub(super) ").unwrap_or(l);
            l.strip_prefix("mod ")?
                .strip_suffix(';')
                .map(str::to_string)
        })
        .collect();
    for c in children {
        let full = format!("{m}::{c}");
        if !known.contains(&full) {
            continue;
        }
        let mut rebuilt = String::with_capacity(code.len());
        let mut rest = code.as_str();
        while let Some(at) = rest.find(&format!("{c}::")) {
            let before = rest[..at].chars().next_back();
            let bare = !before.is_some_and(|b| b.is_alphanumeric() || b == '_' || b == ':');
            rebuilt.push_str(&rest[..at]);
            if bare {
                rebuilt.push_str(&format!("crate::{full}::"));
            } else {
                rebuilt.push_str(&format!("{c}::"));
            }
            rest = &rest[at + c.len() + 2..];
        }
        rebuilt.push_str(rest);
        code = rebuilt.replace(&format!("self::crate::{full}"), &format!("crate::{full}"));
    }
    let mut out = Vec::new();
    for (at, _) in code.match_indices("crate::") {
        let rest = &code[at + 7..];
        let path: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
            .collect();
        let path = path.trim_end_matches(':').to_string();
        let mut cands = vec![];
        let braced = rest[path.len()..].starts_with("::{");
        if !braced {
            cands.push(path.clone());
        }
        if braced {
            let inner: String = rest[path.len() + 3..]
                .chars()
                .take_while(|c| *c != '}')
                .collect();
            for part in inner.split(',') {
                let part = part
                    .trim()
                    .split(" as ")
                    .next()
                    .unwrap_or("")
                    .replace('{', "");
                if !part.is_empty() {
                    // an item of `path` itself names `path`; a child module names the child
                    let full = format!("{path}::{part}");
                    let head = format!("{path}::{}", part.split("::").next().unwrap_or(""));
                    if known.contains(&head) {
                        cands.push(full);
                    } else {
                        cands.push(path.clone());
                    }
                }
            }
        }
        for c in cands {
            let segs: Vec<&str> = c.split("::").collect();
            for k in (1..=segs.len()).rev() {
                let s = segs[..k].join("::");
                if known.contains(&s) {
                    out.push(s);
                    break;
                }
            }
        }
    }
    out
}

#[test]
fn the_import_graph_has_no_circle_and_models_never_import_studies() {
    let src = sources();
    let known: std::collections::HashSet<String> = src.iter().map(|s| s.0.clone()).collect();
    let edges: std::collections::HashMap<String, Vec<String>> = src
        .iter()
        .map(|(m, t)| {
            let mut e = imports(m, t, &known);
            e.retain(|x| x != m);
            e.sort();
            e.dedup();
            (m.clone(), e)
        })
        .collect();
    // drivers: the registry, the study trait, the CLI; nothing below them imports them
    let driver =
        |m: &str| ["studies", "study", "cli", "main"].contains(&m.split("::").next().unwrap());
    for (m, es) in &edges {
        if !driver(m) {
            for e in es.iter().filter(|e| driver(e)) {
                panic!("model module {m} imports the driver module {e}");
            }
        }
    }
    // no circle between files (depth-first search for back edges; every one reported)
    fn visit(
        m: &str,
        edges: &std::collections::HashMap<String, Vec<String>>,
        state: &mut std::collections::HashMap<String, u8>,
        path: &mut Vec<String>,
        circles: &mut Vec<String>,
    ) {
        state.insert(m.to_string(), 1);
        path.push(m.to_string());
        for e in edges.get(m).into_iter().flatten() {
            match state.get(e.as_str()) {
                Some(1) => {
                    let from = path.iter().position(|p| p == e).unwrap_or(0);
                    circles.push(format!("{} → {e}", path[from..].join(" → ")));
                }
                Some(_) => {}
                None => visit(e, edges, state, path, circles),
            }
        }
        path.pop();
        state.insert(m.to_string(), 2);
    }
    let mut state = std::collections::HashMap::new();
    let mut circles = Vec::new();
    let mut names: Vec<&String> = edges.keys().collect();
    names.sort();
    for m in names {
        if !state.contains_key(m.as_str()) {
            visit(m, &edges, &mut state, &mut Vec::new(), &mut circles);
        }
    }
    assert!(
        circles.is_empty(),
        "{} import circles between files:\n{}",
        circles.len(),
        circles.join("\n")
    );
}

/// Hand-written functions longer than 150 lines and files longer than 600 allowed to
/// stay (none: every one has been split).
const LONG_FUNCTIONS: &[&str] = &[];
const LONG_FILES: &[&str] = &[];

#[test]
fn no_function_over_150_lines_and_no_file_over_600() {
    let mut long_fns = Vec::new();
    let mut long_files = Vec::new();
    for (m, text) in sources() {
        let lines: Vec<&str> = text.lines().collect();
        if lines.len() > 600 && !LONG_FILES.contains(&m.as_str()) {
            long_files.push(format!("{m} ({} lines)", lines.len()));
        }
        for (k, l) in lines.iter().enumerate() {
            let t = l.trim_start();
            let Some(rest) = ["pub fn ", "fn ", "pub(super) fn ", "pub(crate) fn "]
                .iter()
                .find_map(|p| t.strip_prefix(p))
            else {
                continue;
            };
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            // the body: from the first `{` to its matching `}` (string and char literals
            // and comments ignored)
            let (mut depth, mut started, mut end) = (0i32, false, k);
            'outer: for (j, line) in lines.iter().enumerate().skip(k) {
                let code = line.split("//").next().unwrap_or("");
                let mut in_str = false;
                let mut prev = ' ';
                for c in code.chars() {
                    if c == '"' && prev != '\\' {
                        in_str = !in_str;
                    } else if !in_str && c == '{' {
                        depth += 1;
                        started = true;
                    } else if !in_str && c == '}' {
                        depth -= 1;
                    }
                    prev = c;
                }
                if !started && code.trim_end().ends_with(';') {
                    break;
                }
                if started && depth <= 0 {
                    end = j;
                    break 'outer;
                }
            }
            let full = format!("{m}::{name}");
            if end - k + 1 > 150 && !LONG_FUNCTIONS.contains(&full.as_str()) {
                long_fns.push(format!("{full} ({} lines)", end - k + 1));
            }
        }
    }
    assert!(
        long_fns.is_empty(),
        "functions over 150 lines: {long_fns:?}"
    );
    assert!(
        long_files.is_empty(),
        "files over 600 lines: {long_files:?}"
    );
}

/// The model layers: pure numerics, no knowledge of where results live, how maps are
/// memoised or how reports look.
const MODELS: &[&str] = &[
    "microfacet",
    "integrate",
    "ltc",
    "multiscale",
    "tensor",
    "filters",
    "survey",
    "visibility",
    "fit",
    "kernels",
    "leadr",
    "linalg",
    "optimize",
    "jacobian",
];

#[test]
fn models_never_read_results_call_memo_or_format_reports() {
    let src = sources();
    let known: std::collections::HashSet<String> = src.iter().map(|s| s.0.clone()).collect();
    let upper = |m: &str| ["results", "memo", "report"].contains(&m.split("::").next().unwrap());
    let mut found: Vec<(String, String)> = Vec::new();
    for (m, t) in &src {
        if !MODELS.contains(&m.split("::").next().unwrap()) {
            continue;
        }
        for e in imports(m, t, &known) {
            if upper(&e) {
                let top = e.split("::").next().unwrap().to_string();
                found.push((m.clone(), top));
            }
        }
    }
    found.sort();
    found.dedup();
    assert!(
        found.is_empty(),
        "model modules reaching up (pass data and a ParMap in instead): {found:?}"
    );
}

/// The top-level folders as a graph (an arrow where any file of one names a file of the
/// other): it has no circle, so the pipeline reads one way at folder level too, and
/// report/ draws and says where a run is without knowing any model or result.
#[test]
fn folders_point_one_way_and_report_knows_no_model() {
    let src = sources();
    let known: std::collections::HashSet<String> = src.iter().map(|s| s.0.clone()).collect();
    let top = |m: &str| m.split("::").next().unwrap_or("").to_string();
    let mut edges: std::collections::BTreeMap<String, std::collections::BTreeSet<String>> =
        Default::default();
    for (m, t) in &src {
        for e in imports(m, t, &known) {
            if top(&e) != top(m) {
                edges.entry(top(m)).or_default().insert(top(&e));
            }
        }
    }
    let report: Vec<&String> = edges
        .get("report")
        .into_iter()
        .flatten()
        .filter(|e| !["error", "progress", "io"].contains(&e.as_str()))
        .collect();
    assert!(report.is_empty(), "report/ reaches into {report:?}");
    // circles at folder level: a folder that reaches itself through others
    let mut circles = Vec::new();
    for start in edges.keys() {
        let mut seen = std::collections::BTreeSet::new();
        let mut stack: Vec<String> = edges[start].iter().cloned().collect();
        while let Some(x) = stack.pop() {
            if &x == start {
                circles.push(start.clone());
                break;
            }
            if seen.insert(x.clone()) {
                stack.extend(edges.get(&x).into_iter().flatten().cloned());
            }
        }
    }
    assert!(
        circles.is_empty(),
        "folders on an import circle: {circles:?} (arrows: {edges:?})"
    );
}

/// The modules that may touch the disk, and why. Everything else, every study included,
/// hands its files to the driver as `io::Outputs`, which publishes them as one set.
const WRITERS: &[(&str, &str)] = &[
    (
        "io",
        "the one publisher of output sets, and lone atomic files",
    ),
    (
        "main",
        "the driver: publishes each command's set; the generated documents",
    ),
    (
        "cli::batch",
        "the `slurm` command publishes its scripts as a set",
    ),
    (
        "cli::prefilter",
        "the `prefilter` command publishes its mips as a set",
    ),
    (
        "studies::run",
        "the `regen` driver publishes each study's set",
    ),
    ("memo::cache", "cache entries, not results"),
    ("memo::shards", "shard files, not results"),
    (
        "studies::performance::main_job",
        "the main job's own profile under target/",
    ),
    (
        "codegen::validators",
        "a scratch file for an external validator",
    ),
    ("tensor::compare", "the scratch script TensorLy runs in"),
];

/// What writes a file or publishes a set, as it appears in the source.
const WRITES: &[&str] = &[
    "write_atomic(",
    "fs::write(",
    "File::create(",
    "create_dir_all(",
    "OpenOptions",
    "fs::rename(",
    "in_set(",
    ".publish(",
];

#[test]
fn no_study_writes_files_itself() {
    let mut found = Vec::new();
    let mut writers: Vec<&str> = Vec::new();
    for (m, t) in sources() {
        let code: String = t
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        let hits: Vec<&str> = WRITES
            .iter()
            .copied()
            .filter(|w| code.contains(w))
            .collect();
        if hits.is_empty() {
            continue;
        }
        match WRITERS.iter().find(|(w, _)| *w == m) {
            Some((w, _)) => writers.push(w),
            None => found.push(format!("{m}: {hits:?}")),
        }
    }
    found.sort();
    assert!(
        found.is_empty(),
        "modules that write files themselves (add them to an io::Outputs the driver publishes): {found:?}"
    );
    let stale: Vec<&str> = WRITERS
        .iter()
        .map(|w| w.0)
        .filter(|w| !writers.contains(w))
        .collect();
    assert!(
        stale.is_empty(),
        "listed as writers but write nothing (remove them from WRITERS): {stale:?}"
    );
}

/// Markdown tables are written by one writer, `report::table::Table`: no code outside it
/// writes a separator row ("|---", "|:---") or a row literal ("| … |" at the start of a
/// string). Doc comments may hold tables (rustdoc renders them).
#[test]
fn markdown_tables_go_through_the_one_writer() {
    let hand_built = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .filter(|l| {
                l.contains("|---")
                    || l.contains("|:---")
                    || l.contains("\"| ")
                    || l.contains("\"|{")
            })
            .map(|l| l.trim().chars().take(60).collect())
            .collect()
    };
    let mut found = Vec::new();
    for (m, text) in sources() {
        if m == "report::table" {
            continue;
        }
        for l in hand_built(&text) {
            found.push(format!("{m}: {l}"));
        }
    }
    assert!(
        found.is_empty(),
        "hand-built markdown tables (use report::table::Table): {found:?}"
    );
}

/// A study computes its typed result, then renders it (`study!` takes `computes f`,
/// `f: fn(&Ctx) -> Result<R>`; `no_study_writes_files_itself` keeps the writing with the
/// driver). This test holds the rendering side to formatting: a module under studies/
/// named for rendering (`report`, `render`, `plots`) runs no memoised map and no rayon
/// loop — what it shows was computed before it.
#[test]
fn report_code_formats_and_never_computes() {
    const COMPUTES: [&str; 6] = [
        "memo::",
        "Memo,",
        "map_items(",
        "par_iter(",
        "into_par_iter(",
        "use rayon",
    ];
    let mut renders = 0;
    let mut computing = Vec::new();
    for (m, text) in sources() {
        if !m.starts_with("studies::") {
            continue;
        }
        let last = m.rsplit("::").next().unwrap_or(&m);
        if !(last.contains("report") || last == "render" || last == "plots") {
            continue;
        }
        renders += 1;
        let code = text.split("#[cfg(test)]").next().unwrap_or("");
        for w in COMPUTES {
            if code.contains(w) {
                computing.push(format!("{m}: {w}"));
            }
        }
    }
    assert!(renders >= 10, "found only {renders} report modules");
    assert!(
        computing.is_empty(),
        "report code that computes (move it to the study's compute step): {computing:?}"
    );
}

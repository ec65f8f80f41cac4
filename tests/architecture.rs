//! ARCHITECTURE.md stays true: every hand-written file under src/ is named in it.

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
fn every_source_file_is_named_in_architecture_md() {
    let arch = std::fs::read_to_string("ARCHITECTURE.md").unwrap();
    let named: std::collections::HashSet<String> = arch.lines().flat_map(names).collect();
    let mut missing = Vec::new();
    let mut stack = vec![Path::new("src").to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                if !p.ends_with("generated") {
                    stack.push(p);
                }
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p.strip_prefix("src").unwrap().display().to_string();
                if !named.contains(&rel) && rel != "lib.rs" {
                    missing.push(rel);
                }
            }
        }
    }
    missing.sort();
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md does not name: {missing:?}"
    );
}

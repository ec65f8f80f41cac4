//! The names the generated items carry in WGSL. Every function and constant of a
//! generated module is prefixed (`ndfb_`, `NDFB_`), so that a module pasted next to an
//! engine's own code (which has its own `PI`, `D_GGX`, …) never collides, in every form:
//! plain WGSL, naga_oil and WESL (where the module path namespaces them a second time).
//! The Rust twins keep the bare names: Rust modules already namespace them.

/// Prefix of generated WGSL functions.
pub const FN_PREFIX: &str = "ndfb_";
/// Prefix of generated WGSL constants.
pub const CONST_PREFIX: &str = "NDFB_";

/// The WGSL name of a generated function or constant (constants are upper case).
pub fn wgsl_name(ident: &str) -> String {
    if ident.chars().any(|c| c.is_ascii_lowercase()) {
        format!("{FN_PREFIX}{ident}")
    } else {
        format!("{CONST_PREFIX}{ident}")
    }
}

/// Rename every identifier of `text` that is in `idents` to its WGSL name; comments
/// (`//` to the end of the line; WGSL has no string literals) are left as written.
pub fn apply(text: &str, idents: &[&str]) -> String {
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    for line in text.split_inclusive('\n') {
        let (code, comment) = match line.find("//") {
            Some(i) => line.split_at(i),
            None => (line, ""),
        };
        let b = code.as_bytes();
        let mut i = 0;
        while i < b.len() {
            let c = b[i];
            if c.is_ascii_alphabetic() || c == b'_' {
                let start = i;
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                    i += 1;
                }
                let word = &code[start..i];
                if idents.contains(&word) {
                    out.push_str(&wgsl_name(word));
                } else {
                    out.push_str(word);
                }
            } else if c.is_ascii_digit() {
                // a number literal (1e-5, 0x2au, 2.0f): never an identifier
                let start = i;
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'.' || b[i] == b'_')
                    || (i > start
                        && (b[i] == b'-' || b[i] == b'+')
                        && matches!(b[i - 1], b'e' | b'E')
                        && !code[start..i].starts_with("0x"))
                {
                    i += 1;
                }
                out.push_str(&code[start..i]);
            } else {
                let ch = code[i..].chars().next().expect("char");
                out.push(ch);
                i += ch.len_utf8();
            }
        }
        out.push_str(comment);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renames_identifiers_not_comments_or_literals() {
        let t = "let a: f32 = ggx_d(x, 1e-5, PI) + ggx_dx; // ggx_d stays\nconst PI: f32 = 3.0;\n";
        assert_eq!(
            apply(t, &["ggx_d", "PI"]),
            "let a: f32 = ndfb_ggx_d(x, 1e-5, NDFB_PI) + ggx_dx; // ggx_d stays\nconst NDFB_PI: f32 = 3.0;\n"
        );
    }
}

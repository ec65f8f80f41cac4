//! The deliverables' tables of results/performance.md (benches/deliverables.rs): every
//! generated shader through naga and the Khronos validators, and the prefilter tool on a
//! 2048² map next to the per-mip re-read a one-pass-per-mip tool does.

use super::{fmt_time, Timed};

const SHADER_COLUMNS: [&str; 7] = [
    "naga parse + validate",
    "spv",
    "msl",
    "hlsl",
    "glsl",
    "spirv-val",
    "glslangValidator",
];

/// Module × step (criterion mean; "—" where not measured, e.g. a validator absent).
pub(super) fn shaders_table(timed: &[Timed]) -> String {
    let mut modules: Vec<&str> = timed
        .iter()
        .filter_map(|t| t.group.strip_prefix("shaders/"))
        .collect();
    modules.dedup();
    if modules.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## Shaders: translation and validation per module\n\nEach generated module with its compute harness (results/shaders.md): naga 30's WGSL front end with full validation, each back end on the validated module, and the external validators on the back end's output (process start and a temporary file included; most of glslangValidator's time is its start-up). Criterion mean per call with its 95 % confidence interval.\n\n| module |");
    for c in SHADER_COLUMNS {
        md.push_str(&format!(" {c} |"));
    }
    md.push_str("\n|---|");
    md.push_str(&"---|".repeat(SHADER_COLUMNS.len()));
    md.push('\n');
    for m in modules {
        md.push_str(&format!("| {m} |"));
        for c in SHADER_COLUMNS {
            let cell = timed
                .iter()
                .find(|t| t.group == format!("shaders/{m}") && t.function == c)
                .map_or("—".to_string(), |t| {
                    format!(
                        "{} ({} – {})",
                        fmt_time(t.mean_ns),
                        fmt_time(t.lo_ns),
                        fmt_time(t.hi_ns)
                    )
                });
            md.push_str(&format!(" {cell} |"));
        }
        md.push('\n');
    }
    md
}

/// The prefilter tool at 2048².
pub(super) fn prefilter_table(timed: &[Timed]) -> String {
    let rows: Vec<&Timed> = timed.iter().filter(|t| t.group == "prefilter").collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## prefilter: roughness mips of a 2048² normal map\n\nThe whole tool on an 8-bit 2048² PNG with one α (12 levels; goal < 1 s on 2 cores), its parts, and, for the complexity, the same statistics computed the way a one-pass-per-mip tool (Filament's roughness-prefilter) does: every level re-reads its 2^l × 2^l base block, O(N log N) against the pyramid's O(N).\n\n| step | time (95 % CI) |\n|---|---|\n");
    for t in rows {
        md.push_str(&format!(
            "| {} | {} ({} – {}) |\n",
            t.function,
            fmt_time(t.mean_ns),
            fmt_time(t.lo_ns),
            fmt_time(t.hi_ns)
        ));
    }
    md
}

//! The external validators of the translated shaders: `spirv-val` (SPIRV-Tools, Debian
//! spirv-tools) for SPIR-V and `glslangValidator` (Debian glslang-tools) for GLSL. No
//! validator for MSL or HLSL runs on Linux without Apple's or Microsoft's compilers;
//! those outputs are reported as translated, not validated. An absent tool is a
//! verdict of its own, never an error.

use super::backends::Backend;
use std::process::Command;

/// A validator's verdict on one translated shader.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Verdict {
    Valid,
    /// The validator's first line of complaint.
    Invalid(String),
    /// The tool is not installed (or failed to start).
    ToolAbsent,
    /// No validator exists for this back end on this platform.
    NoValidator,
}

impl Verdict {
    /// The verdict in a table cell.
    pub fn cell(&self, tool: &str) -> String {
        match self {
            Verdict::Valid => format!("valid ({tool})"),
            Verdict::Invalid(m) => format!("INVALID ({tool}: {m})"),
            Verdict::ToolAbsent => format!("not run ({tool} absent)"),
            Verdict::NoValidator => "not validated (no validator on Linux)".into(),
        }
    }
}

/// The validator of a back end: (program, arguments before the file, file extension).
pub fn tool(b: Backend) -> Option<(&'static str, &'static [&'static str], &'static str)> {
    match b {
        Backend::Spv => Some(("spirv-val", &["--target-env", "vulkan1.0"], "spv")),
        // glslangValidator picks the stage from the extension; #version 450 core is in the file
        Backend::Glsl => Some(("glslangValidator", &[], "comp")),
        Backend::Msl | Backend::Hlsl => None,
    }
}

/// The first line of a tool's `--version` output, or None when it is absent.
pub fn version(program: &str) -> Option<String> {
    let out = Command::new(program).arg("--version").output().ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    text.lines().next().map(|l| l.trim().to_string())
}

/// Run the back end's validator over `bytes` (written to a private temporary file).
pub fn validate(b: Backend, bytes: &[u8]) -> Verdict {
    let Some((program, args, ext)) = tool(b) else {
        return Verdict::NoValidator;
    };
    static COUNTER: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let path = std::env::temp_dir().join(format!(
        "ndfbench-validate-{}-{n}.{ext}",
        std::process::id()
    ));
    if std::fs::write(&path, bytes).is_err() {
        return Verdict::ToolAbsent;
    }
    let out = Command::new(program).args(args).arg(&path).output();
    let _ = std::fs::remove_file(&path);
    match out {
        Err(_) => Verdict::ToolAbsent,
        Ok(o) if o.status.success() => Verdict::Valid,
        Ok(o) => {
            let text = format!(
                "{}{}",
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            );
            let line = text
                .lines()
                .map(str::trim)
                .find(|l| !l.is_empty() && !l.ends_with(&format!(".{ext}")))
                .unwrap_or("failed")
                .replace(path.display().to_string().as_str(), "FILE");
            Verdict::Invalid(line.chars().take(160).collect())
        }
    }
}

//! Replacing one section of an existing results/performance.md (`bench-report
//! --main-job-only`, `--compact-only`, `--ltc-fit-only`): the rest of the page kept byte for byte.

use crate::error::Result;
use std::path::Path;

/// Replace the section of an existing results/performance.md that starts with `head`
/// (up to the next `## ` heading) by `section`; an absent page or section is an error.
pub(super) fn replace_section(
    set: &mut crate::io::Outputs,
    results: &Path,
    head: &str,
    section: &str,
) -> Result<String> {
    let path = results.join("performance.md");
    let (p, md) = (
        path.display(),
        std::fs::read_to_string(&path).unwrap_or_default(),
    );
    let name = head.trim_start_matches("\n## ");
    let start = md.find(head).ok_or_else(|| {
        let why = format!("{p}: no section \"{name}\" to refresh (run bench-report in full)");
        crate::error::Error::InvalidArgument(why)
    })?;
    let end = md[start + head.len()..]
        .find("\n## ")
        .map_or(md.len(), |k| start + head.len() + k);
    let out = format!("{}{}{}", &md[..start], section, &md[end..]);
    set.put(&path, out.as_bytes());
    Ok(format!("{p}: section \"{name}\" refreshed"))
}

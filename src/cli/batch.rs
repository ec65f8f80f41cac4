//! Batch runs beyond one machine: the `regen --shard` / `merge` arguments and `slurm`,
//! which writes a Slurm job array (one shard per array task) and a merge job that runs
//! after every task has succeeded (`--dependency=afterok`).

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// `slurm`: write the batch scripts of a sharded run of one study.
#[derive(clap::Args, Clone, Debug)]
pub struct SlurmArgs {
    /// The study's exact name (a spec of fits/, e.g. `ltc-ggx`).
    #[arg(long)]
    pub only: String,
    /// How many shards (array tasks), 1 … 4096.
    #[arg(long)]
    pub shards: usize,
    /// At most this many tasks at once (`--array=0-(N−1)%M`); 0: no limit.
    #[arg(long, default_value_t = 0)]
    pub max_running: usize,
    /// CPUs per array task (`--cpus-per-task`); rayon uses them all.
    #[arg(long, default_value_t = 1)]
    pub cpus: usize,
    #[arg(long, value_enum, default_value_t = crate::integrate::Preset::Default)]
    pub preset: crate::integrate::Preset,
    /// Slurm partition (omitted: the cluster's default).
    #[arg(long)]
    pub partition: Option<String>,
    /// Directory for the scripts, the shard files (`shards/`) and the logs (`logs/`).
    #[arg(long)]
    pub out: PathBuf,
}

fn abs(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).map_err(|e| Error::Io {
        path: p.display().to_string(),
        msg: e.to_string(),
    })
}

/// Quote for a POSIX shell.
fn q(p: &Path) -> String {
    format!("'{}'", p.display().to_string().replace('\'', "'\\''"))
}

/// A path written into an `#SBATCH` line, which Slurm reads without shell quoting: one
/// with white space, a quote, a backslash, `$`, a backtick, `%` (Slurm's file-name
/// patterns) or a control character is refused, naming the flag it came from.
fn sbatch_path(flag: &str, p: &Path) -> Result<()> {
    let s = p.display().to_string();
    if let Some(c) = s
        .chars()
        .find(|c| c.is_whitespace() || c.is_control() || "'\"\\$`%".contains(*c))
    {
        return Err(Error::InvalidArgument(format!(
            "{flag} {}: Slurm's #SBATCH --output line cannot quote {}; choose a directory without white space, quotes, backslashes, $, backticks, % or control characters",
            crate::error::quoted(&s),
            crate::error::quoted(&c.to_string())
        )));
    }
    Ok(())
}

/// The three scripts (file name, text): `array.sbatch`, `merge.sbatch`, `submit.sh`.
pub fn scripts(
    a: &SlurmArgs,
    exe: &Path,
    fits: &Path,
    results: &Path,
) -> Result<Vec<(String, String)>> {
    if a.shards == 0 || a.shards > crate::memo::shards::MAX_SHARDS {
        return Err(Error::Shard(format!(
            "--shards {}: 1 … {}",
            a.shards,
            crate::memo::shards::MAX_SHARDS
        )));
    }
    if a.cpus == 0 || a.cpus > 1024 {
        return Err(Error::InvalidArgument(format!(
            "--cpus {}: 1 … 1024",
            a.cpus
        )));
    }
    if !a
        .only
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    {
        return Err(Error::InvalidArgument(format!(
            "--only {}: not a study name",
            crate::error::quoted(&a.only)
        )));
    }
    if let Some(p) = &a.partition {
        if !p
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_,.".contains(c))
        {
            return Err(Error::InvalidArgument(format!(
                "--partition {}: not a partition name",
                crate::error::quoted(p)
            )));
        }
    }
    let (exe, fits, results, out) = (abs(exe)?, abs(fits)?, abs(results)?, abs(&a.out)?);
    let shards = out.join("shards");
    let logs = out.join("logs");
    sbatch_path("--out", &logs)?;
    let limit = if a.max_running > 0 {
        format!("%{}", a.max_running)
    } else {
        String::new()
    };
    let part = a
        .partition
        .as_ref()
        .map_or(String::new(), |p| format!("#SBATCH --partition={p}\n"));
    let cwd = results.parent().map_or(results.clone(), Path::to_path_buf);
    let head = format!(
        "#!/bin/bash\n# Written by `ndfbench slurm --only {} --shards {}`: one shard of the study per array task.\n",
        a.only, a.shards
    );
    // the two jobs share their header and the command's prefix
    let job = |name: &str, sbatch: &str, log: &str, args: &str| {
        format!(
            "{head}#SBATCH --job-name={name}\n{sbatch}#SBATCH --cpus-per-task={cpus}\n#SBATCH --output={logs}/{log}.out\n{part}set -euo pipefail\ncd {cwd}\nexport RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-{cpus}}}\"\nexec {exe} --fits {fits} --results {results} {args}\n",
            cpus = a.cpus,
            logs = logs.display(),
            cwd = q(&cwd),
            exe = q(&exe),
            fits = q(&fits),
            results = q(&results),
        )
    };
    let array = job(
        &format!("ndfb-{}", a.only),
        &format!("#SBATCH --array=0-{}{limit}\n", a.shards - 1),
        &format!("{}-%a", a.only),
        &format!(
            "regen --only {} --preset {} --shard \"${{SLURM_ARRAY_TASK_ID}}/{}\" --shard-dir {}",
            a.only,
            a.preset.name(),
            a.shards,
            q(&shards)
        ),
    );
    let merge = job(
        &format!("ndfb-{}-merge", a.only),
        "",
        &format!("{}-merge", a.only),
        &format!("merge {}", q(&shards)),
    );
    let submit = format!(
        "#!/bin/sh\n# Submit the array, then the merge once every task has succeeded.\n# Extra arguments go to the merge's sbatch (e.g. --wait to block until it is done).\nset -eu\ncd \"$(dirname \"$0\")\"\nmkdir -p {logs} {shards}\njid=$(sbatch --parsable array.sbatch)\njid=${{jid%%;*}}\necho \"array job $jid ({n} tasks)\"\nsbatch --parsable --dependency=afterok:\"$jid\" \"$@\" merge.sbatch\n",
        logs = q(&logs),
        shards = q(&shards),
        n = a.shards
    );
    Ok(vec![
        ("array.sbatch".into(), array),
        ("merge.sbatch".into(), merge),
        ("submit.sh".into(), submit),
    ])
}

/// Write the scripts into `a.out` (one output set; `submit.sh` made executable).
pub fn write_scripts(
    set: &mut crate::io::Outputs,
    a: &SlurmArgs,
    exe: &Path,
    fits: &Path,
    results: &Path,
) -> Result<Vec<String>> {
    let files = scripts(a, exe, fits, results)?;
    let mut written = Vec::new();
    for (name, text) in &files {
        let p = a.out.join(name);
        set.put(&p, text.as_bytes());
        written.push(p.display().to_string());
    }
    Ok(written)
}

/// Make the written scripts executable (after the set is published).
pub fn make_executable(out: &Path) {
    #[cfg(unix)]
    for name in ["array.sbatch", "merge.sbatch", "submit.sh"] {
        use std::os::unix::fs::PermissionsExt;
        let p = out.join(name);
        let _ = std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755));
    }
}

/// `regen --only NAME --shard K/N`: one shard file, nothing else.
pub fn shard(
    fits: &Path,
    results: &Path,
    only: Option<&str>,
    preset: crate::integrate::Preset,
    spec: &str,
    dir: &Path,
) -> Result<bool> {
    let name = only
        .ok_or_else(|| Error::Shard("--shard needs --only with the study's exact name".into()))?;
    let ks = crate::memo::shards::parse_spec(spec)?;
    let p = crate::studies::shard(fits, results, name, preset, ks, dir)?;
    println!("wrote shard {}/{} of {name}: {}", ks.0, ks.1, p.display());
    Ok(true)
}

/// `merge SHARDS…`: the study's output set from a complete set of shards.
pub fn merge(fits: &Path, results: &Path, shards: &[PathBuf]) -> Result<bool> {
    let (o, secs) = crate::studies::merge(fits, results, shards)?;
    println!(
        "{:<5} {:<24} {} (merged; the shards computed for {secs:.1} s in all)",
        if o.passed { "pass" } else { "FAIL" },
        o.name,
        o.summary
    );
    Ok(o.passed)
}

/// `slurm`: the scripts, published as one set, made executable.
pub fn slurm(a: &SlurmArgs, fits: &Path, results: &Path) -> Result<bool> {
    // the study is validated exactly as `regen --only NAME --shard K/N` validates it
    crate::studies::check_sharded(fits, &a.only)?;
    let exe = std::env::current_exe().map_err(|e| Error::Io {
        path: "current executable".into(),
        msg: e.to_string(),
    })?;
    let w = crate::io::in_set("slurm", &a.out.join(".manifest.json"), |set| {
        write_scripts(set, a, &exe, fits, results)
    })?;
    make_executable(&a.out);
    println!(
        "wrote {}; submit with {}/submit.sh",
        w.join(", "),
        a.out.display()
    );
    Ok(true)
}

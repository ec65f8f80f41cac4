//! File output: every file is written to a temporary sibling and renamed, and every
//! *set* of files that belong together (one study's JSON, reports and plots; one
//! `prefilter` or `scene` output) is published in one step:
//!
//! 1. the code that makes a set writes nothing: it adds each file's bytes to an
//!    [`Outputs`] value, which is data like any other result;
//! 2. the driver hands it to [`Outputs::publish`], which checks every target first (a
//!    directory in the way of a file, an unwritable parent) and writes nothing if any
//!    fails; then it writes and syncs every temporary file, removes the set's old
//!    manifest, renames the temporaries into place and writes the manifest (paths, sizes
//!    and FNV-1a hashes) last;
//! 3. a set whose making failed is dropped: nothing is written.
//!
//! A run killed between the renames leaves a set without a manifest, or one whose files
//! disagree with it: [`set_is_complete`] tells. Temporary files of processes that no longer
//! exist are removed by the next commit into the same directories (and are git-ignored).

use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

pub(crate) fn io_err(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::Io {
        path: path.display().to_string(),
        msg: e.to_string(),
    }
}

fn tmp_path(path: &Path) -> Result<PathBuf> {
    let file_name = path.file_name().ok_or_else(|| {
        Error::InvalidArgument(format!("'{}' is not a file path", path.display()))
    })?;
    Ok(path.with_file_name(format!(
        ".{}.tmp.{}",
        file_name.to_string_lossy(),
        std::process::id()
    )))
}

/// Write `bytes` to a temporary sibling of `path` and sync it; returns the temporary path.
fn write_tmp(path: &Path, bytes: &[u8]) -> Result<PathBuf> {
    if let Some(parent) = path.parent() {
        if !parent.as_os_str().is_empty() {
            std::fs::create_dir_all(parent).map_err(io_err(path))?;
        }
    }
    let tmp = tmp_path(path)?;
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(io_err(path)(e));
    }
    Ok(tmp)
}

/// Write `bytes` to `path` atomically (temp file in the same directory + rename; parent
/// directories are created): a lone file (a generated document, a cache entry, a shard).
/// A set of files that belong together goes through [`Outputs`].
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = write_tmp(path, bytes)?;
    if path.is_dir() {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::Io {
            path: path.display().to_string(),
            msg: "a directory is in the way".into(),
        });
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io_err(path)(e)
    })
}

/// The files of one output set, as data (see the module doc): paths and bytes in the order
/// they were added; a path added twice keeps its last bytes.
#[derive(Debug, Default)]
#[must_use = "an output set is written only when published"]
pub struct Outputs {
    files: Vec<(PathBuf, Vec<u8>)>,
}

impl Outputs {
    /// An empty set.
    pub fn new() -> Outputs {
        Outputs::default()
    }

    /// Add the file `path` with `bytes` (replacing an earlier file of the same path).
    pub fn put(&mut self, path: impl Into<PathBuf>, bytes: impl AsRef<[u8]>) {
        let path = path.into();
        self.files.retain(|(p, _)| *p != path);
        self.files.push((path, bytes.as_ref().to_vec()));
    }

    /// The bytes of `path`, if the set holds it.
    pub fn get(&self, path: &Path) -> Option<&[u8]> {
        self.files
            .iter()
            .find(|(p, _)| p == path)
            .map(|(_, b)| b.as_slice())
    }

    /// The paths of the set, in the order added.
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        self.files.iter().map(|(p, _)| p.as_path())
    }

    /// How many files the set holds.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// Whether the set holds no file.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }
}

/// The SHA-256 of `bytes`, lower-case hex: what a result records of a file it was made
/// from (`studies::engines::inputs`, `results::fits_sha256`).
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// FNV-1a 64 of a byte string (manifest checksums: detects a mixed set, not an attacker).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// A published set's manifest (`<results>/.sets/<name>.json`).
#[derive(serde::Serialize, serde::Deserialize)]
struct Manifest {
    set: String,
    complete: bool,
    files: Vec<ManifestFile>,
}

/// One file of a set: its path, size and FNV-1a hash.
#[derive(serde::Serialize, serde::Deserialize)]
struct ManifestFile {
    path: String,
    bytes: usize,
    fnv1a64: String,
}

fn manifest_text(name: &str, files: &[(PathBuf, Vec<u8>)]) -> String {
    let m = Manifest {
        set: name.into(),
        complete: true,
        files: files
            .iter()
            .map(|(p, b)| ManifestFile {
                path: p.display().to_string(),
                bytes: b.len(),
                fnv1a64: format!("{:016x}", fnv1a(b)),
            })
            .collect(),
    };
    // through a JSON value: keys sorted, as every file this program writes
    let v = serde_json::to_value(&m).unwrap_or_default();
    serde_json::to_string_pretty(&v).unwrap_or_default() + "\n"
}

/// A set to publish: its name, its manifest and its files.
struct Stage {
    manifest: PathBuf,
    name: String,
    files: Vec<(PathBuf, Vec<u8>)>,
}

impl Outputs {
    /// Publish the set named `name`, whose manifest is `manifest` (see the module doc).
    /// Returns the paths written.
    pub fn publish(self, name: &str, manifest: &Path) -> Result<Vec<PathBuf>> {
        let st = Stage {
            manifest: manifest.to_path_buf(),
            name: name.to_string(),
            files: self.files,
        };
        // 1. every target must be writable as a file before anything is written
        for (p, _) in &st.files {
            if p.is_dir() {
                return Err(Error::Io {
                    path: p.display().to_string(),
                    msg: "a directory is in the way; nothing of the set was written".into(),
                });
            }
            let mut a = p.parent();
            while let Some(d) = a {
                if !d.as_os_str().is_empty() && d.exists() && !d.is_dir() {
                    return Err(Error::Io {
                        path: d.display().to_string(),
                        msg: "a file is in the way of a directory; nothing of the set was written"
                            .into(),
                    });
                }
                a = d.parent();
            }
        }
        // one writer per results folder: the lock is held from the temporaries to the
        // manifest, so two runs' sets are published one after the other
        let _lock = PublishLock::acquire(st.manifest.parent().unwrap_or(Path::new(".")))?;
        // 2. temporaries, all or none
        let mut tmps = Vec::new();
        for (p, b) in &st.files {
            match write_tmp(p, b) {
                Ok(t) => tmps.push(t),
                Err(e) => {
                    for t in &tmps {
                        let _ = std::fs::remove_file(t);
                    }
                    return Err(e);
                }
            }
        }
        // 3. the old manifest goes first, the new one last
        let _ = std::fs::remove_file(&st.manifest);
        for ((p, _), t) in st.files.iter().zip(&tmps) {
            if let Err(e) = std::fs::rename(t, p) {
                for t in &tmps {
                    let _ = std::fs::remove_file(t);
                }
                return Err(io_err(p)(e));
            }
        }
        let tmp = write_tmp(&st.manifest, manifest_text(&st.name, &st.files).as_bytes())?;
        std::fs::rename(&tmp, &st.manifest).map_err(io_err(&st.manifest))?;
        // 4. temporaries left by killed runs in the same directories
        let mut dirs: Vec<PathBuf> = st
            .files
            .iter()
            .chain(std::iter::once(&(st.manifest.clone(), Vec::new())))
            .filter_map(|(p, _)| p.parent().map(Path::to_path_buf))
            .collect();
        dirs.sort();
        dirs.dedup();
        for d in dirs {
            remove_stale_temporaries(&d);
        }
        Ok(st.files.into_iter().map(|(p, _)| p).collect())
    }
}

/// An advisory lock on a results folder while a set is published: the file
/// `.publish.lock` beside the set's manifest, created exclusively and holding the
/// holder's pid. A second writer waits for it (saying so once on stderr) and refuses with
/// a one-line error after [`LOCK_WAIT_S`] seconds; a lock whose process no longer runs
/// (Linux: no /proc/PID), or an unreadable one older than the wait, is taken over.
pub struct PublishLock {
    path: PathBuf,
}

/// How long a writer waits for another's lock before it refuses.
pub const LOCK_WAIT_S: u64 = 120;

impl PublishLock {
    /// The lock of `dir` (created if absent).
    pub fn acquire(dir: &Path) -> Result<PublishLock> {
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        let path = dir.join(".publish.lock");
        let me = std::process::id();
        let start = std::time::Instant::now();
        let mut said = false;
        loop {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut f) => {
                    f.write_all(format!("{me}\n").as_bytes())
                        .map_err(io_err(&path))?;
                    return Ok(PublishLock { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(e) => return Err(io_err(&path)(e)),
            }
            let holder = std::fs::read_to_string(&path)
                .ok()
                .and_then(|t| t.trim().parse::<u32>().ok());
            let stale = match holder {
                Some(pid) => pid != me && !process_runs(pid),
                // a lock being written, or garbage: stale once it has outlived the wait
                None => std::fs::metadata(&path)
                    .and_then(|m| m.modified())
                    .ok()
                    .and_then(|t| t.elapsed().ok())
                    .is_some_and(|a| a.as_secs() > LOCK_WAIT_S),
            };
            if stale {
                eprintln!(
                    "{}: taking over the lock of a run that no longer runs",
                    crate::error::one_line(&path.display().to_string())
                );
                let _ = std::fs::remove_file(&path);
                continue;
            }
            if start.elapsed().as_secs() >= LOCK_WAIT_S {
                return Err(Error::Io {
                    path: crate::error::one_line(&dir.display().to_string()),
                    msg: format!(
                        "another run (pid {}) is publishing into this folder and has held it for {LOCK_WAIT_S} s; nothing written",
                        holder.map_or("unknown".into(), |p| p.to_string())
                    ),
                });
            }
            if !said && holder != Some(me) {
                eprintln!(
                    "waiting for another run (pid {}) publishing into {}",
                    holder.map_or("unknown".into(), |p| p.to_string()),
                    crate::error::one_line(&dir.display().to_string())
                );
                said = true;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
    }
}

impl Drop for PublishLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Whether process `pid` runs (Linux: /proc/PID; elsewhere every holder is assumed alive).
fn process_runs(pid: u32) -> bool {
    if !Path::new("/proc/self").exists() {
        return true;
    }
    Path::new(&format!("/proc/{pid}")).exists()
}

/// Remove `.NAME.tmp.PID` files in `dir` whose process no longer runs (Linux: /proc/PID).
pub fn remove_stale_temporaries(dir: &Path) {
    let Ok(rd) = std::fs::read_dir(if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    }) else {
        return;
    };
    if !Path::new("/proc/self").exists() {
        // without /proc (not Linux) live and dead writers cannot be told apart
        return;
    }
    let me = std::process::id();
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        if !name.starts_with('.') {
            continue;
        }
        let Some((_, pid)) = name.rsplit_once(".tmp.") else {
            continue;
        };
        let Ok(pid) = pid.parse::<u32>() else {
            continue;
        };
        let alive = pid == me || Path::new(&format!("/proc/{pid}")).exists();
        if !alive {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Whether the set whose manifest is `manifest` was published completely: the manifest
/// exists and every file it lists has the recorded size and hash.
pub fn set_is_complete(manifest: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(manifest) else {
        return false;
    };
    let Ok(m) = serde_json::from_str::<Manifest>(&text) else {
        return false;
    };
    m.complete
        && m.files.iter().all(|f| {
            std::fs::read(&f.path)
                .is_ok_and(|b| b.len() == f.bytes && format!("{:016x}", fnv1a(&b)) == f.fnv1a64)
        })
}

/// Let `f` make the set `name` into an [`Outputs`] and publish it if `f` succeeds.
pub fn in_set<T>(
    name: &str,
    manifest: &Path,
    f: impl FnOnce(&mut Outputs) -> Result<T>,
) -> Result<T> {
    let mut out = Outputs::new();
    let v = f(&mut out)?;
    out.publish(name, manifest)?;
    Ok(v)
}

/// Where the manifest of the results set `name` lives: `<results>/.sets/<name>.json`
/// (git-ignored: a manifest records one run, and the committed files speak for themselves).
pub fn results_manifest(results: &Path, name: &str) -> PathBuf {
    results.join(".sets").join(format!("{name}.json"))
}

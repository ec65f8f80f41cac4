//! The code version: one SHA-256 over every source file, what the sources compile in
//! (`include_str!` of the example scenes in fits/render/), the manifest and the lock file,
//! compiled in as `NDFB_CODE_HASH`. Shard files and the result cache carry it, so that
//! shards of different builds never merge and a cache entry never outlives its code.

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            files(&p, out);
        } else if p
            .extension()
            .is_some_and(|x| x == "rs" || x == "wgsl" || x == "toml")
        {
            out.push(p);
        }
    }
}

fn main() {
    let mut list = Vec::new();
    files(Path::new("src"), &mut list);
    files(Path::new("fits/render"), &mut list);
    list.push("Cargo.toml".into());
    list.push("Cargo.lock".into());
    list.sort();
    let mut h = Sha256::new();
    for p in &list {
        // the path and the length frame each file, so no two trees hash alike
        let bytes = std::fs::read(p).unwrap_or_default();
        h.update(p.to_string_lossy().as_bytes());
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(&bytes);
    }
    let hex: String = h.finalize().iter().map(|b| format!("{b:02x}")).collect();
    println!("cargo:rustc-env=NDFB_CODE_HASH={hex}");
    println!("cargo:rerun-if-changed=src");
    println!("cargo:rerun-if-changed=fits/render");
    println!("cargo:rerun-if-changed=Cargo.toml");
    println!("cargo:rerun-if-changed=Cargo.lock");
}

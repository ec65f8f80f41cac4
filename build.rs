//! The code versions compiled in:
//!
//! - `NDFB_CODE_HASH`: one SHA-256 over every source file, what the sources compile in
//!   (`include_str!` of the example scenes in fits/render/), the manifest and the lock
//!   file. Shard files carry it, so that shards of different builds never merge.
//! - `$OUT_DIR/unit_hashes.rs`: one hash per unit of the library (a top-level module, or
//!   one study), over the files that unit reaches (`src/memo/deps.rs`). A study's cache
//!   entries are keyed by its unit's hash, so an edit the study cannot reach leaves them
//!   warm.

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

#[path = "src/memo/deps.rs"]
mod deps;

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
    let mut all: Vec<(String, Vec<u8>)> = Vec::new();
    for p in &list {
        // the path and the length frame each file, so no two trees hash alike
        let bytes = std::fs::read(p).unwrap_or_default();
        h.update(p.to_string_lossy().as_bytes());
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(&bytes);
        let rel = p.to_string_lossy().replace('\\', "/");
        all.push((rel, bytes));
    }
    let hex: String = h.finalize().iter().map(|b| format!("{b:02x}")).collect();
    println!("cargo:rustc-env=NDFB_CODE_HASH={hex}");
    let units = deps::unit_hashes(&all);
    let mut rs = String::from(
        "/// Each unit of the library and the hash of the files it reaches (build.rs).\npub const UNIT_HASHES: &[(&str, &str)] = &[\n",
    );
    for (u, h) in &units {
        rs.push_str(&format!("    ({u:?}, {h:?}),\n"));
    }
    rs.push_str("];\n");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::write(out.join("unit_hashes.rs"), rs).expect("OUT_DIR is writable");
    println!("cargo:rerun-if-changed=src");
    println!("cargo:rerun-if-changed=fits/render");
    println!("cargo:rerun-if-changed=Cargo.toml");
    println!("cargo:rerun-if-changed=Cargo.lock");
}

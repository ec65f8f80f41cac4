//! Fuzzing every parser of outside input: fit specs, the render and `scene` TOML, the
//! engine-check scene file, PNG normal and height maps, shard files, cache entries and
//! the shipped LTC tables (three.js's ES module, Bevy's KTX2). Each parser gets
//! structure-aware cases (valid inputs mutated: bytes flipped, set, inserted, deleted,
//! a range duplicated, the tail cut) and raw bytes. The invariant: a finite result, or a
//! typed error whose message is one line — never a panic, a hang or an allocation beyond
//! the parser's stated bounds.
//!
//! CI runs 2 000 cases per parser. The documented run (≥ 100 000 per parser, its counts
//! in results/fuzz/):
//!
//! ```text
//! PROPTEST_CASES=100000 NDFB_FUZZ_OUT=results/fuzz cargo test --release --test fuzz
//! ```

mod common;

use ndfbench::Error;
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

const CI_CASES: u32 = 2_000;

/// One mutation of a byte string.
#[derive(Clone, Debug)]
enum Op {
    Flip(usize, u8),
    Set(usize, u8),
    Insert(usize, u8),
    Delete(usize, usize),
    Duplicate(usize, usize),
    Truncate(usize),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        (any::<usize>(), 0u8..8).prop_map(|(p, b)| Op::Flip(p, b)),
        (any::<usize>(), any::<u8>()).prop_map(|(p, b)| Op::Set(p, b)),
        (any::<usize>(), any::<u8>()).prop_map(|(p, b)| Op::Insert(p, b)),
        (any::<usize>(), 1usize..64).prop_map(|(p, n)| Op::Delete(p, n)),
        (any::<usize>(), 1usize..64).prop_map(|(p, n)| Op::Duplicate(p, n)),
        any::<usize>().prop_map(Op::Truncate),
    ]
}

fn apply(seed: &[u8], ops: &[Op]) -> Vec<u8> {
    let mut v = seed.to_vec();
    for o in ops {
        let n = v.len().max(1);
        match *o {
            Op::Flip(p, b) if !v.is_empty() => v[p % n] ^= 1 << b,
            Op::Set(p, b) if !v.is_empty() => v[p % n] = b,
            Op::Insert(p, b) => v.insert(p % (v.len() + 1), b),
            Op::Delete(p, k) if !v.is_empty() => {
                let a = p % n;
                v.drain(a..(a + k).min(v.len()));
            }
            Op::Duplicate(p, k) if !v.is_empty() => {
                let a = p % n;
                let chunk = v[a..(a + k).min(v.len())].to_vec();
                v.splice(a..a, chunk);
            }
            Op::Truncate(p) => v.truncate(p % (v.len() + 1)),
            _ => {}
        }
    }
    v
}

/// A case: a valid seed mutated (three in four), or raw bytes.
fn input(seeds: usize) -> impl Strategy<Value = (Option<usize>, Vec<Op>, Vec<u8>)> {
    prop_oneof![
        3 => (0..seeds, prop::collection::vec(op(), 1..6))
            .prop_map(|(s, ops)| (Some(s), ops, Vec::new())),
        1 => prop::collection::vec(any::<u8>(), 0..2048).prop_map(|b| (None, Vec::new(), b)),
    ]
}

fn bytes_of(seeds: &[Vec<u8>], case: &(Option<usize>, Vec<Op>, Vec<u8>)) -> Vec<u8> {
    match case.0 {
        Some(s) => apply(&seeds[s], &case.1),
        None => case.2.clone(),
    }
}

/// Counts of one parser's run, written to `$NDFB_FUZZ_OUT/<name>.json` when set.
struct Tally {
    name: &'static str,
    ok: AtomicUsize,
    err: AtomicUsize,
}

impl Tally {
    fn new(name: &'static str) -> Tally {
        Tally {
            name,
            ok: AtomicUsize::new(0),
            err: AtomicUsize::new(0),
        }
    }
    /// The invariant on one outcome: finite when Ok, one line when Err.
    fn judge<T>(&self, r: Result<T, Error>, finite: impl Fn(&T) -> bool) -> Result<(), String> {
        match r {
            Ok(v) => {
                self.ok.fetch_add(1, Ordering::Relaxed);
                if finite(&v) {
                    Ok(())
                } else {
                    Err(format!("{}: accepted with a non-finite value", self.name))
                }
            }
            Err(e) => {
                self.err.fetch_add(1, Ordering::Relaxed);
                let m = e.to_string();
                if m.contains('\n') || m.contains('\r') || m.is_empty() {
                    Err(format!("{}: not a one-line message: {m:?}", self.name))
                } else {
                    Ok(())
                }
            }
        }
    }
    fn publish(&self) {
        let (ok, err) = (
            self.ok.load(Ordering::Relaxed),
            self.err.load(Ordering::Relaxed),
        );
        assert!(ok + err > 0, "{}: no case ran", self.name);
        if let Ok(dir) = std::env::var("NDFB_FUZZ_OUT") {
            let dir = PathBuf::from(dir);
            std::fs::create_dir_all(&dir).unwrap();
            let v = serde_json::json!({
                "command": "PROPTEST_CASES=100000 NDFB_FUZZ_OUT=results/fuzz cargo test --release --test fuzz",
                "parser": self.name,
                "cases": ok + err,
                "accepted": ok,
                "typed_errors": err,
                "panics": 0,
            });
            std::fs::write(
                dir.join(format!("{}.json", self.name)),
                serde_json::to_string_pretty(&v).unwrap() + "\n",
            )
            .unwrap();
        }
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn files(dir: &str, ext: &str) -> Vec<Vec<u8>> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    v.sort();
    v.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

fn scratch(name: &str) -> PathBuf {
    common::scratch("fuzz", name)
}

/// Run `check` on `config(CI_CASES)` cases over `seeds`.
fn fuzz(
    name: &'static str,
    seeds: Vec<Vec<u8>>,
    check: impl Fn(&Tally, &[u8]) -> Result<(), String>,
) {
    assert!(!seeds.is_empty(), "{name}: no seed");
    let tally = Tally::new(name);
    let mut runner = proptest::test_runner::TestRunner::new(common::config(CI_CASES));
    let result = runner.run(&input(seeds.len()), |case| {
        let b = bytes_of(&seeds, &case);
        check(&tally, &b).map_err(TestCaseError::fail)
    });
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
    tally.publish();
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn fuzz_fit_specs() {
    fuzz("fit-spec", files("fits", "toml"), |t, b| {
        t.judge(
            ndfbench::fit::spec::FitSpec::parse(&text(b), "fuzz.toml"),
            |_| true,
        )
    });
}

#[test]
fn fuzz_render_scenes() {
    fuzz("render-scene", files("fits/render", "toml"), |t, b| {
        t.judge(
            ndfbench::render::scene::Scene::parse(&text(b), "fuzz.toml"),
            |_| true,
        )
    });
}

#[test]
fn fuzz_scene_files() {
    fuzz("scene", files("tests/scenes", "toml"), |t, b| {
        t.judge(ndfbench::scene::Scene::parse(&text(b), "fuzz.toml"), |_| {
            true
        })
    });
}

#[test]
fn fuzz_engine_scenes() {
    let seed = std::fs::read(root().join("engines/three/scenes.json")).unwrap();
    fuzz("engine-scenes", vec![seed], |t, b| {
        t.judge(
            ndfbench::engines::scenes::EngineScenes::parse(&text(b)),
            |_| true,
        )
    });
}

/// A small PNG (RGB or grey, 8 or 16 bit) from the image crate.
fn png(w: u32, grey: bool, px: impl Fn(u32, u32) -> [u16; 3]) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    if grey {
        let img = image::ImageBuffer::<image::Luma<u16>, _>::from_fn(w, w, |x, y| {
            image::Luma([px(x, y)[0]])
        });
        image::DynamicImage::ImageLuma16(img)
            .write_to(&mut out, image::ImageFormat::Png)
            .unwrap();
    } else {
        let img = image::ImageBuffer::<image::Rgb<u8>, _>::from_fn(w, w, |x, y| {
            let p = px(x, y);
            image::Rgb([p[0] as u8, p[1] as u8, p[2] as u8])
        });
        image::DynamicImage::ImageRgb8(img)
            .write_to(&mut out, image::ImageFormat::Png)
            .unwrap();
    }
    out.into_inner()
}

#[test]
fn fuzz_normal_maps() {
    let seeds = vec![
        png(8, false, |x, y| {
            [128 + (x as u16 * 7) % 40, 128 - (y as u16 * 5) % 40, 250]
        }),
        png(4, false, |_, _| [128, 128, 255]),
    ];
    let dir = scratch("normal");
    let path = dir.join("map.png");
    fuzz("normal-map-png", seeds, |t, b| {
        std::fs::write(&path, b).unwrap();
        t.judge(
            ndfbench::filters::footprint::NormalMap::from_png(&path),
            |m| m.normals.iter().all(|n| n.iter().all(|c| c.is_finite())),
        )
    });
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fuzz_height_maps() {
    let seeds = vec![png(16, true, |x, y| {
        [((x * 977 + y * 131) % 65536) as u16; 3]
    })];
    let dir = scratch("height");
    let path = dir.join("h.png");
    fuzz("height-map-png", seeds, |t, b| {
        std::fs::write(&path, b).unwrap();
        t.judge(
            ndfbench::visibility::HeightField::from_png(&path, 4.0),
            |_| true,
        )
    });
    let _ = std::fs::remove_dir_all(&dir);
}

/// A shard file of a one-shard set, and the identity it must match.
fn shard_seed(dir: &Path) -> (Vec<u8>, ndfbench::memo::shards::Identity) {
    use ndfbench::memo::shards::{write, Identity, Part};
    let id = Identity {
        study: "fuzz".into(),
        code: "c".into(),
        spec: "s".into(),
        inputs: "i".into(),
        preset: "quick".into(),
    };
    let part = Part {
        label: "the map".into(),
        items_total: 3,
        indices: vec![0, 1, 2],
        values: vec![0.25.into(), (-1.5e-7).into(), 3.0e22.into()],
        seconds: 0.5,
    };
    let p = write(dir, &id, 0, 1, part).unwrap();
    (std::fs::read(p).unwrap(), id)
}

#[test]
fn fuzz_shard_files() {
    let dir = scratch("shard");
    let (seed, id) = shard_seed(&dir);
    let path = dir.join("fuzz.shard-0-of-1.json");
    fuzz("shard-file", vec![seed], |t, b| {
        std::fs::write(&path, b).unwrap();
        let r = ndfbench::memo::shards::load_set(std::slice::from_ref(&path), &id)
            .and_then(|p| p.into_items::<f64>("the map", 3));
        // accepted only with the values written (the seal refuses any other content)
        t.judge(r, |v| *v == [0.25, -1.5e-7, 3.0e22])
    });
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fuzz_cache_entries() {
    use ndfbench::memo::cache::{load, store};
    let dir = scratch("cache");
    let path = dir.join("entry.json");
    let values = vec![0.02277, -3.5, 1.25e-7, 6.0e22];
    store(&path, "k", "the map", &values);
    let seed = std::fs::read(&path).unwrap();
    let intact = seed.clone();
    fuzz("cache-entry", vec![seed], |t, b| {
        std::fs::write(&path, b).unwrap();
        // a cache entry is never an error: intact content or a miss
        let got = load::<f64>(&path, "k", "the map", 4);
        let r: Result<Option<Vec<f64>>, Error> = Ok(got);
        t.judge(r, |g| match g {
            // accepted only with the stored values (a changed digit is never used)
            Some(v) => *v == values,
            None => true,
        })?;
        if b == intact.as_slice() && load::<f64>(&path, "k", "the map", 4).is_none() {
            return Err("an intact entry was not read".into());
        }
        Ok(())
    });
    let _ = std::fs::remove_dir_all(&dir);
}

/// three.js's module shape, 2×2 cells.
fn module_seed() -> Vec<u8> {
    let m1 = "1, 0, 0.5, 0, 0.9, -0.01, 0.4, 0.02, 1.2, 0, 0.6, 0, 0.8, 1e-5, 0.3, -0.1";
    let m2 = "1, 0, 0, 1, 0.9, 0.1, 0, 1, 0.5, 0.2, 0, 1, 0.3, 0.3, 0, 1";
    format!(
        "const LTC_MAT_1 = [ {m1} ];\nconst LTC_MAT_2 = [ {m2} ];\nexport {{ LTC_MAT_1, LTC_MAT_2 }};\n"
    )
    .into_bytes()
}

#[test]
fn fuzz_shipped_es_modules() {
    fuzz("three-es-module", vec![module_seed()], |t, b| {
        let r = ndfbench::ltc::compare::Shipped::parse(&text(b), "LTC_MAT_1", "LTC_MAT_2")
            .and_then(|s| s.check_comparable("fuzz.js").map(|_| s));
        t.judge(r, |s| {
            s.mat
                .iter()
                .flatten()
                .chain(s.mag.iter().flatten())
                .all(|x| x.is_finite())
        })
    });
}

#[test]
fn fuzz_bevy_ktx2() {
    let seed = std::fs::read(root().join("results/textures/ltc_ggx.ktx2")).unwrap();
    fuzz("bevy-ktx2", vec![seed], |t, b| {
        t.judge(ndfbench::ltc::upload::bevy_ktx2(b), |s| {
            s.mat
                .iter()
                .flatten()
                .chain(s.mag.iter().flatten())
                .all(|x| !x.is_nan())
        })
    });
}

/// What fuzzing found, kept as regression cases: an enumerated value echoed raw broke a
/// message over two lines (`ndf = "beckma\nn"`).
#[test]
fn regressions_found_by_fuzzing() {
    let seed = text(&files("tests/scenes", "toml")[0]);
    let line = seed
        .lines()
        .find(|l| l.trim_start().starts_with("ndf"))
        .expect("the seed names its NDF");
    let bad = seed.replace(line, "ndf = \"beckma\\nn\"");
    let t = Tally::new("regression");
    let r = ndfbench::scene::Scene::parse(&bad, "fuzz.toml");
    assert!(r.is_err());
    t.judge(r, |_| true).unwrap();
}

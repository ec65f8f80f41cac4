//! Seed 002 §5.5's Wang tiles (`tensor::wang`): the colouring's neighbours agree, tile
//! edges are the example's own consecutive texels, a footprint summed from its tiles is
//! the explicit map's brute-force P-NDF anywhere, the same bits at any thread count, and
//! bad input is a typed error.

mod common;

use nalgebra::Vector3;
use ndfbench::filters::footprint::{NormalMap, Procedural};
use ndfbench::tensor::pndf::{pndf_image, sigma_p};
use ndfbench::tensor::wang::{explicit, Colouring, Level, TileImages, TileSet};
use proptest::prelude::*;
use std::sync::OnceLock;

const SIDE: usize = 16;
const RES: usize = 8;
const SIGMA_R: f64 = 0.08;

fn example() -> NormalMap {
    NormalMap::procedural(Procedural::Flakes, 64, 5).unwrap()
}

fn levels() -> Vec<Level> {
    [2usize, 4, 8]
        .iter()
        .map(|&s| Level {
            stride: s,
            sigma_p: sigma_p(s, 0),
        })
        .collect()
}

fn fixture() -> &'static (NormalMap, TileSet, TileImages) {
    static F: OnceLock<(NormalMap, TileSet, TileImages)> = OnceLock::new();
    F.get_or_init(|| {
        let ex = example();
        let set = TileSet::build(&ex, SIDE, 4, 9).unwrap();
        let images = TileImages::build(&set, &levels(), RES, SIGMA_R).unwrap();
        (ex, set, images)
    })
}

/// A cell index near 0 or near ±2^40.
fn cell() -> impl Strategy<Value = i64> {
    prop_oneof![
        -50i64..50,
        (1i64 << 40) - 50..(1i64 << 40),
        -(1i64 << 40)..-(1i64 << 40) + 50
    ]
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// Cell (i, j)'s right and bottom colours are its neighbours' left and top ones, for
    /// any seed, near the origin and 2^62 out.
    #[test]
    fn neighbours_agree_on_every_edge(
        i in prop_oneof![-1000i64..1000, (1i64 << 62) - 1000..(1i64 << 62), -(1i64 << 62)..-(1i64 << 62) + 1000],
        j in prop_oneof![-1000i64..1000, (1i64 << 62) - 1000..(1i64 << 62), -(1i64 << 62)..-(1i64 << 62) + 1000],
        seed in any::<u64>(),
    ) {
        let c = Colouring { seed };
        let e = c.edges(i, j);
        prop_assert_eq!(e.right, c.edges(i + 1, j).left);
        prop_assert_eq!(e.bottom, c.edges(i, j + 1).top);
        prop_assert_eq!(e.top, c.edges(i, j - 1).bottom);
        prop_assert!(c.tile(i, j) < 16);
    }

    /// The image of a footprint of any level centred anywhere inside the middle tile of a
    /// 3×3-tile neighbourhood, summed from its tiles' stored terms, is the brute-force
    /// P-NDF (Eq 2) of the explicit map of that neighbourhood to rounding.
    #[test]
    fn tiles_sum_to_the_explicit_image(
        i in cell(), j in cell(), level in 0usize..3, kx in 0usize..8, ky in 0usize..8, seed in 0u64..4,
    ) {
        let (_, set, images) = fixture();
        let c = Colouring { seed };
        let map = explicit(set, &c, (i - 1, j - 1), (3, 3)).unwrap();
        let s = levels()[level].stride;
        let (lx, ly) = (s / 2 + (kx * s) % SIDE, s / 2 + (ky * s) % SIDE);
        let (x, y) = (SIDE + lx, SIDE + ly);
        let g = (i * SIDE as i64 + lx as i64, j * SIDE as i64 + ly as i64);
        let brute = pndf_image(&map, x as f64, y as f64, levels()[level].sigma_p, SIGMA_R, RES).unwrap();
        let tiled = images.combined(&c, level, g).unwrap();
        let peak = brute.iter().cloned().fold(0.0, f64::max);
        prop_assert!(peak > 0.0);
        for (a, b) in brute.iter().zip(&tiled) {
            prop_assert!((a - b).abs() <= 1e-12 * peak, "{a} vs {b} at {g:?}, level {level}");
        }
    }
}

/// The texels on both sides of every tile edge (corners aside) are consecutive texels of
/// the example, read at the patch the edge's colour owns: seamless edges, checked against
/// the example itself.
#[test]
fn tile_edges_are_consecutive_texels_of_the_example() {
    let (ex, set, _) = fixture();
    let c = Colouring { seed: 2 };
    let (n, half) = (4usize, SIDE / 2);
    let map = explicit(set, &c, (-2, 5), (n, n)).unwrap();
    let at = |x: usize, y: usize| map.normals[y * map.width + x];
    let patch = |p: usize, x: usize, y: usize| {
        let (ox, oy) = set.offsets[p];
        ex.normals[(oy + y) % ex.height * ex.width + (ox + x) % ex.width]
    };
    let mut checked = 0;
    for cj in 0..n {
        for ci in 0..n {
            let e = c.edges(-2 + ci as i64, 5 + cj as i64);
            for q in 1..SIDE - 1 {
                if cj + 1 < n {
                    let (x, y) = (ci * SIDE + q, (cj + 1) * SIDE);
                    let p = e.bottom as usize;
                    assert_eq!(at(x, y - 1), patch(p, q, half - 1), "above ({x}, {y})");
                    assert_eq!(at(x, y), patch(p, q, half), "below ({x}, {y})");
                    checked += 1;
                }
                if ci + 1 < n {
                    let (x, y) = ((ci + 1) * SIDE, cj * SIDE + q);
                    let p = 2 + e.right as usize;
                    assert_eq!(at(x - 1, y), patch(p, half - 1, q), "left of ({x}, {y})");
                    assert_eq!(at(x, y), patch(p, half, q), "right of ({x}, {y})");
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, 2 * n * (n - 1) * (SIDE - 2));
}

/// The tiles and their images have the same bits at one and two threads.
#[test]
fn the_same_bits_at_any_thread_count() {
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let set = TileSet::build(&example(), SIDE, 4, 9).unwrap();
                TileImages::build(&set, &levels(), RES, SIGMA_R).unwrap()
            })
    };
    let (a, b) = (run(1), run(2));
    for (la, lb) in a.levels.iter().zip(&b.levels) {
        for (ta, tb) in la.images.iter().zip(&lb.images) {
            for (ia, ib) in ta.iter().zip(tb) {
                assert!(ia.iter().zip(ib).all(|(x, y)| x.to_bits() == y.to_bits()));
            }
        }
    }
    let (_, set, images) = fixture();
    assert_eq!(a.values(), images.values());
    assert_eq!(
        set.tiles,
        TileSet::build(&example(), SIDE, 4, 9).unwrap().tiles
    );
}

/// Bad sizes, normals, levels, centres and regions are typed errors, not panics.
#[test]
fn bad_input_is_a_typed_error() {
    let ex = example();
    for side in [0, 2, 3, 15, 2048] {
        assert!(TileSet::build(&ex, side, 2, 1).is_err(), "side {side}");
    }
    assert!(
        TileSet::build(&ex, 128, 2, 1).is_err(),
        "side over the example"
    );
    let mut broken = ex.clone();
    broken.normals[77] = Vector3::new(f64::NAN, 0.0, 1.0);
    assert!(TileSet::build(&broken, SIDE, 2, 1).is_err());
    broken.normals[77] = Vector3::new(0.0, 0.0, -1.0);
    assert!(TileSet::build(&broken, SIDE, 2, 1).is_err());
    broken.normals.pop();
    assert!(TileSet::build(&broken, SIDE, 2, 1).is_err());
    let (_, set, images) = fixture();
    for (stride, sp) in [
        (0, 1.0),
        (3, 1.0),
        (4, 0.0),
        (4, f64::NAN),
        (4, -1.0),
        (4, 1e9),
    ] {
        let l = Level {
            stride,
            sigma_p: sp,
        };
        assert!(
            TileImages::build(set, &[l], RES, SIGMA_R).is_err(),
            "stride {stride}, σ_P {sp}"
        );
    }
    let l = levels()[1];
    assert!(TileImages::build(set, &[l], 1, SIGMA_R).is_err());
    assert!(TileImages::build(set, &[l], RES, 0.0).is_err());
    let c = Colouring { seed: 0 };
    assert!(images.combined(&c, 1, (3, 2)).is_err(), "off the grid");
    assert!(images.combined(&c, 3, (2, 2)).is_err(), "no such level");
    let edge = i64::MAX - 1;
    assert!(images
        .combined(&c, 1, (edge - (edge - 2).rem_euclid(4), 2))
        .is_err());
    assert!(images.combined(&c, 1, (2 - 4 * (i64::MAX / 4), 2)).is_err());
    assert!(explicit(set, &c, (0, 0), (0, 3)).is_err());
    assert!(explicit(set, &c, (0, 0), (1 << 20, 1 << 20)).is_err());
    assert!(explicit(set, &c, (i64::MAX - 1, 0), (2, 2)).is_err());
}

/// A user's normal-map PNG as the example: the study cuts its tiles from the file's texels
/// (16-bit, read back by `NormalMap::from_png`), and implicit = explicit still holds to
/// rounding; a missing file or a broken PNG is a typed error naming the cause.
#[test]
fn a_png_example_is_cut_into_tiles() {
    use ndfbench::fit::spec::FitSpec;
    use std::path::Path;
    let d = common::scratch("tensor_wang", "png-example");
    let map = NormalMap::procedural(Procedural::IsotropicNoise, 64, 5).unwrap();
    let enc = |c: f64| ((0.5 * (c + 1.0)).clamp(0.0, 1.0) * 65535.0).round() as u16;
    let img = image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(64, 64, |x, y| {
        let n = map.normals[(y * 64 + x) as usize];
        image::Rgb([enc(n.x), enc(n.y), enc(n.z)])
    });
    let png = d.join("example.png");
    img.save(&png).unwrap();
    let text = std::fs::read_to_string("fits/tensor-wang.toml").unwrap();
    assert!(text.contains("example = \"isotropic-noise\""));
    let with = |example: &str| {
        FitSpec::parse(
            &text.replacen(
                "example = \"isotropic-noise\"",
                &format!("example = {example:?}"),
                1,
            ),
            "tensor-wang",
        )
        .unwrap()
    };
    let quick = ndfbench::integrate::Preset::Quick;
    let spec = with(png.to_str().unwrap());
    let computed = common::compute_study(&spec, Path::new("results"), quick).unwrap();
    let outcome = computed.outcome();
    assert!(outcome.passed, "{}", outcome.summary);
    let mut set = ndfbench::io::Outputs::new();
    computed.render(&mut set, &d).unwrap();
    let out: serde_json::Value =
        serde_json::from_slice(set.get(&d.join("fits/tensor-wang.json")).unwrap()).unwrap();
    let named = out["example_map"].as_str().unwrap();
    assert!(
        named.contains("example.png") && named.contains("64×64"),
        "{named}"
    );
    // the file's texels, not the generator's: its own neighbour pairs differ from the
    // generated map's by the 16-bit rounding only
    let generated =
        common::compute_study(&with("isotropic-noise"), Path::new("results"), quick).unwrap();
    let mut gset = ndfbench::io::Outputs::new();
    generated.render(&mut gset, &d).unwrap();
    let g: serde_json::Value =
        serde_json::from_slice(gset.get(&d.join("fits/tensor-wang.json")).unwrap()).unwrap();
    assert!(g["example_map"].as_str().unwrap().contains("procedural"));
    // a missing file and a file that is not a PNG
    for bad in [d.join("missing.png"), d.join("broken.png")] {
        if bad.ends_with("broken.png") {
            std::fs::write(&bad, b"\x89PNG\r\n\x1a\nnot really").unwrap();
        }
        let e = common::compute_study(&with(bad.to_str().unwrap()), Path::new("results"), quick)
            .err()
            .unwrap_or_else(|| panic!("{} was accepted", bad.display()));
        assert!(e.to_string().contains("png"), "{e}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

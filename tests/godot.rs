//! Godot 4's LTC files (results/textures/godot/ltc_lut{1,2}.dds) as Godot's build embeds
//! them and as its shader reads them (`ndfbench::engines::godot`, transcribed from
//! area_lights_inc.glsl and make_ltc_lut.py). No Godot binary runs here: these check the
//! files' bytes, the layout conversion against our own LTC evaluation (three.js's frame
//! and our exact edge integral, written independently of Godot's), and Godot's edge fit.

use nalgebra::Vector3;
use ndfbench::engines::godot::{
    acos_approx, from_inverse, godot_exact, godot_value, lookup, row_cos, to_inverse, N,
};
use ndfbench::engines::{table_value, EngineScenes, Rect};
use std::path::Path;

fn read_dds(k: usize) -> Vec<[f64; 4]> {
    let b = std::fs::read(format!("results/textures/godot/ltc_lut{k}.dds")).unwrap();
    // make_ltc_lut.py drops 148 bytes and Godot uploads 64·64·16 bytes as RGBA32F
    assert_eq!(b.len(), 148 + N * N * 16, "ltc_lut{k}.dds size");
    assert_eq!(&b[..4], b"DDS ");
    let u32at = |o: usize| u32::from_le_bytes(b[o..o + 4].try_into().unwrap());
    assert_eq!(u32at(4), 124, "DDS_HEADER size");
    assert_eq!(
        (u32at(12), u32at(16)),
        (N as u32, N as u32),
        "height, width"
    );
    assert_eq!(&b[84..88], b"DX10");
    assert_eq!(u32at(128), 2, "DXGI_FORMAT_R32G32B32A32_FLOAT");
    assert_eq!(u32at(132), 3, "TEXTURE2D");
    b[148..]
        .chunks_exact(16)
        .map(|t| {
            std::array::from_fn(|c| {
                f32::from_le_bytes(t[4 * c..4 * c + 4].try_into().unwrap()) as f64
            })
        })
        .collect()
}

/// Surface points of every engine-check scene (a 5×5 grid on the plane).
fn points() -> Vec<(f64, f64, Rect, Vector3<f64>)> {
    let s = EngineScenes::read(Path::new("engines/three/scenes.json")).unwrap();
    let mut out = Vec::new();
    for sc in &s.scenes {
        let light = Rect::of(&sc.light).unwrap();
        for a in 0..5 {
            for b in 0..5 {
                let x = Vector3::new(
                    s.plane_half * (a as f64 / 2.0 - 1.0) * 0.9,
                    s.plane_half * (b as f64 / 2.0 - 1.0) * 0.9,
                    0.0,
                );
                if light.lights(&x) {
                    out.push((sc.roughness, sc.view_deg, light, x));
                }
            }
        }
    }
    out
}

#[test]
fn the_conversion_to_godots_matrix_form_keeps_every_lobe_of_our_table() {
    let t = ndfbench::results::ltc::table(Path::new("results"), "ltc-ggx").unwrap();
    let pts = points();
    let mut worst: f64 = 0.0;
    for (k, c) in t.cells.iter().enumerate() {
        let m = [c[0], c[1], c[2], c[3]];
        let g = from_inverse(m).unwrap();
        let back = to_inverse(g).unwrap();
        for q in 0..4 {
            assert!(
                (back[q] - m[q]).abs() <= 1e-12 * m.iter().map(|v| v.abs()).fold(0.0, f64::max),
                "cell {k}: round trip {back:?} against {m:?}"
            );
        }
        // Godot's frame and matrix with the exact edges = our frame and matrix, at a few
        // points per cell
        let gg = [g[0], g[1], g[2], g[3], g[4], c[4]];
        for (_, _, light, x) in pts.iter().skip(k % 7).step_by(97) {
            let ours = table_value(&[c[0], c[1], c[2], c[3], c[4]], light, x);
            let godot = godot_exact(&gg, light, x);
            let rel = (godot - ours).abs() / ours.abs().max(1e-300);
            if ours > 1e-12 {
                worst = worst.max(rel);
            }
            assert!(
                (godot - ours).abs() <= 1e-9 * ours.abs() + 1e-15,
                "cell {k} at {x:?}: Godot's form {godot}, ours {ours}"
            );
        }
    }
    eprintln!("Godot's matrix form against ours: worst relative difference {worst:.1e}");
}

#[test]
fn the_files_hold_our_table_at_godots_texel_centres() {
    let t = ndfbench::results::ltc::table(Path::new("results"), "ltc-ggx").unwrap();
    let (l1, l2) = (read_dds(1), read_dds(2));
    // every row's N·V is the one whose acos_approx is the row's angle
    for j in 0..N {
        let want = j as f64 / (N - 1) as f64 * std::f64::consts::FRAC_PI_2;
        assert!((acos_approx(row_cos(j)) - want).abs() < 1e-12, "row {j}");
    }
    let pts = points();
    // columns 0 and 1 (r < 0.02) are read at Godot's clamp r = 0.02, between texels
    for j in (0..N).step_by(3) {
        for i in (2..N).step_by(3) {
            let r = i as f64 / (N - 1) as f64;
            let x = row_cos(j);
            let g = lookup(&l1, &l2, r, x);
            let e = t.bilinear(r * r, x, false);
            for (_, _, light, p) in pts.iter().skip((i + j) % 11).step_by(53) {
                let ours = table_value(&[e[0], e[1], e[2], e[3], e[4]], light, p);
                let godot = godot_exact(&g, light, p);
                // f32 storage of five entries and their inversion: 1e-5 relative
                assert!(
                    (godot - ours).abs() <= 1e-5 * ours.abs() + 1e-12,
                    "texel ({i}, {j}) at {p:?}: Godot {godot}, ours {ours}"
                );
            }
        }
    }
}

#[test]
fn godots_edge_fit_is_within_its_measured_bound_of_the_exact_edges() {
    let (l1, l2) = (read_dds(1), read_dds(2));
    let pts = points();
    let mut worst: f64 = 0.0;
    // per scene (the points come scene by scene), relative to the scene's brightest point
    for scene in pts.chunk_by(|a, b| a.0 == b.0 && a.1 == b.1 && a.2.c == b.2.c) {
        let (r, view) = (scene[0].0, scene[0].1);
        let g = lookup(&l1, &l2, r, view.to_radians().cos());
        let vals: Vec<(f64, f64)> = scene
            .iter()
            .map(|(_, _, light, x)| (godot_value(&g, light, x), godot_exact(&g, light, x)))
            .collect();
        let peak = vals.iter().map(|v| v.1).fold(0.0, f64::max);
        for (fit, exact) in vals {
            assert!(fit.is_finite() && fit >= 0.0);
            if exact > 1e-3 * peak {
                worst = worst.max((fit - exact).abs() / exact);
            }
        }
    }
    eprintln!("Hill's edge fit in Godot's evaluation: worst relative error {worst:.2e} (points above 1e-3 of their scene's peak)");
    // Hill's rational fit of θ/sin θ is good to about 1e-3 of a form factor away from
    // the lobe's far tail (measured 7.4e-4 here; deep in the tail, where the edges
    // cancel, 5e-3); a transcription error (a wrong axis, a lost 2π, the x < 0 branch)
    // is percent-level or worse
    assert!(
        worst < 3e-3,
        "Godot's edge fit is {worst:.2e} from the exact edges"
    );
}

#[test]
fn acos_approx_is_the_approximation_godot_ships() {
    // Godot's constant: a first-order fit of acos with the exact ends
    assert!((acos_approx(0.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert!(acos_approx(1.0).abs() < 1e-15);
    assert!((acos_approx(-1.0) - std::f64::consts::PI).abs() < 1e-15);
    // and between them within 0.01 rad of acos (a first-order fit times √(1 − x);
    // measured 0.0090 rad at worst on [0, 1])
    let worst = (0..=1000)
        .map(|k| {
            let x = k as f64 / 1000.0;
            (acos_approx(x) - x.acos()).abs()
        })
        .fold(0.0, f64::max);
    assert!(worst < 0.01, "acos_approx error {worst}");
}

//! The compact GGX table's generated code (`codegen::compact`) against the series it was
//! generated from (results/fits/ltc-compact.json, `ltc::compact::Compact`):
//!
//! - Rust (src/generated/ltc_compact.rs) equals `Compact::eval_f32` bit for bit over the
//!   whole input range, out-of-range inputs included;
//! - its rebuilt binary16 table is within one binary16 step plus the f32 form's bound of
//!   `Compact::rebuild` (the f64 series rounded once), entry by entry;
//! - the ES module (results/textures/three/ltc_compact.js), run by node, gives the Rust
//!   form's f32 bits at every texel and at 10 000 other points, its rebuild's binary16
//!   bits, and a nearest-binary16 conversion equal to the `half` crate's on 200 000 f32
//!   numbers across every exponent, and a RangeError for a side below 2 (skips with one
//!   line without node);
//! - the WGSL module parses and validates with naga.
//!
//! The committed files are stale-checked by tests/codegen.rs with the other generated code.

mod common;

use ndfbench::codegen::compact;
use ndfbench::generated::ltc_compact::{
    ltc_compact, LTC_COMPACT_ALPHA_MIN, LTC_COMPACT_N, LTC_COMPACT_TRANSFORM,
};
use ndfbench::ltc::compact::Compact;
use proptest::prelude::*;
use std::path::Path;

fn series() -> Compact {
    compact::read(Path::new("results"))
        .unwrap()
        .expect("results/fits/ltc-compact.json is committed")
        .0
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// The generated Rust evaluation is `Compact::eval_f32`, bit for bit, at any (r, t)
    /// an engine can pass (clamped outside [0, 1]; the ends and tiny values included).
    #[test]
    fn generated_rust_is_the_f32_form_bit_for_bit(
        r in prop_oneof![Just(0.0f32), Just(1.0f32), Just(1e-30f32), -0.5f32..1.5, 0.0f32..1e-3],
        t in prop_oneof![Just(0.0f32), Just(1.0f32), Just(1e-30f32), -0.5f32..1.5, 0.999f32..1.0],
    ) {
        let c = series();
        let want = c.eval_f32(&c.coeffs_f32(), r, t);
        let got = ltc_compact(r, t);
        for ch in 0..6 {
            prop_assert_eq!(got[ch].to_bits(), want[ch].to_bits(), "channel {} at ({}, {})", ch, r, t);
        }
    }
}

/// The texels of the generated rebuild: f32 values at (i, j)/(n − 1).
fn rebuilt_f32(n: usize) -> Vec<[f32; 6]> {
    (0..n * n)
        .map(|k| {
            ltc_compact(
                (k % n) as f32 / (n - 1) as f32,
                (k / n) as f32 / (n - 1) as f32,
            )
        })
        .collect()
}

/// Rounding the f32 evaluation to binary16 stays within one binary16 step of rounding the
/// f64 series once (`Compact::rebuild`, what results/ltc-compact.md judged) plus the f32
/// form's own bound, 8·p·ε₃₂·Σ|c| (times α(r) for an over-α channel; tests/ltc_compact.rs
/// proves it): entry by entry, near a channel's zeros too, where one f32 rounding of O(1)
/// coefficients is many binary16 steps of a tiny entry.
#[test]
fn the_generated_rebuild_is_within_its_bound_of_the_judged_one() {
    let c = series();
    let n = LTC_COMPACT_N;
    let judged = c.rebuild(n).unwrap();
    let ours = rebuilt_f32(n);
    let sums: Vec<f64> = c
        .channels
        .iter()
        .map(|s| s.coeffs.iter().map(|v| v.abs()).sum())
        .collect();
    let (mut differ, mut beyond_a_step) = (0, 0);
    for (k, v) in ours.iter().enumerate() {
        let r = (k % n) as f64 / (n - 1) as f64;
        let h = judged.half.as_ref().unwrap()[k];
        for ch in 0..6 {
            let a = half::f16::from_f32(v[ch]);
            let step = (half::f16::from_bits(h[ch].to_bits() + 1).to_f64() - h[ch].to_f64()).abs();
            let scale = match c.channels[ch].transform {
                ndfbench::ltc::compact::Transform::OverAlpha => (r * r).max(c.alpha_min),
                _ => 1.0,
            };
            let bound = step + 8.0 * c.p as f64 * f64::from(f32::EPSILON) * sums[ch] * scale;
            let d = (a.to_f64() - h[ch].to_f64()).abs();
            assert!(
                d <= bound,
                "texel {k} channel {ch}: {a} vs {} (bound {bound:e})",
                h[ch]
            );
            differ += usize::from(a != h[ch]);
            beyond_a_step += usize::from(d > step);
        }
    }
    eprintln!(
        "generated binary16 rebuild: {differ} of {} entries differ from the judged one, {beyond_a_step} by more than one step",
        6 * n * n
    );
}

/// The WGSL library (no entry point, no bindings) and the compute rebuild parse and
/// validate with naga; the rebuild holds the library's text.
#[test]
fn the_wgsl_modules_validate() {
    let lib = std::fs::read_to_string("results/wgsl/ltc_compact.wgsl").unwrap();
    ndfbench::codegen::validate::validate_wgsl(&lib, "ltc_compact.wgsl").unwrap();
    assert!(!lib.contains("@compute") && !lib.contains("@group"));
    let rebuild = std::fs::read_to_string("results/wgsl/ltc_compact_rebuild.wgsl").unwrap();
    ndfbench::codegen::validate::validate_wgsl(&rebuild, "ltc_compact_rebuild.wgsl").unwrap();
    assert!(rebuild.contains("@compute") && rebuild.contains("fn ltc_compact_rebuild"));
    assert!(rebuild.starts_with(&lib));
}

/// The straight-line WGSL channels, run by a small interpreter of their `let` lines in f32
/// (each line `a`, `a + b`, `a + b * c` or `a + b * c - d`, evaluated as WGSL does:
/// (a + (b·c)) − d), then through each channel's transform as `ltc_compact_mat`/`_mag`
/// apply it: the Rust form's bits at every texel and 10 000 other points. So the text a
/// GPU compiles holds the Rust form's coefficients in its order of operations.
#[test]
fn the_wgsl_text_is_the_rust_form() {
    let lib = std::fs::read_to_string("results/wgsl/ltc_compact.wgsl").unwrap();
    let mut bodies: Vec<Vec<(String, Vec<String>)>> = Vec::new();
    let mut returns = Vec::new();
    for line in lib.lines().map(str::trim) {
        let open = returns.len() < bodies.len();
        if line.starts_with("fn ltc_compact_ch") {
            bodies.push(Vec::new());
        } else if let (Some(rest), true) = (line.strip_prefix("let "), open) {
            let (name, expr) = rest.trim_end_matches(';').split_once(" = ").unwrap();
            let e = expr.split_whitespace().map(String::from).collect();
            bodies.last_mut().unwrap().push((name.to_string(), e));
        } else if let (Some(r), true) = (line.strip_prefix("return "), open) {
            returns.push(r.trim_end_matches(';').to_string());
        }
    }
    assert_eq!(bodies.len(), 6, "six channel functions");
    let eval = |ch: usize, x: f32, y: f32| -> f32 {
        let mut env = std::collections::HashMap::from([("x".to_string(), x), ("y".to_string(), y)]);
        let val = |env: &std::collections::HashMap<String, f32>, t: &str| -> f32 {
            env.get(t)
                .copied()
                .unwrap_or_else(|| t.parse::<f32>().unwrap_or_else(|_| panic!("token {t}")))
        };
        for (name, e) in &bodies[ch] {
            let v = match e.len() {
                1 => val(&env, &e[0]),
                3 => {
                    assert_eq!(e[1], "+");
                    val(&env, &e[0]) + val(&env, &e[2])
                }
                5 => {
                    assert_eq!((e[1].as_str(), e[3].as_str()), ("+", "*"));
                    val(&env, &e[0]) + val(&env, &e[2]) * val(&env, &e[4])
                }
                7 => {
                    assert_eq!(
                        (e[1].as_str(), e[3].as_str(), e[5].as_str()),
                        ("+", "*", "-")
                    );
                    val(&env, &e[0]) + val(&env, &e[2]) * val(&env, &e[4]) - val(&env, &e[6])
                }
                _ => panic!("line {name} = {e:?}"),
            };
            env.insert(name.clone(), v);
        }
        val(&env, &returns[ch])
    };
    for (r, t) in points() {
        let want = ltc_compact(r, t);
        let (rc, tc) = (r.clamp(0.0, 1.0), t.clamp(0.0, 1.0));
        let (x, y) = (2.0 * rc - 1.0, 2.0 * tc - 1.0);
        let alpha = (rc * rc).max(LTC_COMPACT_ALPHA_MIN);
        for ch in 0..6 {
            let v = eval(ch, x, y);
            let got = match LTC_COMPACT_TRANSFORM[ch] {
                1 => v.exp(),
                2 => v * alpha,
                _ => v,
            };
            assert_eq!(
                got.to_bits(),
                want[ch].to_bits(),
                "channel {ch} at ({r}, {t}): {got} vs {}",
                want[ch]
            );
        }
    }
}

/// Points the JS run evaluates: every texel, then 10 000 from a fixed sequence over
/// [−0.25, 1.25]² (outside the range too).
fn points() -> Vec<(f32, f32)> {
    let n = LTC_COMPACT_N;
    let mut p: Vec<(f32, f32)> = (0..n * n)
        .map(|k| {
            (
                (k % n) as f32 / (n - 1) as f32,
                (k / n) as f32 / (n - 1) as f32,
            )
        })
        .collect();
    let mut s: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    for _ in 0..10_000 {
        p.push((1.5 * next() - 0.25, 1.5 * next() - 0.25));
    }
    p
}

/// f32 numbers across every exponent (and both signs, zeros, subnormals, infinities) for
/// the binary16 conversion.
fn sweep() -> Vec<f32> {
    let mut v: Vec<f32> = (0..200_000u64)
        .map(|k| f32::from_bits((k * 21_474u64 + (k % 7) * 3) as u32))
        .filter(|x| !x.is_nan())
        .collect();
    v.extend([
        0.0,
        -0.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
        65504.0,
        65520.0,
        6.0e-8,
        2.98e-8,
    ]);
    v
}

/// The ES module under node gives the Rust form's bits: at every texel and the other
/// points, its rebuild's f32 and binary16 arrays, and its binary16 conversion on the sweep.
#[test]
fn the_es_module_gives_the_rust_bits() {
    if std::process::Command::new("node")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("skipped: node is not installed");
        return;
    }
    let d = common::scratch("codegen-compact", "js");
    std::fs::copy(
        "results/textures/three/ltc_compact.js",
        d.join("ltc_compact.mjs"),
    )
    .unwrap();
    let pts = points();
    let sw = sweep();
    let input = serde_json::json!({
        "points": pts.iter().map(|(r, t)| [r.to_bits(), t.to_bits()]).collect::<Vec<_>>(),
        "sweep": sw.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
    });
    std::fs::write(d.join("in.json"), input.to_string()).unwrap();
    std::fs::write(
        d.join("run.mjs"),
        r#"import { ltcCompact, rebuild, toHalf } from './ltc_compact.mjs';
import { readFileSync, writeFileSync } from 'node:fs';
const input = JSON.parse(readFileSync(new URL('./in.json', import.meta.url)));
const b = new Float32Array(1), u = new Uint32Array(b.buffer);
const bits = (x) => { b[0] = x; return u[0]; };
const fromBits = (x) => { u[0] = x; return b[0]; };
const values = input.points.map(([r, t]) => Array.from(ltcCompact(fromBits(r), fromBits(t)), bits));
const rb = rebuild();
writeFileSync(new URL('./out.json', import.meta.url), JSON.stringify({
  values,
  mat: Array.from(rb.mat, bits), mag: Array.from(rb.mag, bits),
  matHalf: Array.from(rb.matHalf), magHalf: Array.from(rb.magHalf),
  sweep: input.sweep.map((x) => toHalf(fromBits(x))),
  refused: [1, 0, 2.5, NaN].map((n) => { try { rebuild(n); return false; } catch (e) { return e instanceof RangeError; } }),
}));
"#,
    )
    .unwrap();
    let out = std::process::Command::new("node")
        .arg(d.join("run.mjs"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let o: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("out.json")).unwrap()).unwrap();
    let u32s = |k: &str| -> Vec<u32> {
        o[k].as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_u64().unwrap() as u32)
            .collect()
    };
    for (q, (r, t)) in pts.iter().enumerate() {
        let want = ltc_compact(*r, *t);
        let got: Vec<u32> = o["values"][q]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_u64().unwrap() as u32)
            .collect();
        for ch in 0..6 {
            assert_eq!(got[ch], want[ch].to_bits(), "channel {ch} at ({r}, {t})");
        }
    }
    let n = LTC_COMPACT_N;
    let texels = rebuilt_f32(n);
    let (mat, mag, mat_h, mag_h) = (u32s("mat"), u32s("mag"), u32s("matHalf"), u32s("magHalf"));
    for (k, v) in texels.iter().enumerate() {
        for c in 0..4 {
            assert_eq!(mat[4 * k + c], v[c].to_bits(), "LTC_MAT_1 texel {k}.{c}");
            assert_eq!(
                mat_h[4 * k + c],
                u32::from(half::f16::from_f32(v[c]).to_bits())
            );
        }
        for c in 0..2 {
            assert_eq!(
                mag[4 * k + c],
                v[4 + c].to_bits(),
                "LTC_MAT_2 texel {k}.{c}"
            );
            assert_eq!(
                mag_h[4 * k + c],
                u32::from(half::f16::from_f32(v[4 + c]).to_bits())
            );
        }
        assert_eq!([mag[4 * k + 2], mag[4 * k + 3]], [0, 0]);
    }
    for (x, h) in sw.iter().zip(u32s("sweep")) {
        assert_eq!(
            h,
            u32::from(half::f16::from_f32(*x).to_bits()),
            "binary16 of {x:e} ({:#010x})",
            x.to_bits()
        );
    }
    // a side that leaves no grid spacing (or no integer side) is a RangeError, not NaN texels
    assert_eq!(o["refused"], serde_json::json!([true, true, true, true]));
    let _ = std::fs::remove_dir_all(&d);
}

/// The WGSL compute rebuild (`ltc_compact_rebuild`) run on the adapter present (llvmpipe
/// or lavapipe in CI; skips with one line without one): every texel of both rgba16float
/// textures within two binary16 steps plus twice the f32 form's bound of the Rust form's
/// nearest binary16 — a GPU may fuse multiply-adds and round a store to binary16 either
/// way — and the two unused channels zero.
#[test]
fn the_wgsl_rebuild_runs_within_its_bound() {
    let gpu = match ndfbench::gpu::Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("skipped: {e}");
            return;
        }
    };
    let c = series();
    let n = LTC_COMPACT_N;
    let text = std::fs::read_to_string("results/wgsl/ltc_compact_rebuild.wgsl").unwrap();
    let [m1, m2] = match gpu.fill_two_rgba16f(&text, "ltc_compact_rebuild", n) {
        Ok(m) => m,
        // an adapter without rgba16float storage textures (naga validated the module above)
        Err(e) if e.to_string().contains("refused") => {
            eprintln!("skipped: {e}");
            return;
        }
        Err(e) => panic!("{e}"),
    };
    let sums: Vec<f64> = c
        .channels
        .iter()
        .map(|s| s.coeffs.iter().map(|v| v.abs()).sum())
        .collect();
    let ours = rebuilt_f32(n);
    let mut same = 0;
    for (k, v) in ours.iter().enumerate() {
        let r = (k % n) as f64 / (n - 1) as f64;
        let got: [u16; 6] = [m1[k][0], m1[k][1], m1[k][2], m1[k][3], m2[k][0], m2[k][1]];
        assert_eq!(
            [m2[k][2], m2[k][3]],
            [0, 0],
            "texel {k}: LTC_2's unused channels"
        );
        for ch in 0..6 {
            let want = half::f16::from_f32(v[ch]);
            let g = half::f16::from_bits(got[ch]);
            let step = (half::f16::from_bits(want.to_bits() + 1).to_f64() - want.to_f64()).abs();
            let scale = match c.channels[ch].transform {
                ndfbench::ltc::compact::Transform::OverAlpha => (r * r).max(c.alpha_min),
                _ => 1.0,
            };
            let bound = 2.0 * step + 16.0 * c.p as f64 * f64::from(f32::EPSILON) * sums[ch] * scale;
            assert!(
                (g.to_f64() - want.to_f64()).abs() <= bound,
                "texel {k} channel {ch} on {}: {g} vs {want} (bound {bound:e})",
                gpu.info.name
            );
            same += usize::from(g == want);
        }
    }
    eprintln!(
        "WGSL rebuild on {}: {same} of {} binary16 entries equal the Rust form's",
        gpu.info.name,
        6 * n * n
    );
}

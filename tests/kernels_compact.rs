//! The compact LTC kernels (texture-free series, bilinear lookup of the rebuilt binary16
//! table) on 16 384 R2 points of (r, t) plus the extremes (0, 1e-7, 1e-4, 1 − 1e-7, 1, and
//! values outside [0, 1] down to ±1e30, which clamp): the scalar series equals
//! `Compact::eval_f32` bit for bit, the scalar lookup is within its f32 bound of
//! `ltc::table::bilinear` in f64, and the AVX2 forms equal the scalar ones bit for bit
//! (a channel stored as a logarithm: within 4 ulp, the lane-wise e^x). Bad input is a
//! typed error. Without AVX2+FMA the SIMD comparisons skip with a line.

use ndfbench::kernels::{ltc_compact_lookup, ltc_compact_series, Backend, CompactF32, TableF32};
use ndfbench::ltc::compact::{Compact, Transform};

/// The GGX and sheen series of results/fits/ltc-compact.json.
fn series() -> Vec<(String, Compact)> {
    let text = std::fs::read_to_string("results/fits/ltc-compact.json").unwrap();
    let v: ndfbench::results::ltc_compact::LtcCompact = serde_json::from_str(&text).unwrap();
    v.families
        .into_iter()
        .map(|f| (f.table, f.series))
        .collect()
}

fn points() -> (Vec<f32>, Vec<f32>) {
    let g = 1.324_717_957_244_746_f64;
    let (a1, a2) = (1.0 / g, 1.0 / (g * g));
    let mut r: Vec<f32> = (0..16_384)
        .map(|k| (0.5 + a1 * k as f64).fract() as f32)
        .collect();
    let mut t: Vec<f32> = (0..16_384)
        .map(|k| (0.5 + a2 * k as f64).fract() as f32)
        .collect();
    let ext = [
        -1e30f32,
        -0.5,
        0.0,
        1e-7,
        1e-4,
        0.5,
        1.0 - 1e-7,
        1.0,
        1.5,
        1e30,
    ];
    for a in ext {
        for b in ext {
            r.push(a);
            t.push(b);
        }
    }
    // a length that leaves a tail for the scalar finish
    r.push(0.3);
    t.push(0.7);
    (r, t)
}

fn ulps(a: f32, b: f32) -> u32 {
    if a == b {
        return 0;
    }
    let key = |x: f32| {
        let i = x.to_bits() as i32;
        if i < 0 {
            i32::MIN - i
        } else {
            i
        }
    };
    (key(a) as i64 - key(b) as i64).unsigned_abs() as u32
}

fn run_series(b: Backend, s: &CompactF32, r: &[f32], t: &[f32]) -> Vec<f32> {
    let mut out = vec![0.0; 6 * r.len()];
    ltc_compact_series(b, s, r, t, &mut out).unwrap();
    out
}

fn run_lookup(b: Backend, tab: &TableF32, r: &[f32], t: &[f32]) -> Vec<f32> {
    let mut out = vec![0.0; 6 * r.len()];
    ltc_compact_lookup(b, tab, r, t, &mut out).unwrap();
    out
}

#[test]
fn the_series_kernels_are_the_f32_form() {
    let (r, t) = points();
    let len = r.len();
    for (name, c) in series() {
        let s = CompactF32::of(&c).unwrap();
        let k = c.coeffs_f32();
        let scalar = run_series(Backend::Scalar, &s, &r, &t);
        let per_pixel = run_series(Backend::PerPixel, &s, &r, &t);
        for i in 0..len {
            let want = c.eval_f32(&k, r[i], t[i]);
            for ch in 0..6 {
                assert_eq!(
                    scalar[ch * len + i].to_bits(),
                    want[ch].to_bits(),
                    "{name} ch {ch} at ({}, {})",
                    r[i],
                    t[i]
                );
                assert_eq!(per_pixel[ch * len + i].to_bits(), want[ch].to_bits());
            }
        }
        if !Backend::Avx2.available() {
            eprintln!("skipping SIMD comparison: this CPU has no AVX2+FMA");
            continue;
        }
        let avx = run_series(Backend::Avx2, &s, &r, &t);
        let mut worst = 0;
        for ch in 0..6 {
            let log = c.channels[ch].transform == Transform::Log;
            for i in 0..len {
                let (a, b) = (avx[ch * len + i], scalar[ch * len + i]);
                let u = ulps(a, b);
                worst = worst.max(u);
                if log {
                    assert!(
                        u <= 4,
                        "{name} ch {ch} (log) at ({}, {}): {a} vs {b}, {u} ulp",
                        r[i],
                        t[i]
                    );
                } else {
                    assert_eq!(
                        a.to_bits(),
                        b.to_bits(),
                        "{name} ch {ch} at ({}, {})",
                        r[i],
                        t[i]
                    );
                }
            }
        }
        eprintln!("{name}: AVX2 series within {worst} ulp of the scalar form");
    }
}

#[test]
fn the_lookup_kernels_read_the_table_as_a_sampler_does() {
    let (r, t) = points();
    let len = r.len();
    for (name, c) in series() {
        let table = c.rebuild(64).unwrap();
        let tab = TableF32::of(&table).unwrap();
        let n = tab.n;
        let scalar = run_lookup(Backend::Scalar, &tab, &r, &t);
        assert_eq!(scalar, run_lookup(Backend::PerPixel, &tab, &r, &t));
        let eps = f32::EPSILON as f64;
        let mut worst: f64 = 0.0;
        for i in 0..len {
            let want = ndfbench::ltc::table::bilinear(n, r[i] as f64, t[i] as f64, |a, b| {
                table.half_cell(a + n * b).map(|h| h.to_f64())
            });
            // the four texels around the point: their size M and spread D
            let x = (r[i] as f64).clamp(0.0, 1.0) * (n - 1) as f64;
            let y = (t[i] as f64).clamp(0.0, 1.0) * (n - 1) as f64;
            let (i0, j0) = (
                (x.floor() as usize).min(n - 2),
                (y.floor() as usize).min(n - 2),
            );
            for ch in 0..6 {
                let tex: Vec<f64> = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .iter()
                    .map(|(a, b)| table.half_cell(i0 + a + n * (j0 + b))[ch].to_f64())
                    .collect();
                let m = tex.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let d = tex.iter().fold(f64::MIN, |m, v| m.max(*v))
                    - tex.iter().fold(f64::MAX, |m, v| m.min(*v));
                // six roundings of values ≤ M, and the weights' rounding (x = r(n − 1) to
                // within ε·x, so each weight to within 2ε(n − 1)) times the spread
                let bound = eps * (6.0 * m + 4.0 * (n - 1) as f64 * d) + 1e-30;
                let got = scalar[ch * len + i] as f64;
                worst = worst.max((got - want[ch]).abs() / bound);
                assert!(
                    (got - want[ch]).abs() <= bound,
                    "{name} ch {ch} at ({}, {}): {got} vs {}",
                    r[i],
                    t[i],
                    want[ch]
                );
            }
        }
        eprintln!("{name}: f32 lookup at most {worst:.3} of its bound from the f64 bilinear");
        if Backend::Avx2.available() {
            let avx = run_lookup(Backend::Avx2, &tab, &r, &t);
            for i in 0..6 * len {
                assert_eq!(avx[i].to_bits(), scalar[i].to_bits(), "{name} entry {i}");
            }
        } else {
            eprintln!("skipping SIMD comparison: this CPU has no AVX2+FMA");
        }
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    let (_, c) = series().remove(0);
    let s = CompactF32::of(&c).unwrap();
    let tab = TableF32::of(&c.rebuild(8).unwrap()).unwrap();
    let mut out = vec![0.0; 12];
    for b in [Backend::Scalar, Backend::PerPixel] {
        // NaN, ±∞
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let e = ltc_compact_series(b, &s, &[0.5, bad], &[0.5, 0.5], &mut out).unwrap_err();
            assert!(e.to_string().contains("finite"), "{e}");
            let e = ltc_compact_lookup(b, &tab, &[0.5, 0.5], &[bad, 0.5], &mut out).unwrap_err();
            assert!(e.to_string().contains("finite"), "{e}");
        }
        // lengths: t shorter, output not six per pixel
        assert!(ltc_compact_series(b, &s, &[0.5, 0.5], &[0.5], &mut out).is_err());
        assert!(ltc_compact_lookup(b, &tab, &[0.5, 0.5], &[0.5, 0.5], &mut out[..11]).is_err());
    }
    // a table whose planes are shorter than n² (its AVX2 form gathers by index)
    let mut short = tab.clone();
    short.planes[3].truncate(10);
    for b in [Backend::Scalar, Backend::PerPixel, Backend::Avx2] {
        if b.available() {
            let e = ltc_compact_lookup(b, &short, &[0.5, 0.9], &[0.5, 0.9], &mut out).unwrap_err();
            assert!(e.to_string().contains("planes"), "{e}");
        }
    }
    // a binary16 table of another length than its cells
    let mut odd = c.rebuild(8).unwrap();
    odd.half = Some(vec![[half::f16::ZERO; 6]; 3]);
    assert!(TableF32::of(&odd).is_err());
    // a table of side 1 has no spacing
    let mut one = c.rebuild(2).unwrap();
    one.n = 1;
    one.cells.truncate(1);
    one.half = None;
    assert!(TableF32::of(&one).is_err());
    // a series that fails its own check
    let mut broken = c.clone();
    broken.channels[0].coeffs.pop();
    assert!(CompactF32::of(&broken).is_err());
}

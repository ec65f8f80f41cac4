//! Criterion benches of the deliverables engines take: every generated shader through
//! naga (parse + validate, each back end) and through the Khronos validators where they
//! are installed; the prefilter tool on a 2048² normal map (the whole chain, and the
//! per-mip re-read of the base level that a one-pass-per-mip tool such as Filament's
//! roughness-prefilter does); every shipped LTC table's per-pixel cost (the bilinear
//! lookup of its binary16 entries and the quad integral). `cargo run --release -- bench-report` renders them into
//! results/performance.md.

use criterion::{criterion_group, criterion_main, Criterion};
use ndfbench::codegen::{backends, shaders, validators};
use ndfbench::prefilter;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

fn shader_benches(c: &mut Criterion) {
    let results = Path::new("results");
    for (name, rel) in shaders::sources(results) {
        let Ok(src) = std::fs::read_to_string(results.join(&rel)) else {
            continue;
        };
        let shader = backends::harnessed(&src, &rel).expect("harness");
        let mut g = c.benchmark_group(format!("shaders/{name}"));
        g.sample_size(10)
            .warm_up_time(Duration::from_millis(300))
            .measurement_time(Duration::from_secs(1));
        g.bench_function("naga parse + validate", |b| {
            b.iter(|| {
                let m = naga::front::wgsl::parse_str(black_box(&shader)).unwrap();
                naga::valid::Validator::new(
                    naga::valid::ValidationFlags::all(),
                    backends::CAPABILITIES,
                )
                .validate(&m)
                .unwrap()
            })
        });
        let module = naga::front::wgsl::parse_str(&shader).unwrap();
        let info = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            backends::CAPABILITIES,
        )
        .validate(&module)
        .unwrap();
        for be in backends::BACKENDS {
            g.bench_function(be.name(), |b| {
                b.iter(|| backends::write(be, black_box(&module), &info).unwrap())
            });
            if let (Some((program, _, _)), Ok(bytes)) =
                (validators::tool(be), backends::write(be, &module, &info))
            {
                if validators::version(program).is_some() {
                    g.bench_function(program, |b| {
                        b.iter(|| validators::validate(be, black_box(&bytes)))
                    });
                }
            }
        }
        g.finish();
    }
}

/// A smooth 2048² test map (two sine ripples), written once as an 8-bit PNG.
fn map_2k() -> std::path::PathBuf {
    let p = std::env::temp_dir().join("ndfbench-bench-2k.png");
    if !p.exists() {
        let img = image::RgbImage::from_fn(2048, 2048, |x, y| {
            let (a, b) = (
                0.35 * (x as f64 * 0.11).sin() + 0.1 * (y as f64 * 0.53).cos(),
                0.3 * (y as f64 * 0.07 + x as f64 * 0.02).sin(),
            );
            let l = (a * a + b * b + 1.0).sqrt();
            image::Rgb([a / l, b / l, 1.0 / l].map(|c| ((c * 0.5 + 0.5) * 255.0).round() as u8))
        });
        img.save(&p).unwrap();
    }
    p
}

fn prefilter_benches(c: &mut Criterion) {
    let input = map_2k();
    let options = prefilter::Options {
        input: input.clone(),
        roughness: None,
        alpha: Some(0.09),
        channel: prefilter::input::Channel::Auto,
        filter: prefilter::Filter::Vmf,
        store: prefilter::Store::Perceptual,
        format: prefilter::Format::R8,
        layout: prefilter::Layout::R,
        normals: prefilter::NormalMips::Renormalised,
        reconstruct_z: false,
        results: "results".into(),
    };
    let mut g = c.benchmark_group("prefilter");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(8));
    g.bench_function("2048²: decode + O(N) pyramid + rule", |b| {
        b.iter(|| prefilter::run(black_box(options.clone())).unwrap())
    });
    g.bench_function(
        "2048²: all of it, files rendered (KTX2 + PNG per level)",
        |b| {
            b.iter(|| {
                let o = prefilter::run(black_box(options.clone())).unwrap();
                prefilter::output::render(&o, "bench").unwrap()
            })
        },
    );
    // the statistics of every level by re-reading the base level (one pass per mip,
    // O(N log N)), for the complexity comparison
    let o = prefilter::run(options.clone()).unwrap();
    let base = o.levels[0].clone();
    g.bench_function("2048²: statistics by the O(N) pyramid", |b| {
        b.iter_batched(
            || prefilter::input::Normals {
                width: base.width,
                height: base.height,
                bits: 8,
                n: base.mean_n.clone(),
            },
            |n| prefilter::chain::pyramid(n, &prefilter::input::Roughness::Constant(0.09)),
            criterion::BatchSize::LargeInput,
        )
    });
    g.bench_function(
        "2048²: statistics by one pass per mip over the base (f64)",
        |b| {
            b.iter(|| {
                let mut s = 0.0;
                for l in 1..o.levels.len() {
                    let (w, h) = ((base.width >> l).max(1), (base.height >> l).max(1));
                    for j in 0..h {
                        for i in 0..w {
                            s += prefilter::chain::direct(black_box(&base), l, i, j).1;
                        }
                    }
                }
                s
            })
        },
    );
    g.finish();
}

/// Per pixel with each shipped LTC table: the bilinear lookup of the stored binary16
/// entries at (α, cos θ) and norm × the quad integral of M⁻¹P with the rational edge
/// form, over 1024 deterministic pixels (α, cos θ on a lattice; four quads).
fn ltc_table_benches(c: &mut Criterion) {
    use ndfbench::ltc::fit::inverse_from_production;
    use ndfbench::ltc::polygon::{check_lights, ltc_integral, EdgeForm};
    let mut g = c.benchmark_group("ltc-tables");
    g.measurement_time(Duration::from_secs(3));
    let pixels: Vec<(f64, f64, usize)> = (0..1024)
        .map(|k| {
            let a = ((k % 32) as f64 + 0.5) / 32.0;
            let ct = ((k / 32) as f64 + 0.5) / 32.0;
            (a * a, ct, k % 4)
        })
        .collect();
    let lights: Vec<Vec<nalgebra::Vector3<f64>>> = check_lights(0.6)
        .into_iter()
        .map(|(_, l)| l.vertices)
        .collect();
    for kind in &ndfbench::codegen::textures::TABLES {
        let Ok(t) = ndfbench::ltc::table::read(Path::new("results"), kind.fit) else {
            continue;
        };
        g.bench_function(format!("{}: 1024 pixels", kind.stem), |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for &(a, ct, q) in &pixels {
                    let e = t.bilinear(black_box(a), black_box(ct), true);
                    let minv = inverse_from_production(&[e[0], e[1], e[2], e[3]]);
                    sum += e[4] * ltc_integral(&minv, &lights[q], EdgeForm::Rational);
                }
                sum
            })
        });
    }
    if let Ok(t) = ndfbench::ltc::aniso_table::read(Path::new("results")) {
        let h = t.to_half();
        g.bench_function("ltc_ggx_aniso: 1024 pixels", |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for (k, &(a, ct, q)) in pixels.iter().enumerate() {
                    let ay = a * (0.25 + 0.75 * ((k * 7) % 32) as f64 / 31.0);
                    let phi = 0.1 * (k % 31) as f64;
                    let e = h.lookup(black_box(a), black_box(ay), black_box(phi), black_box(ct));
                    let minv =
                        ndfbench::ltc::aniso::inverse_of(&ndfbench::ltc::aniso_table::inv7(&e));
                    sum += e[7] * ltc_integral(&minv, &lights[q], EdgeForm::Rational);
                }
                sum
            })
        });
    }
    g.finish();
}

criterion_group!(
    benches,
    prefilter_benches,
    shader_benches,
    ltc_table_benches
);
criterion_main!(benches);

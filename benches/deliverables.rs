//! Criterion benches of the deliverables engines take: every generated shader through
//! naga (parse + validate, each back end) and through the Khronos validators where they
//! are installed; the prefilter tool on a 2048² normal map (the whole chain, and the
//! per-mip re-read of the base level that a one-pass-per-mip tool such as Filament's
//! roughness-prefilter does); every shipped LTC table's per-pixel cost (the bilinear
//! lookup of its binary16 entries and the quad integral); the compact LTC tables'
//! texture-free series against the lookup of their rebuilt table; every render method's shading
//! pass per pixel on one core (the G-buffer, each approximation of the example scenes,
//! seed 002's brute force and CP query); every representation of the survey study
//! (results/filters-survey.md) evaluated as the lobe it shades. `cargo run --release -- bench-report`
//! renders them into results/performance.md.

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
        filter: prefilter::Choice::Filter(ndfbench::filters::registry::Filter::of("vmf-2")),
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
        let Ok(t) = ndfbench::results::ltc::table(Path::new("results"), kind.fit) else {
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
    if let Ok(t) = ndfbench::results::ltc_aniso::aniso_table(Path::new("results")) {
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

/// The compact LTC tables (results/fits/ltc-compact.json) per pixel, 4096 pixels of
/// (r, t) on an R2 sequence: the texture-free series at each degree the study tried (the
/// stored series resized: the cost depends on the degree alone) against the bilinear
/// lookup of the rebuilt binary16 table, on each kernel backend.
fn ltc_compact_benches(c: &mut Criterion) {
    use ndfbench::kernels::{
        ltc_compact_lookup, ltc_compact_series, Backend, CompactF32, TableF32,
    };
    let Ok(text) = std::fs::read_to_string("results/fits/ltc-compact.json") else {
        return;
    };
    let Ok(file) = serde_json::from_str::<ndfbench::results::ltc_compact::LtcCompact>(&text) else {
        return;
    };
    let n = 4096;
    let g2 = 1.324_717_957_244_746_f64;
    let r: Vec<f32> = (0..n)
        .map(|k| (0.5 + k as f64 / g2).fract() as f32)
        .collect();
    let t: Vec<f32> = (0..n)
        .map(|k| (0.5 + k as f64 / (g2 * g2)).fract() as f32)
        .collect();
    let mut out = vec![0.0f32; 6 * n];
    let mut g = c.benchmark_group("ltc-compact");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for f in &file.families {
        let name = f.table.trim_start_matches("ltc-");
        let tab = TableF32::of(&f.series.rebuild(f.n).unwrap()).unwrap();
        let mut degrees: Vec<usize> = f.forms.iter().map(|x| x.p).collect();
        degrees.sort();
        degrees.dedup();
        for b in [Backend::PerPixel, Backend::Scalar, Backend::Avx2] {
            if !b.available() {
                continue;
            }
            g.bench_function(
                criterion::BenchmarkId::new(format!("{name} lookup"), b.name()),
                |bch| {
                    bch.iter(|| ltc_compact_lookup(b, &tab, black_box(&r), &t, &mut out).unwrap())
                },
            );
            for &p in &degrees {
                let s = CompactF32::of(&f.series.resized(p).unwrap()).unwrap();
                g.bench_function(
                    criterion::BenchmarkId::new(format!("{name} series p{p}"), b.name()),
                    |bch| {
                        bch.iter(|| ltc_compact_series(b, &s, black_box(&r), &t, &mut out).unwrap())
                    },
                );
            }
        }
    }
    g.finish();
}

/// One core, each example scene at its own size (256²): the G-buffer pass over the whole
/// image, then each method's shading of the 64² pixels at the image centre (so the
/// footprints are the default render's).
fn render_benches(c: &mut Criterion) {
    use ndfbench::render::{geometry::*, glints, light, methods, scene::*, texture::Texture};
    let Ok(consts) = ndfbench::results::render::constants(Path::new("results")) else {
        return;
    };
    let mut g = c.benchmark_group("render");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(2));
    for (name, text) in ndfbench::studies::render::SCENES {
        let Ok(sc) = Scene::parse(text, name) else {
            continue;
        };
        let Ok(map) = ndfbench::render::normal_map(&sc, Path::new("fits/render")) else {
            continue;
        };
        let tex = Texture::new(map);
        let lights = light::resolve(&sc.lights);
        let cam = Camera::at_frame(&sc.camera, 0);
        let surf = Surface::new(&sc.surface, sc.render.scales[0]);
        let gb = methods::gbuffer(&cam, &surf, &tex);
        let w = cam.width;
        let (x0, y0) = ((w - 64) / 2, (cam.height - 64) / 2);
        let window: Vec<usize> = (0..4096).map(|i| (y0 + i / 64) * w + x0 + i % 64).collect();
        let n = window.len();
        g.bench_function(format!("{name}: G-buffer, {} pixels", gb.len()), |b| {
            b.iter(|| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(1)
                    .build()
                    .map(|p| p.install(|| methods::gbuffer(&cam, &surf, &tex).len()))
            })
        });
        let alpha = sc.material.alpha as f32;
        let consts = consts.clone().with_alpha(sc.material.alpha);
        let list: &[&str] = match sc.render.methods {
            MethodSet::Multiscale => &methods::MULTISCALE,
            MethodSet::SpecularAa => &methods::SPECULAR_AA,
            _ => &[],
        };
        for key in list {
            let Ok(m) = methods::Method::new(key, &consts) else {
                continue;
            };
            g.bench_function(format!("{name}: {}, {n} pixels", m.key()), |b| {
                b.iter(|| {
                    window
                        .iter()
                        .map(|&k| methods::shade(m, &gb, w, black_box(k), alpha, &lights, &consts))
                        .sum::<f32>()
                })
            });
        }
        if sc.render.methods == MethodSet::Glints {
            let sr = sc.material.sigma_r;
            g.bench_function(format!("{name}: pndf-brute, {n} pixels"), |b| {
                b.iter(|| {
                    window
                        .iter()
                        .filter_map(|&k| {
                            gb[k].as_ref().map(|p| {
                                glints::brute(
                                    &cam,
                                    p,
                                    &tex,
                                    &lights,
                                    sr,
                                    (k % w) as f64 + 0.5,
                                    (k / w) as f64 + 0.5,
                                )
                            })
                        })
                        .sum::<f32>()
                })
            });
            let plan =
                ndfbench::studies::render::builtin_params(ndfbench::integrate::Preset::Quick)
                    .expect("fits/render.toml")
                    .glints;
            if let Ok(imgs) = glints::pndf_grid(&tex, plan.res, plan.stride, 4.6, sr) {
                for rank in [8usize, 32] {
                    let Ok(cp) =
                        glints::CpGlints::build(&imgs, plan.res, plan.stride, plan.t, rank, 10, 5)
                    else {
                        continue;
                    };
                    g.bench_function(format!("{name}: cp-r{rank}, {n} pixels"), |b| {
                        b.iter(|| {
                            window
                                .iter()
                                .filter_map(|&k| gb[k].as_ref().map(|p| cp.shade(p, &tex, &lights)))
                                .sum::<f32>()
                        })
                    });
                }
            }
            g.bench_function(format!("{name}: plain-mip, {n} pixels"), |b| {
                b.iter(|| {
                    window
                        .iter()
                        .filter_map(|&k| gb[k].as_ref().map(|p| glints::mip(p, &lights, sr)))
                        .sum::<f32>()
                })
            });
        }
    }
    g.finish();
}

/// One footprint of the survey study (flakes, 64² map, level 3: 8×8 texels; GGX α 0.05):
/// every representation's lobe at 1024 seeded (v, l) pairs around the mean normal's
/// mirror direction, and the isotropic vMF 2/κ lobe for scale.
fn survey_benches(c: &mut Criterion) {
    use nalgebra::Vector3;
    use ndfbench::filters::footprint::{NormalMap, Procedural};
    use ndfbench::studies::filters::survey::fit_footprint;
    use ndfbench::survey::{sh::Zonal, BaseLobe};
    use rand::{Rng, SeedableRng};
    let Ok(map) = NormalMap::procedural(Procedural::Flakes, 64, 7) else {
        return;
    };
    let base = BaseLobe {
        kind: ndfbench::microfacet::NdfKind::Ggx,
        alpha: 0.05,
    };
    let zonal = Zonal::new(base, 320);
    let Ok(fit) = fit_footprint(&map, 3, 9, base, &zonal, 11) else {
        return;
    };
    let n = fit.shading.normal();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let pairs: Vec<(Vector3<f64>, Vector3<f64>)> = (0..1024)
        .map(|_| {
            let jitter = |r: &mut rand_chacha::ChaCha8Rng| {
                Vector3::new(r.random::<f64>() - 0.5, r.random::<f64>() - 0.5, 0.0) * 0.4
            };
            let v = (Vector3::new(0.4, 0.1, 0.9) + jitter(&mut rng)).normalize();
            let l = (n * (2.0 * v.dot(&n)) - v + jitter(&mut rng)).normalize();
            (v, Vector3::new(l.x, l.y, l.z.abs().max(1e-3)).normalize())
        })
        .collect();
    let mut g = c.benchmark_group("survey");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(1));
    g.warm_up_time(Duration::from_millis(300));
    for (i, rep) in fit.reps.iter().enumerate() {
        g.bench_function(format!("row {i:02}: 1024 lobes"), |b| {
            b.iter(|| {
                pairs
                    .iter()
                    .map(|(v, l)| fit.shading.value(&**rep, black_box(v), l))
                    .sum::<f64>()
            })
        });
    }
    let s = ndfbench::microfacet::Microsurface::ggx(
        ndfbench::microfacet::Roughness::iso(0.08).expect("α > 0"),
    );
    let f = ndfbench::microfacet::lobe::Frame::around(n);
    g.bench_function("isotropic GGX lobe: 1024 lobes", |b| {
        b.iter(|| {
            pairs
                .iter()
                .map(|(v, l)| ndfbench::microfacet::lobe::lobe(&s, &f, black_box(v), l))
                .sum::<f64>()
        })
    });
    g.finish();
}

/// One lookup of every visibility method from its filtered parameters (1024 seeded
/// queries): the horizon forms from an 8×8 bumps footprint's stored moments, the shadow
/// methods from a layered-scene footprint's filtered parameters.
fn visibility_benches(c: &mut Criterion) {
    use ndfbench::visibility::horizon::{self, Dir, HdfMoments, LegendreHorizon};
    use ndfbench::visibility::shadow::{Method, Occluders, Precision, Receiver, Scene};
    use ndfbench::visibility::{HeightField, Relief};
    use rand::{Rng, SeedableRng};
    let Ok(hf) = HeightField::procedural(Relief::Bumps, 64, 3) else {
        return;
    };
    let texels = hf.block(3, 2, 2);
    let th = horizon::stored_horizons(&hf, &texels);
    let mom = HdfMoments::new(&th);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let dirs: Vec<(Dir, Dir)> = (0..1024)
        .map(|_| {
            let mut d = || Dir {
                elev: 0.1 + 1.2 * rng.random::<f64>(),
                azim: 6.28 * rng.random::<f64>(),
            };
            (d(), d())
        })
        .collect();
    let mut g = c.benchmark_group("visibility");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(1));
    g.warm_up_time(Duration::from_millis(300));
    g.bench_function("horizon: Fournier ramp, 1024 lookups", |b| {
        b.iter(|| {
            dirs.iter()
                .map(|(v, _)| horizon::fournier(&mom, black_box(v)))
                .sum::<f64>()
        })
    });
    g.bench_function("horizon: Tan erf, 1024 lookups", |b| {
        b.iter(|| {
            dirs.iter()
                .map(|(v, _)| horizon::tan_erf(&mom, black_box(v)))
                .sum::<f64>()
        })
    });
    g.bench_function("horizon: Tan erf + Eq 28, 1024 lookups", |b| {
        b.iter(|| {
            dirs.iter()
                .map(|(v, l)| {
                    let (a, bb) = (
                        horizon::tan_erf(&mom, l),
                        horizon::tan_erf(&mom, black_box(v)),
                    );
                    horizon::joint_eq28(a, bb, v.cos_between(l))
                })
                .sum::<f64>()
        })
    });
    for k in [8usize, 32] {
        let lg = LegendreHorizon::new(&th, k);
        g.bench_function(format!("horizon: Legendre {k}, 1024 lookups"), |b| {
            b.iter(|| dirs.iter().map(|(v, _)| lg.eval(black_box(v))).sum::<f64>())
        });
    }
    let sc = Scene {
        occluders: Occluders::Layers,
        receiver: Receiver::Parallel,
        size: 64,
    };
    let z = sc.depth_map();
    let fp = hf.block(3, 3, 3);
    let ds: Vec<f64> = (0..1024).map(|_| 0.5 + 0.5 * rng.random::<f64>()).collect();
    for m in [
        Method::Vsm,
        Method::Csm {
            terms: 16,
            fixed: true,
        },
        Method::Esm { c: 40.0 },
        Method::Evsm { c: 20.0 },
    ] {
        let f = m.filter(&z, 64, &fp, Precision::F32);
        g.bench_function(format!("shadow: {m:?}, 1024 lookups"), |b| {
            b.iter(|| ds.iter().map(|d| m.lookup(&f, black_box(*d))).sum::<f64>())
        });
    }
    g.finish();
}

/// Seed 002's P-NDF at the paper's footprint (stride 32, σ_P = 1.5·32/√12, 256² bins) of a
/// 512² flakes map: the f64 brute force of Eq 2 (rayon over rows), the factored-Gaussian
/// splat the paper-scale study runs on (one core), and the f32 compute shader on the
/// adapter wgpu picks (64 footprints per call), where there is one that is not a CPU.
fn pndf_benches(c: &mut Criterion) {
    use ndfbench::filters::footprint::{NormalMap, Procedural};
    use ndfbench::tensor::pndf::{pndf_image, pndf_image_separable, sigma_p};
    let Ok(map) = NormalMap::procedural(Procedural::Flakes, 512, 3) else {
        return;
    };
    let sp = sigma_p(32, 0);
    let mut g = c.benchmark_group("pndf");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(5));
    g.bench_function("f64 brute force (rayon): 1 footprint, 256²", |b| {
        b.iter(|| pndf_image(&map, black_box(80.0), 80.0, sp, 0.02, 256))
    });
    g.bench_function("f64 factored splat (one core): 1 footprint, 256²", |b| {
        b.iter(|| pndf_image_separable(&map, black_box(80.0), 80.0, sp, 0.02, 256))
    });
    match ndfbench::gpu::Gpu::new() {
        // a software rasteriser (lavapipe/llvmpipe) needs ~4 min per call here: its time
        // says nothing about a GPU, so it is not benchmarked
        Ok(gpu) if gpu.info.device_type == wgpu::DeviceType::Cpu => {
            eprintln!(
                "pndf: GPU bench skipped: {} is a CPU adapter",
                gpu.info.name
            )
        }
        Ok(gpu) => {
            let centres: Vec<(f64, f64)> = (0..64)
                .map(|k| (16.0 + 32.0 * (k % 8) as f64, 16.0 + 32.0 * (k / 8) as f64))
                .collect();
            g.bench_function(
                format!(
                    "f32 GPU brute force ({}): 64 footprints, 256²",
                    gpu.info.name
                ),
                |b| b.iter(|| gpu.pndf_images(&map, black_box(&centres), sp, 0.02, 256)),
            );
        }
        Err(why) => eprintln!("pndf: GPU bench skipped: {why}"),
    }
    g.finish();
}

criterion_group!(
    benches,
    pndf_benches,
    prefilter_benches,
    shader_benches,
    ltc_table_benches,
    ltc_compact_benches,
    render_benches,
    survey_benches,
    visibility_benches
);
criterion_main!(benches);

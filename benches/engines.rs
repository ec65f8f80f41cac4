//! Criterion benches: time per integral of every engine on the three convergence
//! integrands (at the settings of `Engine::bench_level`), rayon scaling of MC, and the
//! cost of the f64 reference vs f32 shading forms. `cargo run --release -- bench-report`
//! turns the output into results/performance.md, next to each configuration's error.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nalgebra::Vector3;
use ndfbench::integrate::mc::{mis, CosineHemisphere, Strategy};
use ndfbench::microfacet::sampling::NdfSampler;
use ndfbench::microfacet::shading::{self, Rough32};
use ndfbench::microfacet::{Microsurface, Roughness};
use ndfbench::studies::convergence::{integrands, run_engine, Engine};
use std::hint::black_box;
use std::time::Duration;

fn engines(c: &mut Criterion) {
    for ig in integrands() {
        let mut g = c.benchmark_group(format!("engines/{}", ig.key));
        g.sample_size(10)
            .warm_up_time(Duration::from_millis(300))
            .measurement_time(Duration::from_secs(2));
        for e in Engine::ALL {
            let level = e.bench_level();
            g.bench_with_input(BenchmarkId::new(e.name(), level), &level, |b, &l| {
                b.iter(|| run_engine(&ig, e, l, 7))
            });
        }
        g.finish();
    }
}

fn rayon_scaling(c: &mut Criterion) {
    let s = Microsurface::ggx(Roughness::iso(0.1).unwrap());
    let f = |m: &Vector3<f64>| s.d(m) * m.z.max(0.0);
    let ns = NdfSampler { surface: s };
    let strat: [&dyn Strategy<Vector3<f64>>; 2] = [&ns, &CosineHemisphere];
    let mut g = c.benchmark_group("rayon-scaling");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(3));
    let max = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let mut threads = vec![1usize];
    let mut t = 2;
    while t <= max {
        threads.push(t);
        t *= 2;
    }
    if *threads.last().unwrap() != max {
        threads.push(max);
    }
    for t in threads {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap();
        g.bench_with_input(BenchmarkId::new("mis-2^20", t), &t, |b, _| {
            b.iter(|| pool.install(|| mis(&f, &strat, 1 << 20, 3)))
        });
    }
    g.finish();
}

fn shading_forms(c: &mut Criterion) {
    let r = Roughness::rotated(0.05, 0.3, 0.4).unwrap();
    let s = Microsurface::ggx(r);
    let r32 = Rough32::from(&r);
    let dirs: Vec<Vector3<f64>> = (0..1024)
        .map(|k| {
            let t = (k as f64 / 1024.0) * 1.5;
            Vector3::new(
                t.sin() * (k as f64).cos(),
                t.sin() * (k as f64).sin(),
                t.cos(),
            )
        })
        .collect();
    let d32: Vec<[f32; 3]> = dirs
        .iter()
        .map(|d| [d.x as f32, d.y as f32, d.z as f32])
        .collect();
    let mut g = c.benchmark_group("shading-1024");
    g.throughput(Throughput::Elements(1024));
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    g.bench_function("ggx-d-f64", |b| {
        b.iter(|| dirs.iter().map(|m| s.d(black_box(m))).sum::<f64>())
    });
    g.bench_function("ggx-d-f32", |b| {
        b.iter(|| {
            d32.iter()
                .map(|m| shading::d_ggx(&r32, *black_box(m)))
                .sum::<f32>()
        })
    });
    g.bench_function("ggx-lambda-f64", |b| {
        b.iter(|| dirs.iter().map(|o| s.lambda(black_box(o))).sum::<f64>())
    });
    g.bench_function("ggx-lambda-f32", |b| {
        b.iter(|| {
            d32.iter()
                .map(|o| shading::lambda_ggx(&r32, *black_box(o)))
                .sum::<f32>()
        })
    });
    let sb = Microsurface::beckmann(r);
    g.bench_function("beckmann-lambda-f64", |b| {
        b.iter(|| dirs.iter().map(|o| sb.lambda(black_box(o))).sum::<f64>())
    });
    g.bench_function("beckmann-lambda-f32", |b| {
        b.iter(|| {
            d32.iter()
                .map(|o| shading::lambda_beckmann(&r32, *black_box(o)))
                .sum::<f32>()
        })
    });
    g.finish();
}

/// The four ways to get α_me from ‖b̄‖ (seed 000 §3.3), 1024 inputs per iteration.
fn alpha_me(c: &mut Criterion) {
    use ndfbench::multiscale::alpha_me::Table;
    use ndfbench::multiscale::mrl::{alpha_from_one_minus, alpha_me_paper, mrl_pair};
    let spec = ndfbench::studies::multiscale_alpha_me::params_in(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("fits")
            .as_path(),
    )
    .expect("fits/multiscale-alpha-me.toml");
    let (lo, hi) = (spec.alpha_min, spec.alpha_max);
    let coeffs = spec.fit().unwrap();
    let table = Table::build(spec.table_entries, lo, hi);
    let inputs: Vec<(f64, f64)> = (0..1024)
        .map(|i| mrl_pair(lo * (hi / lo).powf((i as f64 + 0.5) / 1024.0)))
        .collect();
    let mut g = c.benchmark_group("alpha-me");
    g.throughput(Throughput::Elements(1024));
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    g.bench_function("paper-eq5", |b| {
        b.iter(|| {
            inputs
                .iter()
                .map(|&(b, _)| alpha_me_paper(black_box(b)))
                .sum::<f64>()
        })
    });
    g.bench_function("ours", |b| {
        b.iter(|| {
            inputs
                .iter()
                .map(|&(_, y)| coeffs.eval(black_box(y)))
                .sum::<f64>()
        })
    });
    g.bench_function("table", |b| {
        b.iter(|| {
            inputs
                .iter()
                .map(|&(_, y)| table.eval(black_box(y)))
                .sum::<f64>()
        })
    });
    g.bench_function("newton", |b| {
        b.iter(|| {
            inputs
                .iter()
                .map(|&(_, y)| alpha_from_one_minus(black_box(y)).unwrap())
                .sum::<f64>()
        })
    });
    g.finish();
}

/// Beckmann Λ(ν): exact (erfc), Walter's rational, the refitted rational; 1024 ν per iteration.
fn smith_lambda(c: &mut Criterion) {
    use ndfbench::microfacet::lambda::{beckmann, walter_printed};
    use ndfbench::microfacet::lambda_fit::{fit, grids, rational};
    let (train, _) = grids(600, 1e-3, 10.0);
    let (p, _) = fit(&train, 4000).unwrap();
    let nus: Vec<f64> = (0..1024)
        .map(|i| 1e-3 * (1e4f64).powf((i as f64 + 0.5) / 1024.0))
        .collect();
    let mut g = c.benchmark_group("smith-lambda");
    g.throughput(Throughput::Elements(1024));
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    g.bench_function("exact-erfc", |b| {
        b.iter(|| nus.iter().map(|&n| beckmann(black_box(n))).sum::<f64>())
    });
    g.bench_function("walter", |b| {
        b.iter(|| {
            nus.iter()
                .map(|&n| walter_printed(black_box(n)))
                .sum::<f64>()
        })
    });
    g.bench_function("ours", |b| {
        b.iter(|| nus.iter().map(|&n| rational(&p, black_box(n))).sum::<f64>())
    });
    g.finish();
}

/// LEADR N×N grid estimate (rough specular × environment), cost against N (seed 001 §3.5).
fn leadr(c: &mut Criterion) {
    use nalgebra::Vector3;
    use ndfbench::leadr::{grid_estimate, Grid, Slopes};
    let v = Vector3::new(0.5, 0.1, 0.86).normalize();
    let sun = Vector3::new(0.5, 0.2, 0.8).normalize();
    let env = |n: &Vector3<f64>| {
        let r = n * (2.0 * n.dot(&v)) - v;
        0.5 + 0.5 * r.z + 10.0 * (50.0 * (r.dot(&sun) - 1.0)).exp()
    };
    let s = Slopes::iso(0.3);
    let mut g = c.benchmark_group("leadr");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    for n in [3usize, 5, 8, 16, 32] {
        let grid = Grid::gauss_hermite(n);
        g.bench_with_input(BenchmarkId::new("grid", n), &n, |b, _| {
            b.iter(|| grid_estimate(&grid, &s, black_box(&v), &env, None))
        });
    }
    g.finish();
}

/// f32 shading forms of the footprint filters, 1024 inputs per iteration.
fn filters(c: &mut Criterion) {
    use ndfbench::filters::rules as r;
    let n = 1024usize;
    let inp: Vec<(f32, f32, [f32; 3], [f32; 3])> = (0..n)
        .map(|i| {
            let t = i as f32 / n as f32;
            (
                0.02 + 0.5 * t,
                0.9 + 0.0999 * (1.0 - t),
                [0.1 * t, -0.05, 0.02 * t],
                [-0.03, 0.08 * t, 0.01],
            )
        })
        .collect();
    // the generated α_me constants (both branches), as the shaders use them
    let (small, large) = (ndfbench::kernels::ALPHA_ME_C, ndfbench::kernels::ALPHA_ME_D);
    let mut g = c.benchmark_group("filters");
    g.throughput(Throughput::Elements(n as u64));
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    macro_rules! bench {
        ($id:expr, $f:expr) => {
            g.bench_function($id, |b| {
                b.iter(|| inp.iter().map(|x| $f(black_box(x))).sum::<f32>())
            });
        };
    }
    bench!("toksvig-bp", |x: &(f32, f32, [f32; 3], [f32; 3])| {
        r::toksvig_bp(x.0, x.1)
    });
    bench!("toksvig", |x: &(f32, f32, [f32; 3], [f32; 3])| {
        r::toksvig_alpha2(x.0, x.1, 2.0)
    });
    bench!("vmf", |x: &(f32, f32, [f32; 3], [f32; 3])| r::vmf(
        x.0, x.1, 2.0
    ));
    bench!("lean", |x: &(f32, f32, [f32; 3], [f32; 3])| r::lean(
        x.0, x.2
    )[0]);
    bench!("seed000-paper", |x: &(f32, f32, [f32; 3], [f32; 3])| {
        r::seed000_paper(x.0, x.1)
    });
    bench!("seed000-moment", |x: &(f32, f32, [f32; 3], [f32; 3])| {
        r::seed000_moment_fit(x.1, 0.98, &small, &large)
    });
    bench!(
        "deferred",
        |x: &(f32, f32, [f32; 3], [f32; 3])| r::deferred(x.0, x.2, x.3, 0.25, 0.18)
    );
    bench!("eigen", |x: &(f32, f32, [f32; 3], [f32; 3])| r::eigen_eq10(
        x.0,
        [x.2[0], x.2[1]],
        [x.3[0], x.3[1]],
        0.25,
        0.18
    ));
    bench!("rect", |x: &(f32, f32, [f32; 3], [f32; 3])| {
        r::kaplanyan_rect(x.0, [x.2[0], x.2[1]], [x.3[0], x.3[1]], 0.25, 0.18)
    });
    bench!("projected", |x: &(f32, f32, [f32; 3], [f32; 3])| {
        r::projected_space(x.0, x.2, x.3, 0.1, 0.04)
    });
    bench!("on-alpha", |x: &(f32, f32, [f32; 3], [f32; 3])| {
        r::deferred_on_alpha(x.0, x.2, x.3, 0.25, 0.18)
    });
    bench!("forward", |x: &(f32, f32, [f32; 3], [f32; 3])| {
        r::forward_matrix(x.0, [x.2[0], x.2[1]], [x.3[0], x.3[1]], 0.25)[0]
    });
    g.finish();
}

/// Batched SIMD kernels vs their scalar twins, 64 to 1M pixels.
fn kernels(c: &mut Criterion) {
    use ndfbench::kernels::{self as k, Backend, DeferredIn, SpecularIn};
    let max = 1usize << 20;
    let data = k::bench_inputs(max);
    for (name, sizes) in [
        ("kernel-ggx-specular", [64usize, 4096, 65536, 1 << 20]),
        ("kernel-deferred", [64, 4096, 65536, 1 << 20]),
        ("kernel-multiscale", [64, 4096, 65536, 1 << 20]),
        ("kernel-ltc-quad", [64, 4096, 65536, 1 << 20]),
        ("kernel-leadr", [64, 4096, 65536, 1 << 20]),
    ] {
        let mut g = c.benchmark_group(name);
        g.sample_size(10)
            .warm_up_time(Duration::from_millis(200))
            .measurement_time(Duration::from_millis(600));
        for n in sizes {
            g.throughput(Throughput::Elements(n as u64));
            let mut out = vec![0.0f32; n];
            for b in [Backend::PerPixel, Backend::Scalar, Backend::Avx2] {
                if !b.available() {
                    continue;
                }
                g.bench_with_input(BenchmarkId::new(b.name(), n), &n, |bch, &n| {
                    bch.iter(|| {
                        let c = &data.cols;
                        match name {
                            "kernel-ggx-specular" => k::ggx_specular(
                                b,
                                &SpecularIn {
                                    l: [&c[0][..n], &c[1][..n], &c[2][..n]],
                                    v: [&c[3][..n], &c[4][..n], &c[5][..n]],
                                    alpha: &c[6][..n],
                                },
                                &mut out,
                            ),
                            "kernel-deferred" => k::deferred_roughness(
                                b,
                                &DeferredIn {
                                    alpha: &c[6][..n],
                                    du: [&c[7][..n], &c[8][..n], &c[9][..n]],
                                    dv: [&c[10][..n], &c[11][..n], &c[12][..n]],
                                },
                                0.25,
                                0.18,
                                &mut out,
                            ),
                            "kernel-ltc-quad" => k::ltc_quad(
                                b,
                                &k::LtcQuadIn {
                                    m: [&c[15][..n], &c[16][..n], &c[17][..n], &c[18][..n]],
                                    p: std::array::from_fn(|j| &c[19 + j][..n]),
                                },
                                &mut out,
                            ),
                            "kernel-leadr" => k::leadr5(
                                b,
                                &k::LeadrIn {
                                    s: [
                                        &c[31][..n],
                                        &c[32][..n],
                                        &c[33][..n],
                                        &c[34][..n],
                                        &c[35][..n],
                                    ],
                                    v: [&c[36][..n], &c[37][..n], &c[38][..n]],
                                },
                                &mut out,
                            ),
                            _ => k::multiscale_alpha(b, &c[13][..n], &c[14][..n], &mut out),
                        }
                        .unwrap();
                        black_box(out[n - 1])
                    })
                });
            }
        }
        g.finish();
    }
}

/// Seed 002 §4.4, §5.2: range-query time against box size (O(R)) next to the naive sum,
/// and the cost of one hierarchical importance sample.
fn tensor(c: &mut Criterion) {
    use ndfbench::tensor::query::{range, range_naive, Sat};
    use ndfbench::tensor::sample::{sample, total};
    let cp = ndfbench::verify::tensor::random_cp(16, [256, 256, 4], 3);
    let sat = Sat::build(&cp);
    let mut g = c.benchmark_group("tensor-range");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(600));
    for w in [1usize, 4, 16, 64, 256] {
        g.bench_with_input(BenchmarkId::new("sat", w), &w, |b, &w| {
            b.iter(|| range(&cp, &sat, black_box((0, w - 1)), black_box((0, w - 1)), 1))
        });
        if w <= 64 {
            g.bench_with_input(BenchmarkId::new("naive", w), &w, |b, &w| {
                b.iter(|| range_naive(&cp, black_box((0, w - 1)), black_box((0, w - 1)), 1))
            });
        }
    }
    // the same box at every depth (footprint level) of the tensor
    for z in 0..4usize {
        g.bench_with_input(BenchmarkId::new("sat-level", z), &z, |b, &z| {
            b.iter(|| {
                range(
                    &cp,
                    &sat,
                    black_box((96, 159)),
                    black_box((96, 159)),
                    black_box(z),
                )
            })
        });
    }
    g.finish();
    let small = ndfbench::verify::tensor::random_cp(16, [16, 16, 4], 4);
    let ssat = Sat::build(&small);
    let tot = total(&small, 1);
    let mut g = c.benchmark_group("tensor-sample");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(600));
    g.bench_function("hierarchical-16", |b| {
        let mut k = 0u64;
        b.iter(|| {
            k = k.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let u = (k >> 11) as f64 / (1u64 << 53) as f64;
            sample(&small, &ssat, 1, tot, [u, 0.3, 0.7])
        })
    });
    g.finish();
}

/// Seed 002 Table 3: one BRDF evaluation and one BRDF sample of the glinty BRDF (D from
/// a point query of the compressed P-NDF; sampling by block CDF, hierarchical descent and
/// tent, Fig 8) against a plain GGX microfacet BRDF (Walter et al. 2007; visible-normal
/// sampling), at ranks 8, 16 and 32, over the same 1024 inputs in turn.
fn tensor_brdf(c: &mut Criterion) {
    use ndfbench::tensor::brdf::{table3_ndf, Glinty, Microfacet};
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2022);
    let incident: Vec<[f64; 3]> = (0..1024)
        .map(|_| {
            let (ct, phi) = (
                0.35 + 0.65 * rng.random::<f64>(),
                std::f64::consts::TAU * rng.random::<f64>(),
            );
            let st = (1.0 - ct * ct).sqrt();
            [st * phi.cos(), st * phi.sin(), ct]
        })
        .collect();
    let us: Vec<[f64; 4]> = (0..1024).map(|_| rng.random()).collect();
    let plain = Microfacet {
        alpha: 0.1,
        f0: 0.9,
    };
    let mut g = c.benchmark_group("tensor-brdf");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    let mut pairs_for = |glinty: &Glinty| -> Vec<([f64; 3], [f64; 3])> {
        // (i, o) pairs whose half vector lies where the footprint's NDF is not zero
        let mut pairs = Vec::new();
        let mut k = 0usize;
        while pairs.len() < 1024 && k < 1 << 20 {
            let i = incident[k % 1024];
            if let Some(s) = glinty.sample(&i, rng.random()) {
                pairs.push((i, s.o));
            }
            k += 1;
        }
        pairs
    };
    let mut micro_pairs = None;
    for rank in [8usize, 16, 32] {
        let Ok(ndf) = table3_ndf(rank) else {
            eprintln!("tensor-brdf: rank {rank} skipped (compression failed)");
            continue;
        };
        let glinty = Glinty {
            ndf: &ndf,
            image: 5,
            alpha_g: 0.1,
            f0: 0.9,
        };
        let pairs = pairs_for(&glinty);
        let mp = micro_pairs.get_or_insert_with(|| pairs.clone()).clone();
        let mut k = 0usize;
        g.bench_with_input(BenchmarkId::new("eval-ours", rank), &rank, |b, _| {
            b.iter(|| {
                k = (k + 1) & 1023;
                let (i, o) = &pairs[k % pairs.len()];
                glinty.eval(black_box(i), black_box(o))
            })
        });
        g.bench_with_input(BenchmarkId::new("sample-ours", rank), &rank, |b, _| {
            b.iter(|| {
                k = (k + 1) & 1023;
                glinty.sample(black_box(&incident[k]), black_box(us[k]))
            })
        });
        if rank == 8 {
            g.bench_function("eval-microfacet", |b| {
                b.iter(|| {
                    k = (k + 1) & 1023;
                    let (i, o) = &mp[k % mp.len()];
                    plain.eval(black_box(i), black_box(o))
                })
            });
            g.bench_function("sample-microfacet", |b| {
                b.iter(|| {
                    k = (k + 1) & 1023;
                    let u = us[k];
                    plain.sample(black_box(&incident[k]), black_box([u[0], u[1]]))
                })
            });
        }
    }
    g.finish();
}

/// The cost of fitting one LTC cell (Nelder–Mead on moving samples and on fixed nodes, and
/// Levenberg–Marquardt on fixed nodes;
/// four parameters, the default preset's 24×24 samples per technique) and of integrating one pixel's quad light
/// with each edge form (f64, clipped to the horizon), next to their errors in
/// results/ltc-ggx.md.
fn ltc(c: &mut Criterion) {
    use ndfbench::ltc::fit::{fit_cell, Method, Metric};
    use ndfbench::ltc::polygon::{ltc_integral, EdgeForm};
    use ndfbench::ltc::target::{GgxTarget, LtcTarget};
    let mut g = c.benchmark_group("ltc-fit-cell");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(2));
    for (label, alpha, theta_deg) in [("a0.25-t45", 0.25f64, 45.0f64), ("a0.01-t80", 0.01, 80.0)] {
        let t = GgxTarget::new(alpha, theta_deg.to_radians()).unwrap();
        let (_, _, _, z) = t.moments(32);
        let (norm, _, _) = t.norm_quad(1e-9);
        let p0 = [alpha.ln(), alpha.ln(), 0.0, 0.0];
        // Nelder–Mead on moving samples (the tables' route) and with the cubic stage's
        // trials on fixed nodes (`Method::FixedNodes`)
        for (name, method) in [
            (label.to_string(), Method::NelderMead),
            (format!("fixed-nodes {label}"), Method::FixedNodes),
        ] {
            g.bench_function(name, |b| {
                b.iter(|| fit_cell(&t, &z, norm, black_box(&p0), 24, Metric::Cubic, method, 400))
            });
        }
        // the fast route: Levenberg–Marquardt on fixed nodes, same start and sample count
        g.bench_function(format!("levenberg-marquardt {label}"), |b| {
            b.iter(|| {
                ndfbench::ltc::gauss_newton::fit_cell_lm(
                    &t,
                    &z,
                    norm,
                    black_box(&p0),
                    24,
                    50,
                    false,
                )
            })
        });
    }
    g.finish();
    ltc_columns(c);
    // one pixel = one quad through one LTC; 256 random (M⁻¹, quad) pairs from the kernel
    // benchmark inputs, time per pixel = time / 256
    let d = ndfbench::kernels::bench_inputs(256);
    let cols = &d.cols;
    let cases: Vec<(nalgebra::Matrix3<f64>, Vec<Vector3<f64>>)> = (0..256)
        .map(|i| {
            let a: Vec<f64> = (15..31).map(|k| cols[k][i] as f64).collect();
            let m = nalgebra::Matrix3::new(a[0], 0.0, a[2], 0.0, 1.0, 0.0, a[1], 0.0, a[3]);
            let quad = (0..4)
                .map(|v| Vector3::new(a[4 + 3 * v], a[5 + 3 * v], a[6 + 3 * v]))
                .collect();
            (m, quad)
        })
        .collect();
    let mut g = c.benchmark_group("ltc-polygon");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(800))
        .throughput(Throughput::Elements(256));
    for (name, form) in [
        ("exact", EdgeForm::Exact),
        ("rational", EdgeForm::Rational),
        ("cubic", EdgeForm::Cubic),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                cases
                    .iter()
                    .map(|(m, q)| ltc_integral(m, black_box(q), form))
                    .sum::<f64>()
            })
        });
    }
    g.finish();
}

/// Seed 002 §5.5: one NDF value at one h of a footprint on the Wang-tiled map (the
/// tensor-wang study's default tiles, per-tile CPs at rank 8): the colour hash and one
/// point query per covered tile, for level-0 footprints inside 1, across 2 and across 4
/// tiles and a level-1 one across 4; against Eq 2 summed over the window's texels of the
/// explicit map at both levels.
fn tensor_wang(c: &mut Criterion) {
    use ndfbench::filters::footprint::{NormalMap, Procedural};
    use ndfbench::tensor::cp::AlsOptions;
    use ndfbench::tensor::pndf::sigma_p;
    use ndfbench::tensor::wang::{
        explicit, Colouring, CompressedTiles, Level, TileImages, TileSet,
    };
    let (side, res, sr) = (32usize, 32usize, 0.02);
    let levels = [4usize, 8].map(|s| Level {
        stride: s,
        sigma_p: sigma_p(s, 0),
    });
    let built = NormalMap::procedural(Procedural::IsotropicNoise, 128, 13).and_then(|ex| {
        let set = TileSet::build(&ex, side, 8, 13)?;
        let images = TileImages::build(&set, &levels, res, sr)?;
        let opts = AlsOptions {
            rank: 8,
            tol: 1e-4,
            max_iters: 200,
            restarts: 2,
            seed: 13,
            nonnegative: false,
        };
        let tiles = CompressedTiles::compress(&images, side.min(16), &opts)?;
        Ok((set, images, tiles))
    });
    let Ok((set, images, tiles)) = built else {
        eprintln!("tensor-wang: skipped (the tiles failed to build)");
        return;
    };
    let colouring = Colouring { seed: 13 };
    let hs: Vec<(f64, f64)> = (0..64)
        .map(|k| {
            (
                -0.3 + 0.6 * (k % 8) as f64 / 7.0,
                -0.3 + 0.6 * (k / 8) as f64 / 7.0,
            )
        })
        .collect();
    let Ok(map) = explicit(&set, &colouring, (0, 0), (2, 2)) else {
        return;
    };
    let mut g = c.benchmark_group("tensor-wang");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    // level 0 (stride 4, a 15² window): inside 1 tile, across 2 and across 4
    for (covered, centre) in [(1usize, (14i64, 14i64)), (2, (30, 14)), (4, (30, 30))] {
        let mut k = 0usize;
        g.bench_with_input(
            BenchmarkId::new("tiles-rank8", covered),
            &covered,
            |b, _| {
                b.iter(|| {
                    k = (k + 1) & 63;
                    let cells = images.cover(0, black_box(centre)).unwrap_or_default();
                    tiles.d(&colouring, 0, &cells, hs[k].0, hs[k].1)
                })
            },
        );
    }
    // level 1 (stride 8, a 29² window), across 4 tiles
    let mut k = 0usize;
    g.bench_with_input(BenchmarkId::new("tiles-rank8-stride8", 4), &4, |b, _| {
        b.iter(|| {
            k = (k + 1) & 63;
            let cells = images.cover(1, black_box((28, 28))).unwrap_or_default();
            tiles.d(&colouring, 1, &cells, hs[k].0, hs[k].1)
        })
    });
    // Eq 2 at one h over the window's texels of the explicit map, same footprints
    for (name, level, centre) in [
        ("explicit-brute-force", 0usize, (30i64, 30i64)),
        ("explicit-brute-force-stride8", 1, (28, 28)),
    ] {
        let (sp, reach) = (
            levels[level].sigma_p,
            (4.0 * levels[level].sigma_p).ceil() as i64,
        );
        let mut k = 0usize;
        g.bench_with_input(BenchmarkId::new(name, 4), &4, |b, _| {
            b.iter(|| {
                k = (k + 1) & 63;
                let (hx, hy) = hs[k];
                let (cx, cy) = black_box(centre);
                let (mut num, mut wsum) = (0.0, 0.0);
                for y in cy - reach..=cy + reach {
                    for x in cx - reach..=cx + reach {
                        let (ux, uy) = (x as f64 + 0.5 - cx as f64, y as f64 + 0.5 - cy as f64);
                        let gp = (-(ux * ux + uy * uy) / (2.0 * sp * sp)).exp();
                        let n = map.normals[y as usize * map.width + x as usize];
                        let e = ((n.x - hx).powi(2) + (n.y - hy).powi(2)) / (2.0 * sr * sr);
                        num += gp * (-e).exp();
                        wsum += gp;
                    }
                }
                num / (wsum * 2.0 * std::f64::consts::PI * sr * sr)
            })
        });
    }
    g.finish();
}

/// Seed 002 Table 2's wave row, per unit of work: one CP-ALS sweep of the tensor-wave
/// study's RGB tensor shape (16 × 16 × 768 slices, R = 16; one call with its start), and
/// one coherence window of Eq 3 (FFT of the windowed phase, binned to a 64² image) at the
/// study's σ_c = 2 µm (256² patch) and at σ_c = 8 µm, inside the paper's 5–10 µm (1024²).
/// bench-report projects Table 2's minutes from them (performance.md).
fn tensor_wave(c: &mut Criterion) {
    use ndfbench::tensor::cp::{cp_als, AlsOptions, Tensor3};
    use ndfbench::tensor::wave::{bin, gndf_fft, sampled_for, Waves, WAVELENGTHS};
    let (t, slices) = (16usize, 768usize);
    let data: Vec<f64> = (0..t * t * slices)
        .map(|k| ((k as f64 * 0.618_033_988_7).fract() - 0.3).max(0.0))
        .collect();
    let Ok(tensor) = Tensor3::new([t, t, slices], data) else {
        eprintln!("tensor-wave: skipped (the tensor failed to build)");
        return;
    };
    let mut g = c.benchmark_group("tensor-wave");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(3));
    let opts = AlsOptions {
        rank: 16,
        tol: 0.0,
        max_iters: 1,
        restarts: 1,
        seed: 11,
        nonnegative: false,
    };
    g.bench_function(BenchmarkId::new("cp-als sweep, R = 16", "16x16x768"), |b| {
        b.iter(|| cp_als(black_box(&tensor), &opts).map(|cp| cp.rel_error))
    });
    // the study's 32 µm tile at σ_c = 2 µm; a 64 µm tile at 8 µm, whose 1024² patch must
    // fit in the sampled field
    for (sigma_c, period) in [(2.0f64, 32.0), (8.0, 64.0)] {
        let Ok((hf, m)) = Waves::new(128, 16, period, 0.15, 12)
            .and_then(|noise| sampled_for(&noise, WAVELENGTHS[0], sigma_c))
        else {
            continue;
        };
        let one = || {
            gndf_fft(&hf, black_box((8.0, 8.0)), sigma_c, WAVELENGTHS[3], m)
                .and_then(|gn| bin(&gn, 64))
                .map(|img| img[0])
        };
        if let Err(e) = one() {
            eprintln!("tensor-wave: window at σ_c = {sigma_c} skipped ({e})");
            continue;
        }
        g.bench_function(
            BenchmarkId::new("window: Eq 3 FFT + 64² binning", m),
            |b| b.iter(one),
        );
    }
    g.finish();
}

/// One θ column of the 64² GGX table per fitting route, as the table fits it
/// (`ltc::fit::fit_column`: each cell warm-started from its rougher neighbour, with its
/// moments, albedo, cubic stage, L2 polish and rounded storage; 24² samples, ≤ 400
/// iterations per stage): the cost per cell of each route the work study judges. The
/// parameter is the column's cell count; the table's bilinear pass is not in it.
fn ltc_columns(c: &mut Criterion) {
    use ndfbench::ltc::fit::{fit_column, Grid, Method, Metric, Polish, TRAIN_OFFSET};
    use ndfbench::ltc::target::GgxTarget;
    let grid = Grid {
        n: 64,
        alpha_min: 1e-5,
    };
    let mut g = c.benchmark_group("ltc-fit-column");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(5));
    // t = √(1 − cos θ) = j/63: θ ≈ 42° and ≈ 85°
    for j in [32usize, 60] {
        let deg = grid.theta(j).to_degrees().round();
        for (route, method) in [
            ("reference (moving samples)", Method::NelderMead),
            ("fixed nodes, cubic stage", Method::FixedNodes),
            ("fixed nodes, every stage", Method::FixedNodesAll),
        ] {
            let plan = (Metric::Cubic, method, 400, Polish::NelderMead);
            g.bench_with_input(
                BenchmarkId::new(format!("{route}, θ {deg}°"), grid.n),
                &j,
                |b, &j| {
                    b.iter(|| {
                        fit_column(grid, j, &GgxTarget::new, 24, plan, TRAIN_OFFSET, &|| {})
                            .unwrap()
                    })
                },
            );
        }
    }
    g.finish();
}

criterion_group!(
    benches,
    ltc,
    tensor,
    tensor_brdf,
    tensor_wang,
    tensor_wave,
    kernels,
    filters,
    engines,
    rayon_scaling,
    shading_forms,
    alpha_me,
    smith_lambda,
    leadr
);
criterion_main!(benches);

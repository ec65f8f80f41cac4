//! Seed 002 §5.4 (`tensor::envsg`): spherical Gaussians against their closed forms, Eq 8's
//! support, the range-query box mean against point queries, the point estimator against
//! the quadrature truth, and typed errors.

mod common;

use nalgebra::Vector3;
use ndfbench::filters::footprint::{NormalMap, Procedural};
use ndfbench::tensor::brdf::CompressedNdf;
use ndfbench::tensor::cluster::stack_blocks;
use ndfbench::tensor::cp::AlsOptions;
use ndfbench::tensor::envsg::{fit, query_side, Env, Read, Sg, SgEnv, Shading};
use ndfbench::tensor::pndf::{pndf_image, sigma_p};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use std::sync::OnceLock;

fn ndf() -> &'static CompressedNdf {
    static N: OnceLock<CompressedNdf> = OnceLock::new();
    N.get_or_init(|| {
        let map = NormalMap::procedural(Procedural::Flakes, 64, 2).unwrap();
        let imgs: Vec<Vec<f64>> = [0, 1]
            .iter()
            .map(|&l| pndf_image(&map, 32.0, 32.0, sigma_p(8, l), 0.03, 32).unwrap())
            .collect();
        let refs: Vec<&[f64]> = imgs.iter().map(|v| v.as_slice()).collect();
        let stack = stack_blocks(&refs, 32, 8).unwrap().unwrap();
        let o = AlsOptions {
            rank: 8,
            tol: 1e-6,
            max_iters: 200,
            restarts: 1,
            seed: 1,
            nonnegative: true,
        };
        CompressedNdf::compress(&stack, 32, &o).unwrap()
    })
}

fn axis() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0f64..1.0, 0.0f64..std::f64::consts::TAU).prop_map(|(z, p)| {
        let r = (1.0 - z * z).sqrt();
        Vector3::new(r * p.cos(), r * p.sin(), z)
    })
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// Eq 8: the SG equals ε at θ from its axis and exceeds it inside, for A from 1e-3
    /// to 1e3 and λ from 1e-2 to 1e4 (θ = 0 when A ≤ ε, π when all of the sphere exceeds ε).
    #[test]
    fn compact_support_is_where_the_sg_meets_eps(
        mu in axis(), la in -2.0f64..4.0, aa in -3.0f64..3.0, eps in 1e-4f64..0.99, f in 0.0f64..1.0,
    ) {
        let (lambda, amp) = (10f64.powf(la), 10f64.powf(aa));
        let g = Sg::new(mu, lambda, amp).unwrap();
        let th = g.support(eps);
        prop_assert!((0.0..=std::f64::consts::PI).contains(&th));
        let t = if mu.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
        let b = t.cross(&mu).normalize();
        let at = |a: f64| mu * a.cos() + b * a.sin();
        if amp <= eps {
            prop_assert_eq!(th, 0.0);
        } else if th < std::f64::consts::PI {
            prop_assert!((g.eval(&at(th)) / eps - 1.0).abs() < 1e-6, "G(θ) = {} for ε {eps}", g.eval(&at(th)));
            prop_assert!(g.eval(&at(f * th)) >= eps * (1.0 - 1e-9));
        } else {
            prop_assert!(g.eval(&(-mu)) >= eps * (1.0 - 1e-9));
        }
    }

    /// The box mean by range queries equals the mean of the point queries over the same
    /// pixels (clipped to the image), for boxes anywhere, borders and outside included
    /// (non-negative CP, so neither read clamps).
    #[test]
    fn box_mean_is_the_mean_of_point_queries(
        image in 0usize..2, x0 in -8i64..36, y0 in -8i64..36, w in 0i64..40, h in 0i64..40,
    ) {
        let n = ndf();
        let (x1, y1) = (x0 + w, y0 + h);
        let got = n.box_mean(image, (x0, x1), (y0, y1));
        let (cx0, cx1, cy0, cy1) = (x0.max(0), x1.min(31), y0.max(0), y1.min(31));
        if cx0 > cx1 || cy0 > cy1 {
            prop_assert!(got.is_none());
        } else {
            let c = |p: i64| -1.0 + (p as f64 + 0.5) / 16.0;
            let mut s = 0.0;
            for y in cy0..=cy1 {
                for x in cx0..=cx1 {
                    // the point query clamps each pixel at 0; the range query the box
                    s += n.d(image, c(x), c(y));
                }
            }
            let mean = s / ((cx1 - cx0 + 1) * (cy1 - cy0 + 1)) as f64;
            let peak = (0..1024).map(|q| n.d(image, c(q % 32), c(q / 32))).fold(0.0, f64::max);
            // non-negative factors: no clamp acts, and the range sums (SAT differences) equal
            // the pixels' sums to rounding
            prop_assert!((got.unwrap() - mean).abs() <= 1e-9 * peak, "{} vs {mean}", got.unwrap());
        }
    }
}

/// vMF sampling against its closed-form mean cosine coth λ − 1/λ and the density's
/// integral against a sphere quadrature, λ from 0.1 to 1e4.
#[test]
fn von_mises_fisher_matches_its_closed_forms() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
    let mu = Vector3::new(0.3, -0.5, 0.81).normalize();
    for lambda in [0.1, 1.0, 10.0, 100.0, 1e4] {
        let g = Sg::new(mu, lambda, 2.0).unwrap();
        let n: usize = 1 << 16;
        let v: Vec<f64> = (0..n).map(|_| g.sample(rng.random()).dot(&mu)).collect();
        let m = v.iter().sum::<f64>() / n as f64;
        let se = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n * (n - 1)) as f64).sqrt();
        let expected = 1.0 / lambda.tanh() - 1.0 / lambda;
        assert!(
            (m - expected).abs() <= 5.0 * se + 1e-12,
            "λ {lambda}: {m} vs {expected} ± {se}"
        );
    }
    // ∫ G dω and ∫ pdf dω by the midpoint rule over a fine equirectangular grid
    let env = Env::procedural(2048, 1024, 0.0).unwrap();
    for lambda in [0.5, 4.0, 40.0] {
        let g = Sg::new(mu, lambda, 3.0).unwrap();
        let (mut i, mut p) = (0.0, 0.0);
        for y in 0..1024 {
            for x in 0..2048 {
                let (d, w) = env.texel(x, y);
                i += w * g.eval(&d);
                p += w * g.pdf(&d);
            }
        }
        assert!(
            (i / g.integral() - 1.0).abs() < 1e-4,
            "λ {lambda}: {i} vs {}",
            g.integral()
        );
        assert!((p - 1.0).abs() < 1e-4, "λ {lambda}: ∫pdf = {p}");
    }
}

/// The point-query estimator is unbiased: its mean over 2^16 draws agrees with the
/// midpoint-rule truth within 4 s.e. (plus the rule's bar), for one SG and a mixture.
#[test]
fn the_point_estimator_agrees_with_the_quadrature() {
    let n = ndf();
    let o = Vector3::new(0.5f64.sin(), 0.0, 0.5f64.cos());
    let mirror = Vector3::new(-o.x, -o.y, o.z);
    let envs = [
        SgEnv {
            lobes: vec![Sg::new(mirror, 20.0, 1.0).unwrap()],
        },
        SgEnv {
            lobes: vec![
                Sg::new(mirror, 200.0, 5.0).unwrap(),
                Sg::new(Vector3::new(0.0, 0.3, 1.0), 2.0, 0.7).unwrap(),
            ],
        },
    ];
    for (k, env) in envs.iter().enumerate() {
        for image in 0..2 {
            let sh = Shading { ndf: n, image, o };
            let (r8, r16) = (sh.reference(env, 8), sh.reference(env, 16));
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(k as u64 * 7 + image as u64);
            let v: Vec<f64> = (0..1 << 16)
                .map(|_| sh.sample(env, Read::Point, rng.random()).unwrap())
                .collect();
            let m = v.iter().sum::<f64>() / v.len() as f64;
            let se = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>()
                / (v.len() * (v.len() - 1)) as f64)
                .sqrt();
            assert!(
                (m - r16).abs() <= 4.0 * se + (r16 - r8).abs(),
                "env {k}, image {image}: {m} ± {se} vs {r16}"
            );
            // a prefiltered read of a one-pixel square is the point read
            let tiny = sh
                .sample(
                    env,
                    Read::Prefiltered {
                        eps: 0.99,
                        scale: 1e-6,
                    },
                    [0.3, 0.4, 0.5],
                )
                .unwrap();
            let point = sh.sample(env, Read::Point, [0.3, 0.4, 0.5]).unwrap();
            assert!(
                (tiny - point).abs() <= 1e-9 * point.abs(),
                "{tiny} vs {point}"
            );
        }
    }
}

/// The SG fit of the procedural sky puts a lobe on the sun and lowers the error with
/// every lobe; bad arguments are typed errors.
#[test]
fn the_fit_finds_the_sun_and_bad_input_is_an_error() {
    let env = Env::procedural(128, 64, 20.0).unwrap();
    let sun = Vector3::new(
        40f64.to_radians().sin() * 30f64.to_radians().cos(),
        40f64.to_radians().sin() * 30f64.to_radians().sin(),
        40f64.to_radians().cos(),
    );
    let mut last = f64::INFINITY;
    for k in 1..=4 {
        let f = fit(&env, k, 16, &[2.0, 32.0, 512.0]).unwrap();
        let e = env.rel_error(&f);
        assert!(e < last, "{k} lobes: {e} not below {last}");
        last = e;
        if k >= 2 {
            let on_sun = f.lobes.iter().any(|a| {
                a.lambda >= 512.0 && Vector3::from(a.axis).dot(&sun) > 2f64.to_radians().cos()
            });
            assert!(on_sun, "{k} lobes: none narrow on the sun: {:?}", f.lobes);
        }
    }
    assert!(Sg::new(Vector3::zeros(), 1.0, 1.0).is_err());
    assert!(Sg::new(Vector3::z(), 0.0, 1.0).is_err());
    assert!(Sg::new(Vector3::z(), f64::NAN, 1.0).is_err());
    assert!(Sg::new(Vector3::z(), 1.0, -1.0).is_err());
    assert!(Env::procedural(2, 2, 1.0).is_err());
    assert!(Env::procedural(64, 32, f64::NAN).is_err());
    assert!(fit(&env, 0, 16, &[1.0]).is_err());
    assert!(fit(&env, 2, 16, &[]).is_err());
    let dark = Env::procedural(64, 32, 0.0).map(|mut e| {
        e.radiance.iter_mut().for_each(|v| *v = 0.0);
        e
    });
    assert!(fit(&dark.unwrap(), 2, 16, &[1.0]).is_err());
    assert!(SgEnv { lobes: vec![] }.sample([0.1, 0.2, 0.3]).is_err());
    assert!(ndf().box_mean(5, (0, 3), (0, 3)).is_none());
    // Eq 9's side: at least one pixel, at most 2·res, whatever θ and scale
    assert_eq!(query_side(f64::NAN, 32, 0.5), 1);
    assert_eq!(query_side(std::f64::consts::PI, 32, 1e300), 64);
    assert_eq!(query_side(std::f64::consts::FRAC_PI_4, 32, 0.5), 8);
}

/// A user's equirectangular PNG: 8-bit values decode through the sRGB curve of IEC
/// 61966-2-1 (128 → 0.2158605…, by hand from the standard's formula) weighted by Rec. 709's
/// luminance, row 0 at the zenith; a 16-bit encoding of the procedural sky reads back to
/// its radiance within the quantisation; the 2×2 average is the mean of its blocks.
#[test]
fn an_equirectangular_png_reads_as_radiance() {
    let d = common::scratch("tensor_envsg", "png-env");
    // 8-bit: a red top row, grey 128 elsewhere
    let img = image::RgbImage::from_fn(16, 8, |_, y| {
        if y == 0 {
            image::Rgb([255, 0, 0])
        } else {
            image::Rgb([128, 128, 128])
        }
    });
    let p8 = d.join("grey.png");
    img.save(&p8).unwrap();
    let env = Env::from_png(&p8, 3.0).unwrap();
    assert_eq!((env.width, env.height), (16, 8));
    let grey = 0.215_860_500_113_899_26;
    assert!((env.radiance[16 * 5 + 3] - 3.0 * grey).abs() < 1e-12);
    assert!((env.radiance[7] - 3.0 * 0.2126).abs() < 1e-12);
    let (top, _) = env.texel(7, 0);
    assert!(top.z > 0.9, "row 0 is at the zenith: {top:?}");
    let half = env.halved().unwrap();
    assert_eq!((half.width, half.height), (8, 4));
    assert!((half.radiance[2] - 3.0 * (0.2126 + grey) / 2.0).abs() < 1e-12);
    assert!((half.radiance[8 + 2] - 3.0 * grey).abs() < 1e-12);
    // 16-bit: the procedural sky over its peak, sRGB-encoded here
    let sky = Env::procedural(64, 32, 20.0).unwrap();
    let peak = sky.radiance.iter().cloned().fold(0.0, f64::max);
    let encode = |l: f64| {
        let c = if l <= 0.0031308 {
            12.92 * l
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        };
        (c * 65535.0).round() as u16
    };
    let img16 = image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(64, 32, |x, y| {
        let v = encode(sky.radiance[(y * 64 + x) as usize] / peak);
        image::Rgb([v, v, v])
    });
    let p16 = d.join("sky.png");
    img16.save(&p16).unwrap();
    let back = Env::from_png(&p16, peak).unwrap();
    for (a, b) in back.radiance.iter().zip(&sky.radiance) {
        assert!((a - b).abs() <= 2e-4 * b.max(0.05 * peak), "{a} vs {b}");
    }
    // typed errors: a missing file, a broken one, a bad scale, a map too small to halve
    std::fs::write(d.join("broken.png"), b"\x89PNG\r\n\x1a\nnothing").unwrap();
    for (p, s) in [
        (d.join("missing.png"), 1.0),
        (d.join("broken.png"), 1.0),
        (p8.clone(), 0.0),
        (p8.clone(), f64::NAN),
        (p8.clone(), f64::INFINITY),
    ] {
        assert!(Env::from_png(&p, s).is_err(), "{} at {s}", p.display());
    }
    let tiny = image::RgbImage::from_pixel(4, 2, image::Rgb([9, 9, 9]));
    tiny.save(d.join("tiny.png")).unwrap();
    let t = Env::from_png(&d.join("tiny.png"), 1.0).unwrap();
    assert!(t.halved().is_err());
    let _ = std::fs::remove_dir_all(&d);
}

/// The study fits a user's PNG instead of the procedural sky when `environment` names one,
/// and says so; a name that is neither is a typed error naming the key.
#[test]
fn the_study_fits_a_png_environment() {
    use ndfbench::fit::spec::FitSpec;
    use std::path::Path;
    let d = common::scratch("tensor_envsg", "png-study");
    let sky = Env::procedural(64, 32, 20.0).unwrap();
    let img = image::ImageBuffer::<image::Luma<u16>, _>::from_fn(64, 32, |x, y| {
        let l = sky.radiance[(y * 64 + x) as usize] / 20.6;
        image::Luma([((1.055 * l.powf(1.0 / 2.4) - 0.055).clamp(0.0, 1.0) * 65535.0) as u16])
    });
    let png = d.join("sky.png");
    img.save(&png).unwrap();
    let text = std::fs::read_to_string("fits/tensor-envsg.toml").unwrap();
    let from = "environment = \"procedural\"";
    assert!(text.contains(from));
    let with = |e: &str| {
        FitSpec::parse(
            &text.replacen(from, &format!("environment = {e:?}"), 1),
            "tensor-envsg",
        )
        .unwrap()
    };
    let quick = ndfbench::integrate::Preset::Quick;
    let c =
        common::compute_study(&with(png.to_str().unwrap()), Path::new("results"), quick).unwrap();
    let mut set = ndfbench::io::Outputs::new();
    c.render(&mut set, &d).unwrap();
    let out: serde_json::Value =
        serde_json::from_slice(set.get(&d.join("fits/tensor-envsg.json")).unwrap()).unwrap();
    let fit = &out["fit"];
    assert!(fit["environment"].as_str().unwrap().contains("sky.png"));
    assert_eq!(fit["resolutions"][0][0], 64);
    assert_eq!(fit["resolutions"][1][0], 32);
    let e = fit["rel_error"][0].as_f64().unwrap();
    assert!(e > 0.0 && e < 1.0, "{e}");
    match common::compute_study(&with("no-such-sky.png"), Path::new("results"), quick) {
        Err(e) => assert!(e.to_string().contains("environment"), "{e}"),
        Ok(_) => panic!("a missing environment was accepted"),
    }
    let _ = std::fs::remove_dir_all(&d);
}

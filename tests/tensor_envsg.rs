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

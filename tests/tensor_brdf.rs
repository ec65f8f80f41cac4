//! Seed 002's glinty BRDF (D from a compressed P-NDF, Fig 8 sampling) and the plain GGX
//! microfacet BRDF it is timed against (Table 3): both read back what they were built
//! from, and both samplers' weights are unbiased estimates of the albedo ∫ f o_z dω,
//! checked against a deterministic quadrature at two resolutions.

use ndfbench::tensor::brdf::{
    table3_images, table3_ndf, table3_options, CompressedNdf, Glinty, Microfacet, TABLE3_RES,
    TABLE3_T, V3,
};
use ndfbench::tensor::cluster::stack_blocks;
use ndfbench::tensor::cp::rel_error;
use rand::{Rng, SeedableRng};

fn dir(theta_deg: f64, phi: f64) -> V3 {
    let t = theta_deg.to_radians();
    [t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos()]
}

/// ∫ f(i, o) o_z dω_o by the change of variable o ↔ h (dω_o = 4 (i·h) dω_h) in polar
/// (θ_h, φ_h), midpoint rule with n × 4n nodes.
fn albedo_quadrature(f: &dyn Fn(&V3, &V3) -> f64, i: &V3, n: usize) -> f64 {
    let (dt, dp) = (
        std::f64::consts::FRAC_PI_2 / n as f64,
        std::f64::consts::TAU / (4 * n) as f64,
    );
    let mut s = 0.0;
    for a in 0..n {
        let th = (a as f64 + 0.5) * dt;
        for b in 0..4 * n {
            let ph = (b as f64 + 0.5) * dp;
            let h = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
            let c = i[0] * h[0] + i[1] * h[1] + i[2] * h[2];
            if c <= 0.0 {
                continue;
            }
            let o = [
                2.0 * c * h[0] - i[0],
                2.0 * c * h[1] - i[1],
                2.0 * c * h[2] - i[2],
            ];
            if o[2] <= 0.0 {
                continue;
            }
            s += f(i, &o) * o[2] * 4.0 * c * th.sin() * dt * dp;
        }
    }
    s
}

/// Mean weight and its standard error over n samples (a failed sample weighs 0).
fn mc(
    sample: &dyn Fn(&mut rand_chacha::ChaCha8Rng) -> Option<f64>,
    n: usize,
    seed: u64,
) -> (f64, f64) {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let (mut s, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let w = sample(&mut rng).unwrap_or(0.0);
        assert!(w.is_finite() && w >= 0.0, "weight {w}");
        s += w;
        s2 += w * w;
    }
    let m = s / n as f64;
    (m, ((s2 / n as f64 - m * m) / (n as f64 - 1.0)).sqrt())
}

#[test]
fn the_compressed_ndf_reads_each_image_back_through_its_blocks() {
    // Σ over every image and pixel of (D at the pixel centre − the image)² must be the
    // CP's squared error ‖T − T̂‖² over the stacked blocks (all-zero blocks read 0), which
    // `rel_error` sums entry by entry from the tensor itself.
    let images = table3_images().unwrap();
    let refs: Vec<&[f64]> = images.iter().map(|v| v.as_slice()).collect();
    let stack = stack_blocks(&refs, TABLE3_RES, TABLE3_T).unwrap().unwrap();
    let dropped = stack.slots.iter().flatten().filter(|s| s.is_none()).count();
    assert!(dropped > 0, "the test wants all-zero blocks too");
    let ndf = CompressedNdf::compress(&stack, TABLE3_RES, &table3_options(8)).unwrap();
    let cell = 2.0 / TABLE3_RES as f64;
    let mut sq = 0.0;
    for (k, img) in images.iter().enumerate() {
        for j in 0..TABLE3_RES {
            for i in 0..TABLE3_RES {
                let (hx, hy) = (
                    -1.0 + (i as f64 + 0.5) * cell,
                    -1.0 + (j as f64 + 0.5) * cell,
                );
                sq += (ndf.d(k, hx, hy) - img[j * TABLE3_RES + i]).powi(2);
            }
        }
    }
    let e = rel_error(&stack.tensor, ndf.cp()) * stack.tensor.norm();
    assert!(
        (sq.sqrt() - e).abs() <= 1e-9 * e,
        "read back {:.12e}, tensor error {e:.12e}",
        sq.sqrt()
    );
    // outside the image, past the last image, and a malformed stack
    assert_eq!(ndf.d(0, 1.0, 0.0), 0.0);
    assert_eq!(ndf.d(images.len(), 0.0, 0.0), 0.0);
    assert!(CompressedNdf::compress(&stack, TABLE3_RES * 2, &table3_options(8)).is_err());
    assert!(stack_blocks(&refs, TABLE3_RES, 7).is_err());
}

#[test]
fn glinty_sampling_is_an_unbiased_estimate_of_the_albedo() {
    let ndf = table3_ndf(8).unwrap();
    for (image, theta) in [(0usize, 0.0), (5, 35.0), (10, 70.0)] {
        let g = Glinty {
            ndf: &ndf,
            image,
            alpha_g: 0.1,
            f0: 0.9,
        };
        let i = dir(theta, 0.7);
        let f = |i: &V3, o: &V3| g.eval(i, o);
        let (q1, q2) = (
            albedo_quadrature(&f, &i, 1000),
            albedo_quadrature(&f, &i, 2000),
        );
        let (m, se) = mc(
            &|r| g.sample(&i, r.random()).map(|s| s.weight),
            200_000,
            7 + image as u64,
        );
        assert!(q2 > 0.05, "albedo {q2}");
        assert!(
            (m - q2).abs() <= 4.0 * se + (q2 - q1).abs(),
            "image {image}, θ {theta}: MC {m} ± {se}, quadrature {q2} (coarse {q1})"
        );
        // each weight is f·o_z over the density `pdf` gives for its direction
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let (mut agree, mut n) = (0, 0);
        for _ in 0..2000 {
            if let Some(s) = g.sample(&i, rng.random()) {
                n += 1;
                let w = g.eval(&i, &s.o) * s.o[2] / g.pdf(&i, &s.o);
                agree += usize::from((w - s.weight).abs() <= 1e-9 * s.weight);
            }
        }
        // a half vector on a pixel edge may round into the neighbour: a few per mille
        assert!(
            n > 500 && agree * 1000 >= n * 995,
            "θ {theta}: {agree} of {n} agree"
        );
    }
}

#[test]
fn microfacet_visible_normal_sampling_is_an_unbiased_estimate_of_the_albedo() {
    for (alpha, theta) in [(0.1, 10.0), (0.3, 45.0), (0.6, 80.0)] {
        let b = Microfacet { alpha, f0: 0.9 };
        let i = dir(theta, 1.9);
        let f = |i: &V3, o: &V3| b.eval(i, o);
        let (q1, q2) = (
            albedo_quadrature(&f, &i, 1000),
            albedo_quadrature(&f, &i, 2000),
        );
        let (m, se) = mc(&|r| b.sample(&i, r.random()).map(|s| s.weight), 200_000, 11);
        assert!(
            (m - q2).abs() <= 4.0 * se + (q2 - q1).abs(),
            "α {alpha}, θ {theta}: MC {m} ± {se}, quadrature {q2} (coarse {q1})"
        );
        // the closed-form weight F·G2/G1 (Heitz 2018) is f·o_z/pdf
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for _ in 0..2000 {
            if let Some(s) = b.sample(&i, rng.random()) {
                let w = b.eval(&i, &s.o) * s.o[2] / b.pdf(&i, &s.o);
                assert!((w - s.weight).abs() <= 1e-9 * w, "{w} vs {}", s.weight);
            }
        }
    }
}

#[test]
fn the_extremes_give_finite_consistent_weights() {
    // α = 1e-4 and 89.99° for the plain BRDF; 89.99° and a grazing 88° for ours
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
    for (alpha, theta) in [(1e-4, 0.0), (1e-4, 89.99), (1.0, 89.99), (0.5, 60.0)] {
        let b = Microfacet { alpha, f0: 0.04 };
        let i = dir(theta, 0.3);
        for _ in 0..10_000 {
            if let Some(s) = b.sample(&i, rng.random()) {
                assert!(s.weight.is_finite() && s.weight >= 0.0 && s.o[2] > 0.0);
                let w = b.eval(&i, &s.o) * s.o[2] / b.pdf(&i, &s.o);
                assert!(
                    (w - s.weight).abs() <= 1e-6 * w.max(1e-300),
                    "α {alpha}, θ {theta}: {w} vs {}",
                    s.weight
                );
            }
        }
        // below the horizon: zero, never NaN
        assert_eq!(b.eval(&dir(91.0, 0.0), &i), 0.0);
        assert_eq!(b.eval(&i, &[0.0, 0.0, -1.0]), 0.0);
    }
    let ndf = table3_ndf(8).unwrap();
    for theta in [88.0, 89.99] {
        let g = Glinty {
            ndf: &ndf,
            image: 3,
            alpha_g: 0.1,
            f0: 0.9,
        };
        let i = dir(theta, 2.0);
        for _ in 0..10_000 {
            if let Some(s) = g.sample(&i, rng.random()) {
                assert!(
                    s.weight.is_finite() && s.weight >= 0.0 && s.o[2] > 0.0,
                    "θ {theta}: {s:?}"
                );
            }
        }
    }
    // an image index past the stack samples nothing and reads zero
    let g = Glinty {
        ndf: &ndf,
        image: ndf.images(),
        alpha_g: 0.1,
        f0: 0.9,
    };
    assert!(g.sample(&dir(30.0, 0.0), [0.5; 4]).is_none());
    assert_eq!(g.eval(&dir(30.0, 0.0), &dir(30.0, 3.14)), 0.0);
}

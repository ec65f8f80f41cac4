//! The survey's representations (seed 004 §3.2): closed forms they must reduce to, their
//! normalisation by an independent quadrature, the SH basis and zonal coefficients
//! against published values, EM's pitfalls, and finiteness over the extremes.

mod common;

use nalgebra::Vector3;
use ndfbench::integrate::quad::gauss_legendre;
use ndfbench::microfacet::NdfKind;
use ndfbench::survey::em::{
    inverse_langevin, langevin, merge_slopes, merge_vmf, vmf_log_norm, SlopeMixture, VmfMixture,
    KAPPA_MAX,
};
use ndfbench::survey::fournier::{fit, Target};
use ndfbench::survey::sh::{
    coefficients_needed, index, sh_basis, zonal_coefficients, HanSh, VmfConvolved, Zonal,
};
use ndfbench::survey::single::{OlanoNorth, SggxLobe, SlopeGaussian};
use ndfbench::survey::{BaseLobe, ExactPdf, NormalPdf, Shading, Texels};
use proptest::prelude::*;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

fn dir(theta: f64, phi: f64) -> V3 {
    V3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// ∫ f over the sphere by a Gauss–Legendre product in (cos θ, φ) about z, split at the
/// equator and refined near the pole (an independent rule from `survey::sphere_integral`).
fn sphere_gl(f: &dyn Fn(&V3) -> f64, n: usize) -> f64 {
    let (x, w) = gauss_legendre(n);
    let mut s = 0.0;
    // θ pieces: [0, 0.3], [0.3, 1], [1, π/2], [π/2, π]
    let br = [0.0, 0.3, 1.0, PI / 2.0, PI];
    for seg in br.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        for (xi, wi) in x.iter().zip(&w) {
            let th = 0.5 * (a + b) + 0.5 * (b - a) * xi;
            let np = 2 * n;
            let mut ring = 0.0;
            for k in 0..np {
                ring += f(&dir(th, 2.0 * PI * (k as f64 + 0.5) / np as f64));
            }
            s += 0.5 * (b - a) * wi * th.sin() * ring * 2.0 * PI / np as f64;
        }
    }
    s
}

fn footprint(tilts: &[(f64, f64)]) -> Vec<V3> {
    tilts.iter().map(|&(t, p)| dir(t, p)).collect()
}

#[test]
fn base_lobe_is_a_density_with_its_moments() {
    for kind in [NdfKind::Ggx, NdfKind::Beckmann] {
        for alpha in [0.1, 0.3, 1.0] {
            let b = BaseLobe { kind, alpha };
            let z = sphere_gl(&|d| b.q(d.z), 96);
            assert!((z - 1.0).abs() < 2e-4, "{kind:?} α {alpha}: ∫q = {z}");
            let m = b.moments();
            let c1 = sphere_gl(&|d| b.q(d.z) * d.z, 96);
            let c2 = sphere_gl(&|d| b.q(d.z) * d.z * d.z, 96);
            assert!(
                (m[0] - c1).abs() < 2e-4 && (m[1] - c2).abs() < 2e-4,
                "{m:?} vs {c1} {c2}"
            );
            assert!((m[2] - 0.5 * (1.0 - m[1])).abs() < 1e-12);
        }
    }
}

#[test]
fn single_texel_representations_reduce_to_the_base_lobe() {
    // one texel: SGGX of S = α²I + (1 − α²)nnᵀ is exactly GGX about n; Schilling's and Olano
    // & Baker's slope Gaussians (variance α²/2) and one of Tan's lobes are exactly Beckmann
    let n = [dir(0.3, 0.7)];
    let w = [1.0];
    for alpha in [1e-3, 0.05, 0.4] {
        let ggx = Texels {
            normals: &n,
            weights: &w,
            base: BaseLobe {
                kind: NdfKind::Ggx,
                alpha,
            },
        };
        let bk = Texels {
            normals: &n,
            weights: &w,
            base: BaseLobe {
                kind: NdfKind::Beckmann,
                alpha,
            },
        };
        let (eg, eb) = (ExactPdf::new(&ggx), ExactPdf::new(&bk));
        let sggx = SggxLobe::new(&ggx).unwrap();
        let sch = SlopeGaussian::schilling(&bk).unwrap();
        let flat = [V3::z()];
        let bz = Texels {
            normals: &flat,
            weights: &w,
            base: BaseLobe {
                kind: NdfKind::Beckmann,
                alpha,
            },
        };
        let ob = SlopeGaussian::olano_baker(&bz).unwrap();
        let tan = SlopeMixture::fit(&flat, &w, 1, alpha).unwrap();
        let ez = ExactPdf::new(&bz);
        for k in 0..200 {
            let th = alpha * 3.0 * (k as f64 / 200.0);
            let h = ndfbench::microfacet::lobe::Frame::around(n[0]).world(&dir(th, 0.1 * k as f64));
            let rel = |a: f64, b: f64| ((a - b) / b.max(1e-300)).abs();
            // S has condition number 1/α²: its inverse carries ~1e-16/α² of rounding
            let tol = 1e-13 / (alpha * alpha);
            assert!(
                rel(sggx.pdf(&h), eg.pdf(&h)) < tol,
                "SGGX α {alpha}: {} vs {}",
                sggx.pdf(&h),
                eg.pdf(&h)
            );
            assert!(rel(sch.pdf(&h), eb.pdf(&h)) < 1e-9, "Schilling α {alpha}");
            let hz = dir(th, 0.1 * k as f64);
            assert!(
                rel(ob.pdf(&hz), ez.pdf(&hz)) < 1e-9,
                "Olano–Baker α {alpha}"
            );
            assert!(rel(tan.pdf(&hz), ez.pdf(&hz)) < 1e-6, "Tan α {alpha}");
        }
    }
}

#[test]
fn representations_integrate_to_one() {
    let n = footprint(&[
        (0.0, 0.0),
        (0.35, 0.2),
        (0.3, 2.5),
        (0.5, 4.0),
        (0.1, 1.0),
        (0.25, 5.5),
    ]);
    let w = vec![1.0 / n.len() as f64; n.len()];
    for kind in [NdfKind::Ggx, NdfKind::Beckmann] {
        let base = BaseLobe { kind, alpha: 0.3 };
        let t = Texels {
            normals: &n,
            weights: &w,
            base,
        };
        let z = Zonal::new(base, 200);
        let reps: Vec<(&str, Box<dyn NormalPdf>, f64)> = vec![
            ("exact", Box::new(ExactPdf::new(&t)), 2e-4),
            (
                "Schilling",
                Box::new(SlopeGaussian::schilling(&t).unwrap()),
                2e-4,
            ),
            (
                "Olano–Baker",
                Box::new(SlopeGaussian::olano_baker(&t).unwrap()),
                2e-4,
            ),
            ("Olano–North", Box::new(OlanoNorth::new(&t).unwrap()), 2e-4),
            ("SGGX", Box::new(SggxLobe::new(&t).unwrap()), 2e-4),
            (
                "Tan 2",
                Box::new(SlopeMixture::fit(&n, &w, 2, 0.3).unwrap()),
                2e-4,
            ),
            ("SH 7", Box::new(HanSh::new(&t, &z, 7).unwrap()), 2e-3),
            (
                "vMF 2",
                Box::new(VmfConvolved::new(&VmfMixture::fit(&n, &w, 2).unwrap(), &z)),
                2e-3,
            ),
        ];
        for (name, r, tol) in &reps {
            let s = sphere_gl(&|d| r.pdf(d), 128);
            assert!((s - 1.0).abs() < *tol, "{kind:?} {name}: ∫ = {s}");
        }
    }
}

#[test]
fn sh_basis_is_orthonormal_and_signed_as_published() {
    let l = 6;
    let nc = (l + 1) * (l + 1);
    let mut gram = vec![0.0; nc * nc];
    let mut y = vec![0.0; nc];
    let (x, w) = gauss_legendre(24);
    for (xi, wi) in x.iter().zip(&w) {
        let th = xi.acos();
        for k in 0..32 {
            let d = dir(th, 2.0 * PI * k as f64 / 32.0);
            sh_basis(l, &d, &mut y);
            for i in 0..nc {
                for j in 0..nc {
                    gram[i * nc + j] += wi * 2.0 * PI / 32.0 * y[i] * y[j];
                }
            }
        }
    }
    for i in 0..nc {
        for j in 0..nc {
            let e = if i == j { 1.0 } else { 0.0 };
            assert!(
                (gram[i * nc + j] - e).abs() < 1e-12,
                "⟨Y{i}, Y{j}⟩ = {}",
                gram[i * nc + j]
            );
        }
    }
    // Y_00 = 1/(2√π), Y_10 = √(3/4π) z, Y_20 = √(5/16π)(3z² − 1)
    let d = dir(0.7, 1.9);
    sh_basis(2, &d, &mut y);
    assert!((y[0] - 0.5 / PI.sqrt()).abs() < 1e-15);
    assert!((y[index(1, 0)] - (3.0 / (4.0 * PI)).sqrt() * d.z).abs() < 1e-15);
    assert!((y[index(2, 0)] - (5.0 / (16.0 * PI)).sqrt() * (3.0 * d.z * d.z - 1.0)).abs() < 1e-14);
    assert!((y[index(1, 1)].abs() - (3.0 / (4.0 * PI)).sqrt() * d.x.abs()).abs() < 1e-15);
    assert!((y[index(1, -1)].abs() - (3.0 / (4.0 * PI)).sqrt() * d.y.abs()).abs() < 1e-15);
}

#[test]
fn zonal_coefficients_of_the_clamped_cosine_match_ramamoorthi_hanrahan() {
    // Ramamoorthi & Hanrahan 2001: Â_l = 2π ∫₀¹ t P_l(t) dt = π, 2π/3, π/4, 0, −π/24, 0, π/64
    let k = zonal_coefficients(&|t| t.max(0.0), 1.0, 6);
    let want = [
        PI,
        2.0 * PI / 3.0,
        PI / 4.0,
        0.0,
        -PI / 24.0,
        0.0,
        PI / 64.0,
    ];
    for (l, (a, b)) in k.iter().zip(want).enumerate() {
        assert!((a - b).abs() < 1e-9, "l = {l}: {a} vs {b}");
    }
}

#[test]
fn sh_rule_of_thumb_counts_are_monotone_and_finite() {
    let mut prev = 0;
    for e in [1.0, 4.0, 16.0, 64.0, 256.0] {
        let n = coefficients_needed(e, 0.05).expect("converges below degree 600");
        assert!(n >= prev, "exponent {e}: {n} < {prev}");
        prev = n;
    }
    // a constant (e = 0 on the hemisphere) still needs more than one coefficient: the
    // clamp at the horizon is a step
    assert!(coefficients_needed(0.0, 0.05).unwrap() > 1);
}

#[test]
fn em_pitfalls_identical_points_and_kappa_overflow() {
    // every texel the same normal, four lobes: components empty → dropped, variance floored,
    // κ capped; nothing NaN, weights sum to 1, the density finite at the normal
    let n = vec![dir(0.2, 0.4); 9];
    let w = vec![1.0 / 9.0; 9];
    let s = SlopeMixture::fit(&n, &w, 4, 0.05).unwrap();
    assert!(s.log.dropped > 0 && s.log.floored > 0, "{:?}", s.log);
    assert!((s.comps.iter().map(|c| c.weight).sum::<f64>() - 1.0).abs() < 1e-12);
    assert!(s.pdf(&n[0]).is_finite() && s.pdf(&n[0]) > 0.0);
    let v = VmfMixture::fit(&n, &w, 4).unwrap();
    assert!(v.log.dropped > 0 && v.log.kappa_capped > 0, "{:?}", v.log);
    assert!(v
        .comps
        .iter()
        .all(|c| c.kappa <= KAPPA_MAX && c.kappa.is_finite()));
    assert!(v.density(&n[0]).is_finite() && v.density(&n[0]) > 0.0);
    // two distinct normals, four lobes: at most two survive
    let n2: Vec<V3> = (0..8)
        .map(|i| if i % 2 == 0 { V3::z() } else { dir(0.4, 0.0) })
        .collect();
    let w2 = vec![0.125; 8];
    let v2 = VmfMixture::fit(&n2, &w2, 4).unwrap();
    assert!(v2.comps.len() <= 2, "{} lobes", v2.comps.len());
    let s2 = SlopeMixture::fit(&n2, &w2, 4, 0.05).unwrap();
    assert!(s2.comps.len() <= 2 && s2.comps.iter().all(|c| c.var.is_finite()));
    // the log normaliser against its direct form where that is safe, and at the ends
    for k in [1e-2f64, 0.5, 3.0, 30.0, 300.0] {
        let direct = (k / (4.0 * PI * k.sinh())).ln();
        assert!(
            (vmf_log_norm(k) - direct).abs() < 1e-12 * direct.abs().max(1.0),
            "κ {k}"
        );
    }
    assert!(
        vmf_log_norm(1e-300).is_finite()
            && vmf_log_norm(1e8).is_finite()
            && vmf_log_norm(1e300).is_finite()
    );
    // bad input is a typed error
    assert!(SlopeMixture::fit(&[], &[], 2, 0.1).is_err());
    assert!(VmfMixture::fit(&n, &w, 0).is_err());
}

#[test]
fn langevin_inverts() {
    for i in 0..=100 {
        let k = 10f64.powf(-3.0 + 10.0 * i as f64 / 100.0);
        let r = langevin(k);
        let k2 = inverse_langevin(r);
        // beyond κ ~ 1e7 the mean length 1 − 1/κ carries only ~1e-9 of κ
        let tol = if k < 1e6 { 1e-7 } else { 1e-2 };
        assert!(((k2 - k) / k).abs() < tol, "κ {k}: A = {r}, back {k2}");
    }
}

#[test]
fn merging_aligned_children_keeps_their_lobes_and_counts_sharp_edges() {
    let a: Vec<V3> = footprint(&[(0.0, 0.0), (0.02, 0.0), (0.6, 1.0), (0.62, 1.0)]);
    let w = vec![0.25; 4];
    let s = SlopeMixture::fit(&a, &w, 2, 0.05).unwrap();
    let m = merge_slopes(&[s.clone(), s.clone(), s.clone(), s.clone()]);
    assert_eq!(m.misaligned, 0);
    for (x, y) in m.lobes.iter().zip(&s.comps) {
        assert!((x.weight - y.weight).abs() < 1e-12 && (x.mean - y.mean).norm() < 1e-12);
        assert!((x.var - y.var).abs() < 1e-12 * y.var.max(1e-14));
    }
    // children whose second lobes point to opposite sides cannot be aligned
    let b: Vec<V3> = footprint(&[(0.0, 0.0), (0.02, 0.0), (0.6, 4.0), (0.62, 4.0)]);
    let sb = SlopeMixture::fit(&b, &w, 2, 0.05).unwrap();
    let m2 = merge_slopes(&[s.clone(), sb.clone(), s.clone(), sb.clone()]);
    assert!(m2.misaligned > 0, "{m2:?}");
    let v = VmfMixture::fit(&a, &w, 2).unwrap();
    let vb = VmfMixture::fit(&b, &w, 2).unwrap();
    assert_eq!(
        merge_vmf(&[v.clone(), v.clone(), v.clone(), v.clone()], 0.05).misaligned,
        0
    );
    assert!(merge_vmf(&[v.clone(), vb.clone(), v, vb], 0.05).misaligned > 0);
}

#[test]
fn fournier_fits_one_lobe_to_a_beckmann_lobe() {
    // a Beckmann lobe of α = 0.25 is close to Blinn–Phong with e = 2/α² − 2 = 30; one
    // fitted lobe must get within a few per cent, two no worse
    let n = [V3::z()];
    let w = [1.0];
    let t = Texels {
        normals: &n,
        weights: &w,
        base: BaseLobe {
            kind: NdfKind::Beckmann,
            alpha: 0.25,
        },
    };
    let target = Target::new(&t, 512, 7);
    let f1 = fit(&t, &target, 1, 200).unwrap();
    assert!(f1.fit_rel_l2 < 0.05, "{f1:?}");
    assert!((f1.lobes[0].e - 30.0).abs() < 6.0, "{f1:?}");
    let f2 = fit(&t, &target, 2, 200).unwrap();
    assert!(f2.fit_rel_l2 <= f1.fit_rel_l2 + 1e-9);
    assert!(fit(&t, &target, 0, 10).is_err());
}

proptest! {
    #![proptest_config(common::config(10_000))]
    /// Over α from 1e-4 to 1, footprints tilted up to 80° and every view and light
    /// direction down to the horizon: every cheap representation's lobe is finite and ≥ 0.
    #[test]
    fn survey_lobes_are_finite(
        la in -4.0f64..0.0,
        t1 in 0.0f64..1.4, p1 in 0.0f64..6.3, t2 in 0.0f64..1.4, p2 in 0.0f64..6.3,
        tv in 0.0f64..1.5706, pv in 0.0f64..6.3, tl in 0.0f64..1.5706, pl in 0.0f64..6.3,
        ggx in any::<bool>(),
    ) {
        let alpha = 10f64.powf(la);
        let kind = if ggx { NdfKind::Ggx } else { NdfKind::Beckmann };
        let n = [dir(t1, p1), dir(t2, p2), V3::z()];
        let w = [0.5, 0.25, 0.25];
        let base = BaseLobe { kind, alpha };
        let t = Texels { normals: &n, weights: &w, base };
        let reps: Vec<Box<dyn NormalPdf>> = vec![
            Box::new(ExactPdf::new(&t)),
            Box::new(SlopeGaussian::schilling(&t).unwrap()),
            Box::new(SlopeGaussian::olano_baker(&t).unwrap()),
            Box::new(SggxLobe::new(&t).unwrap()),
            Box::new(SlopeMixture::fit(&n, &w, 2, alpha).unwrap()),
            Box::new(VmfConvolved::new(&VmfMixture::fit(&n, &w, 2).unwrap(), &Zonal::new(base, 40))),
        ];
        let sh = Shading::new(kind, t.mean_normal(), alpha.max(0.1)).unwrap();
        let (v, l) = (dir(tv, pv), dir(tl, pl));
        for r in &reps {
            let x = sh.value(&**r, &v, &l);
            prop_assert!(x.is_finite() && x >= 0.0, "{x}");
        }
    }
}

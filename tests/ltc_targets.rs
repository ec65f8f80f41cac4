//! The LTC targets beyond GGX (Charlie sheen with both visibility terms, Burley diffuse in
//! both roughness conventions): their closed-form properties, their albedo by the targets'
//! own nested adaptive quadrature against an independent Gauss–Legendre product in other
//! variables (to 1e-6) and against Monte Carlo within its error, and the generic fitter
//! running on them.

mod common;

use nalgebra::Vector3;
use ndfbench::integrate::quad::{gk15, gl_2d, Tol};
use ndfbench::ltc::diffuse::{BurleyRoughness, BurleyTarget};
use ndfbench::ltc::fit::{self, Method, Metric};
use ndfbench::ltc::sheen::{charlie_d, ek_lambda, CharlieTarget, SheenVisibility};
use ndfbench::ltc::target::LtcTarget;
use ndfbench::parmap::Plain;
use proptest::prelude::*;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

#[test]
fn charlie_ndf_projects_to_unit_area() {
    // ∫ D(h) h_z dh = 2π ∫_0^{π/2} D(θ) cos θ sin θ dθ = 1 for every α (closed form:
    // (2 + 1/α) / (1/α + 2))
    for alpha in [1e-3, 0.01, 0.1, 0.3, 0.7, 1.0] {
        let t = Tol::new(1e-14, 1e-12, 1_000_000);
        let e = gk15(
            &|th: f64| 2.0 * PI * charlie_d(th.cos(), alpha) * th.cos() * th.sin(),
            0.0,
            PI / 2.0,
            t,
        );
        assert!((e.value - 1.0).abs() < 1e-9, "α = {alpha}: {}", e.value);
    }
}

#[test]
fn estevez_kulla_lambda_is_continuous_and_positive() {
    // the two branches meet at cos θ = ½ (by construction of the fit) and Λ → 0 at normal
    // incidence is not required, but Λ must be positive and decreasing in cos θ
    for alpha in [0.01, 0.2, 0.5, 1.0] {
        let below = ek_lambda(0.5 - 1e-12, alpha);
        let above = ek_lambda(0.5, alpha);
        assert!((below - above).abs() <= 1e-9 * above, "α = {alpha}");
        let mut prev = f64::INFINITY;
        for k in 1..=100 {
            let c = k as f64 / 100.0;
            let l = ek_lambda(c, alpha);
            assert!(
                l > 0.0 && l <= prev * (1.0 + 1e-12),
                "α = {alpha}, cos {c}: {l} after {prev}"
            );
            prev = l;
        }
    }
}

/// ∫ f dl by a Gauss–Legendre product in (θ_l, φ) over the whole hemisphere, φ ∈ [0, 2π]
/// (no symmetry used), n × n nodes.
/// (split at θ_l = 60°, where Estevez & Kulla's Λ switches branch with a kink).
/// Cells of n × n nodes each.
fn gl_albedo(t: &dyn LtcTarget, n: usize) -> f64 {
    let f = |th: f64, phi: f64| {
        let l = V3::new(th.sin() * phi.cos(), th.sin() * phi.sin(), th.cos());
        t.eval(&l).0 * th.sin()
    };
    // also split at the mirror direction θ_v, φ = π (the Charlie lobe's cone point for α ≥ ½)
    let tv = t.view().z.acos();
    let mut cuts = vec![0.0, PI / 3.0, tv, PI / 2.0];
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut sum = 0.0;
    for w in cuts.windows(2) {
        for ph in [[0.0, PI], [PI, 2.0 * PI]] {
            sum += gl_2d(&f, [w[0], w[1]], ph, n, n).value;
        }
    }
    sum
}

fn targets() -> Vec<(String, Box<dyn LtcTarget>)> {
    let mut out: Vec<(String, Box<dyn LtcTarget>)> = Vec::new();
    for &alpha in &[0.01, 0.02, 0.05, 0.25, 0.6, 1.0] {
        for &deg in &[0.0, 40.0, 75.0, 88.0] {
            let th = f64::to_radians(deg);
            for r in [BurleyRoughness::Paper, BurleyRoughness::Engines] {
                out.push((
                    format!("Burley {r:?} α {alpha} θ {deg}"),
                    Box::new(BurleyTarget::new(alpha, th, r).unwrap()),
                ));
            }
            for v in [SheenVisibility::EstevezKulla, SheenVisibility::Neubelt] {
                out.push((
                    format!("Charlie {v:?} α {alpha} θ {deg}"),
                    Box::new(CharlieTarget::new(alpha, th, v).unwrap()),
                ));
            }
        }
    }
    out
}

#[test]
fn albedo_quadrature_agrees_with_an_independent_product_rule_to_1e_6() {
    let mut worst = (0.0f64, String::new());
    for (name, t) in targets() {
        let (a, err, fres) = t.albedo(1e-10);
        let g = gl_albedo(&*t, 200);
        if (a - g).abs() / a > worst.0 {
            worst = ((a - g).abs() / a, name.clone());
        }
        // an absolute floor of 1e-12: the Charlie lobe at α = 0.01 seen head-on has an
        // albedo of 5e-18 (all its energy sits at grazing half-vectors)
        assert!(
            (a - g).abs() <= 1e-6 * a + 1e-12,
            "{name}: adaptive {a} (± {err:.1e}) vs Gauss–Legendre {g}"
        );
        assert!(a > 0.0 && fres >= 0.0 && fres < a, "{name}: {a} {fres}");
    }
    eprintln!("largest relative difference {:.1e} ({})", worst.0, worst.1);
}

#[test]
fn albedo_quadrature_agrees_with_monte_carlo_within_its_error() {
    for (name, t) in targets() {
        let (a, _, _) = t.albedo(1e-9);
        let (mc, _, se, _) = t.moments(256);
        // an absolute floor of 1e-9 (invisible energy): at α ≤ 0.02 head-on the Charlie
        // lobe (albedo ~3e-10) lies where neither sampler puts 256² samples
        assert!(
            (a - mc).abs() <= 4.0 * se + 1e-9,
            "{name}: quadrature {a} vs MC {mc} ± {se:.2e}"
        );
    }
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// Both lobes are reciprocal: BRDF(l, v) = BRDF(v, l), on random directions down to
    /// 89.99° (the values divided by the cosine they carry).
    #[test]
    fn sheen_and_burley_are_reciprocal(
        a in 1e-3f64..1.0, tv in 0.0f64..89.99, tl in 0.0f64..89.99, phi in 0.0f64..(2.0 * PI),
        which in 0usize..4,
    ) {
        let (tv, tl) = (tv.to_radians(), tl.to_radians());
        let l = V3::new(tl.sin() * phi.cos(), tl.sin() * phi.sin(), tl.cos());
        // the swapped pair, rotated so that the new view lies in the xz-plane
        let v_old = V3::new(tv.sin(), 0.0, tv.cos());
        let rot = nalgebra::Rotation3::from_axis_angle(&V3::z_axis(), -phi);
        let v_new = rot * v_old;
        let brdf = |view: f64, l: &V3| -> f64 {
            let f = match which {
                0 => BurleyTarget::new(a, view, BurleyRoughness::Paper).unwrap().value(l),
                1 => BurleyTarget::new(a, view, BurleyRoughness::Engines).unwrap().value(l),
                2 => CharlieTarget::new(a, view, SheenVisibility::EstevezKulla).unwrap().value(l),
                _ => CharlieTarget::new(a, view, SheenVisibility::Neubelt).unwrap().value(l),
            };
            f / l.z
        };
        let x = brdf(tv, &l);
        let y = brdf(tl, &v_new);
        prop_assert!((x - y).abs() <= 1e-10 * x.abs().max(1e-300), "{} vs {}", x, y);
        prop_assert!(x.is_finite() && x >= 0.0);
    }
}

#[test]
fn the_generic_fitter_beats_the_plain_cosine_on_every_new_target() {
    // one cell of each target at a moderate view: the fitted LTC's held-out relative L2
    // must be below that of M = I (the clamped cosine, scaled to the same norm)
    for (name, t) in targets().into_iter().filter(|(n, _)| n.contains("θ 40")) {
        let (norm, _, _) = t.albedo(1e-9);
        let (_, _, _, z) = t.moments(32);
        let (p, _) = fit::fit_cell(
            &*t,
            &z,
            norm,
            &[0.0; 4],
            16,
            Metric::Cubic,
            Method::NelderMead,
            200,
        )
        .unwrap();
        let zt = fit::turn(&z, p[3]);
        let (m11, m22, m13) = fit::params_to_m(&p);
        let ltc = ndfbench::ltc::dist::LtcDist::new(fit::matrix(m11, m22, m13, &zt)).unwrap();
        let (_, fitted) = fit::metrics(&*t, &ltc, norm, 32, 0.25);
        let cosine = ndfbench::ltc::dist::LtcDist::new(nalgebra::Matrix3::identity()).unwrap();
        let (_, plain) = fit::metrics(&*t, &cosine, norm, 32, 0.25);
        eprintln!(
            "{name}: fitted L2 {:.2} % vs cosine {:.2} %",
            100.0 * fitted,
            100.0 * plain
        );
        assert!(
            fitted <= plain * (1.0 + 1e-9),
            "{name}: fitted {fitted} vs cosine {plain}"
        );
    }
}

#[test]
fn bad_roughness_is_a_typed_error() {
    for a in [0.0, -1.0, f64::NAN, f64::INFINITY, 1.5] {
        assert!(CharlieTarget::new(a, 0.3, SheenVisibility::Neubelt).is_err());
        assert!(BurleyTarget::new(a, 0.3, BurleyRoughness::Paper).is_err());
    }
}

/// The generic fitter through the lobe dispatcher (`Lobe::Ggx`) fits a GGX table
/// bit-identical to the one fitted with `GgxTarget` directly (the committed ltc-ggx
/// table was regenerated through the generic bilinear pass and storage to the same bits).
#[test]
fn the_lobe_dispatcher_changes_no_bit_of_a_ggx_fit() {
    use ndfbench::ltc::fit::{fit_table, Grid, Method, Metric};
    use ndfbench::ltc::lobes::Lobe;
    use ndfbench::ltc::target::GgxTarget;
    let grid = Grid {
        n: 4,
        alpha_min: 1e-4,
    };
    let a = fit_table(
        &Plain,
        grid,
        &GgxTarget::new,
        8,
        Metric::Cubic,
        Method::NelderMead,
        60,
        ndfbench::ltc::fit::Polish::NelderMead,
        &|| {},
    )
    .unwrap();
    let b = fit_table(
        &Plain,
        grid,
        &|al, th| Lobe::Ggx.target(al, th),
        8,
        Metric::Cubic,
        Method::NelderMead,
        60,
        ndfbench::ltc::fit::Polish::NelderMead,
        &|| {},
    )
    .unwrap();
    for (ca, cb) in a.cells.iter().flatten().zip(b.cells.iter().flatten()) {
        assert_eq!(ca.inv.map(f64::to_bits), cb.inv.map(f64::to_bits));
        assert_eq!(ca.norm.to_bits(), cb.norm.to_bits());
        assert_eq!(ca.fresnel.to_bits(), cb.fresnel.to_bits());
    }
}

/// The Charlie sampler's density is what it samples: its integral over the upper
/// hemisphere (by quadrature) equals the fraction of samples that land above the horizon
/// (counted on a 512² stratified set), and ∫ f/p over its samples is the albedo.
#[test]
fn charlie_mixture_density_integrates_to_its_acceptance() {
    for &alpha in &[0.01, 0.1, 0.5, 1.0] {
        for &deg in &[0.0, 45.0, 80.0, 89.0] {
            let t =
                CharlieTarget::new(alpha, f64::to_radians(deg), SheenVisibility::Neubelt).unwrap();
            let (mass, _, _) = ndfbench::ltc::hemisphere::albedo(&|l| t.pdf(l), &t.v, &[], 1e-9);
            let n = 512;
            let mut hit = 0usize;
            for i in 0..n {
                for j in 0..n {
                    let u = [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
                    if t.sample(u).is_some() {
                        hit += 1;
                    }
                }
            }
            let frac = hit as f64 / (n * n) as f64;
            // stratified counting: the error is ~ the boundary's share of the strata
            assert!(
                (mass - frac).abs() < 5e-3,
                "α {alpha} θ {deg}: ∫p = {mass} but {frac} of the samples land above the horizon"
            );
            assert!(
                mass <= 1.0 + 1e-6 && mass >= 0.5 - 1e-6,
                "α {alpha} θ {deg}: {mass}"
            );
        }
    }
}

/// The f64 reference of the WGSL lookup reproduces any table that is linear in the
/// texel coordinates exactly (bilinear interpolation is exact on bilinear data), at the
/// shipped coordinates x = √α (n − 1), y = √(1 − cos θ)(n − 1), clamped at the edges.
#[test]
fn table_bilinear_reference_is_exact_on_linear_tables() {
    use ndfbench::ltc::table::FittedTable;
    let n = 9;
    let lin = |x: f64, y: f64| -> [f64; 6] {
        std::array::from_fn(|c| 0.5 + c as f64 * x - 0.25 * y + 0.1 * x * y)
    };
    let cells: Vec<[f64; 6]> = (0..n * n)
        .map(|k| lin((k % n) as f64, (k / n) as f64))
        .collect();
    let t = FittedTable {
        n,
        cells,
        half: None,
    };
    for &(alpha, cos_theta) in &[
        (0.0, 1.0),
        (1.0, 0.0),
        (0.3, 0.7),
        (0.05, 0.999),
        (0.99, 0.01),
        (2.0, -1.0),
    ] {
        let got = t.bilinear(alpha, cos_theta, false);
        let x = f64::clamp(alpha, 0.0, 1.0).sqrt() * (n - 1) as f64;
        let y = (1.0 - f64::clamp(cos_theta, 0.0, 1.0)).sqrt() * (n - 1) as f64;
        let want = lin(x, y);
        for c in 0..6 {
            assert!(
                (got[c] - want[c]).abs() < 1e-12,
                "α {alpha} cos θ {cos_theta} channel {c}: {} vs {}",
                got[c],
                want[c]
            );
        }
    }
}

/// A direction on the whole sphere from two uniforms, biased toward the horizon (|z| down
/// to ~1e-9) where the masking terms are steepest.
fn sphere_dir(u: f64, phi: f64, horizon: bool) -> V3 {
    let z = if horizon {
        (2.0 * u - 1.0).signum() * (2.0 * u - 1.0).abs().powi(9)
    } else {
        2.0 * u - 1.0
    };
    let s = (1.0 - z * z).max(0.0).sqrt();
    V3::new(s * phi.cos(), s * phi.sin(), z)
}

proptest! {
    #![proptest_config(common::config(10_000))]

    /// The targets' values, with Λ(v) and G1(v) computed once per target, are bit for bit
    /// those of the microfacet model's own D, G1 and height-correlated G2 (and of the
    /// Charlie target's separate value and density): from α = 1e-4, θ to 89.99°, l over
    /// the whole sphere and to within 1e-9 of the horizon.
    #[test]
    fn target_values_are_the_models_bit_for_bit(
        la in -4.0f64..0.0, ay_ratio in 0.05f64..1.0, th in 0.0f64..89.99,
        u in 0.0f64..1.0, phi in 0.0f64..6.2832, horizon in any::<bool>(), az in 0.0f64..3.1416,
    ) {
        use ndfbench::ltc::aniso::AnisoGgxTarget;
        use ndfbench::ltc::target::GgxTarget;
        use ndfbench::microfacet::{Microsurface, Roughness};
        let alpha = 10f64.powf(la);
        let theta = th.to_radians();
        let l = sphere_dir(u, phi, horizon);
        let t = GgxTarget::new(alpha, theta).unwrap();
        let v = t.v;
        let s = Microsurface::ggx(Roughness::iso(alpha).unwrap());
        let model = |s: &Microsurface| -> (f64, f64) {
            if l.z <= 0.0 {
                return (0.0, 0.0);
            }
            let h = (v + l).normalize();
            let d = s.d(&h);
            (d * s.g2_correlated(&l, &v, &h) / (4.0 * v.z), d * s.g1_dir(&v) / (4.0 * v.z))
        };
        let (f, p) = LtcTarget::eval(&t, &l);
        prop_assert_eq!((f.to_bits(), p.to_bits()), {
            let (a, b) = model(&s);
            (a.to_bits(), b.to_bits())
        });
        let (ax, ay) = (alpha, alpha * ay_ratio);
        let ta = AnisoGgxTarget::new(ax, ay, theta, az).unwrap();
        let sa = Microsurface::ggx(Roughness::rotated(ax, ay, az).unwrap());
        let (f, p) = ta.eval(&l);
        let (a, b) = model(&sa);
        prop_assert_eq!((f.to_bits(), p.to_bits()), (a.to_bits(), b.to_bits()));
        for vis in [SheenVisibility::EstevezKulla, SheenVisibility::Neubelt] {
            let c = CharlieTarget::new(alpha, theta, vis).unwrap();
            let (f, p) = c.eval(&l);
            prop_assert_eq!((f.to_bits(), p.to_bits()), (c.value(&l).to_bits(), c.pdf(&l).to_bits()));
        }
    }
}

//! What an LTC is fitted to: a cosine-weighted BRDF lobe for one (roughness, view) cell.
//!
//! The fitter (`ltc::fit`) sees a target only through [`LtcTarget`]: its view, its value
//! with the density of its own importance sampler, that sampler, a width that scales the
//! optimiser's first frame-turn step, and its albedo by quadrature (with the Fresnel
//! moment ∫f·(1 − v·h)⁵). New BRDFs plug in by implementing the trait.
//! [`GgxTarget`] is the GGX lobe of Heitz et al. 2016 (seed 000 Eq 1's fitted table).

use crate::error::Result;
use crate::integrate::mc::Strategy;
use crate::lanes::{map, Dirs, Lanes, LANES};
use crate::ltc::chart::Chart;
use crate::microfacet::sampling::VndfSampler;
use crate::microfacet::surface::g2_from_lambdas;
use crate::microfacet::{g2_lanes, Microsurface, NdfKind, Roughness};
use nalgebra::Vector3;

type V3 = Vector3<f64>;

/// A cosine-weighted BRDF lobe f(l) = BRDF(l, v)·l_z for a fixed view v (v_y = 0).
pub trait LtcTarget: Sync {
    /// The view direction (in the xz-plane, v_z > 0).
    fn view(&self) -> V3;
    /// (f(l), density of l under [`LtcTarget::sample`]); (0, 0) below the horizon.
    fn eval(&self, l: &V3) -> (f64, f64);
    /// [`LtcTarget::eval`] of the four directions of `l` whose lane is `live` ((0, 0)
    /// elsewhere): each lane's bits are `eval`'s. A target whose value is a chain of
    /// divisions and roots computes the lanes step by step (`ltc::lanes`).
    fn eval_lanes(&self, l: &Dirs, live: [bool; LANES]) -> [(f64, f64); LANES] {
        std::array::from_fn(|i| {
            if live[i] {
                self.eval(&l.get(i))
            } else {
                (0.0, 0.0)
            }
        })
    }
    /// An importance sample of f (None where it lands below the horizon).
    fn sample(&self, u: [f64; 2]) -> Option<V3>;
    /// A width of the lobe (α for microfacet lobes; 1 for diffuse): scales the first
    /// frame-turn step of the fit.
    fn width(&self) -> f64;
    /// (∫f, its error estimate, ∫f·(1 − v·h)⁵) by quadrature to `tol`.
    fn albedo(&self, tol: f64) -> (f64, f64, f64);
    /// A chart of the sphere in which f is a smooth, broad function (what the held-out
    /// integrals of `ltc::lobe_error` follow the target's lobe with): by default the
    /// upper hemisphere of directions itself.
    fn chart(&self) -> Chart {
        Chart::direction(nalgebra::Matrix3::identity())
    }
    /// (∫f, ∫f(1 − v·h)⁵, standard error of ∫f, mean direction ∫f·l / |∫f·l|) by
    /// importance sampling on an n×n stratified set.
    fn moments(&self, n: usize) -> (f64, f64, f64, V3) {
        let v = self.view();
        let (mut s, mut s2, mut fr) = (0.0, 0.0, 0.0);
        let mut dir = V3::zeros();
        let cnt = (n * n) as f64;
        for i in 0..n {
            for j in 0..n {
                let u = [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
                if let Some(l) = self.sample(u) {
                    let (f, p) = self.eval(&l);
                    if p > 0.0 {
                        let w = f / p;
                        s += w;
                        s2 += w * w;
                        let h = (v + l).normalize();
                        fr += w * (1.0 - v.dot(&h)).max(0.0).powi(5);
                        dir += l * w;
                    }
                }
            }
        }
        let mean = s / cnt;
        let se = ((s2 / cnt - mean * mean).max(0.0) / cnt).sqrt();
        let d = if dir.norm() > 0.0 {
            dir.normalize()
        } else {
            V3::z()
        };
        (mean, fr / cnt, se, d)
    }
}

/// A microfacet lobe seen from a fixed view v: Λ(v) and G1(v) are computed once, since
/// every value of the lobe needs them (a fitter evaluates it millions of times).
pub(crate) struct FixedView {
    surface: Microsurface,
    v: V3,
    lambda_v: f64,
    g1_v: f64,
    /// D's constant factor (`Microsurface::d_norm`).
    d_norm: f64,
}

impl FixedView {
    pub(crate) fn new(surface: Microsurface, v: V3) -> FixedView {
        FixedView {
            surface,
            v,
            lambda_v: surface.lambda(&v),
            g1_v: surface.g1_dir(&v),
            d_norm: surface.d_norm(),
        }
    }

    /// (f(l), density of l under VNDF sampling + reflection) of the cosine-weighted lobe
    /// with height-correlated G2 and F = 1: f = D(h)·G2(l, v)/(4 v_z) (seed 003 Eq 14),
    /// density D(h)·G1(v)/(4 v_z). The same operations as `Microsurface::g1_dir` and
    /// `g2_correlated`, with Λ(v) and G1(v) from `new`: the same bits.
    pub(crate) fn eval(&self, l: &V3) -> (f64, f64) {
        if l.z <= 0.0 {
            return (0.0, 0.0);
        }
        let h = (self.v + l).normalize();
        let d = self.surface.d_with(&h, self.d_norm);
        let pdf = d * self.g1_v / (4.0 * self.v.z);
        let g2 = if l.dot(&h) <= 0.0 || self.v.dot(&h) <= 0.0 {
            0.0
        } else {
            g2_from_lambdas(self.surface.lambda(l), self.lambda_v)
        };
        (d * g2 / (4.0 * self.v.z), pdf)
    }

    /// [`Self::eval`] of four directions, step by step across the lanes (`crate::lanes`):
    /// for GGX the half-vectors and G2 here, D and Λ(l) by `Microsurface::d_lanes` and
    /// `lambda_lanes`, the same operations in the same order, so each lane's bits are
    /// `eval`'s; other NDFs lane by lane through `eval`.
    pub(crate) fn eval_lanes(&self, l: &Dirs) -> (Lanes, Lanes) {
        let sf = &self.surface;
        if sf.kind != NdfKind::Ggx {
            let r: [(f64, f64); LANES] = std::array::from_fn(|i| self.eval(&l.get(i)));
            return (map(|i| r[i].0), map(|i| r[i].1));
        }
        let v = &self.v;
        let s = l.plus(v);
        let h = s.over(&s.norm());
        let d = sf.d_lanes(&h, self.d_norm);
        let lam = sf.lambda_lanes(l);
        let (lh, vh) = (
            l.dot(&h),
            map(|i| v.x * h.x[i] + v.y * h.y[i] + v.z * h.z[i]),
        );
        let g2 = g2_lanes(&lh, &vh, &lam, &[self.lambda_v; LANES]);
        // as `eval`: only l_z ≤ 0 is (0, 0) (a NaN l_z is evaluated)
        let f = map(|i| {
            if l.z[i] <= 0.0 {
                0.0
            } else {
                d[i] * g2[i] / (4.0 * v.z)
            }
        });
        let p = map(|i| {
            if l.z[i] <= 0.0 {
                0.0
            } else {
                d[i] * self.g1_v / (4.0 * v.z)
            }
        });
        (f, p)
    }
}

/// The GGX BRDF of one cell: cosine-weighted, height-correlated Smith G2, F = 1.
pub struct GgxTarget {
    pub alpha: f64,
    pub v: V3,
    surface: Microsurface,
    vndf: VndfSampler,
    seen: FixedView,
}

impl GgxTarget {
    /// θ in radians (clamped to ≤ 89.99° so that v_z > 0), α > 0.
    pub fn new(alpha: f64, theta: f64) -> Result<GgxTarget> {
        let th = theta.clamp(0.0, crate::ltc::hemisphere::THETA_MAX_DEG.to_radians());
        let v = V3::new(th.sin(), 0.0, th.cos());
        let surface = Microsurface::ggx(Roughness::iso(alpha)?);
        Ok(GgxTarget {
            alpha,
            v,
            surface,
            vndf: VndfSampler::new(surface, v)?,
            seen: FixedView::new(surface, v),
        })
    }
    /// (f(l), density of l under VNDF sampling + reflection).
    pub fn eval(&self, l: &V3) -> (f64, f64) {
        self.seen.eval(l)
    }
    /// Sample l by VNDF + reflection (None if it lands below the horizon).
    pub fn sample(&self, u: [f64; 2]) -> Option<V3> {
        let m = self.vndf.sample(u)?;
        let l = m * (2.0 * self.v.dot(&m)) - self.v;
        (l.z > 0.0).then_some(l)
    }
    /// (∫f, its error estimate, ∫f(1 − v·h)⁵) by nested adaptive sphere quadrature in
    /// half-vector space: ∫f dl = ∫ D(h)·G2(l(h), v)·(v·h)/v_z dh (reflection Jacobian
    /// 4 v·h), where the lobe sits at the pole for every view.
    pub fn norm_quad(&self, tol: f64) -> (f64, f64, f64) {
        let rule = crate::integrate::sphere::SphereRule::hemisphere(self.alpha);
        microfacet_albedo(&self.surface, &self.v, &rule, tol)
    }
}

/// (∫f, its error estimate, ∫f(1 − v·h)⁵) of the cosine-weighted microfacet lobe of
/// `surface` (height-correlated G2, F = 1) seen from `v`, by nested adaptive sphere
/// quadrature in half-vector space on the polar layout `rule` (about z), the mirror
/// horizon l_z = 0 of `v` added to its break points:
/// ∫f dl = ∫ D(h)·G2(l(h), v)·(v·h)/v_z dh (reflection Jacobian 4 v·h).
pub fn microfacet_albedo(
    surface: &Microsurface,
    v: &V3,
    rule: &crate::integrate::sphere::SphereRule,
    tol: f64,
) -> (f64, f64, f64) {
    use crate::integrate::quad::Tol;
    use crate::integrate::sphere::integrate_sphere_lanes;
    // four half-vectors at a time (`crate::lanes`): D and Λ(l) by `d_lanes` and
    // `lambda_lanes`, Λ(v) and D's factor once; each lane's bits are those of the
    // one-vector form, D·G2·(v·h)/v_z with `Microsurface::g2_correlated`
    // (`tests::microfacet_albedo_in_lanes_is_one_vector_at_a_time`)
    let (lambda_v, d_norm) = (surface.lambda(v), surface.d_norm());
    let g = |h: &Dirs, fres: bool| -> Lanes {
        let vh = map(|i| v.x * h.x[i] + v.y * h.y[i] + v.z * h.z[i]);
        let l = Dirs {
            x: map(|i| h.x[i] * (2.0 * vh[i]) - v.x),
            y: map(|i| h.y[i] * (2.0 * vh[i]) - v.y),
            z: map(|i| h.z[i] * (2.0 * vh[i]) - v.z),
        };
        let d = surface.d_lanes(h, d_norm);
        let lam = surface.lambda_lanes(&l);
        let g2 = g2_lanes(&l.dot(h), &vh, &lam, &[lambda_v; LANES]);
        map(|i| {
            if vh[i] <= 0.0 || h.z[i] <= 0.0 || l.z[i] <= 0.0 {
                return 0.0;
            }
            let w = d[i] * g2[i] * vh[i] / v.z;
            if fres {
                w * (1.0 - vh[i]).powi(5)
            } else {
                w
            }
        })
    };
    // l_z = 0 is a kink of the integrand along a curve of half-vectors: without its
    // crossings as break points the adaptive rule converged to values off by up to 9e-7
    // (α 0.012 at 89.99°) while reporting 1e-9, and spent 4–10× the evaluations
    let rule = rule.clone().with_mirror_horizon(*v);
    let t = Tol::new(tol, tol, 20_000_000);
    let a = integrate_sphere_lanes(&|h| g(h, false), &rule, t);
    let b = integrate_sphere_lanes(&|h| g(h, true), &rule, t);
    (a.value, a.error, b.value)
}

impl LtcTarget for GgxTarget {
    fn view(&self) -> V3 {
        self.v
    }
    fn eval(&self, l: &V3) -> (f64, f64) {
        GgxTarget::eval(self, l)
    }
    fn eval_lanes(&self, l: &Dirs, live: [bool; LANES]) -> [(f64, f64); LANES] {
        let (f, p) = self.seen.eval_lanes(l);
        std::array::from_fn(|i| if live[i] { (f[i], p[i]) } else { (0.0, 0.0) })
    }
    fn sample(&self, u: [f64; 2]) -> Option<V3> {
        GgxTarget::sample(self, u)
    }
    fn width(&self) -> f64 {
        self.alpha
    }
    fn albedo(&self, tol: f64) -> (f64, f64, f64) {
        self.norm_quad(tol)
    }
    /// Half-vectors from the projected NDF's LTC, M = diag(α, α, 1) (D(h)·h_z is exactly
    /// that LTC), reflected about the view.
    fn chart(&self) -> Chart {
        Chart::half_vector(nalgebra::Matrix3::from_diagonal(&V3::new(
            self.alpha, self.alpha, 1.0,
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::tests::direction;
    use crate::lanes::{Dirs, LANES};
    use nalgebra::Matrix3;
    use rand::{Rng, SeedableRng};

    /// α by case: 1e-4, 1, else log-uniform in [1e-4, 1].

    /// The microfacet lobe (`FixedView`) and the LTC (`LtcDist`) in lanes give each lane
    /// the bits of their scalar forms: 12 000 sets of four directions (below, on and above
    /// the horizon, ±0, 1e-300, NaN, off the unit sphere) against isotropic GGX at α from
    /// 1e-4 to 1, rotated anisotropic GGX, GGX with a mean slope and Beckmann (the
    /// lane-by-lane path), views up to 89.99°, and random M.
    #[test]
    fn lobes_and_ltcs_are_the_scalar_bits() {
        use crate::ltc::target::FixedView;
        use crate::ltc::LtcDist;
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for case in 0..12_000 {
            let surface = crate::microfacet::lobe::tests::surface_of(case, &mut r);
            let th = if case % 5 == 0 {
                89.99f64.to_radians()
            } else {
                r.random_range(0.0..1.5707)
            };
            let view = FixedView::new(surface, V3::new(th.sin(), 0.0, th.cos()));
            let d: Vec<V3> = (0..LANES).map(|_| direction(&mut r)).collect();
            let (f, p) = view.eval_lanes(&Dirs::of(&d));
            for i in 0..LANES {
                let (f1, p1) = view.eval(&d[i]);
                assert!(
                    same(f[i], f1) && same(p[i], p1),
                    "case {case} lane {i}: {:?}",
                    d[i]
                );
            }
            let m = Matrix3::from_fn(|_, _| r.random_range(-2.0..2.0));
            let Ok(ltc) = LtcDist::new(m) else { continue };
            let (img, ok) = ltc.from_cosine_lanes(&Dirs::of(&d));
            let g = ltc.eval_lanes(&Dirs::of(&d));
            for i in 0..LANES {
                match ltc.from_cosine(&d[i]) {
                    Some(x) => {
                        assert!(ok[i]);
                        (0..3).for_each(|c| assert!(same(img.get(i)[c], x[c])));
                    }
                    None => assert!(!ok[i]),
                }
                assert!(
                    same(g[i], ltc.eval_reference(&d[i])),
                    "case {case} lane {i}"
                );
                assert!(same(ltc.eval(&d[i]), ltc.eval_reference(&d[i])));
            }
        }
    }

    /// `microfacet_albedo`, its half-vectors four at a time, gives the bits of the
    /// one-vector form as written before (value, error estimate, Fresnel moment):
    /// isotropic and rotated anisotropic GGX and Beckmann (lane by lane) at α from 1e-4
    /// to 1, views to 89.99°, two tolerances.
    #[test]
    fn microfacet_albedo_in_lanes_is_one_vector_at_a_time() {
        use crate::integrate::quad::Tol;
        use crate::integrate::sphere::{integrate_sphere, SphereRule};
        use crate::microfacet::{Microsurface, Roughness};
        let one_vector_at_a_time = |s: &Microsurface, v: &V3, rule: &SphereRule, tol: f64| {
            let g = |h: &V3, fres: bool| {
                let vh = v.dot(h);
                if vh <= 0.0 || h.z <= 0.0 {
                    return 0.0;
                }
                let l = h * (2.0 * vh) - v;
                if l.z <= 0.0 {
                    return 0.0;
                }
                let w = s.d(h) * s.g2_correlated(&l, v, h) * vh / v.z;
                if fres {
                    w * (1.0 - vh).powi(5)
                } else {
                    w
                }
            };
            let rule = rule.clone().with_mirror_horizon(*v);
            let t = Tol::new(tol, tol, 20_000_000);
            let a = integrate_sphere(&|h| g(h, false), &rule, t);
            let b = integrate_sphere(&|h| g(h, true), &rule, t);
            [a.value, a.error, b.value]
        };
        let mut n = 0;
        for (k, alpha) in [1e-4, 0.012, 0.3, 1.0].into_iter().enumerate() {
            for th in [0.0f64, 0.8, 1.4, 89.99f64.to_radians()] {
                let rough = if k % 2 == 0 {
                    Roughness::iso(alpha)
                } else {
                    Roughness::rotated(alpha, 0.4, 0.6)
                }
                .unwrap();
                for s in [Microsurface::ggx(rough), Microsurface::beckmann(rough)] {
                    let v = V3::new(th.sin(), 0.0, th.cos());
                    let rule = SphereRule::sphere(V3::z(), alpha);
                    let tol = if n % 2 == 0 { 1e-9 } else { 1e-6 };
                    let got = microfacet_albedo(&s, &v, &rule, tol);
                    let want = one_vector_at_a_time(&s, &v, &rule, tol);
                    assert_eq!(
                        [got.0, got.1, got.2].map(f64::to_bits),
                        want.map(f64::to_bits),
                        "alpha {alpha} theta {th}: {got:?} vs {want:?}"
                    );
                    n += 1;
                }
            }
        }
        assert_eq!(n, 32);
    }

    /// Every target's `eval_lanes` gives each live lane `eval`'s bits and (0, 0) to the
    /// others: GGX, anisotropic GGX, both sheens (their four powers overlapping) and both
    /// diffuse roughnesses, 12 000 sets of four extreme directions with random live lanes.
    #[test]
    fn targets_in_lanes_are_their_eval() {
        use crate::ltc::aniso::AnisoGgxTarget;
        use crate::ltc::diffuse::{BurleyRoughness, BurleyTarget};
        use crate::ltc::sheen::{CharlieTarget, SheenVisibility};
        use crate::ltc::target::{GgxTarget, LtcTarget};
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for case in 0..12_000 {
            let alpha = crate::microfacet::lobe::tests::alpha_of(case, &mut r);
            let th = if case % 5 == 0 {
                89.99f64.to_radians()
            } else {
                r.random_range(0.0..1.5707)
            };
            let t: Box<dyn LtcTarget> = match case % 6 {
                0 => Box::new(GgxTarget::new(alpha, th).unwrap()),
                1 => Box::new(
                    AnisoGgxTarget::new(alpha, r.random_range(1e-4..1.0), th, 0.7).unwrap(),
                ),
                2 => Box::new(
                    CharlieTarget::new(alpha.max(0.01), th, SheenVisibility::EstevezKulla).unwrap(),
                ),
                3 => Box::new(
                    CharlieTarget::new(alpha.max(0.01), th, SheenVisibility::Neubelt).unwrap(),
                ),
                4 => Box::new(BurleyTarget::new(alpha, th, BurleyRoughness::Paper).unwrap()),
                _ => Box::new(BurleyTarget::new(alpha, th, BurleyRoughness::Engines).unwrap()),
            };
            let d: Vec<V3> = (0..LANES).map(|_| direction(&mut r)).collect();
            let live: [bool; LANES] = std::array::from_fn(|_| r.random_range(0..4) > 0);
            let got = t.eval_lanes(&Dirs::of(&d), live);
            for i in 0..LANES {
                let want = if live[i] { t.eval(&d[i]) } else { (0.0, 0.0) };
                assert!(
                    same(got[i].0, want.0) && same(got[i].1, want.1),
                    "case {case} lane {i}: {:?} {:?} vs {want:?}",
                    d[i],
                    got[i]
                );
            }
        }
    }

    /// `Chart::map_lanes` gives each lane `Chart::map`'s bits, and reaches exactly the
    /// lanes `map` does: 12 000 sets of four extreme ω, random M (near-singular among
    /// them), direction and half-vector charts, views up to 89.99°.
    #[test]
    fn charts_in_lanes_are_map() {
        use crate::ltc::chart::Chart;
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(13);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for case in 0..12_000 {
            let mut m = Matrix3::from_fn(|_, _| r.random_range(-2.0..2.0));
            if case % 9 == 0 {
                m.set_row(2, &(m.row(0) * 1e-12));
            }
            let chart = if case % 2 == 0 {
                Chart::direction(m)
            } else {
                Chart::half_vector(m)
            };
            let th = if case % 5 == 0 {
                89.99f64.to_radians()
            } else {
                r.random_range(0.0..1.5707)
            };
            let v = V3::new(th.sin(), 0.0, th.cos());
            let det = r.random_range(0.0..3.0);
            let w: Vec<V3> = (0..LANES).map(|_| direction(&mut r)).collect();
            let (l, j, reach) = chart.map_lanes(&Dirs::of(&w), det, &v);
            for i in 0..LANES {
                match chart.map(&w[i], det, &v) {
                    Some((x, jx)) => {
                        assert!(reach[i], "case {case} lane {i}");
                        assert!(
                            same(j[i], jx) && (0..3).all(|c| same(l.get(i)[c], x[c])),
                            "case {case} lane {i}"
                        );
                    }
                    None => assert!(!reach[i], "case {case} lane {i}"),
                }
            }
        }
    }
}

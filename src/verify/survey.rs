//! The identities seed 004 states for its pre-filtering tools (§3.2, §7), each checked by
//! methods independent of the formula:
//! - the best Gaussian of a mixture has the interpolated moments (Nelder–Mead on the
//!   closed-form cross-entropy, and the mixture's moments by quadrature of its density);
//! - a vMF lobe's mean is (coth κ − 1/κ)μ, so a mixture's a_k and a_k(coth κ_k − 1/κ_k)μ_k
//!   interpolate linearly (1D and sphere quadrature);
//! - the SH convolution theorem ∫ k(n·η)p(n)dn = Σ k̂_l p_lm Y_lm(η) (sphere quadrature of
//!   the convolution for a band-limited p).

use super::outcome::{Outcome, Worst};
use crate::integrate::quad::gauss_legendre;
use crate::integrate::Preset;
use crate::survey::em::{inverse_langevin, langevin, vmf_log_norm};
use crate::survey::sh::{index, sh_basis, zonal_coefficients};
use crate::survey::sphere_integral;
use crate::survey::tools::{cross_entropy, moment_match};
use nalgebra::{Matrix2, Rotation2, Vector2, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

type V3 = Vector3<f64>;
type V2 = Vector2<f64>;
type Mix = Vec<(f64, V2, Matrix2<f64>)>;

fn random_mixture(rng: &mut ChaCha8Rng, k: usize) -> Mix {
    let mut w: Vec<f64> = (0..k).map(|_| 0.1 + rng.random::<f64>()).collect();
    let s: f64 = w.iter().sum();
    w.iter_mut().for_each(|x| *x /= s);
    w.into_iter()
        .map(|wi| {
            let mu = V2::new(
                rng.random::<f64>() * 2.0 - 1.0,
                rng.random::<f64>() * 2.0 - 1.0,
            );
            let e = V2::new(
                10f64.powf(-2.0 * rng.random::<f64>()),
                10f64.powf(-2.0 * rng.random::<f64>()),
            );
            let r = *Rotation2::new(rng.random::<f64>() * PI).matrix();
            (
                wi,
                mu,
                r * Matrix2::from_diagonal(&(e * 0.3)) * r.transpose(),
            )
        })
        .collect()
}

/// The mixture's mean and covariance by a Gauss–Legendre product over ±9 s.d. of every
/// component (each component integrated on its own box, in its own eigenframe).
fn quadrature_moments(mix: &Mix, n: usize) -> (V2, Matrix2<f64>) {
    let (x, w) = gauss_legendre(n);
    let (mut m1, mut m2) = (V2::zeros(), Matrix2::zeros());
    for (wi, mu, c) in mix {
        let eig = c.symmetric_eigen();
        let (l, v) = (eig.eigenvalues, eig.eigenvectors);
        let s = V2::new(l[0].sqrt(), l[1].sqrt());
        for (a, wa) in x.iter().zip(&w) {
            for (b, wb) in x.iter().zip(&w) {
                let u = V2::new(9.0 * a, 9.0 * b);
                let dens = (-0.5 * u.norm_squared()).exp() / (2.0 * PI);
                let p = mu + v * V2::new(s.x * u.x, s.y * u.y);
                let q = wi * wa * wb * 81.0 * dens;
                m1 += p * q;
                m2 += p * p.transpose() * q;
            }
        }
    }
    (m1, m2 - m1 * m1.transpose())
}

/// Nelder–Mead (argmin) on the cross-entropy over (m, Cholesky factor of C).
fn minimise_cross_entropy(mix: &Mix) -> (V2, Matrix2<f64>) {
    use argmin::core::{CostFunction, Executor, State};
    use argmin::solver::neldermead::NelderMead;
    struct Ce<'a>(&'a Mix);
    fn unpack(p: &[f64]) -> (V2, Matrix2<f64>) {
        let l = Matrix2::new(p[2].exp(), 0.0, p[3], p[4].exp());
        (V2::new(p[0], p[1]), l * l.transpose())
    }
    impl CostFunction for Ce<'_> {
        type Param = Vec<f64>;
        type Output = f64;
        fn cost(&self, p: &Vec<f64>) -> Result<f64, argmin::core::Error> {
            let (m, c) = unpack(p);
            Ok(cross_entropy(self.0, &m, &c).unwrap_or(f64::INFINITY))
        }
    }
    // a wide simplex from (0, I), then restarts from the best point with a small one
    let mut best = vec![0.0, 0.0, 0.0, 0.0, 0.0];
    for step in [0.5, 0.05, 0.05, 0.05] {
        let mut s = vec![best.clone()];
        for k in 0..5 {
            let mut q = best.clone();
            q[k] += step;
            s.push(q);
        }
        let solver = NelderMead::new(s)
            .with_sd_tolerance(1e-15)
            .expect("simplex");
        if let Ok(r) = Executor::new(Ce(mix), solver)
            .configure(|c| c.max_iters(4000))
            .run()
        {
            if let Some(p) = r.state().get_best_param() {
                best = p.clone();
            }
        }
    }
    unpack(&best)
}

fn mat_rel(a: &Matrix2<f64>, b: &Matrix2<f64>) -> f64 {
    (a - b).norm() / b.norm()
}

/// The best Gaussian fit of a Gaussian mixture has the interpolated moments.
pub fn moment_matching(p: Preset) -> Outcome {
    let n_cases = if p == Preset::Quick { 12 } else { 48 };
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0004);
    let (mut wq, mut wo) = (Worst::default(), Worst::default());
    let mut grad_max = 0.0f64;
    for i in 0..n_cases {
        let k = [2, 3, 5][i % 3];
        let mix = random_mixture(&mut rng, k);
        let (m, c) = moment_match(&mix);
        let (qm, qc) = quadrature_moments(&mix, 96);
        let eq = ((qm - m).norm() + (qc - c).norm()) / (m.norm() + c.norm());
        wq.update(eq, || format!("case {i}, {k} lobes: quadrature moments"));
        let (om, oc) = minimise_cross_entropy(&mix);
        let eo = (om - m).norm() / c.norm().sqrt() + mat_rel(&oc, &c);
        wo.update(eo, || {
            format!("case {i}, {k} lobes: Nelder–Mead optimum {om:?} vs {m:?}")
        });
        // the cross-entropy's central-difference gradient in m at the moment match
        let h = 1e-5;
        for d in [V2::x(), V2::y()] {
            let f = |s: f64| cross_entropy(&mix, &(m + d * s), &c).unwrap_or(f64::NAN);
            grad_max = grad_max.max(((f(h) - f(-h)) / (2.0 * h)).abs());
        }
    }
    let worst = wq.err.max(wo.err);
    let tol = 1e-5;
    Outcome {
        id: "gaussian-moment-matching",
        title: "The best Gaussian of a mixture has the interpolated moments",
        source: "seed 004 §3.2.1 (Olano & North) and §7.2",
        ranges: format!("{n_cases} seeded 2D mixtures of 2, 3 and 5 Gaussians, means in [−1, 1]², standard deviations 0.05–0.55, aspect up to 10:1, rotated"),
        cases: n_cases,
        worst_error: worst,
        error_kind: "rel (quadrature / Nelder–Mead vs Σw(Σ_i + μ_iμ_iᵀ))",
        worst_case: if wq.err >= wo.err { wq.case } else { wo.case },
        tolerance: tol,
        passed: worst <= tol && wq.err <= 1e-9,
        seconds: 0.0,
        notes: vec![
            format!("moments by quadrature of the mixture's density: worst relative difference {:.1e}", wq.err),
            format!("Nelder–Mead minimum of the cross-entropy: worst distance {:.1e} (relative, mean in units of the s.d.)", wo.err),
            format!("largest |∂H/∂m| at the moment match (central differences, h = 1e-5): {grad_max:.1e}"),
        ],
    }
}

/// ∫_{-1}^{1} g(t) C(κ)e^{κt} 2π dt on pieces of 1 − t scaled by 1/κ (log-stable).
fn vmf_1d(kappa: f64, g: &dyn Fn(f64) -> f64) -> f64 {
    let (x, w) = gauss_legendre(64);
    let s = (1.0 / kappa.max(1e-300)).min(2.0);
    let mut br: Vec<f64> = [0.0, s, 4.0 * s, 16.0 * s, 64.0 * s]
        .iter()
        .map(|v| v.min(2.0))
        .collect();
    br.push(2.0);
    br.dedup();
    let ln = vmf_log_norm(kappa);
    let mut acc = 0.0;
    for seg in br.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        for (xi, wi) in x.iter().zip(&w) {
            let u = 0.5 * (a + b) + 0.5 * (b - a) * xi;
            let t = 1.0 - u;
            acc += 0.5 * (b - a) * wi * 2.0 * PI * (ln + kappa * t).exp() * g(t);
        }
    }
    acc
}

/// A vMF lobe's mean is A(κ)μ, A = coth κ − 1/κ; so a mixture's interpolable quantities are
/// a_k and a_k A(κ_k) μ_k.
pub fn vmf_mixture_moments(p: Preset) -> Outcome {
    let nk = if p == Preset::Quick { 25 } else { 81 };
    let mut w1 = Worst::default();
    for i in 0..nk {
        let kappa = 10f64.powf(-3.0 + 8.0 * i as f64 / (nk - 1) as f64);
        let z = vmf_1d(kappa, &|_| 1.0);
        let m = vmf_1d(kappa, &|t| t);
        let a = langevin(kappa);
        w1.update(((m / z - a) / a).abs().max((z - 1.0).abs()), || {
            format!(
                "κ = {kappa:.3e}: ∫ = {z:.15}, E[μ·η] = {:.15} vs A(κ) = {a:.15}",
                m / z
            )
        });
    }
    // blends of two seeded two-lobe mixtures: the blend's mean by sphere quadrature
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0022);
    let mut w2 = Worst::default();
    let mut naive = 0.0f64;
    let blends = if p == Preset::Quick { 4 } else { 12 };
    for b in 0..blends {
        let lobe = |rng: &mut ChaCha8Rng| {
            let t = rng.random::<f64>() * 1.2;
            let ph = rng.random::<f64>() * 2.0 * PI;
            let mu = V3::new(t.sin() * ph.cos(), t.sin() * ph.sin(), t.cos());
            (
                0.2 + rng.random::<f64>(),
                mu,
                10f64.powf(0.5 + 1.5 * rng.random::<f64>()),
            )
        };
        let ma = [lobe(&mut rng), lobe(&mut rng)];
        let mb = [lobe(&mut rng), lobe(&mut rng)];
        let lam = rng.random::<f64>();
        let norm = |m: &[(f64, V3, f64); 2]| m[0].0 + m[1].0;
        let (na, nb) = (norm(&ma), norm(&mb));
        // the blend's mean, each lobe integrated around its own axis (the integral is linear)
        let mut mean = V3::zeros();
        for (m, n, wgt) in [(&ma, na, lam), (&mb, nb, 1.0 - lam)] {
            for (a, mu, k) in m.iter() {
                let ln = vmf_log_norm(*k);
                for ax in 0..3 {
                    let f = |d: &V3| (ln + k * mu.dot(d)).exp() * d[ax];
                    mean[ax] += wgt * a / n * sphere_integral(&f, mu, 1.0 / k.sqrt(), 256).0;
                }
            }
        }
        let interp = ma
            .iter()
            .map(|(a, mu, k)| mu * (lam * a / na * langevin(*k)))
            .sum::<V3>()
            + mb.iter()
                .map(|(a, mu, k)| mu * ((1.0 - lam) * a / nb * langevin(*k)))
                .sum::<V3>();
        w2.update((mean - interp).norm() / interp.norm(), || {
            format!("blend {b}, λ = {lam:.3}")
        });
        // interpolating κ and μ themselves (lobe by lobe) instead
        let wrong: V3 = (0..2)
            .map(|k| {
                let a = lam * ma[k].0 / na + (1.0 - lam) * mb[k].0 / nb;
                let mu = (ma[k].1 * lam + mb[k].1 * (1.0 - lam)).normalize();
                mu * (a * langevin(lam * ma[k].2 + (1.0 - lam) * mb[k].2))
            })
            .sum();
        naive = naive.max((mean - wrong).norm() / interp.norm());
    }
    let mut w3 = Worst::default();
    for i in 0..=60 {
        let kappa = 10f64.powf(-3.0 + 9.0 * i as f64 / 60.0);
        let back = inverse_langevin(langevin(kappa));
        let tol = if kappa < 1e6 { 1.0 } else { 1e6 }; // A(κ) = 1 − 1/κ loses κ's digits
        w3.update(((back - kappa) / kappa).abs() / tol, || {
            format!("A⁻¹(A(κ)) at κ = {kappa:.3e}: {back:.6e}")
        });
    }
    let worst = w1.err.max(w2.err);
    let tol = 1e-9;
    Outcome {
        id: "vmf-mixture-moments",
        title: "vMF mixtures: a_k and a_k(coth κ_k − 1/κ_k)μ_k interpolate linearly",
        source: "seed 004 §3.2.2 (Han et al., Eq 22)",
        ranges: format!("κ from 1e-3 to 1e5 ({nk} values); {blends} seeded blends of two-lobe mixtures (κ 3–100, lobes up to 69° off z)"),
        cases: nk + blends,
        worst_error: worst,
        error_kind: "rel (quadrature vs closed form)",
        worst_case: if w1.err >= w2.err { w1.case } else { w2.case },
        tolerance: tol,
        passed: worst <= tol && w3.err <= 1e-8,
        seconds: 0.0,
        notes: vec![
            format!("lobe mean E[μ·η] = coth κ − 1/κ and ∫ = 1: worst {:.1e}", w1.err),
            format!("the blend's mean against the interpolated a_k A(κ_k) μ_k: worst {:.1e}", w2.err),
            format!("interpolating κ_k and μ_k linearly instead misses the blend's mean by up to {:.1} %", 100.0 * naive),
            format!("A⁻¹(A(κ)) round trip: worst {:.1e} relative (below κ = 1e6)", w3.err),
        ],
    }
}

/// The SH convolution theorem for zonal kernels (Funk–Hecke).
pub fn sh_convolution(p: Preset) -> Outcome {
    // a positive density of degree 3: (1 + 0.5 xy + 0.3 z³ + 0.2 x)/(4π) ≥ 0.25/(4π)
    let dens = |d: &V3| (1.0 + 0.5 * d.x * d.y + 0.3 * d.z.powi(3) + 0.2 * d.x) / (4.0 * PI);
    let lmax = 3;
    let nc = (lmax + 1) * (lmax + 1);
    // its coefficients by a product rule exact for degree ≤ 6
    let mut plm = vec![0.0; nc];
    let (x, w) = gauss_legendre(12);
    let mut y = vec![0.0; nc];
    for (xi, wi) in x.iter().zip(&w) {
        let st = (1.0 - xi * xi).sqrt();
        for k in 0..16 {
            let ph = 2.0 * PI * k as f64 / 16.0;
            let d = V3::new(st * ph.cos(), st * ph.sin(), *xi);
            sh_basis(lmax, &d, &mut y);
            for (o, b) in plm.iter_mut().zip(&y) {
                *o += wi * 2.0 * PI / 16.0 * dens(&d) * b;
            }
        }
    }
    let kernels: Vec<(String, Box<dyn Fn(f64) -> f64>, f64)> = {
        let mut v: Vec<(String, Box<dyn Fn(f64) -> f64>, f64)> = Vec::new();
        for e in [1.0f64, 8.0, 64.0] {
            v.push((
                format!("Blinn–Phong e = {e}"),
                Box::new(move |t: f64| if t > 0.0 { t.powf(e) } else { 0.0 }),
                (2.0 / (e + 2.0)).sqrt(),
            ));
        }
        for a in [0.3f64, 0.1] {
            let b = crate::survey::BaseLobe {
                kind: crate::microfacet::NdfKind::Ggx,
                alpha: a,
            };
            v.push((
                format!("GGX D cos θ, α = {a}"),
                Box::new(move |t: f64| b.q(t)),
                a,
            ));
        }
        v
    };
    let dirs = if p == Preset::Quick { 8 } else { 24 };
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_5A);
    let mut worst = Worst::default();
    for (name, k, width) in &kernels {
        let khat = zonal_coefficients(&|t| k(t), *width, lmax);
        for _ in 0..dirs {
            let z = 2.0 * rng.random::<f64>() - 1.0;
            let ph = 2.0 * PI * rng.random::<f64>();
            let s = (1.0 - z * z).sqrt();
            let eta = V3::new(s * ph.cos(), s * ph.sin(), z);
            let direct = sphere_integral(&|n| k(n.dot(&eta)) * dens(n), &eta, *width, 256).0;
            sh_basis(lmax, &eta, &mut y);
            let mut series = 0.0;
            for l in 0..=lmax {
                for m in -(l as i64)..=(l as i64) {
                    series += khat[l] * plm[index(l, m)] * y[index(l, m)];
                }
            }
            worst.update(((series - direct) / direct).abs(), || {
                format!(
                    "{name}, η = {:.3?}: series {series:.12e}, quadrature {direct:.12e}",
                    [eta.x, eta.y, eta.z]
                )
            });
        }
    }
    let tol = 1e-8;
    Outcome {
        id: "sh-convolution",
        title: "SH convolution theorem: ∫k(n·η)p(n)dn = Σ k̂_l p_lm Y_lm(η)",
        source: "seed 004 §3.2.2 (Han et al.) and §7.3.2; Funk–Hecke",
        ranges: format!("a positive degree-3 density; kernels Blinn–Phong e = 1, 8, 64 and GGX D cos θ at α = 0.3, 0.1; {dirs} seeded directions each"),
        cases: kernels.len() * dirs,
        worst_error: worst.err,
        error_kind: "rel (series vs sphere quadrature of the convolution)",
        worst_case: worst.case,
        tolerance: tol,
        passed: worst.err <= tol,
        seconds: 0.0,
        notes: vec![format!("worst relative difference {:.1e} over {} cases", worst.err, worst.n)],
    }
}

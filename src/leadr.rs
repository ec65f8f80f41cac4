//! LEADR numerical integration over a Gaussian slope distribution (seed 001 §3.4–3.7):
//! N×N grids in standardised slope space for rough specular under an environment and
//! rough diffuse under a light, the artificial micronormal of §3.7, and the reference
//! integral by nested adaptive quadrature.
//!
//! Estimator ("Simplified Algorithms 1 and 3", seed 001 §3.5–3.6): with slopes
//! x = x̄ + p_i σ_x, y = ȳ + (p_i r + p_j √(1 − r²)) σ_y and N = normalize(−x, −y, 1),
//! I = Σ w_i w_j S(N) L(N) / Σ w_i w_j S(N), S = max(0, V·N)/(Z·N).

use crate::error::{Error, Result};
use crate::integrate::quad::{adaptive_batched, gk15, Tol};
use nalgebra::Vector3;
use serde::Serialize;

type V3 = Vector3<f64>;

/// A 1D rule in standardised (unit-variance) slope units; the 2D grid is its tensor product.
#[derive(Clone, Debug, Serialize)]
pub struct Grid {
    pub name: String,
    pub nodes: Vec<f64>,
    /// Normalised to sum 1.
    pub weights: Vec<f64>,
}

impl Grid {
    /// The paper's 5×5 grid: p = ±1.8, ±0.9, 0; w = 0.0725, 0.2443, 0.3663 (seed 001 §3.4).
    pub fn paper5() -> Grid {
        Grid {
            name: "paper 5 (spacing 0.9)".into(),
            nodes: vec![-1.8, -0.9, 0.0, 0.9, 1.8],
            weights: vec![0.0725, 0.2443, 0.3663, 0.2443, 0.0725],
        }
    }

    /// N equally spaced nodes with spacing h, weights ∝ the Gaussian density (the paper's
    /// construction: its 5-point weights are φ(p)/Σφ at h = 0.9 to 4 digits).
    pub fn riemann(n: usize, h: f64) -> Grid {
        let nodes: Vec<f64> = (0..n)
            .map(|k| (k as f64 - (n as f64 - 1.0) / 2.0) * h)
            .collect();
        let raw: Vec<f64> = nodes.iter().map(|p| (-0.5 * p * p).exp()).collect();
        let s: f64 = raw.iter().sum();
        Grid {
            name: format!("uniform {n} (h = {h:.3})"),
            nodes,
            weights: raw.iter().map(|w| w / s).collect(),
        }
    }

    /// N-point Gauss–Hermite rule for the standard normal (probabilists' He_n; Newton on the
    /// three-term recurrence).
    pub fn gauss_hermite(n: usize) -> Grid {
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        // physicists' H_n roots z, then x = √2 z; weights ∝ 1/(H'_n(z))² up to normalisation
        let m = n.div_ceil(2);
        let mut z = 0.0f64;
        for i in 0..m {
            z = match i {
                0 => {
                    (2.0 * n as f64 + 1.0).sqrt()
                        - 1.85575 * (2.0 * n as f64 + 1.0).powf(-1.0 / 6.0)
                }
                1 => z - 1.14 * (n as f64).powf(0.426) / z,
                2 => 1.86 * z - 0.86 * nodes[0],
                3 => 1.91 * z - 0.91 * nodes[1],
                _ => 2.0 * z - nodes[i - 2],
            };
            let mut pp = 0.0;
            for _ in 0..100 {
                let (mut p1, mut p2) = (std::f64::consts::PI.powf(-0.25), 0.0);
                for j in 0..n {
                    let p3 = p2;
                    p2 = p1;
                    p1 = z * (2.0 / (j as f64 + 1.0)).sqrt() * p2
                        - ((j as f64) / (j as f64 + 1.0)).sqrt() * p3;
                }
                pp = (2.0 * n as f64).sqrt() * p2;
                let dz = p1 / pp;
                z -= dz;
                if dz.abs() <= 1e-15 * z.abs().max(1.0) {
                    break;
                }
            }
            // store physicists' roots temporarily (descending) for the next initial guesses
            nodes[i] = z;
            nodes[n - 1 - i] = -z;
            let w = 2.0 / (pp * pp);
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        if n % 2 == 1 {
            nodes[n / 2] = 0.0;
        }
        let s: f64 = weights.iter().sum();
        let mut pairs: Vec<(f64, f64)> = nodes
            .iter()
            .zip(&weights)
            .map(|(z, w)| (z * std::f64::consts::SQRT_2, w / s))
            .collect();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        Grid {
            name: format!("Gauss–Hermite {n}"),
            nodes: pairs.iter().map(|p| p.0).collect(),
            weights: pairs.iter().map(|p| p.1).collect(),
        }
    }
}

/// Beckmann slope statistics of a footprint (LEAN/LEADR moments).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Slopes {
    pub x0: f64,
    pub y0: f64,
    pub sx: f64,
    pub sy: f64,
    pub rxy: f64,
}

impl Slopes {
    pub fn iso(sigma: f64) -> Slopes {
        Slopes {
            x0: 0.0,
            y0: 0.0,
            sx: sigma,
            sy: sigma,
            rxy: 0.0,
        }
    }
    fn normal(&self, u: f64, v: f64) -> V3 {
        let x = self.x0 + u * self.sx;
        let y = self.y0 + (u * self.rxy + v * (1.0 - self.rxy * self.rxy).sqrt()) * self.sy;
        V3::new(-x, -y, 1.0).normalize()
    }
    /// Mean normal ω_n̄ ∝ (−x̄, −ȳ, 1).
    pub fn mean_normal(&self) -> V3 {
        V3::new(-self.x0, -self.y0, 1.0).normalize()
    }
}

/// The artificial micronormal of seed 001 §3.7: ω̃ = normalize(ω_n̄ − ε(ω_n̄·ω_o)ω_o), used
/// with weight `weight` (paper: ε = 1.01, weight 1e-5).
pub fn artificial_micronormal(mean: &V3, v: &V3, eps: f64) -> V3 {
    (mean - v * (eps * mean.dot(v))).normalize()
}

/// The N×N grid estimate. `shade(N)` is L(reflect(−V, N)) for specular or E(N) for
/// diffuse. With `artificial = Some((ε, weight))` the §3.7 micronormal is added, so the
/// result stays defined when every grid normal faces away from V (silhouettes).
pub fn grid_estimate(
    g: &Grid,
    s: &Slopes,
    v: &V3,
    shade: &dyn Fn(&V3) -> f64,
    artificial: Option<(f64, f64)>,
) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (pi, wi) in g.nodes.iter().zip(&g.weights) {
        for (pj, wj) in g.nodes.iter().zip(&g.weights) {
            let n = s.normal(*pi, *pj);
            let sa = v.dot(&n).max(0.0) / n.z;
            if sa > 0.0 {
                let w = wi * wj * sa;
                num += w * shade(&n);
                den += w;
            }
        }
    }
    if let Some((eps, weight)) = artificial {
        let n = artificial_micronormal(&s.mean_normal(), v, eps);
        let sa = v.dot(&n).max(0.0) / n.z.abs().max(1e-300);
        num += weight * sa * shade(&n);
        den += weight * sa;
    }
    num / den
}

/// Reference: the same ratio with the Gaussian density, by nested adaptive G7–K15 over
/// (u, v) ∈ [−9, 9]² (mass outside < 1e-18), the kink of max(0, V·N) resolved adaptively.
pub fn reference(s: &Slopes, v: &V3, shade: &dyn Fn(&V3) -> f64, tol: f64) -> Result<f64> {
    let phi = |t: f64| (-0.5 * t * t).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let inner = |u: f64, with_shade: bool| {
        let f = |w: f64| {
            let n = s.normal(u, w);
            let sa = v.dot(&n).max(0.0) / n.z;
            if sa == 0.0 {
                return 0.0;
            }
            phi(w) * sa * if with_shade { shade(&n) } else { 1.0 }
        };
        gk15(&f, -9.0, 9.0, Tol::new(tol * 1e-2, tol * 1e-2, 2_000_000))
    };
    let outer = |with_shade: bool| {
        let eval = |xs: &[f64; 15]| {
            let mut v = [0.0; 15];
            let mut e = [0.0; 15];
            let mut n = 0;
            for (i, &u) in xs.iter().enumerate() {
                let r = inner(u, with_shade);
                v[i] = phi(u) * r.value;
                e[i] = phi(u) * r.error;
                n += r.evals;
            }
            (v, e, n)
        };
        adaptive_batched(
            &eval,
            &[-9.0, -3.0, 0.0, 3.0, 9.0],
            Tol::new(tol, tol, 50_000_000),
        )
    };
    let (num, den) = (outer(true), outer(false));
    if !(den.value > 0.0) {
        return Err(Error::InvalidArgument(
            "reference: the view sees no micronormal (projected area 0)".into(),
        ));
    }
    Ok(num.value / den.value)
}

/// One shading configuration of the study.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Config {
    pub sigma: f64,
    pub theta_o_deg: f64,
    pub specular: bool,
}

/// The smooth test environment (sky gradient + a κ = 50 sun) and light of the study.
fn shade_for(c: &Config, v: V3) -> impl Fn(&V3) -> f64 {
    let sun = V3::new(0.5, 0.2, 0.8).normalize();
    let light = V3::new(-0.3, 0.4, 0.87).normalize();
    let spec = c.specular;
    move |n: &V3| {
        if spec {
            let r = n * (2.0 * n.dot(&v)) - v;
            0.5 + 0.5 * r.z + 10.0 * (50.0 * (r.dot(&sun) - 1.0)).exp()
        } else {
            n.dot(&light).max(0.0)
        }
    }
}

fn view(c: &Config) -> V3 {
    let t = c.theta_o_deg.to_radians();
    V3::new(t.sin() * 0.4f64.cos(), t.sin() * 0.4f64.sin(), t.cos())
}

/// The paper's spacing rule: 0.9, shrunk so that no node lies beyond ±3 (seed 001 §3.4).
pub fn paper_spacing(n: usize) -> f64 {
    if n < 2 {
        return 0.9;
    }
    0.9f64.min(6.0 / (n - 1) as f64)
}

/// Configurations with their reference values.
pub fn configs(sigmas: &[f64], thetas: &[f64]) -> Result<Vec<(Config, f64)>> {
    let mut v = Vec::new();
    for &s in sigmas {
        for &t in thetas {
            for specular in [true, false] {
                let c = Config {
                    sigma: s,
                    theta_o_deg: t,
                    specular,
                };
                let w = view(&c);
                let r = reference(&Slopes::iso(s), &w, &shade_for(&c, w), 1e-10)?;
                v.push((c, r));
            }
        }
    }
    Ok(v)
}

/// (RMS, max) relative error of a grid over configurations of one kind.
pub fn grid_error(g: &Grid, set: &[(Config, f64)], specular: bool) -> (f64, f64) {
    let errs: Vec<f64> = set
        .iter()
        .filter(|(c, _)| c.specular == specular)
        .map(|(c, r)| {
            let w = view(c);
            ((grid_estimate(g, &Slopes::iso(c.sigma), &w, &shade_for(c, w), None) - r) / r).abs()
        })
        .collect();
    let rms = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len() as f64).sqrt();
    (rms, errs.iter().cloned().fold(0.0, f64::max))
}

/// Spacing h of an N-point uniform grid minimising the RMS error on `train` (both kinds),
/// by a scan and Brent (argmin).
pub fn fit_spacing(n: usize, train: &[(Config, f64)]) -> f64 {
    let cost = |h: f64| {
        let g = Grid::riemann(n, h);
        let (a, _) = grid_error(&g, train, true);
        let (b, _) = grid_error(&g, train, false);
        a * a + b * b
    };
    let hs: Vec<f64> = (0..=60).map(|i| 0.2 + 2.0 * i as f64 / 60.0).collect();
    crate::optimize::scan_brent(&cost, &hs, (1e-8, 1e-10), 100)
}

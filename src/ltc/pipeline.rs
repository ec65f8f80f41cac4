//! The pieces of the multi-scale shading pipeline of seed 000 §3–4: a fitted LTC table as a
//! renderer samples it (bilinear), a polygon light shaded through it (`ltc_shade`), and the
//! brute force it is judged against — the exact footprint average of each texel's GGX
//! shading of the same polygon (`brute_force`). The comparison over mip levels, with plain
//! LTC on the renormalised mip normal as the aliasing baseline, is the GGX LTC study's.
use crate::error::Result;
use crate::integrate::mc::Strategy;
use crate::ltc::polygon::{self, EdgeForm, Light};
use crate::microfacet::lobe::{Frame, ViewedLobe};
use crate::microfacet::sampling::VndfSampler;
use crate::microfacet::{Microsurface, Roughness};
use nalgebra::{Matrix3, Vector3};
use rand::{Rng, SeedableRng};

type V3 = Vector3<f64>;

/// The fitted table of results/fits/ltc-ggx.json, looked up bilinearly as a GPU samples
/// the ltc_1/ltc_2 textures (r = √α, t = √(1 − cos θ), clamped to the table).
pub struct LtcTable {
    pub n: usize,
    /// cells[j][i] = [a, b, c, d, norm, fresnel]
    pub cells: Vec<Vec<[f64; 6]>>,
}

impl LtcTable {
    /// The f64 cells of a fitted table (`crate::results::ltc::table` reads one).
    pub fn of(t: &super::table::FittedTable) -> LtcTable {
        let cells = (0..t.n)
            .map(|j| (0..t.n).map(|i| *t.cell(i, j)).collect())
            .collect();
        LtcTable { n: t.n, cells }
    }
    /// Bilinear lookup: (M⁻¹, norm) for roughness α and cos θ of the view.
    pub fn lookup(&self, alpha: f64, cos_theta: f64) -> (Matrix3<f64>, f64) {
        let s = (self.n - 1) as f64;
        let u = (alpha.max(0.0).sqrt() * s).clamp(0.0, s);
        let w = ((1.0 - cos_theta.clamp(0.0, 1.0)).sqrt() * s).clamp(0.0, s);
        let (i0, j0) = (u.floor() as usize, w.floor() as usize);
        let (i1, j1) = ((i0 + 1).min(self.n - 1), (j0 + 1).min(self.n - 1));
        let (fu, fw) = (u - i0 as f64, w - j0 as f64);
        let mut p = [0.0; 6];
        for k in 0..6 {
            let c = |j: usize, i: usize| self.cells[j][i][k];
            p[k] = (1.0 - fw) * ((1.0 - fu) * c(j0, i0) + fu * c(j0, i1))
                + fw * ((1.0 - fu) * c(j1, i0) + fu * c(j1, i1));
        }
        (
            crate::ltc::fit::inverse_from_production(&[p[0], p[1], p[2], p[3]]),
            p[4],
        )
    }
}

/// Shading frame around n with its tangent toward the view (as the shipped LTC shaders):
/// T1 = normalize(v − n(n·v)), T2 = n × T1.
fn view_frame(n: &V3, v: &V3) -> Frame {
    let t = v - n * n.dot(v);
    if t.norm() < 1e-12 {
        return Frame::around(*n);
    }
    let t = t.normalize();
    Frame {
        t,
        b: n.cross(&t),
        n: *n,
    }
}

/// LTC shading of a polygon for normal n, roughness α, view v (world; 0 if v is below n's
/// horizon).
pub fn ltc_shade(table: &LtcTable, n: &V3, alpha: f64, v: &V3, light: &Light) -> f64 {
    let c = n.dot(v);
    if c <= 0.0 {
        return 0.0;
    }
    let f = view_frame(n, v);
    let (minv, norm) = table.lookup(alpha, c);
    let local: Vec<V3> = light.vertices.iter().map(|p| f.local(p)).collect();
    norm * polygon::ltc_integral(&minv, &local, EdgeForm::Exact)
}

/// The footprint average of ∫_P f_x(l) dl with each texel's own GGX lobe (as
/// [`brute_force`] estimates it), exactly: one adaptive cubature over the quad light's
/// parallelogram (dω = |n_P·l| dA/|p|², the shading point at the origin) of the texels'
/// mean lobe, to `rel` relative accuracy (a 2×2 start grid, the panels' K15 ⊗ K15 against
/// G7 ⊗ G7 with the kinked-integrand safety factor: a texel's horizon may cross the light).
/// The start grid sets the cost: every evaluation sums all texels' lobes. Measured on 144
/// cases like the GGX study's (its four 64² maps, levels 0–5, two footprints each, its
/// three views; α = 0.05, tolerance 1e-4): an 8×8 start converged
/// every value far beyond its tolerance (bars ≤ 1e-9) at 7.2× the time of this 2×2 start,
/// whose values stay within 1.5e-8 relative of the 8×8's (4×4: 2.3e-9, 1.9×; 1×1: 1.3e-7, 1.2×).
/// The value ± its error bar; a typed error for a light that is not a parallelogram.
pub fn exact_footprint(
    normals: &[V3],
    alpha: f64,
    v: &V3,
    light: &Light,
    rel: f64,
) -> Result<(crate::integrate::Figure<crate::integrate::Quad>, bool)> {
    use crate::integrate::cubature::{cubature, SAFETY_KINKED};
    let s = Microsurface::ggx(Roughness::iso(alpha)?);
    let q = &light.vertices;
    let parallelogram = q.len() == 4
        && (q[2] - (q[1] + q[3] - q[0])).norm() <= 1e-12 * (q[1] - q[0]).norm().max(1.0);
    if !parallelogram || normals.is_empty() {
        return Err(crate::error::Error::InvalidArgument(
            "exact footprint: a parallelogram light and at least one texel".into(),
        ));
    }
    let views: Vec<ViewedLobe> = normals
        .iter()
        .map(|m| ViewedLobe::new(&s, &Frame::around(*m), v))
        .collect();
    let (o, e1, e2) = (q[0], q[1] - q[0], q[3] - q[0]);
    let an = e1.cross(&e2);
    let area = an.norm();
    let ln = an / area;
    let w = 1.0 / normals.len() as f64;
    let integrand = |a: f64, b: f64, out: &mut [f64]| {
        let p = o + e1 * a + e2 * b;
        let r2 = p.norm_squared();
        if !(r2 > 0.0) {
            return;
        }
        let d = p / r2.sqrt();
        let dw = ln.dot(&d).abs() / r2 * area;
        let sum: f64 = views.iter().map(|t| t.eval(&s, &d)).sum();
        out[0] = sum * w * dw;
    };
    let grid = [0.0, 0.5, 1.0];
    let r = cubature(
        integrand,
        &[SAFETY_KINKED],
        &grid,
        &grid,
        |v| vec![1.0 / v[0].abs().max(1e-300)],
        |v, e| e[0] <= (rel * v[0].abs()).max(1e-14),
        200_000_000 / normals.len() as u64 + 100_000,
    );
    Ok((
        crate::integrate::Figure::<crate::integrate::Quad>::new(r.value[0], r.error[0]),
        r.converged,
    ))
}

/// Brute force: the footprint average of ∫_P f_x(l) dl with each texel's own GGX lobe
/// (D·G2/(4 n_x·v), directions also above the geometric horizon), by Monte Carlo:
/// texels in round robin, one light-area and one VNDF sample each, balance heuristic.
pub fn brute_force(
    normals: &[V3],
    alpha: f64,
    v: &V3,
    light: &Light,
    n: usize,
    seed: u64,
) -> Result<(f64, f64)> {
    let s = Microsurface::ggx(Roughness::iso(alpha)?);
    let frames: Vec<Frame> = normals.iter().map(|m| Frame::around(*m)).collect();
    let views: Vec<ViewedLobe> = frames.iter().map(|f| ViewedLobe::new(&s, f, v)).collect();
    let samplers: Vec<Option<VndfSampler>> = frames
        .iter()
        .map(|f| {
            let vl = f.local(v);
            if vl.z > 1e-9 {
                VndfSampler::new(s, vl).ok()
            } else {
                None
            }
        })
        .collect();
    let v4 = &light.vertices;
    let mut an = V3::zeros();
    for k in 1..v4.len() - 1 {
        an += (v4[k] - v4[0]).cross(&(v4[k + 1] - v4[0]));
    }
    let area = 0.5 * an.norm();
    if !(area > 0.0) {
        return Ok((0.0, 0.0));
    }
    let ln = an.normalize();
    let pdf_light = |d: &V3| -> f64 {
        let dn = d.dot(&ln);
        if dn.abs() < 1e-300 {
            return 0.0;
        }
        let t = v4[0].dot(&ln) / dn;
        if t <= 0.0 || !hit(light, d, &ln, t) {
            return 0.0;
        }
        t * t / (area * dn.abs())
    };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let (mut sum, mut sum2) = (0.0, 0.0);
    for k in 0..n {
        let ti = k % normals.len();
        let (f, sampler, view) = (&frames[ti], &samplers[ti], &views[ti]);
        let pdf_brdf = |d: &V3| -> f64 {
            match sampler {
                Some(smp) => {
                    let (vl, ll) = (f.local(v), f.local(d));
                    if ll.z <= 0.0 {
                        return 0.0;
                    }
                    let h = (vl + ll).normalize();
                    smp.pdf_exact(&h) / (4.0 * vl.dot(&h))
                }
                None => 0.0,
            }
        };
        let mut x = 0.0;
        // light sample
        let (a, b, c) = (
            rng.random::<f64>(),
            rng.random::<f64>(),
            rng.random::<f64>(),
        );
        let p = sample_quad(light, [a, b, c]);
        let d = p.normalize();
        let val = view.eval(&s, &d);
        if val > 0.0 {
            x += val / (pdf_light(&d) + pdf_brdf(&d));
        }
        // BRDF sample
        if let Some(smp) = sampler {
            if let Some(m) = smp.sample([rng.random(), rng.random()]) {
                let h = f.world(&m);
                let d = h * (2.0 * v.dot(&h)) - v;
                let pl = pdf_light(&d);
                if pl > 0.0 {
                    let val = view.eval(&s, &d);
                    if val > 0.0 {
                        x += val / (pl + pdf_brdf(&d));
                    }
                }
            }
        }
        sum += x;
        sum2 += x * x;
    }
    let m = sum / n as f64;
    Ok((m, ((sum2 / n as f64 - m * m).max(0.0) / n as f64).sqrt()))
}

fn hit(light: &Light, d: &V3, ln: &V3, t: f64) -> bool {
    let p = d * t;
    let v = &light.vertices;
    let mut sign = 0.0;
    for k in 0..v.len() {
        let e = v[(k + 1) % v.len()] - v[k];
        let s = e.cross(&(p - v[k])).dot(ln);
        if sign == 0.0 {
            sign = s.signum();
        } else if s * sign < 0.0 {
            return false;
        }
    }
    true
}

fn sample_quad(light: &Light, u: [f64; 3]) -> V3 {
    // two triangles of a quad (convex), chosen by area
    let v = &light.vertices;
    let a1 = 0.5 * (v[1] - v[0]).cross(&(v[2] - v[0])).norm();
    let a2 = 0.5 * (v[2] - v[0]).cross(&(v[3] - v[0])).norm();
    let (p1, p2) = if u[0] * (a1 + a2) < a1 {
        (v[1], v[2])
    } else {
        (v[2], v[3])
    };
    let (mut s, mut t) = (u[1], u[2]);
    if s + t > 1.0 {
        s = 1.0 - s;
        t = 1.0 - t;
    }
    v[0] + (p1 - v[0]) * s + (p2 - v[0]) * t
}

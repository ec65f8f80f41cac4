//! The approximations as an engine shades them: one sample at the pixel centre, the map
//! read through its mip chain at the footprint's level, the roughness filter and the
//! lobe evaluated by the shipped f32 code — the generated twins of the WGSL
//! (`crate::generated::shading`), the f32 forms of `crate::filters::rules`, and the GGX
//! LTC table in the binary16 storage every texture ships (`crate::generated::ltc_table`,
//! bilinear as the sampler reads it), quad lights batched through the SIMD kernel
//! `kernels::ltc_quad` ([`shade_image`]). A G-buffer pass first stores what a deferred
//! renderer would (normal, view, footprint statistics), then each method shades every
//! pixel with its 2×2 quad's derivatives (coarse, as `dpdx`/`dpdy` form them).

use super::geometry::{footprint, Camera, Hit, Surface};
use super::light::Light;
use super::texture::Texture;
use super::truth::shading_frame;
use crate::filters::footprint::Stats;
use crate::filters::registry::{Filter, MapRule, Rule, ScreenRule};
use crate::filters::rules;
use crate::generated::ltc_table::{LTC_1_F16, LTC_2_F16, LTC_TABLE_N};
use crate::generated::shading as gs;
use crate::microfacet::lobe::Frame;
use half::f16;
use nalgebra::Vector3;
use rayon::prelude::*;
use serde::Serialize;

type V3 = Vector3<f64>;

/// What the G-buffer holds for one pixel.
#[derive(Clone, Copy, Debug)]
pub struct GPixel {
    pub hit: Hit,
    /// Unit view direction (world).
    pub view: V3,
    pub stats: Stats,
    /// The renormalised filtered normal, tangent space and world space.
    pub n_t: V3,
    pub n_w: V3,
}

/// The G-buffer of one frame: `None` where the centre ray misses.
pub fn gbuffer(cam: &Camera, surf: &Surface, tex: &Texture) -> Vec<Option<GPixel>> {
    (0..cam.width * cam.height)
        .into_par_iter()
        .map(|k| {
            let (x, y) = ((k % cam.width) as f64 + 0.5, (k / cam.width) as f64 + 0.5);
            let d = cam.dir(x, y);
            let hit = surf.intersect(&cam.eye, &d)?;
            let fp = footprint(cam, &hit, x, y);
            let stats = tex.stats(hit.uv, tex.lod(&fp));
            let mu = V3::from(stats.mean_normal);
            let n_t = if mu.norm() > 1e-12 {
                mu.normalize()
            } else {
                V3::z()
            };
            Some(GPixel {
                hit,
                view: -d,
                stats,
                n_t,
                n_w: hit.frame.world(&n_t),
            })
        })
        .collect()
}

/// The multiscale set's methods (map filters of the registry), in report order.
pub const MULTISCALE: [&str; 6] = [
    "mip-normal",
    "seed000-eq5-eq7",
    "seed000-moment",
    "vmf-2",
    "vmf-refit",
    "lean",
];

/// The specular-AA set's methods (kernels of the registry), in report order.
pub const SPECULAR_AA: [&str; 9] = [
    "none",
    "tokuyoshi-deferred",
    "eq13-refit-box",
    "tokuyoshi-forward",
    "kaplanyan-rect",
    "filament",
    "unity-projected",
    "godot",
    "godot-refit-box",
];

/// A footprint filter of the registry ([`crate::filters::registry`]) as the renderer
/// shades it: its rule resolved once, a refitted filter's with its constant.
#[derive(Clone, Copy, Debug)]
pub struct Method {
    pub filter: Filter,
    rule: Rule,
    constant: Option<f64>,
}

impl Method {
    /// The method of a registry key, with the refitted constants of `c`.
    pub fn new(key: &str, c: &Constants) -> crate::error::Result<Method> {
        let filter = Filter::get(key, "render method")?;
        let constant = filter.family().and_then(|f| c.constant(f));
        Ok(Method {
            filter,
            rule: filter.rule_with(|f| c.constant(f))?,
            constant,
        })
    }

    /// Short file-name key.
    pub fn key(self) -> &'static str {
        self.filter.key()
    }

    /// The name in reports, with a refitted filter's constant.
    pub fn label(self) -> String {
        self.filter.label_with(self.constant)
    }
}

/// The refitted constants the methods read (results/fits/filters.json `fitted`, GGX, by
/// family) and the per-material constant y_mi = 1 − ρ(α) of the product identity,
/// computed once per material as an engine would ([`Constants::with_alpha`]), not per pixel.
#[derive(Clone, Debug, Serialize)]
pub struct Constants {
    pub fitted: Vec<(String, f64)>,
    /// 1 − ρ(α_base) (NaN until [`Constants::with_alpha`] sets it).
    pub y_mi: f32,
}

impl Constants {
    /// The same constants for a material of base roughness α.
    pub fn with_alpha(self, alpha: f64) -> Constants {
        Constants {
            y_mi: (1.0 - crate::multiscale::mrl::mrl(alpha)) as f32,
            ..self
        }
    }

    /// The GGX constant of a fitted family.
    pub fn constant(&self, family: &str) -> Option<f64> {
        self.fitted.iter().find(|f| f.0 == family).map(|f| f.1)
    }
}

/// The filtered lobe a method hands to the shading code.
enum Filtered {
    Iso {
        n_w: V3,
        alpha: f32,
    },
    /// Roughness matrix (xx, yy, xy) in `frame` (world; z the filtered normal).
    Matrix {
        frame: Frame,
        a: [f32; 3],
    },
}

/// The 2×2 quad of pixel k: (n00, n10, n01) world normals, the top-left's frame.
fn quad(g: &[Option<GPixel>], w: usize, k: usize) -> Option<[GPixel; 4]> {
    let (x0, y0) = ((k % w) & !1, (k / w) & !1);
    let at = |x: usize, y: usize| g.get(y * w + x).copied().flatten();
    Some([
        at(x0, y0)?,
        at(x0 + 1, y0)?,
        at(x0, y0 + 1)?,
        at(x0 + 1, y0 + 1)?,
    ])
}

fn a3(v: V3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// The point (or directional) lights' unit direction and irradiance at p.
fn light_dir(light: &Light, p: &V3) -> Option<(V3, f64)> {
    match light {
        Light::Point { pos, intensity } => {
            let d = pos - p;
            let r2 = d.norm_squared();
            Some((d / r2.sqrt(), intensity / r2))
        }
        Light::Directional { dir, irradiance } => Some((*dir, *irradiance)),
        Light::Quad { .. } | Light::Sg(_) => None,
    }
}

fn filter(
    m: Method,
    alpha: f32,
    gp: &GPixel,
    q: Option<&[GPixel; 4]>,
    lights: &[Light],
    c: &Constants,
) -> Filtered {
    let r = gs_r(&gp.stats);
    let iso = |a: f32| Filtered::Iso {
        n_w: gp.n_w,
        alpha: a.max(1e-4),
    };
    // coarse derivatives of the world normal across the quad (zero at a silhouette)
    let (du, dv) = match q {
        Some(q) => (q[1].n_w - q[0].n_w, q[2].n_w - q[0].n_w),
        None => (V3::zeros(), V3::zeros()),
    };
    let (du3, dv3) = (a3(du), a3(dv));
    let f = |x: f64| x as f32;
    match m.rule {
        Rule::Map(MapRule::Lean) => lean(alpha, gp),
        // the generated shading functions where the crate ships one, as engines call them
        Rule::Map(MapRule::Moment) => iso(gs::multiscale_alpha(1.0 - r, c.y_mi)),
        Rule::Map(MapRule::Vmf(k)) => iso(gs::filter_vmf(alpha, r, f(k))),
        Rule::Map(rule) => iso(rule.alpha(alpha, r, || f32::NAN).unwrap_or(alpha)),
        Rule::Screen(ScreenRule::Deferred { s2, delta }) => iso(gs::filter_deferred(
            alpha,
            du3[0],
            du3[1],
            du3[2],
            dv3[0],
            dv3[1],
            dv3[2],
            f(s2),
            f(delta),
        )),
        Rule::Screen(ScreenRule::ProjectedSpace { s2, delta }) => iso(gs::filter_projected(
            alpha,
            du3[0],
            du3[1],
            du3[2],
            dv3[0],
            dv3[1],
            dv3[2],
            f(s2),
            f(delta),
        )),
        Rule::Screen(rule @ (ScreenRule::None | ScreenRule::DeferredOnAlpha { .. })) => {
            iso(rule.alpha_from_normals(alpha, du3, dv3).unwrap_or(alpha))
        }
        Rule::Screen(rule @ (ScreenRule::KaplanyanRect { .. } | ScreenRule::Eigen { .. })) => {
            let Some(q) = q else { return iso(alpha) };
            // Listing 3 as intended: slopes in the quad average's frame; Eq 10: the
            // projected disk of the top-left pixel's frame
            let rect = matches!(rule, ScreenRule::KaplanyanRect { .. });
            let fr = if rect {
                Frame::around((q[0].n_w + q[1].n_w + q[2].n_w + q[3].n_w).normalize())
            } else {
                Frame::around(q[0].n_w)
            };
            let s = |n: &V3| {
                let l = fr.local(n);
                if rect {
                    [(l.x / l.z.abs()) as f32, (l.y / l.z.abs()) as f32]
                } else {
                    [l.x as f32, l.y as f32]
                }
            };
            let (s0, s1, s2) = (s(&q[0].n_w), s(&q[1].n_w), s(&q[2].n_w));
            let d = |a: [f32; 2]| [a[0] - s0[0], a[1] - s0[1]];
            iso(rule.alpha_from_2d(alpha, d(s1), d(s2)).unwrap_or(alpha))
        }
        Rule::Screen(ScreenRule::Forward { slope }) => {
            // the half-vector of the first point/directional light, on each pixel's own
            // projected disk (seed 003 Eq 7) or in its slope space (Eq 2)
            let Some(q) = q else { return iso(alpha) };
            let Some(light) = lights
                .iter()
                .find(|l| matches!(l, Light::Point { .. } | Light::Directional { .. }))
            else {
                return iso(alpha);
            };
            let h = |p: &GPixel| -> [f32; 2] {
                let (l, _) = light_dir(light, &p.hit.p).unwrap_or((V3::z(), 0.0));
                let hl = Frame::around(p.n_w).local(&(p.view + l).normalize());
                if slope {
                    [(-hl.x / hl.z) as f32, (-hl.y / hl.z) as f32]
                } else {
                    [hl.x as f32, hl.y as f32]
                }
            };
            let (h0, h1, h2) = (h(&q[0]), h(&q[1]), h(&q[2]));
            let a = rules::forward_matrix(
                alpha,
                [h1[0] - h0[0], h1[1] - h0[1]],
                [h2[0] - h0[0], h2[1] - h0[1]],
                0.25,
            );
            Filtered::Matrix {
                frame: Frame::around(gp.n_w),
                a,
            }
        }
    }
}

/// LEAN: A = α²I + 2Σ about the mean slope's normal, the covariance's axes kept in the
/// tangent frame.
fn lean(alpha: f32, gp: &GPixel) -> Filtered {
    let cov = gp.stats.covariance().map(|x| x as f32);
    let a = rules::lean(alpha, cov);
    let ms = gp.stats.mean_slope();
    let n_t = V3::new(-ms.x, -ms.y, 1.0).normalize();
    let n_w = gp.hit.frame.world(&n_t);
    let t = gp.hit.frame.t - n_w * n_w.dot(&gp.hit.frame.t);
    Filtered::Matrix {
        frame: Frame {
            t: t.normalize(),
            b: n_w.cross(&t.normalize()),
            n: n_w,
        },
        a,
    }
}

/// |μ| of the filtered statistics, as the f32 texture fetch returns it.
fn gs_r(s: &Stats) -> f32 {
    let m = s.mean_normal.map(|x| x as f32);
    (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt()
}

/// The GGX LTC table as shipped (binary16), bilinear at (α, cos θ) like the sampler:
/// ((a, b, c, d), norm) in f32.
pub fn ltc_lookup(alpha: f32, cos_theta: f32) -> ([f32; 4], f32) {
    let n = LTC_TABLE_N;
    let r = alpha.clamp(0.0, 1.0).sqrt();
    let t = (1.0 - cos_theta.clamp(0.0, 1.0)).sqrt();
    let (x, y) = (r * (n - 1) as f32, t * (n - 1) as f32);
    let (i0, j0) = (
        (x.floor() as usize).min(n - 2),
        (y.floor() as usize).min(n - 2),
    );
    let (fx, fy) = (x - i0 as f32, y - j0 as f32);
    let un = |p: u32| {
        [
            f16::from_bits(p as u16).to_f32(),
            f16::from_bits((p >> 16) as u16).to_f32(),
        ]
    };
    let texel = |i: usize, j: usize| -> [f32; 5] {
        let k = i + n * j;
        let (ab, cd, m) = (
            un(LTC_1_F16[k][0]),
            un(LTC_1_F16[k][1]),
            un(LTC_2_F16[k][0]),
        );
        [ab[0], ab[1], cd[0], cd[1], m[0]]
    };
    let (c00, c10, c01, c11) = (
        texel(i0, j0),
        texel(i0 + 1, j0),
        texel(i0, j0 + 1),
        texel(i0 + 1, j0 + 1),
    );
    let v: [f32; 5] = std::array::from_fn(|c| {
        (c00[c] * (1.0 - fx) + c10[c] * fx) * (1.0 - fy) + (c01[c] * (1.0 - fx) + c11[c] * fx) * fy
    });
    ([v[0], v[1], v[2], v[3]], v[4])
}

/// The SHA-256 (lower-case hex) of the GGX LTC table the methods shade with: for every
/// texel k = i + n·j in turn, its three words `LTC_1_F16[k][0]`, `LTC_1_F16[k][1]`,
/// `LTC_2_F16[k][0]` as little-endian u32 (binary16 pairs, the first in bits 0–15). The
/// render study records it, so that a refit the render was not rerun after is caught
/// (tests/results.rs recomputes it from results/fits/ltc-ggx.json's `table_f16`).
pub fn ltc_table_sha256() -> String {
    let n = LTC_TABLE_N;
    let mut bytes = Vec::with_capacity(n * n * 12);
    for k in 0..n * n {
        for w in [LTC_1_F16[k][0], LTC_1_F16[k][1], LTC_2_F16[k][0]] {
            bytes.extend_from_slice(&w.to_le_bytes());
        }
    }
    crate::io::sha256_hex(&bytes)
}

/// One quad light's LTC evaluation at a pixel: the table's (a, b, c, d) and the quad's
/// vertices in the shading frame (x toward the view), to be integrated by
/// `generated::shading::ltc_quad` (or its SIMD kernel) and multiplied by `scale`
/// (radiance × the table's norm).
#[derive(Clone, Copy, Debug)]
pub struct LtcJob {
    pub m: [f32; 4],
    pub p: [f32; 12],
    pub scale: f32,
}

fn ltc_job(light: &Light, gp: &GPixel, n_w: &V3, alpha: f32) -> Option<LtcJob> {
    let (Some(cs), Light::Quad { radiance, .. }) = (light.corners(), light) else {
        return None;
    };
    let f = shading_frame(n_w, &gp.view);
    let cos_v = gp.view.dot(n_w).clamp(0.0, 1.0) as f32;
    let (m, norm) = ltc_lookup(alpha, cos_v);
    let mut p = [0.0f32; 12];
    for (k, c) in cs.iter().enumerate() {
        p[3 * k..3 * k + 3].copy_from_slice(&a3(f.local(&(c - gp.hit.p))));
    }
    Some(LtcJob {
        m,
        p,
        scale: *radiance as f32 * norm,
    })
}

impl LtcJob {
    /// The scalar twin's value.
    pub fn scalar(&self) -> f32 {
        let (m, p) = (&self.m, &self.p);
        self.scale
            * gs::ltc_quad(
                m[0], m[1], m[2], m[3], p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9],
                p[10], p[11],
            )
    }
}

/// GGX with the roughness matrix A in frame f, D by `ggx_d_matrix` and Smith's G2 with
/// each direction's projected roughness (exact for the anisotropic GGX).
fn matrix_specular(f: &Frame, a: [f32; 3], v: &V3, l: &V3) -> f32 {
    let (vl, ll) = (f.local(v), f.local(l));
    if vl.z <= 0.0 || ll.z <= 0.0 {
        return 0.0;
    }
    let h = (vl + ll).normalize();
    let (h3, v3, l3) = (a3(h), a3(vl), a3(ll));
    let d = gs::ggx_d_matrix(h3[0], h3[1], h3[2], a[0], a[2], a[1]);
    let proj = |o: [f32; 3]| {
        let q = o[0] * o[0] + o[1] * o[1];
        if q > 0.0 {
            ((a[0] * o[0] * o[0] + 2.0 * a[2] * o[0] * o[1] + a[1] * o[1] * o[1]) / q)
                .max(0.0)
                .sqrt()
        } else {
            a[0].max(a[1]).sqrt()
        }
    };
    let lv = gs::ggx_lambda(v3[0], v3[1], v3[2], proj(v3));
    let ll_ = gs::ggx_lambda(l3[0], l3[1], l3[2], proj(l3));
    d / (4.0 * v3[2] * (1.0 + lv + ll_))
}

/// The radiance of pixel `k` by method `m` without its quad lights, and the quad lights'
/// LTC jobs; (0, none) where the centre ray misses or the surface faces away.
pub fn shade_parts(
    m: Method,
    g: &[Option<GPixel>],
    w: usize,
    k: usize,
    alpha: f32,
    lights: &[Light],
    c: &Constants,
) -> (f32, Vec<LtcJob>) {
    let Some(gp) = g[k] else {
        return (0.0, Vec::new());
    };
    // the geometric horizon: a surface facing away from the eye reflects nothing
    if gp.view.dot(&gp.hit.frame.n) <= 0.0 {
        return (0.0, Vec::new());
    }
    let q = quad(g, w, k);
    let flt = filter(m, alpha, &gp, q.as_ref(), lights, c);
    let mut sum = 0.0f32;
    let mut jobs = Vec::new();
    for light in lights {
        match (&flt, light_dir(light, &gp.hit.p)) {
            (Filtered::Iso { n_w, alpha }, Some((l, e))) => {
                let f = Frame::around(*n_w);
                let (vl, ll) = (a3(f.local(&gp.view)), a3(f.local(&l)));
                sum += e as f32 * gs::ggx_specular(ll[0], ll[1], ll[2], vl[0], vl[1], vl[2], *alpha)
            }
            (Filtered::Matrix { frame, a }, Some((l, e))) => {
                sum += e as f32 * matrix_specular(frame, *a, &gp.view, &l)
            }
            (Filtered::Iso { n_w, alpha }, None) => jobs.extend(ltc_job(light, &gp, n_w, *alpha)),
            (Filtered::Matrix { frame, a }, None) => {
                let det = (a[0] * a[1] - a[2] * a[2]).max(0.0);
                jobs.extend(ltc_job(light, &gp, &frame.n, det.sqrt().sqrt()))
            }
        }
    }
    (sum, jobs)
}

/// The radiance of pixel `k` by method `m` (quad lights by the scalar twin); 0 where the
/// centre ray misses.
pub fn shade(
    m: Method,
    g: &[Option<GPixel>],
    w: usize,
    k: usize,
    alpha: f32,
    lights: &[Light],
    c: &Constants,
) -> f32 {
    let (sum, jobs) = shade_parts(m, g, w, k, alpha, lights, c);
    sum + jobs.iter().map(|j| j.scalar()).sum::<f32>()
}

/// A whole image by method `m`: the direct lights per pixel (rayon), then every quad
/// light's LTC integral in one call of the SIMD kernel `kernels::ltc_quad` (AVX2 + FMA
/// where the CPU has it, the scalar twin otherwise) over all pixels in order — one call,
/// so the bits do not depend on the thread count.
pub fn shade_image(
    m: Method,
    g: &[Option<GPixel>],
    w: usize,
    alpha: f32,
    lights: &[Light],
    c: &Constants,
) -> crate::error::Result<Vec<f32>> {
    let parts: Vec<(f32, Vec<LtcJob>)> = (0..g.len())
        .into_par_iter()
        .map(|k| shade_parts(m, g, w, k, alpha, lights, c))
        .collect();
    let owner: Vec<usize> = parts
        .iter()
        .enumerate()
        .flat_map(|(k, (_, j))| std::iter::repeat_n(k, j.len()))
        .collect();
    let jobs: Vec<&LtcJob> = parts.iter().flat_map(|(_, j)| j.iter()).collect();
    let col = |f: &dyn Fn(&LtcJob) -> f32| -> Vec<f32> { jobs.iter().map(|j| f(j)).collect() };
    let mc: [Vec<f32>; 4] = std::array::from_fn(|i| col(&|j| j.m[i]));
    let pc: [Vec<f32>; 12] = std::array::from_fn(|i| col(&|j| j.p[i]));
    let mut out = vec![0.0f32; jobs.len()];
    let inp = crate::kernels::LtcQuadIn {
        m: std::array::from_fn(|i| mc[i].as_slice()),
        p: std::array::from_fn(|i| pc[i].as_slice()),
    };
    crate::kernels::ltc_quad(crate::kernels::Backend::best(), &inp, &mut out)?;
    let mut img: Vec<f32> = parts.iter().map(|(s, _)| *s).collect();
    for ((k, j), v) in owner.iter().zip(&jobs).zip(&out) {
        img[*k] += j.scale * v;
    }
    Ok(img)
}

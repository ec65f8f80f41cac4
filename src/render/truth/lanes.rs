//! The truth's sampled lights four samples at a time (`crate::lanes`), each of its own
//! texel or the same: each sample's direction is drawn as [`Shader::sampled_at`] draws
//! it, then the four densities of the lobes' visible normals and the four lobe values,
//! whose chains of roots and divisions dominate a sample, step by step across the lanes.
//! Each lane performs the one-sample form's operations in their order, so its bits are
//! `sampled_at`'s (`tests::four_samples_are_the_one_sample_bits`).

use super::{Shader, Viewed, V3};
use crate::lanes::{map, Dirs, Lanes, LANES};
use crate::microfacet::lobe::ViewedLobe;
use crate::microfacet::sampling::VndfSampler;
use crate::render::geometry::Hit;
use crate::render::light::Light;

/// One light sample of the truth: the texel's prepared lobe, its hit and its normal.
pub(super) type At<'w> = (&'w Viewed, &'w Hit, &'w V3);

impl Shader<'_> {
    /// [`Shader::sampled_at`] of the uniforms `u[i]` at texel `at[i]`, lane by lane (one
    /// texel may fill several lanes).
    pub(super) fn sampled_lanes(&self, at: [At; LANES], u: [[f64; 3]; LANES]) -> Lanes {
        // `Iterator::sum`'s fold, light by light, from its own starting value
        let mut sum = [std::iter::empty::<f64>().sum::<f64>(); LANES];
        for light in self.lights {
            let q = match light {
                Light::Quad { .. } => self.quad_lanes(light, at, &u),
                Light::Sg(env) => map(|i| {
                    let (w, hit, nt) = at[i];
                    self.sg_sample(env, hit, w, nt, u[i])
                }),
                _ => [0.0; LANES],
            };
            for i in 0..LANES {
                sum[i] += q[i];
            }
        }
        sum
    }

    /// [`Shader::exact_at`] of each texel: the point and directional lights' terms, with
    /// every (texel, light) pair whose direction is above the hit's horizon evaluated four
    /// pairs at a time across texels and lights where the lobe is a microfacet one
    /// (`ViewedLobe::eval_lanes`; a pair below it is `ViewedLobe::eval`'s immediate 0, kept
    /// out of the lanes, which a sky's lights below the horizon would otherwise fill with
    /// work whose value is 0), then each texel's terms summed light by light from 0 as
    /// `exact_at` sums them. Each term has `exact_at`'s bits, so each sum has
    /// (`tests::exact_lights_across_texels_are_exact_at`).
    pub(super) fn exact_texels(&self, at: &[At]) -> Vec<f64> {
        let nl = self.lights.len();
        // per (texel, light), texel-major: its factor and value; the sampled lights' are 0
        let mut terms: Vec<Option<(f64, f64)>> = Vec::with_capacity(at.len() * nl);
        // the pairs whose values the lanes compute: (index into terms, lobe, direction)
        let mut pending: Vec<(usize, &ViewedLobe, V3)> = Vec::new();
        for &(w, hit, nt) in at {
            for light in self.lights {
                let Some((c, l)) = Self::exact_light(light, hit) else {
                    terms.push(None);
                    continue;
                };
                let value = match &w.lobe {
                    // `ViewedLobe::eval`'s first test: 0 at once below the horizon
                    Some(_) if l.z <= 0.0 => 0.0,
                    Some(g) => {
                        pending.push((terms.len(), g, l));
                        0.0
                    }
                    None => self.lobe_in(&w.sf, nt, &w.v, &l),
                };
                terms.push(Some((c, value)));
            }
        }
        for group in pending.chunks(LANES) {
            let pick = |i: usize| &group[i.min(group.len() - 1)];
            let l = Dirs::of(&std::array::from_fn::<V3, LANES, _>(|i| pick(i).2));
            let f = ViewedLobe::eval_lanes(&self.surface, std::array::from_fn(|i| pick(i).1), &l);
            for (i, (k, _, _)) in group.iter().enumerate() {
                if let Some((_, v)) = &mut terms[*k] {
                    *v = f[i];
                }
            }
        }
        (0..at.len())
            .map(|t| {
                let mut sum = 0.0;
                for term in &terms[t * nl..(t + 1) * nl] {
                    sum += match term {
                        Some((c, v)) => c * v,
                        None => 0.0,
                    };
                }
                sum
            })
            .collect()
    }

    /// `quad_sample` of `u[i]` at `at[i]` in lane i.
    fn quad_lanes(&self, light: &Light, at: [At; LANES], u: &[[f64; 3]; LANES]) -> Lanes {
        let Light::Quad { radiance, .. } = light else {
            return [0.0; LANES];
        };
        let mix = map(|i| Self::quad_mix(at[i].0));
        let drawn: [Option<(V3, f64)>; LANES] = std::array::from_fn(|i| {
            let (w, hit, _) = at[i];
            Self::quad_direction(light, hit, w, u[i], mix[i])
        });
        // each direction in its hit's frame; lost lanes carry the frame's normal, and
        // their values are chosen 0 below
        let l: [V3; LANES] = std::array::from_fn(|i| {
            let fr = &at[i].1.frame;
            fr.local(&drawn[i].map_or(fr.n, |(lw, _)| lw))
        });
        let brdf = self.brdf_pdf_lanes(at, &l);
        let f = match at.map(|a| a.0.lobe.as_ref()) {
            [Some(a), Some(b), Some(c), Some(d)] => {
                ViewedLobe::eval_lanes(&self.surface, [a, b, c, d], &Dirs::of(&l))
            }
            _ => map(|i| {
                let (w, _, nt) = at[i];
                self.lobe_at(w, nt, &l[i])
            }),
        };
        map(|i| {
            let Some((_, area_pdf)) = drawn[i] else {
                return 0.0;
            };
            let pdf = mix[i] * area_pdf + (1.0 - mix[i]) * brdf[i];
            if !(pdf > 0.0) {
                return 0.0;
            }
            radiance * f[i] / pdf
        })
    }

    /// The density of direction `l[i]` (in its hit's frame) under lane i's visible-normal
    /// sampling, as `quad_sample`'s `brdf_pdf` computes it (0 without a sampler).
    fn brdf_pdf_lanes(&self, at: [At; LANES], l: &[V3; LANES]) -> Lanes {
        let Some(any) = at.iter().find_map(|a| a.0.vndf.as_ref()) else {
            return [0.0; LANES];
        };
        let vndf = |i: usize| at[i].0.vndf.as_ref().unwrap_or(any);
        let ls: [V3; LANES] = std::array::from_fn(|i| vndf(i).1.local(&l[i]));
        let hs = Dirs {
            x: map(|i| vndf(i).2.x + ls[i].x),
            y: map(|i| vndf(i).2.y + ls[i].y),
            z: map(|i| vndf(i).2.z + ls[i].z),
        };
        let hn = hs.norm();
        let h = hs.over(&hn);
        let pdf = VndfSampler::pdf_lanes(std::array::from_fn(|i| &vndf(i).0), &h);
        let vh = map(|i| {
            let vs = &vndf(i).2;
            vs.x * h.x[i] + vs.y * h.y[i] + vs.z * h.z[i]
        });
        map(|i| {
            if at[i].0.vndf.is_none() || !(hn[i] > 0.0) || ls[i].z <= 0.0 {
                0.0
            } else {
                pdf[i] / (4.0 * vh[i].abs()).max(1e-300)
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filters::footprint::NormalMap;
    use crate::microfacet::lobe::Frame;
    use crate::render::light::resolve;
    use crate::render::scene::{LightSpec, Lobe, SgLobeSpec};
    use crate::render::texture::Texture;
    use rand::{Rng, SeedableRng};

    /// The unit direction at polar angle t and azimuth p.
    fn sph(t: f64, p: f64) -> V3 {
        V3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
    }

    /// A texel's view in its hit's frame (89.99°, below the horizon or above it, by `k`)
    /// and its normal (tilted up to 89°), drawn in that order.
    fn view_and_normal(r: &mut rand_chacha::ChaCha8Rng, k: usize) -> (V3, V3) {
        let vt = match k % 5 {
            0 => 89.99f64.to_radians(),
            1 => r.random_range(1.5707..1.8),
            _ => r.random_range(0.0..1.5707),
        };
        let view = sph(vt, r.random_range(0.0..6.3));
        let nt = sph(
            r.random_range(0.0..89f64.to_radians()),
            r.random_range(0.0..6.3),
        );
        (view, nt)
    }

    /// `sampled_lanes` gives each lane `sampled_at`'s bits: 6000 sets of four samples, of
    /// four texels or fewer (a texel repeated), GGX (roughness 1e-4 to 1), seed 002's Gaussian and the LTC lobe, under a
    /// quad light alone, a quad with a point light and an SG environment, two quads, or a
    /// point light and an 8-light sky (no sampled light: every value 0);
    /// views to 89.99° and below the horizon, texel normals tilted to 89°, uniforms at 0
    /// and just under 1 among them.
    #[test]
    fn four_samples_are_the_one_sample_bits() {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(31);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        // flat: the tests give each texel its normal themselves
        let tex = Texture::new(NormalMap::flat(4));
        let quad = |c: [f64; 3], radiance: f64| LightSpec::Quad {
            center: c,
            u_axis: [1.0, 0.0, 0.0],
            v_axis: [0.0, -2.2, 3.0],
            half_size: [0.8, 0.5],
            radiance,
        };
        let sets = [
            resolve(&[quad([0.0, 3.0, 2.2], 1.0)]),
            resolve(&[
                quad([0.0, 3.0, 2.2], 1.7),
                LightSpec::Point {
                    position: [-3.0, -5.0, 6.0],
                    intensity: 40.0,
                },
                LightSpec::Sg {
                    lobes: vec![SgLobeSpec {
                        axis: [0.0, 0.2, 1.0],
                        lambda: 20.0,
                        amplitude: 2.0,
                    }],
                },
            ]),
            resolve(&[quad([0.0, 0.5, 0.3], 0.3), quad([0.3, -1.0, 1.0], 2.9)]),
            // a point light and an 8-light sky, as the torus scene has
            resolve(&[
                LightSpec::Point {
                    position: [-3.0, -5.0, 6.0],
                    intensity: 40.0,
                },
                LightSpec::Environment {
                    zenith: 0.4,
                    horizon: 0.1,
                    count: 8,
                },
            ]),
        ];
        let uniform = |r: &mut rand_chacha::ChaCha8Rng| match r.random_range(0..8) {
            0 => 0.0,
            1 => 1.0 - f64::EPSILON / 2.0,
            _ => r.random::<f64>(),
        };
        let mut lit = 0;
        for case in 0..6000 {
            let lights = &sets[case % sets.len()];
            let kind = [Lobe::Ggx, Lobe::Ggx, Lobe::Gaussian, Lobe::Ltc][case % 4];
            let alpha = crate::microfacet::lobe::tests::alpha_of(case, &mut r);
            let sh = Shader::new(kind, alpha, alpha.clamp(1e-3, 0.5), lights, &tex).unwrap();
            // four texels, each its own or a copy of the one before
            let mut texels: Vec<(Hit, V3, V3)> = Vec::new();
            for i in 0..LANES {
                if i > 0 && r.random_range(0..3) == 0 {
                    texels.push(texels[i - 1]);
                    continue;
                }
                let p = V3::new(r.random_range(-1.0..1.0), r.random_range(-1.0..1.0), 0.0);
                let hit = Hit {
                    p,
                    frame: Frame::around(V3::z()),
                    uv: [0.3, 0.7],
                    scale: [1.0, 1.0],
                };
                let (view, nt) = view_and_normal(&mut r, case + i);
                let eye = p + view * 2.0;
                texels.push((hit, eye, nt));
            }
            let ws: Vec<Viewed> = texels.iter().map(|(h, e, n)| sh.viewed(h, e, n)).collect();
            let at: [At; LANES] = std::array::from_fn(|i| (&ws[i], &texels[i].0, &texels[i].2));
            let u: [[f64; 3]; LANES] =
                std::array::from_fn(|_| [uniform(&mut r), uniform(&mut r), uniform(&mut r)]);
            let got = sh.sampled_lanes(at, u);

            for i in 0..LANES {
                let want = sh.sampled_at(&ws[i], &texels[i].0, &texels[i].2, u[i]);
                lit += usize::from(want > 0.0);
                assert!(
                    same(got[i], want),
                    "case {case} lane {i}: {} vs {want}",
                    got[i]
                );
            }
        }
        assert!(lit > 3000, "only {lit} samples saw light");
    }

    /// `exact_texels` gives each texel `exact_at`'s bits: 4000 sets of 1 to 13 texels on
    /// tilted hit frames (a torus's), GGX (roughness 1e-4 to 1), seed 002's Gaussian and
    /// the LTC lobe, under a point light and an 8-light sky (most of it below some
    /// horizons), two directional lights, a quad beside a point light (terms 0 among the
    /// others), or no light; views to 89.99° and below the horizon, texel normals tilted
    /// to 89°, texels at the point light itself.
    #[test]
    fn exact_lights_across_texels_are_exact_at() {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(37);
        // flat: the tests give each texel its normal themselves
        let tex = Texture::new(NormalMap::flat(4));
        let point = LightSpec::Point {
            position: [-3.0, -5.0, 6.0],
            intensity: 40.0,
        };
        let sets = [
            resolve(&[
                point.clone(),
                LightSpec::Environment {
                    zenith: 0.4,
                    horizon: 0.1,
                    count: 8,
                },
            ]),
            resolve(&[
                LightSpec::Directional {
                    direction: [0.3, -0.2, 1.0],
                    irradiance: 2.0,
                },
                LightSpec::Directional {
                    direction: [-1.0, 0.1, 0.05],
                    irradiance: 0.7,
                },
            ]),
            resolve(&[
                LightSpec::Quad {
                    center: [0.0, 3.0, 2.2],
                    u_axis: [1.0, 0.0, 0.0],
                    v_axis: [0.0, -2.2, 3.0],
                    half_size: [0.8, 0.5],
                    radiance: 1.0,
                },
                point,
            ]),
            resolve(&[]),
        ];
        let (mut lit, mut terms, mut at_light) = (0, 0, 0);
        for case in 0..4000 {
            let lights = &sets[case % sets.len()];
            let kind = [Lobe::Ggx, Lobe::Ggx, Lobe::Gaussian, Lobe::Ltc][case % 4];
            let alpha = crate::microfacet::lobe::tests::alpha_of(case, &mut r);
            let sh = Shader::new(kind, alpha, alpha.clamp(1e-3, 0.5), lights, &tex).unwrap();
            let n = r.random_range(1..14);
            let texels: Vec<(Hit, V3, V3)> = (0..n)
                .map(|i| {
                    let p = V3::new(
                        r.random_range(-2.0..2.0),
                        r.random_range(-2.0..2.0),
                        r.random_range(-0.5..0.5),
                    );
                    // now and then a texel at the point light itself (r² = 0: an infinite
                    // factor and a NaN direction)
                    let p = if case % 97 == 0 && i == 0 {
                        V3::new(-3.0, -5.0, 6.0)
                    } else {
                        p
                    };
                    let gn = sph(r.random_range(0.0..3.1), r.random_range(0.0..6.3));
                    let hit = Hit {
                        p,
                        frame: Frame::around(gn),
                        uv: [0.3, 0.7],
                        scale: [1.0, 1.0],
                    };
                    let (view, nt) = view_and_normal(&mut r, case + i);
                    let eye = p + hit.frame.world(&view) * 3.0;
                    (hit, eye, nt)
                })
                .collect();
            let ws: Vec<Viewed> = texels.iter().map(|(h, e, n)| sh.viewed(h, e, n)).collect();
            let at: Vec<At> = ws
                .iter()
                .zip(&texels)
                .map(|(w, (h, _, n))| (w, h, n))
                .collect();
            let got = sh.exact_texels(&at);
            assert_eq!(got.len(), n);
            for (i, (w, (h, _, nt))) in ws.iter().zip(&texels).enumerate() {
                let want = sh.exact_at(w, h, nt);
                lit += usize::from(want > 0.0);
                at_light += usize::from(want.is_nan());
                terms += 1;
                assert_eq!(
                    got[i].to_bits(),
                    want.to_bits(),
                    "case {case} texel {i}: {} vs {want}",
                    got[i]
                );
            }
        }
        // lit texels among the light sets that have point or directional lights
        assert!(lit > terms / 4, "only {lit} of {terms} texels lit");
        // the texels at the point light were evaluated (NaN, as exact_at gives)
        assert!(at_light >= 10, "{at_light} texels at the light");
    }
}

//! The renderer under an environment of spherical Gaussians (seed 002 §5.4): the `sg`
//! light's checks, the truth's MIS sample on the extremes, the glint scene's sky against
//! the fit tensor-envsg publishes, and the glint set's estimators against the truth on a
//! flat map, where the P-NDF is the intrinsic Gaussian itself.

mod common;

use nalgebra::Vector3;
use ndfbench::filters::footprint::NormalMap;
use ndfbench::render::geometry::Surface;
use ndfbench::render::light::{self, Light};
use ndfbench::render::scene::{Lobe, Scene};
use ndfbench::render::texture::Texture;
use ndfbench::render::truth::Shader;
use ndfbench::studies::render::{builtin_params, SCENES};
use ndfbench::Error;
use proptest::prelude::*;
use std::path::Path;

type V3 = Vector3<f64>;

const SKY: &str = "glints-plane-sky";

fn sky_text() -> &'static str {
    SCENES.iter().find(|s| s.0 == SKY).expect("the sky scene").1
}

#[test]
fn the_sky_scene_carries_the_sky_tensor_envsg_fitted() {
    let s = Scene::parse(sky_text(), SKY).expect("parses");
    let Some(Light::Sg(env)) = light::resolve(&s.lights).into_iter().next() else {
        panic!("{SKY}: its light is an SG environment");
    };
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("results/fits/tensor-envsg.json").expect("published"),
    )
    .expect("JSON");
    let fitted = json["fit"]["lobes"].as_array().expect("fit.lobes");
    assert_eq!(fitted.len(), env.lobes.len());
    for (g, f) in env.lobes.iter().zip(fitted) {
        let num = |v: &serde_json::Value| v.as_f64().expect("a number");
        assert_eq!(g.lambda, num(&f["lambda"]));
        assert_eq!(g.amp, num(&f["amp"]));
        for k in 0..3 {
            assert!(
                (g.axis[k] - num(&f["axis"][k])).abs() <= 1e-15,
                "{SKY}: axis {:?} against the fit's {}",
                g.axis,
                f["axis"]
            );
        }
    }
}

#[test]
fn bad_sg_lights_are_typed_errors_naming_the_field() {
    let base = sky_text();
    let first =
        "{ axis = [0.24803918541230538, 0.0, 0.96875], lambda = 2.0, amplitude = 0.8547112187395933 }";
    assert!(base.contains(first));
    let all_dark = {
        let mut t = base.to_string();
        for line in base.lines().filter(|l| l.contains("amplitude = ")) {
            let at = line.find("amplitude = ").unwrap();
            t = t.replace(line, &format!("{}amplitude = 0.0 }},", &line[..at]));
        }
        t
    };
    let cases: Vec<(String, &str)> = vec![
        (
            base.replace(
                first,
                "{ axis = [0.0, 0.0, 0.0], lambda = 2.0, amplitude = 1.0 }",
            ),
            "lobes[0].axis",
        ),
        (
            base.replace(
                first,
                "{ axis = [0.0, 0.0, 1.0], lambda = 0.0, amplitude = 1.0 }",
            ),
            "lobes[0].lambda",
        ),
        (
            base.replace(
                first,
                "{ axis = [0.0, 0.0, 1.0], lambda = nan, amplitude = 1.0 }",
            ),
            "lobes[0].lambda",
        ),
        (
            base.replace(
                first,
                "{ axis = [0.0, 0.0, 1.0], lambda = 1e300, amplitude = 1.0 }",
            ),
            "lobes[0].lambda",
        ),
        (
            base.replace(
                first,
                "{ axis = [0.0, 0.0, 1.0], lambda = 2.0, amplitude = -1.0 }",
            ),
            "lobes[0].amplitude",
        ),
        (
            base.replace(
                first,
                "{ axis = [0.0, inf, 1.0], lambda = 2.0, amplitude = 1.0 }",
            ),
            "lobes[0].axis",
        ),
        (
            base.replace(
                first,
                "{ axis = [0.0, 0.0, 1.0], lambda = 2.0, amplitude = 1.0, sharp = 1 }",
            ),
            "sharp",
        ),
        (all_dark, "no light"),
        (
            base.split("lobes = [").next().unwrap().to_string()
                + "lobes = []\n\n[render]\nmethods = \"glints\"\ntruth_samples = 128\nseed = 17\n",
            "lobes",
        ),
        (
            base.replace("methods = \"glints\"", "methods = \"multiscale\""),
            "only render.methods",
        ),
    ];
    for (text, needle) in cases {
        match Scene::parse(&text, "sky.toml") {
            Err(Error::InvalidArgument(m)) => {
                assert!(m.contains(needle), "{m} should name {needle}");
                assert!(!m.contains('\n'), "one line: {m}");
            }
            other => panic!("expected a typed error naming {needle}, got {other:?}"),
        }
    }
}

fn flat_texture() -> Texture {
    Texture::new(NormalMap::flat(4))
}

fn plane() -> Surface {
    let s: Scene = Scene::parse(sky_text(), SKY).expect("parses");
    Surface::new(&s.surface, 1.0)
}

proptest! {
    #![proptest_config(common::config(10_000))]
    /// One MIS sample of an SG environment is finite and non-negative for bandwidths
    /// 1e-3 … 1e5, amplitudes 0 … 1e9, views to 89.99°, texel normals tilted to 89°, the
    /// three lobes at roughness 1e-4 … 1, and uniforms on [0, 1) including 0.
    #[test]
    fn an_sg_sample_is_finite_and_non_negative(
        lambda in prop_oneof![Just(1e-3), Just(1e5), 1e-3f64..1e5],
        amp in prop_oneof![Just(0.0), Just(1e9), 0.0f64..1e3],
        axis_t in 0.0f64..3.14159, axis_p in 0.0f64..6.3,
        view_t in prop_oneof![Just(89.99f64), 0.0f64..89.99], view_p in 0.0f64..6.3,
        tilt in prop_oneof![Just(89.0f64), 0.0f64..89.0], tilt_p in 0.0f64..6.3,
        kind in 0usize..3,
        rough in prop_oneof![Just(1e-4), Just(1.0), 1e-4f64..1.0],
        u in prop::array::uniform3(prop_oneof![Just(0.0), 0.0f64..1.0]),
    ) {
        let sph = |t: f64, p: f64| {
            let (t, p) = (t.to_radians(), p);
            V3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
        };
        let lights = vec![Light::Sg(ndfbench::tensor::envsg::SgEnv {
            lobes: vec![
                ndfbench::tensor::envsg::Sg::new(sph(axis_t.to_degrees(), axis_p), lambda, amp).unwrap(),
                ndfbench::tensor::envsg::Sg::new(V3::z(), 2.0, 1.0).unwrap(),
            ],
        })];
        let tex = flat_texture();
        let lobe = [Lobe::Gaussian, Lobe::Ggx, Lobe::Ltc][kind];
        let sh = Shader::new(lobe, rough, rough.clamp(1e-3, 0.5), &lights, &tex).unwrap();
        let hit = plane().point_at([0.3, 0.7]);
        let eye = hit.p + sph(view_t, view_p) * 2.0;
        let nt = sph(tilt, tilt_p);
        let x = sh.sampled_part(&hit, &eye, &nt, u);
        prop_assert!(x.is_finite() && x >= 0.0, "{x}");
    }
}

/// The sky scene made small and flat: a 32² view of the plane with the flat map, a
/// smooth sky (no sun), σ_r 0.1, so that the P-NDF of every footprint is the intrinsic
/// Gaussian and the CP models hold it (it is rank 1 per block).
fn flat_sky() -> Scene {
    let text = sky_text();
    let head = text.split("lobes = [").next().unwrap();
    let mut s = Scene::parse(
        &(head.to_string()
            + "lobes = [{ axis = [0.0, 0.2, 1.0], lambda = 2.0, amplitude = 1.0 }, { axis = [0.3, 0.5, 0.8], lambda = 20.0, amplitude = 2.0 }]\n\n[render]\nmethods = \"glints\"\ntruth_samples = 256\nseed = 17\n"),
        "flat-sky",
    )
    .expect("parses");
    s.material.normal_map = "flat".into();
    s.material.map_size = 64;
    s.material.sigma_r = 0.1;
    s.camera.width = 32;
    s.camera.height = 32;
    s
}

#[test]
fn the_sg_estimators_agree_with_the_truth_on_a_flat_map() {
    let c = ndfbench::results::render::constants(Path::new("results"))
        .expect("results/fits/filters.json");
    let mut plan = builtin_params(ndfbench::integrate::Preset::Quick)
        .unwrap()
        .glints;
    plan.res = 64;
    plan.stride = 16;
    plan.env_spp_high = 1024;
    let s = flat_sky();
    let r = ndfbench::render::render(&s, Path::new("fits/render"), &c, &plan).expect("renders");
    let v = &r.views[0];
    let truth: f64 = v.truth.iter().map(|t| t.value).sum::<f64>() / v.truth.len() as f64;
    let se = (v.truth.iter().map(|t| t.se().powi(2)).sum::<f64>()).sqrt() / v.truth.len() as f64;
    let mean = |key: &str| -> f64 {
        let m = v
            .methods
            .iter()
            .find(|m| m.key == key)
            .unwrap_or_else(|| panic!("{key}"));
        m.pixels.iter().map(|&p| p as f64).sum::<f64>() / m.pixels.len() as f64
    };
    let last = plan.ranks.last().unwrap();
    // the truth's own bar, and 1 % for the images' 64² bins (0.03 against σ_r = 0.1) and
    // the point query's remaining noise at 1024 draws
    let tol = 4.0 * se + 0.01 * truth;
    for key in [format!("sg-point-r{last}-high"), "sg-plain-mip".into()] {
        let m = mean(&key);
        assert!(
            (m - truth).abs() <= tol,
            "{key}: mean {m} against the truth's {truth} ± {se}"
        );
    }
    // a factor such as 4 v_z against 4 v·h would move the image by far more
    assert!(truth > 0.1, "a lit plane: {truth}");
}

#[test]
fn extreme_sg_scenes_render_finite_images() {
    // the sharpest and the broadest lobe at the largest amplitude, σ_r at both ends of its
    // range, and a camera 0.01° above the plane: every truth value, s.e. and method pixel
    // finite and non-negative
    let c = ndfbench::results::render::constants(Path::new("results")).expect("constants");
    let plan = builtin_params(ndfbench::integrate::Preset::Quick)
        .unwrap()
        .glints;
    let text = sky_text();
    let head = text.split("lobes = [").next().unwrap();
    let with = |lobes: &str| {
        let mut s = Scene::parse(
            &format!("{head}lobes = [{lobes}]\n\n[render]\nmethods = \"glints\"\ntruth_samples = 8\nseed = 17\n"),
            "extreme-sky",
        )
        .expect("parses");
        s.material.map_size = 64;
        s.camera.width = 16;
        s.camera.height = 16;
        s
    };
    let sharp = "{ axis = [0.0, 0.2, 1.0], lambda = 1e5, amplitude = 1e9 }, { axis = [0.0, 0.0, 1.0], lambda = 1e-3, amplitude = 1e9 }";
    let mut cases = Vec::new();
    for sigma in [1e-3, 0.5] {
        let mut s = with(sharp);
        s.material.sigma_r = sigma;
        cases.push(s);
    }
    let mut grazing = with(sharp);
    let e = 0.01f64.to_radians();
    grazing.camera.position = [0.0, -3.0 * e.cos(), 3.0 * e.sin()];
    cases.push(grazing);
    for s in cases {
        let r = ndfbench::render::render(&s, Path::new("fits/render"), &c, &plan).expect("renders");
        for v in &r.views {
            for t in &v.truth {
                assert!(
                    t.value.is_finite() && t.value >= 0.0 && t.se().is_finite(),
                    "σ_r {}: {t:?}",
                    s.material.sigma_r
                );
            }
            assert!(v
                .methods
                .iter()
                .any(|m| m.key.starts_with("sg-prefiltered")));
            for m in &v.methods {
                assert!(
                    m.pixels.iter().all(|p| p.is_finite() && *p >= 0.0),
                    "σ_r {}: {}",
                    s.material.sigma_r,
                    m.key
                );
            }
        }
    }
}

/// The truth's MIS sample of an SG environment, averaged over many uniforms, against the
/// same lobe times the SGs integrated over the hemisphere by a product Gauss–Legendre rule
/// in (cos θ, φ): for each lobe (GGX by visible normals, seed 002's Gaussian by h_xy, the
/// LTC by the SGs alone) and a view near the normal and one at 70°.
#[test]
fn the_sg_mis_sample_is_unbiased_for_every_lobe() {
    use ndfbench::integrate::quad::gauss_legendre;
    use ndfbench::tensor::envsg::{Sg, SgEnv};
    use rand::{Rng, SeedableRng};
    let env = SgEnv {
        lobes: vec![
            Sg::new(V3::new(0.1, 0.2, 1.0), 2.0, 0.7).unwrap(),
            Sg::new(V3::new(0.2, 0.5, 0.8), 40.0, 3.0).unwrap(),
        ],
    };
    let lights = vec![Light::Sg(env.clone())];
    let tex = flat_texture();
    let hit = plane().point_at([0.3, 0.7]);
    let (mu, mw) = gauss_legendre(256);
    let (pu, pw) = gauss_legendre(512);
    for (lobe, rough) in [(Lobe::Ggx, 0.3), (Lobe::Gaussian, 0.08), (Lobe::Ltc, 0.3)] {
        let sh = Shader::new(lobe, rough, rough, &lights, &tex).unwrap();
        for view_deg in [10.0f64, 70.0] {
            let t = view_deg.to_radians();
            let v = V3::new(0.0, -t.sin(), t.cos());
            let eye = hit.p + hit.frame.world(&v) * 3.0;
            // the view as the shader sees it (unit, from the hit toward the eye)
            let vl = hit.frame.local(&(eye - hit.p).normalize());
            let nt = V3::z();
            let mut exact = 0.0;
            for (a, wa) in mu.iter().zip(&mw) {
                let c = 0.5 * (a + 1.0);
                let s = (1.0 - c * c).max(0.0).sqrt();
                for (b, wb) in pu.iter().zip(&pw) {
                    let phi = std::f64::consts::PI * (b + 1.0);
                    let l = V3::new(s * phi.cos(), s * phi.sin(), c);
                    let w = 0.5 * wa * std::f64::consts::PI * wb;
                    exact += w * sh.lobe(&nt, &vl, &l) * env.eval(&hit.frame.world(&l));
                }
            }
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
            let n = 400_000;
            let (mut s1, mut s2) = (0.0, 0.0);
            for _ in 0..n {
                let x = sh.sampled_part(&hit, &eye, &nt, rng.random());
                s1 += x;
                s2 += x * x;
            }
            let mean = s1 / n as f64;
            let se = ((s2 / n as f64 - mean * mean) / (n - 1) as f64).sqrt();
            assert!(
                (mean - exact).abs() <= 4.0 * se + 2e-4 * exact,
                "{lobe:?} at {view_deg}°: MC {mean} ± {se} against the quadrature's {exact}"
            );
            assert!(
                exact > 1e-3,
                "{lobe:?} at {view_deg}°: a lit lobe ({exact})"
            );
        }
    }
}

#[test]
fn an_sg_check_without_its_closed_form_is_refused() {
    // the renderer's check has the SG closed form for the Gaussian lobe only
    let (name, text, nodes) = ndfbench::render::check::scenes()
        .into_iter()
        .find(|c| c.1.contains("kind = \"sg\""))
        .expect("the SG check");
    let ggx = Scene::parse(&text.replace("lobe = \"gaussian\"", "lobe = \"ggx\""), name).unwrap();
    match ndfbench::render::check::run(&ggx, name, nodes) {
        Err(Error::InvalidArgument(m)) => assert!(m.contains("Gaussian lobe only"), "{m}"),
        other => panic!("expected a typed error, got {other:?}"),
    }
}

//! Render scenes as TOML: a camera (optionally moving along a straight path), one
//! surface (plane, sphere, torus) with a normal map, a base roughness, lights (point,
//! quad, directional, an environment as a few directional lights, an environment as a sum
//! of spherical Gaussians) and what to render.
//! Strict and bounded: an unknown key, a non-finite number or a size beyond the limits
//! below is a typed error naming the field (fits/render/*.toml are the examples).

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Largest scene file read.
pub const MAX_SCENE_BYTES: u64 = 64 * 1024;
/// Largest image side.
pub const MAX_SIDE: usize = 2048;
/// Most frames of a camera path, scales of a series, lights.
pub const MAX_FRAMES: usize = 128;
pub const MAX_SCALES: usize = 12;
pub const MAX_LIGHTS: usize = 64;
/// Most truth samples per pixel.
pub const MAX_SAMPLES: usize = 65536;
/// Most truth samples of one render in all (pixels × samples × frames × scales): bounds
/// the work a file can ask for (about an hour on two cores).
pub const MAX_TOTAL_SAMPLES: u64 = 1 << 36;
/// Largest normal map generated.
pub const MAX_MAP_SIZE: usize = 4096;

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    #[serde(default)]
    pub description: String,
    pub camera: CameraSpec,
    pub surface: SurfaceSpec,
    pub material: MaterialSpec,
    pub lights: Vec<LightSpec>,
    pub render: RenderSpec,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    pub position: [f64; 3],
    pub look_at: [f64; 3],
    #[serde(default = "up_z")]
    pub up: [f64; 3],
    /// Vertical field of view (degrees).
    pub fov_deg: f64,
    pub width: usize,
    pub height: usize,
    /// A dolly: the eye moves linearly from `position` to `to` over `frames` frames,
    /// looking at `look_at` throughout.
    #[serde(default)]
    pub path: Option<PathSpec>,
}

fn up_z() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PathSpec {
    pub to: [f64; 3],
    pub frames: usize,
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum SurfaceKind {
    /// z = 0, u = x, v = y.
    Plane,
    /// Centred at the origin, u = φ/2π, v = 1 − θ/π.
    Sphere,
    /// Around z, u = φ/2π around the axis, v = ψ/2π around the tube.
    Torus,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    pub kind: SurfaceKind,
    #[serde(default = "one")]
    pub radius: f64,
    #[serde(default = "tube")]
    pub minor_radius: f64,
    /// Map repeats per unit of u and of v (plane: per world unit).
    pub repeats: [f64; 2],
}

fn one() -> f64 {
    1.0
}
fn tube() -> f64 {
    0.35
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum Lobe {
    /// GGX with the base roughness α around each texel's normal.
    Ggx,
    /// Seed 002's intrinsic lobe: a Gaussian of the half-vector's projection around the
    /// texel normal's, standard deviation `sigma_r` (glints).
    Gaussian,
    /// The isotropic LTC of the GGX table at α (seed 000 Eq 1): the renderer check's lobe.
    Ltc,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    pub lobe: Lobe,
    /// GGX α (the squared perceptual roughness).
    pub alpha: f64,
    #[serde(default = "sigma_r")]
    pub sigma_r: f64,
    /// A procedural generator (isotropic-noise, brushed-metal, flakes, sharp-bumps,
    /// scratches), "flat", or the path of a normal-map PNG.
    pub normal_map: String,
    /// Slope scale of the map (an engine's normal strength): each texel's slope is
    /// multiplied by it (1 = as generated or read).
    #[serde(default = "one")]
    pub normal_scale: f64,
    #[serde(default = "map_size")]
    pub map_size: usize,
    #[serde(default)]
    pub map_seed: u64,
}

impl SurfaceSpec {
    /// The distance from p to the surface: |z| for the plane, ||p| − radius| for the
    /// sphere, |√((ρ − radius)² + z²) − minor_radius| (ρ = √(x² + y²)) for the torus.
    pub fn distance(&self, p: &[f64; 3]) -> f64 {
        match self.kind {
            SurfaceKind::Plane => p[2].abs(),
            SurfaceKind::Sphere => (norm(*p) - self.radius).abs(),
            SurfaceKind::Torus => {
                let q = p[0].hypot(p[1]) - self.radius;
                (q.hypot(p[2]) - self.minor_radius).abs()
            }
        }
    }
}

fn sigma_r() -> f64 {
    0.02
}
fn map_size() -> usize {
    256
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum LightSpec {
    Point {
        position: [f64; 3],
        intensity: f64,
    },
    /// A two-sided emitting rectangle: centre, two orthogonal axes, half sizes.
    Quad {
        center: [f64; 3],
        u_axis: [f64; 3],
        v_axis: [f64; 3],
        half_size: [f64; 2],
        radiance: f64,
    },
    Directional {
        direction: [f64; 3],
        irradiance: f64,
    },
    /// A sky L(ω) = horizon + (zenith − horizon)·ω_z as `count` directional lights on a
    /// Fibonacci set of the upper hemisphere, each carrying L(ω)·2π/count.
    Environment {
        zenith: f64,
        horizon: f64,
        count: usize,
    },
    /// A distant environment L(ω) = Σ A·exp(λ(ω·μ − 1)) (seed 002 §5.4), world axes:
    /// integrated by the truth, importance-sampled by the glint set's estimators.
    Sg {
        lobes: Vec<SgLobeSpec>,
    },
}

/// One spherical Gaussian of an `sg` light: axis μ (normalised), bandwidth λ, amplitude A.
#[derive(Clone, Copy, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SgLobeSpec {
    pub axis: [f64; 3],
    pub lambda: f64,
    pub amplitude: f64,
}

/// Most lobes of one `sg` light.
pub const MAX_SG_LOBES: usize = 64;

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum MethodSet {
    /// Seed 000: the mip-normal filters under quad lights through the LTC table.
    Multiscale,
    /// Seed 003: screen-space specular antialiasing under point and directional lights.
    SpecularAa,
    /// Seed 002: P-NDF glints under a small quad light.
    Glints,
    /// Only the truth (renderer checks).
    TruthOnly,
}

#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RenderSpec {
    pub methods: MethodSet,
    /// Truth samples per pixel (a √n × √n jittered grid when n is a square).
    pub truth_samples: usize,
    /// Where a quad light or an SG environment shines on a pixel's footprint of more texels
    /// than this, each of the truth's two replicates draws this many texels in proportion
    /// to their overlap (one light sample each) instead of shading every texel; absent:
    /// every texel (render::truth::Budget).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth_draws: Option<usize>,
    pub seed: u64,
    /// The map is scaled by each factor in turn (more texels per pixel = farther away).
    #[serde(default = "unit_scale")]
    pub scales: Vec<f64>,
    /// Linear exposure before the tone map.
    #[serde(default = "one")]
    pub exposure: f64,
}

fn unit_scale() -> Vec<f64> {
    vec![1.0]
}

fn bad(msg: String) -> Error {
    Error::InvalidArgument(msg)
}

fn vec_ok(what: &str, v: &[f64]) -> Result<()> {
    if v.iter().all(|x| x.is_finite() && x.abs() <= 1e6) {
        Ok(())
    } else {
        Err(bad(format!(
            "scene: {what} must be finite with |x| ≤ 1e6, got {v:?}"
        )))
    }
}

fn pos(what: &str, x: f64, lo: f64, hi: f64) -> Result<()> {
    if x.is_finite() && x >= lo && x <= hi {
        Ok(())
    } else {
        Err(bad(format!(
            "scene: {what} must be in [{lo}, {hi}], got {x}"
        )))
    }
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

impl Scene {
    /// Parse and check a scene; `origin` names it in messages.
    pub fn parse(text: &str, origin: &str) -> Result<Scene> {
        let s: Scene =
            toml::from_str(text).map_err(|e| crate::fit::spec::toml_error(origin, text, &e))?;
        s.check().map_err(|e| {
            bad(format!(
                "{origin}: {}",
                e.to_string().trim_start_matches("invalid argument: ")
            ))
        })?;
        Ok(s)
    }

    /// Read a scene file (at most [`MAX_SCENE_BYTES`]).
    pub fn load(path: &Path) -> Result<Scene> {
        let io = |e: std::io::Error| Error::Io {
            path: path.display().to_string(),
            msg: e.to_string(),
        };
        let meta = std::fs::metadata(path).map_err(io)?;
        if meta.len() > MAX_SCENE_BYTES {
            return Err(bad(format!(
                "{}: {} bytes exceeds the {MAX_SCENE_BYTES}-byte limit for a scene",
                path.display(),
                meta.len()
            )));
        }
        let text = std::fs::read_to_string(path).map_err(io)?;
        Scene::parse(&text, &path.display().to_string())
    }

    /// Frames of the camera path (1 without one).
    pub fn frames(&self) -> usize {
        self.camera.path.as_ref().map_or(1, |p| p.frames)
    }

    fn check(&self) -> Result<()> {
        let c = &self.camera;
        if self.name.is_empty()
            || self.name.len() > 64
            || !self
                .name
                .chars()
                .all(|ch| ch.is_ascii_alphanumeric() || ch == '-' || ch == '_')
        {
            return Err(bad(format!(
                "scene: name must be 1–64 characters of [A-Za-z0-9_-], got {:?}",
                self.name
            )));
        }
        vec_ok("camera.position", &c.position)?;
        vec_ok("camera.look_at", &c.look_at)?;
        vec_ok("camera.up", &c.up)?;
        pos("camera.fov_deg", c.fov_deg, 1.0, 150.0)?;
        for (w, v) in [("camera.width", c.width), ("camera.height", c.height)] {
            if !(8..=MAX_SIDE).contains(&v) || v % 2 != 0 {
                return Err(bad(format!(
                    "scene: {w} must be even and in [8, {MAX_SIDE}], got {v}"
                )));
            }
        }
        let d = [
            c.look_at[0] - c.position[0],
            c.look_at[1] - c.position[1],
            c.look_at[2] - c.position[2],
        ];
        if !(norm(d) > 1e-9) {
            return Err(bad("scene: camera.position equals camera.look_at".into()));
        }
        if let Some(p) = &c.path {
            vec_ok("camera.path.to", &p.to)?;
            if !(2..=MAX_FRAMES).contains(&p.frames) {
                return Err(bad(format!(
                    "scene: camera.path.frames must be in [2, {MAX_FRAMES}], got {}",
                    p.frames
                )));
            }
            // every frame's eye is validated like camera.position
            for k in 0..p.frames {
                let t = k as f64 / (p.frames - 1) as f64;
                let eye: [f64; 3] =
                    std::array::from_fn(|q| c.position[q] + (p.to[q] - c.position[q]) * t);
                let d: [f64; 3] = std::array::from_fn(|q| c.look_at[q] - eye[q]);
                if !(norm(d) > 1e-9) {
                    return Err(bad(format!(
                        "scene: frame {k} of {} of camera.path puts the eye on camera.look_at",
                        p.frames
                    )));
                }
            }
        }
        let s = &self.surface;
        pos("surface.radius", s.radius, 1e-6, 1e6)?;
        pos("surface.minor_radius", s.minor_radius, 1e-6, 1e6)?;
        if s.kind == SurfaceKind::Torus && s.minor_radius >= s.radius {
            return Err(bad(format!(
                "scene: a torus needs minor_radius < radius, got {} ≥ {}",
                s.minor_radius, s.radius
            )));
        }
        pos("surface.repeats[0]", s.repeats[0], 1e-6, 1e6)?;
        pos("surface.repeats[1]", s.repeats[1], 1e-6, 1e6)?;
        let m = &self.material;
        pos("material.alpha", m.alpha, 1e-4, 1.0)?;
        pos("material.sigma_r", m.sigma_r, 1e-3, 0.5)?;
        pos("material.normal_scale", m.normal_scale, 0.0, 10.0)?;
        if !(2..=MAX_MAP_SIZE).contains(&m.map_size) || !m.map_size.is_power_of_two() {
            return Err(bad(format!(
                "scene: material.map_size must be a power of two in [2, {MAX_MAP_SIZE}], got {}",
                m.map_size
            )));
        }
        self.check_lights()?;
        self.check_render()
    }

    fn check_lights(&self) -> Result<()> {
        if self.lights.is_empty() || self.lights.len() > MAX_LIGHTS {
            return Err(bad(format!(
                "scene: 1 to {MAX_LIGHTS} lights, got {}",
                self.lights.len()
            )));
        }
        for (i, l) in self.lights.iter().enumerate() {
            let w = |f: &str| format!("lights[{i}].{f}");
            match l {
                LightSpec::Point {
                    position,
                    intensity,
                } => {
                    vec_ok(&w("position"), position)?;
                    pos(&w("intensity"), *intensity, 0.0, 1e9)?;
                    self.off_the_surface(&w("position"), position)?;
                }
                LightSpec::Quad {
                    center,
                    u_axis,
                    v_axis,
                    half_size,
                    radiance,
                } => {
                    vec_ok(&w("center"), center)?;
                    vec_ok(&w("u_axis"), u_axis)?;
                    vec_ok(&w("v_axis"), v_axis)?;
                    pos(&w("half_size[0]"), half_size[0], 1e-6, 1e6)?;
                    pos(&w("half_size[1]"), half_size[1], 1e-6, 1e6)?;
                    pos(&w("radiance"), *radiance, 0.0, 1e9)?;
                    let (nu, nv) = (norm(*u_axis), norm(*v_axis));
                    let dot = u_axis[0] * v_axis[0] + u_axis[1] * v_axis[1] + u_axis[2] * v_axis[2];
                    if !(nu > 1e-9 && nv > 1e-9) || dot.abs() > 1e-6 * nu * nv {
                        return Err(bad(format!(
                            "scene: {} and v_axis must be non-zero and orthogonal",
                            w("u_axis")
                        )));
                    }
                }
                LightSpec::Directional {
                    direction,
                    irradiance,
                } => {
                    vec_ok(&w("direction"), direction)?;
                    pos(&w("irradiance"), *irradiance, 0.0, 1e9)?;
                    if !(norm(*direction) > 1e-9) {
                        return Err(bad(format!("scene: {} is zero", w("direction"))));
                    }
                }
                LightSpec::Environment {
                    zenith,
                    horizon,
                    count,
                } => {
                    pos(&w("zenith"), *zenith, 0.0, 1e9)?;
                    pos(&w("horizon"), *horizon, 0.0, 1e9)?;
                    if !(1..=MAX_LIGHTS).contains(count) {
                        return Err(bad(format!(
                            "scene: {} must be in [1, {MAX_LIGHTS}], got {count}",
                            w("count")
                        )));
                    }
                }
                LightSpec::Sg { lobes } => {
                    check_sg(i, lobes)?;
                    // the mip-normal and screen-space sets shade point, directional and quad
                    // lights only: they would drop the environment without a word
                    if !matches!(
                        self.render.methods,
                        MethodSet::Glints | MethodSet::TruthOnly
                    ) {
                        return Err(bad(format!(
                            "scene: lights[{i}] is an SG environment, which only render.methods = \"glints\" or \"truth-only\" shade"
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    /// A point light on the surface has unbounded irradiance 1/r² at the hits beside it
    /// and none defined at its own: a point closer than 1e-9 of the scene's size (the
    /// surface's radius, at least 1, or the light's distance from the origin if larger;
    /// the torus hits converge to 1e-12 of it) is refused.
    fn off_the_surface(&self, what: &str, p: &[f64; 3]) -> Result<()> {
        let d = self.surface.distance(p);
        let size = self.surface.radius.max(1.0).max(norm(*p));
        if d > 1e-9 * size {
            Ok(())
        } else {
            Err(bad(format!(
                "scene: {what} = {p:?} lies on the surface (distance {d:.1e}): a point light there has unbounded irradiance; move it off the surface"
            )))
        }
    }

    fn check_render(&self) -> Result<()> {
        let r = &self.render;
        if !(2..=MAX_SAMPLES).contains(&r.truth_samples) {
            return Err(bad(format!(
                "scene: render.truth_samples must be in [2, {MAX_SAMPLES}], got {}",
                r.truth_samples
            )));
        }
        if let Some(m) = r.truth_draws {
            use crate::render::coverage::MAX_EXACT_TEXELS;
            if !(1..=MAX_EXACT_TEXELS).contains(&m) {
                return Err(bad(format!(
                    "scene: render.truth_draws must be in [1, {MAX_EXACT_TEXELS}], got {m}"
                )));
            }
        }
        if r.scales.is_empty() || r.scales.len() > MAX_SCALES {
            return Err(bad(format!(
                "scene: render.scales needs 1 to {MAX_SCALES} factors, got {}",
                r.scales.len()
            )));
        }
        for (i, f) in r.scales.iter().enumerate() {
            pos(&format!("render.scales[{i}]"), *f, 1.0 / 64.0, 4096.0)?;
        }
        pos("render.exposure", r.exposure, 1e-6, 1e6)?;
        let total = (self.camera.width * self.camera.height) as u64
            * r.truth_samples as u64
            * self.frames() as u64
            * r.scales.len() as u64;
        if total > MAX_TOTAL_SAMPLES {
            return Err(bad(format!(
                "scene: {total} truth samples in all (pixels × samples × frames × scales) exceeds {MAX_TOTAL_SAMPLES}"
            )));
        }
        Ok(())
    }
}

/// An `sg` light: 1 to [`MAX_SG_LOBES`] lobes, each with a non-zero finite axis,
/// λ ∈ [1e-3, 1e5] and A ∈ [0, 1e9], and some light in all.
fn check_sg(i: usize, lobes: &[SgLobeSpec]) -> Result<()> {
    if !(1..=MAX_SG_LOBES).contains(&lobes.len()) {
        return Err(bad(format!(
            "scene: lights[{i}].lobes needs 1 to {MAX_SG_LOBES} lobes, got {}",
            lobes.len()
        )));
    }
    for (k, g) in lobes.iter().enumerate() {
        let w = |f: &str| format!("lights[{i}].lobes[{k}].{f}");
        vec_ok(&w("axis"), &g.axis)?;
        if !(norm(g.axis) > 1e-9) {
            return Err(bad(format!("scene: {} is zero", w("axis"))));
        }
        pos(&w("lambda"), g.lambda, 1e-3, 1e5)?;
        pos(&w("amplitude"), g.amplitude, 0.0, 1e9)?;
    }
    if lobes.iter().all(|g| g.amplitude == 0.0) {
        return Err(bad(format!(
            "scene: lights[{i}] is an SG environment with no light (every amplitude 0)"
        )));
    }
    Ok(())
}

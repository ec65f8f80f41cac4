//! Renders the engine-check scenes (engines/three/scenes.json, the same scenes three.js
//! renders) with Bevy 0.19.1's own PBR shader, headless, into an `Rgba32Float` image that
//! is read back to the CPU, and writes the pixels as JSON for `ndfbench engines`.
//!
//! `--table bevy` keeps the LTC table Bevy embeds (bevy_pbr's `src/ltc/ltc.ktx2`);
//! `--table ours --ktx2 FILE` replaces it through `AreaLightLuts`, the way a user would
//! (`use_ltc_table` below is that recipe, the lines docs/engines.md quotes).
//!
//! The scene in Bevy's terms: a `Plane3d` of normal +z, a `StandardMaterial` with base
//! colour white and metallic 1 (F0 = 1, no diffuse), one `RectLight` of unit radiance
//! (intensity = π·w·h lumens: Bevy divides by w·h·π), range 10⁴ (its smooth range
//! falloff is 1 − 2·10⁻¹⁶ at the scenes' distances), no ambient light, an orthographic
//! camera without MSAA, tone mapping or dithering, exposure 1.
//!
//! Each pixel's world position is where its centre's ray meets the plane, computed here
//! in f64 (the camera is orthographic: the frame maps onto the plane exactly).

use bevy::asset::RenderAssetUsages;
use bevy::camera::{Exposure, ImageRenderTarget, RenderTarget, ScalingMode};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::image::{CompressedImageFormats, ImageSampler, ImageType};
use bevy::light::GlobalAmbientLight;
use bevy::pbr::AreaLightLuts;
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::renderer::RenderAdapterInfo;
use bevy::render::view::Msaa;
use bevy::render::RenderApp;
use bevy::window::ExitCondition;
use serde::{Deserialize, Serialize};
use std::sync::{Arc, Mutex};

/// Replace Bevy's embedded LTC table with a KTX2 file in Bevy's layout (2 layers of
/// 64×64 RGBA16F: M⁻¹'s a, b, c, d, then norm and Fresnel). Call after `add_plugins`.
fn use_ltc_table(app: &mut App, ktx2: &[u8]) -> Result<(), String> {
    let image = Image::from_buffer(
        ktx2,
        ImageType::Extension("ktx2"),
        CompressedImageFormats::NONE,
        false,
        ImageSampler::linear(),
        RenderAssetUsages::RENDER_WORLD,
    )
    .map_err(|e| format!("Bevy cannot read the table: {e}"))?;
    let handle = app.world_mut().resource_mut::<Assets<Image>>().add(image);
    app.sub_app_mut(RenderApp)
        .insert_resource(AreaLightLuts { image: handle });
    Ok(())
}

#[derive(Deserialize)]
struct LightSpec {
    center: [f64; 3],
    look_at: [f64; 3],
    up: [f64; 3],
    width: f64,
    height: f64,
}

#[derive(Deserialize)]
struct SceneSpec {
    name: String,
    roughness: f64,
    view_deg: f64,
    light: LightSpec,
}

#[derive(Deserialize)]
struct Scenes {
    width: usize,
    height: usize,
    plane_half: f64,
    scenes: Vec<SceneSpec>,
}

#[derive(Serialize)]
struct SceneOut {
    name: String,
    radiance: Vec<f64>,
    positions: Vec<f64>,
}

#[derive(Serialize)]
struct RunOut {
    table: String,
    engine: String,
    adapter: String,
    paths: std::collections::BTreeMap<String, Vec<SceneOut>>,
}

#[derive(Resource)]
struct Handles {
    camera: Entity,
    light: Entity,
    material: Handle<StandardMaterial>,
}

/// The latest readback and the frame it arrived in.
#[derive(Default)]
struct Latest {
    frame: u64,
    data: Option<Vec<u8>>,
}

fn v3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

struct Args {
    scenes: String,
    table: String,
    ktx2: Option<String>,
    out: String,
}

fn args() -> Result<Args, String> {
    let mut a = Args {
        scenes: "../three/scenes.json".into(),
        table: String::new(),
        ktx2: None,
        out: String::new(),
    };
    let mut it = std::env::args().skip(1);
    while let Some(k) = it.next() {
        let mut val = || it.next().ok_or_else(|| format!("{k} needs a value"));
        match k.as_str() {
            "--scenes" => a.scenes = val()?,
            "--table" => a.table = val()?,
            "--ktx2" => a.ktx2 = Some(val()?),
            "--out" => a.out = val()?,
            _ => return Err(format!("unknown argument {k:?}")),
        }
    }
    match (a.table.as_str(), &a.ktx2) {
        ("bevy", None) | ("ours", Some(_)) => {}
        _ => return Err("usage: --table bevy | --table ours --ktx2 FILE, and --out FILE".into()),
    }
    if a.out.is_empty() {
        return Err("--out FILE is required".into());
    }
    Ok(a)
}

fn main() {
    if let Err(e) = run() {
        eprintln!("bevy-check: {e}");
        std::process::exit(2);
    }
}

fn run() -> Result<(), String> {
    let a = args()?;
    let text = std::fs::read_to_string(&a.scenes).map_err(|e| format!("{}: {e}", a.scenes))?;
    let sc: Scenes = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", a.scenes))?;
    let (w, h) = (sc.width as u32, sc.height as u32);
    if w == 0 || h == 0 || sc.scenes.is_empty() {
        return Err("the scene file has no pixels or no scenes".into());
    }

    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            })
            // render in the main thread: the render app stays reachable, frames in order
            .disable::<bevy::render::pipelined_rendering::PipelinedRenderingPlugin>()
            .set(bevy::log::LogPlugin {
                level: bevy::log::Level::WARN,
                ..default()
            }),
    );
    if let Some(path) = &a.ktx2 {
        let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
        use_ltc_table(&mut app, &bytes)?;
    }
    app.insert_resource(GlobalAmbientLight {
        color: Color::BLACK,
        brightness: 0.0,
        affects_lightmapped_meshes: true,
    });
    app.insert_resource(ClearColor(Color::NONE));

    let world = app.world_mut();
    let mut image = Image::new_target_texture(w, h, TextureFormat::Rgba32Float, None);
    // the readback copies out of it
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = world.resource_mut::<Assets<Image>>().add(image);
    let s = sc.plane_half as f32;
    let mesh = world
        .resource_mut::<Assets<Mesh>>()
        .add(Mesh::from(Plane3d::new(Vec3::Z, Vec2::splat(s))));
    let material = world
        .resource_mut::<Assets<StandardMaterial>>()
        .add(StandardMaterial {
            base_color: Color::WHITE,
            metallic: 1.0,
            perceptual_roughness: 0.5,
            ..default()
        });
    world.spawn((
        Mesh3d(mesh),
        MeshMaterial3d(material.clone()),
        Transform::IDENTITY,
    ));
    let camera = world
        .spawn((
            Camera3d::default(),
            Camera {
                clear_color: ClearColorConfig::Custom(Color::NONE),
                ..default()
            },
            RenderTarget::Image(ImageRenderTarget {
                handle: target.clone(),
                scale_factor: 1.0,
            }),
            Projection::Orthographic(OrthographicProjection::default_3d()),
            Msaa::Off,
            Tonemapping::None,
            DebandDither::Disabled,
            Exposure {
                ev100: -(1.2f32).log2(),
            },
            Transform::default(),
        ))
        .id();
    let light = world
        .spawn((RectLight::default(), Transform::default()))
        .id();
    world.insert_resource(Handles {
        camera,
        light,
        material,
    });
    let latest = Arc::new(Mutex::new(Latest::default()));
    let frame = Arc::new(Mutex::new(0u64));
    {
        let (latest, frame) = (latest.clone(), frame.clone());
        world
            .spawn(Readback::texture(target.clone()))
            .observe(move |ev: On<ReadbackComplete>| {
                let f = *frame.lock().unwrap();
                let mut l = latest.lock().unwrap();
                l.frame = f;
                l.data = Some(ev.data.clone());
            });
    }
    app.finish();
    app.cleanup();

    let mut out = Vec::new();
    let mut exposure_seen = 1.0f64;
    for (k, scene) in sc.scenes.iter().enumerate() {
        set_scene(&mut app, &sc, scene);
        exposure_seen = camera_exposure(&mut app, camera);
        let data = render_until_stable(&mut app, &latest, &frame, &scene.name)?;
        let px = (w * h) as usize;
        if data.len() < px * 16 {
            return Err(format!(
                "scene {}: the readback has {} bytes, want {}",
                scene.name,
                data.len(),
                px * 16
            ));
        }
        let mut radiance = vec![0.0; px * 4];
        let mut positions = vec![0.0; px * 4];
        let (wf, hf) = (w as f64, h as f64);
        for row in 0..h as usize {
            // rows from the bottom, as three.js's readRenderTargetPixels returns them
            let src_row = h as usize - 1 - row;
            for col in 0..w as usize {
                let src = (src_row * w as usize + col) * 16;
                let dst = (row * w as usize + col) * 4;
                for c in 0..4 {
                    let b: [u8; 4] = data[src + 4 * c..src + 4 * c + 4].try_into().unwrap();
                    radiance[dst + c] = f32::from_le_bytes(b) as f64 / exposure_seen;
                }
                radiance[dst + 3] =
                    f32::from_le_bytes(data[src + 12..src + 16].try_into().unwrap()) as f64;
                // the pixel centre in NDC (y up), its ray meets z = 0 at (−y·s, x·s)
                let xn = (col as f64 + 0.5) / wf * 2.0 - 1.0;
                let yn = (row as f64 + 0.5) / hf * 2.0 - 1.0;
                positions[dst] = -yn * sc.plane_half;
                positions[dst + 1] = xn * sc.plane_half;
                positions[dst + 2] = 0.0;
                positions[dst + 3] = 1.0;
            }
        }
        eprintln!(
            "bevy-check: {} table, scene {} of {}: {}",
            a.table,
            k + 1,
            sc.scenes.len(),
            scene.name
        );
        out.push(SceneOut {
            name: scene.name.clone(),
            radiance,
            positions,
        });
    }
    let adapter = {
        let info = app
            .sub_app(RenderApp)
            .world()
            .resource::<RenderAdapterInfo>();
        format!("{} ({:?})", info.0.name, info.0.backend)
    };
    let mut paths = std::collections::BTreeMap::new();
    paths.insert("half".to_string(), out);
    let run = RunOut {
        table: a.table.clone(),
        engine: "bevy 0.19.1".into(),
        adapter,
        paths,
    };
    let json = serde_json::to_string(&run).map_err(|e| e.to_string())?;
    std::fs::write(&a.out, json).map_err(|e| format!("{}: {e}", a.out))?;
    eprintln!(
        "bevy-check: wrote {} ({} scenes, exposure {exposure_seen})",
        a.out,
        sc.scenes.len()
    );
    Ok(())
}

/// The exposure Bevy multiplies the image by (1 up to f32 rounding).
fn camera_exposure(app: &mut App, camera: Entity) -> f64 {
    app.world()
        .get::<Exposure>(camera)
        .map(|e| e.exposure() as f64)
        .unwrap_or(1.0)
}

fn set_scene(app: &mut App, sc: &Scenes, scene: &SceneSpec) {
    let th = scene.view_deg.to_radians();
    let (c, s) = (th.cos(), sc.plane_half);
    let handles = app.world().resource::<Handles>();
    let (camera, light, material) = (handles.camera, handles.light, handles.material.clone());
    let world = app.world_mut();
    {
        let mut e = world.entity_mut(camera);
        *e.get_mut::<Transform>().unwrap() = Transform::from_translation(Vec3::new(
            (10.0 * th.sin()) as f32,
            0.0,
            (10.0 * c) as f32,
        ))
        .looking_at(Vec3::ZERO, Vec3::new(-c as f32, 0.0, th.sin() as f32));
        *e.get_mut::<Projection>().unwrap() = Projection::Orthographic(OrthographicProjection {
            near: 0.1,
            far: 100.0,
            scaling_mode: ScalingMode::Fixed {
                width: (2.0 * s) as f32,
                height: (2.0 * s * c) as f32,
            },
            ..OrthographicProjection::default_3d()
        });
    }
    {
        let l = &scene.light;
        let mut e = world.entity_mut(light);
        *e.get_mut::<Transform>().unwrap() =
            Transform::from_translation(v3(l.center)).looking_at(v3(l.look_at), v3(l.up));
        *e.get_mut::<RectLight>().unwrap() = RectLight {
            color: Color::WHITE,
            intensity: (std::f64::consts::PI * l.width * l.height) as f32,
            range: 1.0e4,
            width: l.width as f32,
            height: l.height as f32,
        };
    }
    if let Some(mut m) = world
        .resource_mut::<Assets<StandardMaterial>>()
        .get_mut(&material)
    {
        m.perceptual_roughness = scene.roughness as f32;
    }
}

/// Run frames until three readbacks in a row, each from a later frame than the scene
/// change plus a margin, are identical and not all zero; at most 2000 frames.
fn render_until_stable(
    app: &mut App,
    latest: &Arc<Mutex<Latest>>,
    frame: &Arc<Mutex<u64>>,
    name: &str,
) -> Result<Vec<u8>, String> {
    let start = *frame.lock().unwrap();
    let mut last: Option<Vec<u8>> = None;
    let mut same = 0;
    for _ in 0..2000 {
        {
            *frame.lock().unwrap() += 1;
        }
        app.update();
        if let Some(exit) = app.should_exit() {
            return Err(format!(
                "scene {name}: Bevy quit ({exit:?}); its log above says why"
            ));
        }
        let l = latest.lock().unwrap();
        if l.frame < start + 4 {
            continue;
        }
        let Some(d) = &l.data else { continue };
        if d.iter().all(|b| *b == 0) {
            continue;
        }
        if last.as_deref() == Some(d.as_slice()) {
            same += 1;
            if same >= 2 {
                return Ok(d.clone());
            }
        } else {
            same = 0;
            last = Some(d.clone());
        }
    }
    let l = latest.lock().unwrap();
    Err(format!(
        "scene {name}: the image did not settle in 2000 frames (last readback at frame {}, {} bytes, {})",
        l.frame,
        l.data.as_ref().map_or(0, |d| d.len()),
        if l.data.as_ref().is_some_and(|d| d.iter().all(|b| *b == 0)) { "all zero" } else { "not all zero" }
    ))
}

//! bevy_nearfield against `nearfield render`: the built-in Cornell box written by nearfield's
//! exporter (`nearfield export`'s code) and loaded back, rendered by Bevy with the plugin and by
//! nearfield's own `Renderer` from the same camera at 320×180. The plugin's images are read back
//! by copies inside Bevy's frame (`NearFieldReadback`), not from screenshots.
//!
//! One test binary (Bevy is built once): ao, indirect light, ao along a camera path (with Bevy's
//! motion vectors, without them, under Bevy's TAA), refused settings; and the far field: the
//! built-ins' volume baked and read by Bevy in Bevy's units, beside their lights.

use bevy::anti_alias::taa::TemporalAntiAliasing;
use bevy::camera::Hdr;
use bevy::camera::RenderTarget;
use bevy::core_pipeline::prepass::{DeferredPrepass, MotionVectorPrepass};
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::view::Msaa;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::window::ExitCondition;
use bevy_nearfield::far::BakedVolume;
use bevy_nearfield::scene::{self, Shading};
use bevy_nearfield::{
    NearField, NearFieldChecked, NearFieldImages, NearFieldPlugin, NearFieldQuality,
    NearFieldReadback, NearFieldTechnique, ReadbackImages,
};
use nearfield_render::{Aov, GpuContext, RenderSettings, Renderer, TechniqueParams};
use nearfield_scene::CameraPath;
use std::sync::{Arc, Mutex};

const SIZE: (u32, u32) = (320, 180);
/// Frames each app renders before its images are compared (pipelines compile during the first).
const FRAMES: u32 = 24;
/// Frames along the camera path (about a second of the walk at 30 fps).
const PATH_FRAMES: u32 = 32;

/// A built-in scene as `nearfield export` writes it (with its lights), loaded back (a file of
/// its own per call). The tests run one at a time (`--test-threads=1`, the Makefile): nearfield's
/// `GpuContext` beside another test's Bevy device may be taken for it (pipeline_cache.rs).
fn exported(name: &str) -> nearfield_scene::Scene {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let scene = nearfield_scene::builtin::scene(name).unwrap();
    let dir = std::env::temp_dir().join(format!("bevy-nearfield-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}-{call}.glb"));
    let camera = scene.default_camera();
    nearfield_scene::export::write_gltf(&scene, &camera, SIZE.0 as f32 / SIZE.1 as f32, &path)
        .unwrap();
    nearfield_scene::load_scene(&path).unwrap()
}

/// The time (s) of a run's frame k after the warm-up: the paths' rate, 30 frames a second.
fn time_of(k: u32) -> f32 {
    k as f32 / 30.0
}

/// Frames of warm-up: Bevy compiles its pipelines asynchronously, so its first frames draw
/// nothing (measured on lavapipe: the scene appears in the third).
const WARMUP: u32 = 6;

/// How a headless Bevy app runs: the technique, its frames, and how the camera moves.
struct Setup {
    shading: Shading,
    /// None: Bevy alone.
    near_field: Option<NearField>,
    frames: u32,
    /// The camera first renders [`WARMUP`] frames at quality Low (below).
    warmup: bool,
    /// The camera of each frame (frame k after the warm-up takes `path.camera(k)`; the
    /// warm-up stands at `path.camera(0)`); None: the scene's default camera throughout.
    path: Option<CameraPath>,
    /// Bevy's motion-vector prepass on the camera (without it the glue derives the camera's
    /// motion from the two frames' matrices).
    motion_vectors: bool,
    /// Bevy's TAA on the camera (its jittered projection, its motion vectors).
    taa: bool,
    /// The scene lit in Bevy's units: its lights and the environment's sun, a baked volume, and
    /// nearfield's exposure 0 (None: no lights; the unlit parts need none).
    lighting: Option<Lighting>,
}

/// How a run gives the camera the environment (its sun aside) as Bevy's environment light.
#[derive(Clone, Copy, Debug, PartialEq)]
enum EnvMap {
    None,
    /// `scene::environment_map_light`'s maps as an `EnvironmentMapLight`.
    Prefiltered,
    /// Its radiance cube as a `GeneratedEnvironmentMapLight` (Bevy filters it on the GPU).
    Generated,
}

/// What lights a scene in Bevy: [`scene::spawn_lights`] of the scene and `env`, and the volume.
#[derive(Clone)]
struct Lighting {
    env: nearfield_scene::Environment,
    volume: Option<BakedVolume>,
    /// The environment (its sun aside) as the camera's environment light.
    env_map: EnvMap,
    /// With the plugin: the materials drawn deferred, with Bevy's deferred prepass (the
    /// plugin's indirect light reads ρ from that G-buffer, which forward materials leave empty);
    /// false: forward, and the ao pass takes ρ = 0.5.
    deferred: bool,
}

impl Setup {
    fn still(shading: Shading, near_field: NearField, frames: u32, warmup: bool) -> Self {
        Setup {
            shading,
            near_field: Some(near_field),
            frames,
            warmup,
            path: None,
            motion_vectors: false,
            taa: false,
            lighting: None,
        }
    }
}

/// Runs a headless Bevy app on `scene` with the setup's `NearField` on the camera for its
/// frames and returns the images read back (None when the plugin produced none). With
/// `warmup`, the camera first renders [`WARMUP`] frames with the technique at quality Low: the
/// technique is then made anew, so its running mean starts on frames that see Bevy's colour
/// (the indirect light gathers the frame before's colour; frames drawn before Bevy's pipelines
/// are ready are black and would stay in the mean for its `history` frames).
fn run_bevy(scene: &nearfield_scene::Scene, setup: Setup) -> Run {
    let Setup {
        shading,
        near_field,
        frames,
        warmup,
        path,
        motion_vectors,
        taa,
        lighting,
    } = setup;
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                close_when_requested: false,
                ..default()
            })
            .disable::<bevy::winit::WinitPlugin>(),
    )
    .add_plugins(NearFieldPlugin)
    .insert_resource(GlobalAmbientLight {
        brightness: 0.0,
        ..default()
    })
    .insert_resource(ClearColor(Color::BLACK));
    let deferred = near_field.is_some() && lighting.as_ref().is_some_and(|l| l.deferred);
    if deferred {
        app.insert_resource(bevy::pbr::DefaultOpaqueRendererMethod::deferred());
    }
    let scene_copy = scene.clone();
    let mut image = Image::new_target_texture(SIZE.0, SIZE.1, TextureFormat::Rgba16Float, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = app.world_mut().resource_mut::<Assets<Image>>().add(image);
    let target_copy = target.clone();
    let camera_entity = app.world_mut().spawn_empty().id();
    let start = path
        .as_ref()
        .map_or(scene.default_camera(), |p| p.camera(0));
    app.add_systems(
        Startup,
        move |mut commands: Commands,
              mut meshes: ResMut<Assets<Mesh>>,
              mut materials: ResMut<Assets<StandardMaterial>>,
              mut images: ResMut<Assets<Image>>| {
            scene::spawn_scene(
                &mut commands,
                &mut meshes,
                &mut materials,
                &mut images,
                &scene_copy,
                shading,
            );
            if let Some(l) = &lighting {
                scene::spawn_lights(&mut commands, &scene_copy, &l.env);
                if let Some(v) = l.volume.clone() {
                    v.spawn(&mut commands, &mut images);
                }
            }
            let (transform, projection) = scene::camera(&start, SIZE, 0.01);
            let mut camera = commands.entity(camera_entity);
            camera.insert((
                Camera3d::default(),
                RenderTarget::Image(target_copy.clone().into()),
                transform,
                projection,
                Msaa::Off,
                Hdr,
                Tonemapping::None,
                DebandDither::Disabled,
                NearFieldReadback,
            ));
            if motion_vectors {
                camera.insert(MotionVectorPrepass);
            }
            if taa {
                camera.insert(TemporalAntiAliasing::default());
            }
            if let Some(l) = &lighting {
                camera.insert(scene::exposure(0.0));
                let map = |images: &mut Assets<Image>| scene::environment_map_light(images, &l.env);
                match l.env_map {
                    EnvMap::None => {}
                    EnvMap::Prefiltered => {
                        camera.insert(map(&mut images));
                    }
                    EnvMap::Generated => {
                        let m = map(&mut images);
                        camera.insert(bevy::light::GeneratedEnvironmentMapLight {
                            environment_map: m.specular_map,
                            intensity: m.intensity,
                            ..default()
                        });
                    }
                }
            }
            if deferred {
                camera.insert(DeferredPrepass);
            }
        },
    );
    app.finish();
    app.cleanup();
    if let Some(near_field) = near_field.as_ref().filter(|_| warmup) {
        let low = NearField {
            quality: NearFieldQuality::Low,
            ..near_field.clone()
        };
        app.world_mut().entity_mut(camera_entity).insert(low);
        for _ in 0..WARMUP {
            app.update();
        }
    }
    if let Some(near_field) = near_field {
        app.world_mut().entity_mut(camera_entity).insert(near_field);
    }
    let mut sequence = Vec::new();
    for k in 0..frames {
        if let Some(path) = &path {
            let (transform, _) = scene::camera(&path.camera(k), SIZE, 0.01);
            app.world_mut().entity_mut(camera_entity).insert(transform);
        }
        // A moving scene's objects at frame k's time (the warm-up stood at time 0), as
        // `references` poses nearfield's.
        let mut moving = app
            .world_mut()
            .query::<(&scene::SceneMotion, &mut Transform)>();
        for (m, mut transform) in moving.iter_mut(app.world_mut()) {
            *transform = m.transform_at(time_of(k));
        }
        app.update();
        if path.is_some() {
            let images = app.world().resource::<NearFieldImages>().get(camera_entity);
            let images = images.expect("the plugin's images");
            // The read-back is this update's frame: the view was made anew by the first update
            // after the warm-up, so frame k + 1 is the one drawn from path.camera(k).
            assert_eq!(images.frames, k + 1, "read-back frame of update {k}");
            sequence.push(images);
        }
    }
    let images = app.world().resource::<NearFieldImages>().get(camera_entity);
    let checked = app.world().get::<NearFieldChecked>(camera_entity).cloned();
    // What the camera presented: its target image, read back by Bevy.
    let presented = Arc::new(Mutex::new(None));
    let slot = presented.clone();
    app.world_mut().spawn(Screenshot::image(target)).observe(
        move |shot: On<ScreenshotCaptured>| {
            *slot.lock().unwrap() = shot.image.data.clone();
        },
    );
    for _ in 0..16 {
        app.update();
        if presented.lock().unwrap().is_some() {
            break;
        }
    }
    let bytes = presented.lock().unwrap().take().unwrap_or_default();
    let presented: Vec<[f32; 3]> = bytes
        .chunks_exact(8)
        .map(|p| {
            let c = |k: usize| half::f16::from_le_bytes([p[2 * k], p[2 * k + 1]]).to_f32();
            [c(0), c(1), c(2)]
        })
        .collect();
    let lit = presented.iter().filter(|p| p[0] > 0.0).count();
    Run {
        images,
        sequence,
        checked,
        lit,
        presented,
    }
}

/// What a run of the Bevy app gave.
struct Run {
    images: Option<ReadbackImages>,
    /// With a path: every frame's images, in order (frame 1 first).
    sequence: Vec<ReadbackImages>,
    checked: Option<NearFieldChecked>,
    /// Pixels of the camera's target with a red channel above 0.
    lit: usize,
    /// The camera's target (linear, Bevy's exposure applied; no tone mapping), row 0 at the top.
    presented: Vec<[f32; 3]>,
}

/// nearfield's own frames 1..=`frames` of the same view, frame k + 1 drawn from `camera(k)` (as
/// the plugin's along a path): its ao, indirect irradiance, direct radiance and coverage.
fn references(
    scene: &nearfield_scene::Scene,
    env: &nearfield_scene::Environment,
    method: &str,
    params: &TechniqueParams,
    camera: impl Fn(u32) -> nearfield_scene::Camera,
    frames: u32,
) -> Vec<Reference> {
    let ctx = GpuContext::new(None).expect("an adapter (lavapipe in CI)");
    let technique = nearfield_render::technique::Spec::resolve(method, params).unwrap();
    let settings = RenderSettings {
        size: SIZE,
        ..Default::default()
    };
    let mut r = Renderer::new(&ctx, scene, env, None, camera(0), &technique, settings).unwrap();
    (0..frames)
        .map(|k| {
            r.set_camera(camera(k));
            r.set_time(time_of(k));
            r.render_frame();
            let ao = r.read_aov(Aov::Ao);
            let mut rgb = |aov| -> Vec<[f32; 3]> {
                r.read_aov(aov)
                    .pixels
                    .iter()
                    .map(|p| [p[0], p[1], p[2]])
                    .collect()
            };
            let indirect = rgb(Aov::IndirectIrradiance);
            let env = rgb(Aov::EnvIrradiance);
            let direct = rgb(Aov::DirectRadiance);
            Reference {
                covered: ao.pixels.iter().map(|p| p[3] > 0.0).collect(),
                ao: ao.pixels.iter().map(|p| p[0]).collect(),
                indirect,
                env,
                direct,
            }
        })
        .collect()
}

/// nearfield's own frame `frames` of the scene's view.
fn reference(
    scene: &nearfield_scene::Scene,
    env: &nearfield_scene::Environment,
    method: &str,
    params: &TechniqueParams,
    frames: u32,
) -> Reference {
    let camera = scene.default_camera();
    references(scene, env, method, params, |_| camera, frames)
        .pop()
        .unwrap()
}

/// The plugin along `setup`'s path and nearfield's frames from the same cameras (the same
/// technique and resolved settings): `metric` of each frame's pair, frames 1..=PATH_FRAMES.
fn along(
    scene: &nearfield_scene::Scene,
    env: &nearfield_scene::Environment,
    setup: Setup,
    metric: impl Fn(&ReadbackImages, &Reference) -> f64,
) -> Vec<f64> {
    let near_field = setup.near_field.as_ref().expect("a NearField");
    let technique = near_field.technique;
    let params = near_field.params().unwrap();
    let path = setup.path.clone().expect("a path");
    let frames = setup.frames;
    let run = run_bevy(scene, setup);
    let truth = references(
        scene,
        env,
        technique.name(),
        &params,
        |k| path.camera(k),
        frames,
    );
    assert_eq!(run.sequence.len(), frames as usize);
    run.sequence
        .iter()
        .zip(&truth)
        .map(|(images, r)| metric(images, r))
        .collect()
}

/// The mean and the largest of a path's values after its first 16 frames.
fn after_16(values: &[f64]) -> (f64, f64) {
    let settled = &values[16..];
    let worst = settled.iter().cloned().fold(0.0, f64::max);
    (settled.iter().sum::<f64>() / settled.len() as f64, worst)
}

/// Mean |a − b| over the covered pixels, and their count.
fn ao_mae(a: &[f32], b: &[f32], covered: &[bool]) -> (f64, usize) {
    let (sum, n) = a
        .iter()
        .zip(b)
        .zip(covered)
        .filter(|(_, c)| **c)
        .fold((0.0f64, 0usize), |(s, n), ((a, b), _)| {
            (s + (a - b).abs() as f64, n + 1)
        });
    (sum / n.max(1) as f64, n)
}

/// nearfield's images of a frame.
struct Reference {
    ao: Vec<f32>,
    indirect: Vec<[f32; 3]>,
    env: Vec<[f32; 3]>,
    /// The radiance its techniques gather (the plugin's is Bevy's colour).
    direct: Vec<[f32; 3]>,
    /// Where the frame sees a surface.
    covered: Vec<bool>,
}

/// Σ |a − b| / Σ b over the covered pixels and the three channels.
fn relative_error(a: &[[f32; 3]], b: &[[f32; 3]], covered: &[bool]) -> f64 {
    let (mut diff, mut total) = (0.0f64, 0.0f64);
    for ((a, b), c) in a.iter().zip(b).zip(covered) {
        if *c {
            for k in 0..3 {
                diff += (a[k] - b[k]).abs() as f64;
                total += b[k] as f64;
            }
        }
    }
    assert!(total > 0.0, "nothing to compare");
    diff / total
}

#[test]
fn the_plugin_matches_nearfield_render() {
    let scene = exported("cornell");
    let env = scene.default_env.load().unwrap();

    // 1. ao of each technique at the High preset: MAE ≤ 0.01 over the surface pixels.
    for technique in [
        NearFieldTechnique::GTAO,
        NearFieldTechnique::HBIL,
        NearFieldTechnique::VBGI,
        NearFieldTechnique::named("ssao").unwrap(),
    ] {
        let near_field = NearField {
            technique,
            quality: NearFieldQuality::High,
            ..default()
        };
        let params = near_field.params().unwrap();
        let images = run_bevy(&scene, Setup::still(Shading::Lit, near_field, FRAMES, true))
            .images
            .expect("the plugin's images");
        assert_eq!(images.size, SIZE);
        let reference = reference(&scene, &env, technique.name(), &params, images.frames);
        let (mae, n) = ao_mae(&images.ao, &reference.ao, &reference.covered);
        eprintln!(
            "{}: ao MAE {mae:.5} over {n} pixels (frame {})",
            technique.name(),
            images.frames
        );
        assert!(n > (SIZE.0 * SIZE.1 / 4) as usize, "coverage {n}");
        assert!(mae <= 0.01, "{}: ao MAE {mae}", technique.name());
    }

    // 2. indirect irradiance: Bevy's surfaces unlit, showing ρ, which is nearfield's radiance
    // under a white sky with no other light; relative error ≤ 5 % (sum over the surface).
    let mut dark = scene.clone();
    dark.lights.clear();
    for m in &mut dark.materials {
        m.emissive = glam::Vec3::ZERO;
        m.emissive_texture = None;
    }
    let white = nearfield_scene::Environment::constant(glam::Vec3::ONE);
    for technique in [NearFieldTechnique::HBIL, NearFieldTechnique::VBGI] {
        let near_field = NearField {
            technique,
            quality: NearFieldQuality::High,
            ambient_occlusion: false,
            ..default()
        };
        let params = near_field.params().unwrap();
        let images = run_bevy(
            &dark,
            Setup::still(Shading::Unlit(1.0), near_field, FRAMES, true),
        )
        .images
        .expect("the plugin's images");
        let r = reference(&dark, &white, technique.name(), &params, images.frames);
        // The inputs agree: Bevy's colour is nearfield's direct radiance.
        let radiance = relative_error(&images.radiance, &r.direct, &r.covered);
        let rel = relative_error(&images.indirect_irradiance, &r.indirect, &r.covered);
        eprintln!(
            "{}: indirect relative error {rel:.4} (radiance gathered: {radiance:.4})",
            technique.name()
        );
        assert!(radiance <= 0.01, "radiance relative error {radiance}");
        assert!(
            rel <= 0.05,
            "{}: indirect relative error {rel}",
            technique.name()
        );
    }

    // 3. along a camera path (the Cornell box's walk at 30 fps): every frame after the first
    // 16 within ao MAE 0.01 of nearfield's frame from the same camera. With Bevy's motion
    // vectors, without them (the glue's camera motion) and under Bevy's TAA (jittered depth).
    let path = CameraPath::walk(scene.default_camera(), scene.bounds(), 30.0).unwrap();
    for (technique, motion_vectors, taa) in [
        // hbil's ao is gtao's (one horizon search): not run again.
        (NearFieldTechnique::GTAO, true, false),
        (NearFieldTechnique::VBGI, true, false),
        (NearFieldTechnique::VBGI, false, false),
        (NearFieldTechnique::GTAO, true, true),
        (NearFieldTechnique::VBGI, true, true),
    ] {
        let near_field = NearField {
            technique,
            quality: NearFieldQuality::High,
            ..default()
        };
        let setup = Setup {
            path: Some(path.clone()),
            motion_vectors,
            taa,
            ..Setup::still(Shading::Lit, near_field, PATH_FRAMES, true)
        };
        let maes = along(&scene, &env, setup, |images, r| {
            let (mae, n) = ao_mae(&images.ao, &r.ao, &r.covered);
            assert!(n > (SIZE.0 * SIZE.1 / 4) as usize, "coverage {n}");
            mae
        });
        let (mean, worst) = after_16(&maes);
        eprintln!(
            "{} along the walk (motion vectors {motion_vectors}, TAA {taa}): ao MAE over frames \
             17..{PATH_FRAMES} mean {mean:.5}, largest {worst:.5}; frames 1..16 largest {:.5}",
            technique.name(),
            maes[..16].iter().cloned().fold(0.0, f64::max)
        );
        assert!(
            worst <= 0.01,
            "{} along the walk (motion vectors {motion_vectors}, TAA {taa}): ao MAE {worst}",
            technique.name()
        );
    }

    // The light gathered in motion: last frame's colour reprojected to this frame. On the unlit
    // box of part 2 a surface keeps its colour from frame to frame, so the indirect light of
    // every frame after the first 16 of a turn of 1.5° a frame (about 7 pixels a frame) is
    // within 2 % of nearfield's, which gathers the frame's own direct radiance.
    let turn = CameraPath::orbit(scene.default_camera(), 1.5, PATH_FRAMES, 30.0).unwrap();
    for technique in [NearFieldTechnique::HBIL, NearFieldTechnique::VBGI] {
        let near_field = NearField {
            technique,
            quality: NearFieldQuality::High,
            ambient_occlusion: false,
            ..default()
        };
        let setup = Setup {
            path: Some(turn.clone()),
            motion_vectors: true,
            ..Setup::still(Shading::Unlit(1.0), near_field, PATH_FRAMES, true)
        };
        let errors = along(&dark, &white, setup, |images, r| {
            relative_error(&images.indirect_irradiance, &r.indirect, &r.covered)
        });
        let (mean, worst) = after_16(&errors);
        eprintln!(
            "{} turning: indirect relative error over frames 17..{PATH_FRAMES} mean {mean:.4}, \
             largest {worst:.4}",
            technique.name()
        );
        assert!(
            worst <= 0.02,
            "{} turning: indirect relative error {worst}",
            technique.name()
        );
    }

    // An object moving (`cornell-moving`'s box sliding across the floor, 0.7 m a second): the
    // camera stands, Bevy's motion vectors carry the box's motion into the technique's history,
    // and every frame after the first 16 is within ao MAE 0.0035 of nearfield's frame at the
    // same time (which poses the box there and carries its motion in its own motion vectors),
    // over the pixels the box changes: those whose ao in nearfield's frames moves by more than
    // 0.05 from the first frame's, where a history that missed the box's motion shows (vbgi
    // without the motion vectors: 0.0043, docs/src/bevy.md).
    let moving = exported("cornell-moving");
    assert!(moving.moves(), "the export keeps the box's animation");
    let moving_env = moving.default_env.load().unwrap();
    let standing = CameraPath::standing(moving.default_camera(), 2.0, 30.0).unwrap();
    for technique in [NearFieldTechnique::GTAO, NearFieldTechnique::VBGI] {
        let near_field = NearField {
            technique,
            quality: NearFieldQuality::High,
            ..default()
        };
        let params = near_field.params().unwrap();
        let setup = Setup {
            path: Some(standing.clone()),
            motion_vectors: true,
            ..Setup::still(Shading::Lit, near_field, PATH_FRAMES, true)
        };
        let run = run_bevy(&moving, setup);
        let truth = references(
            &moving,
            &moving_env,
            technique.name(),
            &params,
            |k| standing.camera(k),
            PATH_FRAMES,
        );
        let changed: Vec<bool> = (0..truth[0].ao.len())
            .map(|p| {
                truth[0].covered[p]
                    && truth
                        .iter()
                        .any(|r| r.covered[p] && (r.ao[p] - truth[0].ao[p]).abs() > 0.05)
            })
            .collect();
        let pixels = changed.iter().filter(|c| **c).count();
        assert!(pixels > 500, "the box changes {pixels} pixels");
        let maes: Vec<f64> = run
            .sequence
            .iter()
            .zip(&truth)
            .map(|(images, r)| ao_mae(&images.ao, &r.ao, &changed).0)
            .collect();
        let (mean, worst) = after_16(&maes);
        eprintln!(
            "{} with the box moving: ao MAE over the {pixels} \
             pixels it changes, frames 17..{PATH_FRAMES} mean {mean:.5}, largest {worst:.5}; \
             frames 1..16 largest {:.5}",
            technique.name(),
            maes[..16].iter().cloned().fold(0.0, f64::max)
        );
        assert!(
            worst <= 0.0035,
            "{} with the box moving: ao MAE {worst}",
            technique.name()
        );
    }

    // 4. refused settings: one line, no effect, the camera still renders.
    for bad in [
        NearField {
            radius: Some(f32::NAN),
            ..default()
        },
        NearField {
            settings: vec![("slices".into(), "0".into())],
            ..default()
        },
        // Valid settings the render world cannot make: a second depth layer Bevy does not have.
        NearField {
            settings: vec![("thickness".into(), "layer".into())],
            ..default()
        },
        // A registered technique that needs nearfield's scene (its virtual point lights).
        NearField {
            technique: NearFieldTechnique::named("ssdo-vpl").unwrap(),
            ..default()
        },
    ] {
        let e = match bad.params() {
            Err(e) => e,
            Ok(_) => "refused when made".into(),
        };
        assert!(!e.contains('\n'), "one line: {e}");
        let run = run_bevy(
            &scene,
            Setup::still(Shading::Unlit(1.0), bad, WARMUP, false),
        );
        assert!(run.images.is_none(), "a refused NearField produced images");
        assert!(run.checked.is_some_and(|c| c.is_refused()));
        // The camera renders on without the effect: the box's unlit walls are on its target.
        eprintln!("refused ({e}): {} pixels lit", run.lit);
        assert!(
            run.lit > (SIZE.0 * SIZE.1 / 4) as usize,
            "{} pixels lit",
            run.lit
        );
    }
}

/// The linear mean over the covered pixels.
fn mean(image: &[[f32; 3]], covered: &[bool]) -> f64 {
    let (sum, n) = image
        .iter()
        .zip(covered)
        .filter(|(_, c)| **c)
        .fold((0.0f64, 0usize), |(s, n), (p, _)| {
            (s + (p[0] + p[1] + p[2]) as f64 / 3.0, n + 1)
        });
    sum / n.max(1) as f64
}

/// Samples per pixel of the path-traced truth of [`the_far_field_is_read_in_bevys_units`] (its
/// image mean over 57 600 pixels is then known to well under 1 %, and its noise is the same
/// floor under every frame it is compared with).
const TRUTH_SPP: u32 = 64;

/// The far field in Bevy's units (docs/src/bevy.md, "Units"): each built-in, exported with its
/// lights, baked as `nearfield bake --format bevy` bakes it, and drawn by Bevy alone with the
/// scene's lights, the environment's sun and the volume at the file's intensity, at nearfield's
/// exposure 0 (Bevy's diffuse part: no specular lobe). The linear image mean over the surface
/// is within 10 % of `nearfield render --method none --far volume` (its `lambertian` AOV) and
/// within 15 % of the path tracer's. Controls: the volume left out, and its light counted at the
/// example's old factor of 2000, are both far outside. With the plugin on the same frame, the
/// volume its far field, gtao, hbil and vbgi leave the image error against the path tracer no
/// worse than Bevy's without them; hbil without the volume (a white sky) is worse than with it.
#[test]
fn the_far_field_is_read_in_bevys_units() {
    for name in ["cornell", "two-rooms", "closed-box"] {
        let scene = exported(name);
        // The environment as nearfield's commands load it (`--sun auto`: the sky's sun split
        // out as a disc light, which Bevy draws as its directional light).
        let (env, _) = scene
            .default_env
            .load_split(nearfield_scene::sun::SunMode::Auto)
            .unwrap();
        let grid = nearfield_reference::bake::default_grid(&scene).unwrap();
        let settings = nearfield_reference::bake::BakeSettings {
            grid,
            rays: nearfield_reference::bake::default_rays(&scene),
            bounces: nearfield_reference::bake::DEFAULT_BOUNCES,
        };
        let volume = nearfield_reference::bake::bake(&scene, &env, settings, false, None).unwrap();
        // BEVY_SUBDIVISION=K measures another resampling (docs/src/bevy.md, "The far field").
        let k = std::env::var("BEVY_SUBDIVISION")
            .ok()
            .and_then(|k| k.parse().ok())
            .unwrap_or(nearfield_scene::probes::bevy::SUBDIVISION);
        let ktx2 = nearfield_scene::probes::bevy::BevyVolume::resampled(&volume, k).to_ktx2();
        let baked = BakedVolume::from_ktx2(&ktx2).unwrap();

        // nearfield: `none` with the volume as its far field.
        let lambertian = lambertian_none(&scene, &env, Some(&volume));
        let covered: Vec<bool> = lambertian.iter().map(|p| p[3] > 0.0).collect();
        let nearfield: Vec<[f32; 3]> = lambertian.iter().map(rgb).collect();
        let truth = truth(&scene, &env);

        let bevy = |volume: Option<BakedVolume>| {
            let setup = Setup {
                near_field: None,
                lighting: Some(Lighting {
                    env: env.clone(),
                    volume,
                    env_map: EnvMap::None,
                    deferred: false,
                }),
                ..Setup::still(Shading::Diffuse, NearField::default(), FRAMES, false)
            };
            run_bevy(&scene, setup).presented
        };
        let with_volume = bevy(Some(baked.clone()));
        let without = bevy(None);
        let scaled = bevy(Some(BakedVolume {
            intensity: baked.intensity * 2000.0,
            ..baked.clone()
        }));
        assert_eq!(with_volume.len(), covered.len(), "the target's size");

        let (m_bevy, m_nf, m_truth) = (
            mean(&with_volume, &covered),
            mean(&nearfield, &covered),
            mean(&truth, &covered),
        );
        let (m_without, m_scaled) = (mean(&without, &covered), mean(&scaled, &covered));
        eprintln!(
            "{name}: relative error of Bevy + volume against nearfield {:.4}, against the path \
             tracer {:.4} (nearfield's {:.4})",
            relative_error(&with_volume, &nearfield, &covered),
            relative_error(&with_volume, &truth, &covered),
            relative_error(&nearfield, &truth, &covered)
        );
        eprintln!(
            "{name}: image mean Bevy + volume {m_bevy:.4}, nearfield none --far volume \
             {m_nf:.4} ({:.3}×), path tracer {m_truth:.4} ({:.3}×); Bevy without the volume \
             {m_without:.4} ({:.3}×), volume × 2000 {m_scaled:.2} ({:.1}×); {} surface pixels",
            m_bevy / m_nf,
            m_bevy / m_truth,
            m_without / m_truth,
            m_scaled / m_truth,
            covered.iter().filter(|c| **c).count()
        );
        assert!(
            (m_bevy / m_nf - 1.0).abs() <= 0.10,
            "{name}: Bevy {m_bevy} against nearfield {m_nf}"
        );
        assert!(
            (m_bevy / m_truth - 1.0).abs() <= 0.15,
            "{name}: Bevy {m_bevy} against the path tracer {m_truth}"
        );
        // The plugin on Bevy's volume-lit frame (its ao into Bevy's, its indirect light added),
        // the baked volume its far field: counted once, no technique makes the frame worse.
        // Control: hbil without the volume as its far field (a white sky, its near light added
        // on top of the volume's, which holds it already) is worse than with it.
        let bevy_alone = relative_error(&with_volume, &truth, &covered);
        let plugin = |technique: NearFieldTechnique, far: bool, deferred: bool| {
            let volume = BakedVolume {
                volume: baked.volume.clone().filter(|_| far),
                ..baked.clone()
            };
            let setup = Setup {
                lighting: Some(Lighting {
                    env: env.clone(),
                    volume: Some(volume),
                    env_map: EnvMap::None,
                    deferred,
                }),
                ..Setup::still(
                    Shading::Diffuse,
                    NearField {
                        technique,
                        quality: NearFieldQuality::High,
                        ..default()
                    },
                    FRAMES,
                    true,
                )
            };
            let frame = run_bevy(&scene, setup).presented;
            let error = relative_error(&frame, &truth, &covered);
            eprintln!(
                "{name}: Bevy + volume + {}{}{}: relative error {error:.4} (Bevy + volume \
                 {bevy_alone:.4}), mean {:.3}× the truth's",
                technique.name(),
                if far { "" } else { " (a white sky)" },
                if deferred { "" } else { " (forward, ρ = 0.5)" },
                mean(&frame, &covered) / m_truth
            );
            error
        };
        let mut once = 0.0;
        for technique in [
            NearFieldTechnique::GTAO,
            NearFieldTechnique::HBIL,
            NearFieldTechnique::VBGI,
        ] {
            let error = plugin(technique, true, true);
            assert!(
                error <= bevy_alone,
                "{name}: {} {error} against Bevy + volume {bevy_alone}",
                technique.name()
            );
            if technique == NearFieldTechnique::HBIL {
                once = error;
            }
        }
        // gtao on forward materials: no G-buffer, ρ = 0.5 in the ao pass.
        let forward = plugin(NearFieldTechnique::GTAO, true, false);
        assert!(
            forward <= bevy_alone,
            "{name}: gtao forward {forward} against Bevy + volume {bevy_alone}"
        );
        let twice = plugin(NearFieldTechnique::HBIL, false, true);
        assert!(
            twice > once,
            "{name}: hbil on a white sky {twice}, counted once {once}"
        );
        // The controls: the volume's light matters, and its units are not off by a factor.
        assert!(
            (m_without / m_truth - 1.0).abs() > 0.15,
            "{name}: without the volume"
        );
        assert!(m_scaled / m_truth > 2.0, "{name}: the volume at × 2000");
    }
}

/// The rgb of an rgba pixel.
fn rgb(p: &[f32; 4]) -> [f32; 3] {
    [p[0], p[1], p[2]]
}

/// The path tracer's radiance of `scene`'s view under `env` (Lambertian surfaces, the
/// environment and lights, 8 segments, [`TRUTH_SPP`]).
fn truth(scene: &nearfield_scene::Scene, env: &nearfield_scene::Environment) -> Vec<[f32; 3]> {
    let settings = nearfield_reference::ReferenceSettings {
        aov: nearfield_reference::ReferenceAov::Radiance,
        size: SIZE,
        spp: TRUTH_SPP,
        max_depth: 8,
        ..Default::default()
    };
    let camera = scene.default_camera();
    let truth = nearfield_reference::render(scene, env, &camera, &settings, false);
    truth.value.iter().map(rgb).collect()
}

/// nearfield's `lambertian` AOV of `scene`'s view under `env`, drawn with `none`: its direct
/// light and the far field's diffuse light (the volume's, or the environment's unoccluded). Its
/// GPU context is dropped before Bevy makes its own.
fn lambertian_none(
    scene: &nearfield_scene::Scene,
    env: &nearfield_scene::Environment,
    volume: Option<&nearfield_scene::probes::ProbeVolume>,
) -> Vec<[f32; 4]> {
    let ctx = GpuContext::new(None).expect("an adapter (lavapipe in CI)");
    let none =
        nearfield_render::technique::Spec::resolve("none", &TechniqueParams::default()).unwrap();
    let settings = RenderSettings {
        size: SIZE,
        ..Default::default()
    };
    let camera = scene.default_camera();
    let mut r = Renderer::new(&ctx, scene, env, volume, camera, &none, settings).unwrap();
    r.render_frame();
    r.read_aov(Aov::Lambertian).pixels
}

/// The view's environment map as the technique's sky (docs/src/bevy.md, "The far field"): each
/// open built-in, exported with its lights, drawn by Bevy with its lights, the environment's
/// sun, and the rest of the sky as the camera's `EnvironmentMapLight` (or the same radiance as a
/// `GeneratedEnvironmentMapLight`, filtered by Bevy) and no volume, at
/// nearfield's exposure 0, diffuse part only.
/// - The map's light in Bevy (the frame with it less the frame without) is within 5 % of the
///   environment's in `nearfield render --method none` (its `lambertian` AOV with the sky less
///   without it) in the image mean, and within 2 % relative error pixel by pixel (a sky lit
///   from one side, turned, among the cases: a mirrored or turned map would not be).
/// - The plugin's hbil and vbgi read it as their sky: their env-irradiance in Bevy is within
///   10 % (relative error) of nearfield's own under the same environment, and at least 3 times
///   farther from a white sky's.
/// - With the plugin, hbil and vbgi leave the image error against the path tracer no worse
///   than Bevy's frame without them.
#[test]
fn the_environment_map_is_read_as_the_sky() {
    // A sky lit from one side (+X, towards −Z: an orientation any mirroring or turn of the map
    // would move), turned 40° about +Y as `--env-rotation 40` turns a map.
    let mut one_side = nearfield_scene::Environment::from_fn("one side", 256, 128, |d| {
        let k = (d.x - d.z).max(0.0).powi(3);
        glam::Vec3::new(0.05 + 1.5 * k, 0.05 + 0.9 * k, 0.1 + 0.4 * k)
    });
    one_side.rotation = 40f32.to_radians();
    let cases = [
        ("boxes", None, EnvMap::Prefiltered),
        ("columns", None, EnvMap::Generated),
        ("boxes", Some(one_side), EnvMap::Prefiltered),
    ];
    for (name, sky, kind) in cases {
        let scene = exported(name);
        let (scene_env, _) = scene
            .default_env
            .load_split(nearfield_scene::sun::SunMode::Auto)
            .unwrap();
        let name = format!(
            "{name}{} ({kind:?})",
            if sky.is_some() {
                ", a sky lit from one side"
            } else {
                ""
            }
        );
        // The default sky's sun (split out) lights the one-sided sky's scene too.
        let env = match sky {
            Some(sky) => nearfield_scene::Environment {
                sun: scene_env.sun,
                ..sky
            },
            None => scene_env,
        };
        let mut sunlit = env.clone();
        sunlit.texels.fill(glam::Vec3::ZERO);
        let with_sky = lambertian_none(&scene, &env, None);
        let sun_only = lambertian_none(&scene, &sunlit, None);
        let covered: Vec<bool> = with_sky.iter().map(|p| p[3] > 0.0).collect();
        let truth = truth(&scene, &env);
        let run = |technique: Option<NearFieldTechnique>, env_map: EnvMap| {
            let near_field = technique.map(|technique| NearField {
                technique,
                quality: NearFieldQuality::High,
                ..default()
            });
            let setup = Setup {
                near_field: near_field.clone(),
                lighting: Some(Lighting {
                    env: env.clone(),
                    volume: None,
                    env_map,
                    deferred: near_field.is_some(),
                }),
                ..Setup::still(
                    Shading::Diffuse,
                    near_field.unwrap_or_default(),
                    FRAMES,
                    technique.is_some(),
                )
            };
            run_bevy(&scene, setup)
        };
        let alone = run(None, kind).presented;
        let dark = run(None, EnvMap::None).presented;
        assert_eq!(alone.len(), covered.len(), "the target's size");
        let m = |image: &[[f32; 3]]| mean(image, &covered);
        let m_rgba = |image: &[[f32; 4]]| m(&image.iter().map(rgb).collect::<Vec<_>>());
        let bevy_map = m(&alone) - m(&dark);
        let nearfield_map = m_rgba(&with_sky) - m_rgba(&sun_only);
        let bevy_alone = relative_error(&alone, &truth, &covered);
        // The map's light pixel by pixel (a mirrored or turned map moves it).
        let difference = |a: &[[f32; 3]], b: &[[f32; 3]]| -> Vec<[f32; 3]> {
            a.iter()
                .zip(b)
                .map(|(a, b)| [a[0] - b[0], a[1] - b[1], a[2] - b[2]])
                .collect()
        };
        let map_error = relative_error(
            &difference(&alone, &dark),
            &difference(
                &with_sky.iter().map(rgb).collect::<Vec<_>>(),
                &sun_only.iter().map(rgb).collect::<Vec<_>>(),
            ),
            &covered,
        );
        eprintln!(
            "{name}: the environment map's light in Bevy {bevy_map:.4}, in nearfield \
             {nearfield_map:.4} ({:.3}×), relative error {map_error:.4}; image mean Bevy + map {:.4}, nearfield none {:.4}, \
             path tracer {:.4}; relative error of Bevy + map against the path tracer \
             {bevy_alone:.4}",
            bevy_map / nearfield_map,
            m(&alone),
            m_rgba(&with_sky),
            m(&truth)
        );
        assert!(
            (bevy_map / nearfield_map - 1.0).abs() <= 0.05 && map_error <= 0.02,
            "{name}: the map's light in Bevy {bevy_map}, in nearfield {nearfield_map} \
             (relative error {map_error})"
        );
        let white = nearfield_scene::Environment::constant(glam::Vec3::ONE);
        for technique in [NearFieldTechnique::HBIL, NearFieldTechnique::VBGI] {
            let r = run(Some(technique), kind);
            let error = relative_error(&r.presented, &truth, &covered);
            let images = r.images.expect("the plugin's images");
            let params = NearField {
                technique,
                quality: NearFieldQuality::High,
                ..default()
            }
            .params()
            .unwrap();
            let own = reference(&scene, &env, technique.name(), &params, images.frames);
            let on_white = reference(&scene, &white, technique.name(), &params, images.frames);
            let read = relative_error(&images.env_irradiance, &own.env, &covered);
            let not_read = relative_error(&images.env_irradiance, &on_white.env, &covered);
            eprintln!(
                "{name}: Bevy + map + {}: relative error {error:.4} (Bevy + map {bevy_alone:.4}), \
                 mean {:.3}× the truth's; its env-irradiance against nearfield's {read:.4}, \
                 against a white sky's {not_read:.4}",
                technique.name(),
                m(&r.presented) / m(&truth)
            );
            assert!(
                read <= 0.10 && not_read >= 3.0 * read,
                "{name}: {} env-irradiance {read} against nearfield's, {not_read} a white sky's",
                technique.name()
            );
            assert!(
                error <= bevy_alone,
                "{name}: {} {error} against Bevy + map {bevy_alone}",
                technique.name()
            );
        }
    }
}

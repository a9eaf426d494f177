//! Crytek Sponza in Bevy with nearfield's near-field light, and nearfield's probe volume as Bevy's
//! irradiance volume for the far field. The light rig is the scene's own, as nearfield bakes and
//! renders it: the glTF's lights and the environment's sun, in Bevy's units, at nearfield's
//! exposure (docs/src/bevy.md, "Units").
//!
//! ```text
//! cargo +nightly run --release --ignore-rust-version --example sponza -- [SCENE] [options]
//!   --technique gtao|hbil|vbgi|off|bevy-ssao[-low|-medium|-ultra]|gtao-budget
//!                                               what the camera runs (default vbgi); gtao-budget:
//!                                               gtao at Bevy SSAO High's 18 samples a pixel, at
//!                                               half resolution, without denoiser (GTAO_BUDGET)
//!   --quality low|medium|high|ultra             the preset (default high)
//!   --volume FILE.ktx2                          `nearfield bake --format bevy`'s volume,
//!                                               baked with the same --env and --env-intensity
//!   --env FILE.hdr|sky                          the environment: its sun is spawned, and
//!                                               without --volume the rest is the camera's
//!                                               environment map (default: the scene's, as
//!                                               nearfield's)
//!   --env-intensity K                           its radiance × K, in cd/m² (default 1)
//!   --exposure STOPS                            nearfield's exposure (default: 8 for Sponza's
//!                                               view, the book's; 0 for a SCENE given)
//!   --size WxH                                  window size (default 1280x720)
//!   --screenshot FILE.png                       save the window after --frames frames and exit
//!   --frames N                                  (default 60)
//!   --mean                                      render into a linear image (no tone mapping,
//!                                               black background) and print its mean after
//!                                               --frames frames, then exit
//!   --linear FILE.exr                           as --mean, and write that image (EXR)
//!   --move                                      the camera walks (nearfield's `--walk` of the
//!                                               view, back and forth) and a ball rolls across
//!                                               the floor before it, at 60 frames a second
//!   --taa                                       Bevy's TAA on the camera
//!   --bench                                     time off, Bevy's SSAO Low, Medium, High
//!                                               (bevy-ssao) and Ultra, the three techniques
//!                                               and gtao-budget A B A B and print a table,
//!                                               with each effect's GPU time (Bevy's render
//!                                               diagnostics)
//!   --bench-frames N                            timed frames per configuration and round
//!                                               (default 30)
//!   --headless                                  no window: the camera draws into an image
//!                                               (with --bench, --mean or --linear)
//! ```
//! Keys in the window: 0 off, 1 gtao, 2 hbil, 3 vbgi, 4 Bevy's SSAO High, 5 gtao-budget.
//!
//! SCENE defaults to `../shared/assets/scenes/crytek_sponza/Sponza.gltf` (beside the repository).
//! The camera is the one nearfield's fits use in Sponza (`docs/src/fits/sponza-camera.json`).

use bevy::anti_alias::taa::TemporalAntiAliasing;
use bevy::camera::Hdr;
use bevy::camera::RenderTarget;
use bevy::core_pipeline::prepass::{
    DeferredPrepass, DepthPrepass, MotionVectorPrepass, NormalPrepass,
};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::pbr::{ScreenSpaceAmbientOcclusion, ScreenSpaceAmbientOcclusionQualityLevel};
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::view::Msaa;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured, save_to_disk};
use bevy::window::{PresentMode, WindowResolution};
use bevy_nearfield::far::BakedVolume;
use bevy_nearfield::scene::{self, Shading};
use bevy_nearfield::{NearField, NearFieldPlugin, NearFieldTechnique};
use std::time::Instant;

mod bench;
mod options;

use bench::BENCH;
use options::{Options, fail, options};

fn main() {
    let o = options();
    if o.bench && (o.screenshot.is_some() || o.mean) {
        fail("--bench and --screenshot or --mean: one at a time");
    }
    if o.headless && !(o.bench || o.mean) || o.headless && o.screenshot.is_some() {
        fail("--headless: with --bench, --mean or --linear (no window to screenshot)");
    }
    let loaded = nearfield_scene::load_scene(&o.scene).unwrap_or_else(|e| fail(&e.to_string()));
    let volume = o
        .volume
        .as_ref()
        .map(|p| BakedVolume::read(p).unwrap_or_else(|e| fail(&e)));
    let source = match &o.env {
        Some(e) => nearfield_scene::EnvSource::parse(e),
        None => Ok(loaded.default_env.clone()),
    };
    // As nearfield's commands load it (`--sun auto`): the sun split out as a disc light, which
    // Bevy draws as a directional light.
    let (mut env, _) = source
        .and_then(|s| s.load_split(nearfield_scene::sun::SunMode::Auto))
        .unwrap_or_else(|e| fail(&nearfield_scene::one_line(&e.to_string())));
    env.intensity = o.env_intensity;
    let (w, h) = o.size;
    let mut app = App::new();
    if o.headless {
        // No window: the camera draws into an image (setup), frame after frame.
        app.add_plugins(
            DefaultPlugins
                .set(WindowPlugin {
                    primary_window: None,
                    exit_condition: bevy::window::ExitCondition::DontExit,
                    close_when_requested: false,
                    ..default()
                })
                .disable::<bevy::winit::WinitPlugin>(),
        )
        .add_plugins(bevy::app::ScheduleRunnerPlugin::run_loop(
            std::time::Duration::ZERO,
        ));
    } else {
        app.add_plugins(DefaultPlugins.set(WindowPlugin {
            primary_window: Some(Window {
                title: "bevy_nearfield: sponza".into(),
                resolution: WindowResolution::new(w, h).with_scale_factor_override(1.0),
                present_mode: PresentMode::AutoNoVsync,
                ..default()
            }),
            ..default()
        }));
    }
    if o.bench {
        // GPU time of each effect's span (Bevy's `ssao`, the plugin's `nearfield`).
        app.add_plugins(bevy::render::diagnostic::RenderDiagnosticsPlugin);
        app.add_systems(Update, (keys, bench::step, animate).chain());
    } else {
        app.add_systems(Update, (keys, step, animate).chain());
    }
    // A SCENE with glTF node animation plays it in a loop (nothing moves in Sponza).
    app.add_systems(Update, scene::play_scene_motion);
    app.add_plugins(NearFieldPlugin)
        // The plugin's indirect light reads ρ from Bevy's deferred G-buffer, which only
        // deferred materials write; --bench times Bevy's forward path.
        .insert_resource(if o.bench {
            bevy::pbr::DefaultOpaqueRendererMethod::forward()
        } else {
            bevy::pbr::DefaultOpaqueRendererMethod::deferred()
        })
        // The far field is the volume, or without one the camera's environment map.
        .insert_resource(GlobalAmbientLight {
            brightness: 0.0,
            ..default()
        })
        // With --mean the background is black: the mean is the surfaces' light over the frame.
        .insert_resource(ClearColor(if o.mean {
            Color::BLACK
        } else {
            Color::srgb(0.45, 0.6, 0.85)
        }))
        .insert_resource(Scene(loaded, volume, env))
        .insert_resource(Run {
            frame: 0,
            phase: 0,
            last: None,
            times: Vec::new(),
            gpu: Vec::new(),
            span_seen: None,
        })
        .insert_resource(o)
        .add_systems(Startup, setup)
        .run();
}

#[derive(Resource)]
struct Scene(
    nearfield_scene::Scene,
    Option<BakedVolume>,
    nearfield_scene::Environment,
);

#[derive(Resource)]
struct Run {
    frame: u32,
    phase: usize,
    last: Option<Instant>,
    /// (configuration, frame time in ms) of every timed frame.
    times: Vec<(String, f64)>,
    /// (configuration, its effect's GPU time in ms) of every diagnostics measurement in timed
    /// frames, and when the latest counted was synced.
    gpu: Vec<(String, f64)>,
    span_seen: Option<Instant>,
}

#[derive(Component)]
struct TheCamera;

/// The exposure of Sponza's view (stops), the book's for its pictures of it: the arcade is lit
/// by the sky's bounce, at nearfield's scale (an open upward surface E/π = 1).
const SPONZA_EXPOSURE: f32 = 8.0;

/// With `--mean`: the camera's linear target.
#[derive(Resource)]
struct MeanTarget(Handle<Image>);

/// With `--move`: the camera's walk and the rolling ball.
#[derive(Resource)]
struct Motion {
    walk: nearfield_scene::CameraPath,
}

#[derive(Component)]
struct Ball;

/// The ball's radius (m), and the line it rolls along (from, to) on the floor before the camera.
const BALL_RADIUS: f32 = 0.45;
const BALL_LINE: (Vec3, Vec3) = (Vec3::new(2.5, 0.0, -1.5), Vec3::new(2.5, 0.0, 1.5));
/// Seconds the ball takes from one end of its line to the other.
const BALL_SECONDS: f32 = 3.0;
/// The clock of `--move`: frame n shows time n / 60 s, whatever the frame rate, so that a
/// screenshot after `--frames N` is one picture.
const MOVE_FPS: f32 = 60.0;

/// Back and forth over [0, period]: t for the first period, then back down, and so on.
fn ping_pong(t: f32, period: f32) -> f32 {
    let u = t.rem_euclid(2.0 * period);
    if u <= period { u } else { 2.0 * period - u }
}

/// Poses the camera on its walk and the ball on its line for this frame (`--move`).
fn animate(
    run: Res<Run>,
    motion: Option<Res<Motion>>,
    options: Res<Options>,
    mut camera: Single<&mut Transform, (With<TheCamera>, Without<Ball>)>,
    mut ball: Query<&mut Transform, With<Ball>>,
) {
    let Some(motion) = motion else { return };
    let t = run.frame as f32 / MOVE_FPS;
    let walk = &motion.walk;
    let c = walk.camera_at(ping_pong(t, walk.duration()));
    **camera = scene::camera(&c, options.size, 0.05).0;
    let s = ping_pong(t, BALL_SECONDS) / BALL_SECONDS;
    let (from, to) = BALL_LINE;
    let travelled = (to - from).length() * s;
    let dir = (to - from).normalize();
    for mut b in &mut ball {
        b.translation = from.lerp(to, s) + Vec3::Y * BALL_RADIUS;
        // Rolling without slipping: turned about the axis across its path by distance / radius.
        b.rotation = Quat::from_axis_angle(Vec3::Y.cross(dir), travelled / BALL_RADIUS);
    }
}

fn setup(
    mut commands: Commands,
    mut loaded: ResMut<Scene>,
    options: Res<Options>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut images: ResMut<Assets<Image>>,
) {
    scene::spawn_scene(
        &mut commands,
        &mut meshes,
        &mut materials,
        &mut images,
        &loaded.0,
        Shading::Lit,
    );
    // Sponza's view of nearfield's fits, else the scene's own camera (a glTF camera, or one
    // that frames the scene).
    let camera = if options.scene_given {
        loaded.0.default_camera()
    } else {
        nearfield_scene::Camera::new(
            glam::Vec3::new(9.0, 1.5, -0.4),
            glam::Vec3::new(-5.0, 3.5, 0.2),
            60.0,
        )
    };
    let (transform, projection) = scene::camera(&camera, options.size, 0.05);
    let id = commands
        .spawn((
            Camera3d::default(),
            TheCamera,
            transform,
            projection,
            Msaa::Off,
            Hdr,
            Tonemapping::AcesFitted,
            scene::exposure(options.exposure.unwrap_or(if options.scene_given {
                0.0
            } else {
                SPONZA_EXPOSURE
            })),
        ))
        .id();
    // Without a volume, the environment (its sun aside) is the camera's environment map: Bevy's
    // far field, which the technique reads as its sky.
    if loaded.1.is_none() {
        let map = scene::environment_map_light(&mut images, &loaded.2);
        commands.entity(id).insert(map);
    }
    if options.mean || options.headless {
        // The frame into a linear image of the window's size (read back by `step` for --mean).
        let (w, h) = options.size;
        let mut target = Image::new_target_texture(w, h, TextureFormat::Rgba16Float, None);
        target.texture_descriptor.usage |= TextureUsages::COPY_SRC;
        let target = images.add(target);
        commands.entity(id).insert((
            RenderTarget::Image(target.clone().into()),
            Tonemapping::None,
            bevy::core_pipeline::tonemapping::DebandDither::Disabled,
        ));
        commands.insert_resource(MeanTarget(target));
    }
    configure(&mut commands, id, &options.technique, &options);
    if options.taa {
        commands.entity(id).insert(TemporalAntiAliasing::default());
    }
    if options.moving {
        let walk = nearfield_scene::CameraPath::walk(camera, loaded.0.bounds(), MOVE_FPS)
            .unwrap_or_else(|e| fail(&format!("--move: {e}")));
        commands.insert_resource(Motion { walk });
        // A chequered ball, so that its rolling shows.
        let mut ball = Sphere::new(BALL_RADIUS).mesh().uv(32, 16);
        let colours: Vec<[f32; 4]> = ball
            .attribute(Mesh::ATTRIBUTE_POSITION)
            .and_then(|p| p.as_float3())
            .unwrap_or_default()
            .iter()
            .map(|p| {
                let check = ((p[0] * 8.0).floor() + (p[1] * 8.0).floor() + (p[2] * 8.0).floor())
                    .rem_euclid(2.0);
                if check < 1.0 {
                    [0.9, 0.2, 0.1, 1.0]
                } else {
                    [0.9, 0.85, 0.8, 1.0]
                }
            })
            .collect();
        ball.insert_attribute(Mesh::ATTRIBUTE_COLOR, colours);
        commands.spawn((
            Ball,
            Mesh3d(meshes.add(ball)),
            MeshMaterial3d(materials.add(StandardMaterial {
                perceptual_roughness: 0.6,
                ..default()
            })),
            Transform::from_translation(BALL_LINE.0 + Vec3::Y * BALL_RADIUS),
        ));
    }
    scene::spawn_lights(&mut commands, &loaded.0, &loaded.2);
    if let Some(volume) = loaded.1.take() {
        volume.spawn(&mut commands, &mut images);
    }
}

/// Puts configuration `name` on the camera. Under `--bench`, which times every configuration in
/// Bevy's forward path (the added indirect term's one full-screen pass is then not drawn), `off`
/// is the camera without prepasses (what turning an effect on costs includes them). Otherwise
/// the materials are deferred: every configuration has Bevy's depth and deferred prepasses, and
/// the techniques also the motion-vector prepass.
fn configure(commands: &mut Commands, camera: Entity, name: &str, options: &Options) {
    let mut c = commands.entity(camera);
    c.remove::<(
        NearField,
        ScreenSpaceAmbientOcclusion,
        DepthPrepass,
        NormalPrepass,
        MotionVectorPrepass,
        DeferredPrepass,
    )>();
    // Outside --bench the materials are drawn deferred (main): every configuration then
    // needs Bevy's deferred and depth prepasses (its lighting pass rebuilds positions from the
    // prepass depth), or nothing, or nonsense, is drawn.
    if !options.bench {
        c.insert((DepthPrepass, DeferredPrepass));
    }
    let mut settings = Vec::new();
    let technique = match name {
        "gtao" => NearFieldTechnique::GTAO,
        "gtao-budget" => {
            settings = GTAO_BUDGET
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect();
            NearFieldTechnique::GTAO
        }
        "hbil" => NearFieldTechnique::HBIL,
        "vbgi" => NearFieldTechnique::VBGI,
        s if s.starts_with("bevy-ssao") => {
            use ScreenSpaceAmbientOcclusionQualityLevel as Q;
            let quality_level = match s {
                "bevy-ssao-low" => Q::Low,
                "bevy-ssao-medium" => Q::Medium,
                "bevy-ssao-ultra" => Q::Ultra,
                _ => Q::High,
            };
            c.insert(ScreenSpaceAmbientOcclusion {
                quality_level,
                ..default()
            });
            return;
        }
        _ => return,
    };
    c.insert(NearField {
        technique,
        quality: options.quality,
        radius: Some(1.0),
        settings,
        ..default()
    });
    if !options.bench {
        c.insert(MotionVectorPrepass);
    }
}

fn keys(
    mut commands: Commands,
    input: Res<ButtonInput<KeyCode>>,
    camera: Single<Entity, With<TheCamera>>,
    options: Res<Options>,
) {
    for (key, name) in [
        (KeyCode::Digit0, "off"),
        (KeyCode::Digit1, "gtao"),
        (KeyCode::Digit2, "hbil"),
        (KeyCode::Digit3, "vbgi"),
        (KeyCode::Digit4, "bevy-ssao"),
        (KeyCode::Digit5, "gtao-budget"),
    ] {
        if input.just_pressed(key) {
            configure(&mut commands, *camera, name, &options);
        }
    }
}

/// gtao at Bevy SSAO High's budget (3 slices × 3 steps a side: 18 samples a pixel), the cheapest
/// configuration the book's peer run found at least as accurate as Bevy High (results.md,
/// "Costs"): half resolution, no interleaving, no blur, no running mean.
const GTAO_BUDGET: [(&str, &str); 7] = [
    ("slices", "3"),
    ("steps", "3"),
    ("resolution", "half"),
    ("step_power", "1"),
    ("interleaved", "off"),
    ("denoise", "off"),
    ("temporal", "off"),
];
/// Prints the linear mean of the `--mean` target (RGBA16F, Bevy's exposure applied) and writes
/// it to `linear` (EXR) when given.
fn print_mean(shot: &ScreenshotCaptured, size: (u32, u32), linear: Option<&std::path::Path>) {
    let px: Vec<[f32; 3]> = shot
        .image
        .data
        .as_deref()
        .unwrap_or_default()
        .chunks_exact(8)
        .map(|p| {
            let c = |k: usize| half::f16::from_le_bytes([p[2 * k], p[2 * k + 1]]).to_f32();
            [c(0), c(1), c(2)]
        })
        .collect();
    let n = px.len().max(1) as f64;
    let m = |k: usize| px.iter().map(|p| p[k] as f64).sum::<f64>() / n;
    let (r, g, b) = (m(0), m(1), m(2));
    println!(
        "sponza: linear image mean {:.6} (r {r:.6}, g {g:.6}, b {b:.6}) over {} pixels",
        (r + g + b) / 3.0,
        px.len()
    );
    if let Some(path) = linear {
        let image = nearfield_reference::ReferenceImage {
            width: size.0,
            height: size.1,
            value: px.iter().map(|p| [p[0], p[1], p[2], 1.0]).collect(),
            stderr: vec![[0.0; 3]; px.len()],
            depth: vec![0.0; px.len()],
            rays: 0,
        };
        if let Err(e) = nearfield_reference::exr_io::write(&image, path) {
            eprintln!("sponza: {}: {e}", path.display());
        }
    }
}

/// Outside `--bench`: the screenshot or the linear mean after `--frames`, then exit.
fn step(
    mut commands: Commands,
    mut run: ResMut<Run>,
    options: Res<Options>,
    mean_target: Option<Res<MeanTarget>>,
    mut exit: MessageWriter<AppExit>,
) {
    run.frame += 1;
    if run.frame == options.frames {
        if let Some(path) = &options.screenshot {
            commands
                .spawn(Screenshot::primary_window())
                .observe(save_to_disk(path.clone()));
        }
        if let Some(target) = &mean_target {
            let (size, linear) = (options.size, options.linear.clone());
            commands.spawn(Screenshot::image(target.0.clone())).observe(
                move |shot: On<ScreenshotCaptured>| print_mean(&shot, size, linear.as_deref()),
            );
        }
    }
    if (options.screenshot.is_some() || options.mean) && run.frame == options.frames + 5 {
        exit.write(AppExit::Success);
    }
}

//! Bevy 0.20's screen-space ambient occlusion (`ScreenSpaceAmbientOcclusion`: depth mip chain,
//! visibility-bitmask AO, 3×3 spatial denoise) on a scene exported by `nearfield export`: frame
//! times with SSAO off and at each quality preset, and each preset's AO as EXR so that
//! `nearfield compare --image bevy-high=ao-high.exr` measures it against nearfield's reference.
//!
//! Usage: bevy-ssao-peer SCENE.glb [--size 1280x720] [--radius 0.5] [--warmup 10] [--frames 30]
//!        [--rounds 2] [--presets off,low,medium,high,ultra] [--sun ELEVATION,AZIMUTH,RADIUS]
//!        [--out DIR]
//!
//! With `--sun` (degrees: nearfield's sun, as `nearfield render` prints it) a further timed
//! configuration, "sun", adds a directional light with Bevy's shadows to "off": cascaded shadow
//! maps with Bevy's default filter, or, built with `--features pcss`, percentage-closer soft
//! shadows sized to the disc (`soft_shadow_size`, Bevy's `experimental_pbr_pcss`, which makes
//! every frame dearer, "off" included). It is the frame of a Bevy app that draws the same sun
//! as nearfield's `none` frame, for timing only (no AO is read from it).
//!
//! Timing: one window (no vsync), frames measured from the start of one frame to the next.
//! Round 0 runs every configuration untimed (pipelines compile on first use); then `--rounds`
//! rounds go through the configurations in turn (off, low, …, off, low, …), so that a drift of
//! the machine touches all of them alike. "off" is the camera without SSAO *and* without the
//! depth and normal prepasses SSAO requires: what enabling SSAO costs a Bevy app.
//!
//! AO: Bevy applies its AO only to indirect (ambient) light, through `ssao_multibounce(ao,
//! albedo)`. The scene is drawn with ambient light only, no tonemapping or dither, every surface
//! a rough grey dielectric of albedo 0.02 (where the multibounce curve is the identity to within
//! 0.07 %), so a pixel's value with SSAO is its value without SSAO × Bevy's AO: the AO written is
//! that ratio, from two screenshots (8-bit sRGB; brightness calibrated so the brightest pixel
//! without SSAO is 0.85). Background pixels get 1 (the comparison masks them out).

use bevy::asset::RenderAssetUsages;
use bevy::camera::{PerspectiveProjection, Projection};
use bevy::core_pipeline::prepass::{DepthPrepass, NormalPrepass};
use bevy::mesh::Indices;
use bevy::pbr::{ScreenSpaceAmbientOcclusion, ScreenSpaceAmbientOcclusionQualityLevel as Q};
use bevy::prelude::*;
use bevy::render::render_resource::PrimitiveTopology;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::render::view::{DebandDither, Msaa, Tonemapping};
use bevy::window::{PresentMode, WindowResolution};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Instant;

const ALBEDO: f32 = 0.02;

#[derive(Clone)]
struct Options {
    scene: PathBuf,
    size: (u32, u32),
    radius: f32,
    warmup: u32,
    frames: u32,
    rounds: u32,
    presets: Vec<String>,
    /// The sun's direction towards it and its angular radius (rad).
    sun: Option<(Vec3, f32)>,
    out: PathBuf,
}

fn usage(msg: &str) -> ! {
    eprintln!("bevy-ssao-peer: error: {msg}");
    eprintln!(
        "usage: bevy-ssao-peer SCENE.glb [--size WxH] [--radius R] [--warmup N] [--frames N] [--rounds N] [--presets off,low,medium,high,ultra] [--sun ELEVATION,AZIMUTH,RADIUS] [--out DIR]"
    );
    std::process::exit(2)
}

fn parse_options() -> Options {
    let mut args = std::env::args().skip(1);
    let mut o = Options {
        scene: PathBuf::new(),
        size: (1280, 720),
        radius: 0.5,
        warmup: 10,
        frames: 30,
        rounds: 2,
        presets: ["off", "low", "medium", "high", "ultra"]
            .map(String::from)
            .to_vec(),
        sun: None,
        out: PathBuf::from("bevy-ssao"),
    };
    let mut scene = None;
    while let Some(a) = args.next() {
        let mut value = |name: &str| {
            args.next()
                .unwrap_or_else(|| usage(&format!("{name} needs a value")))
        };
        let number = |name: &str, v: String| -> u32 {
            v.parse()
                .ok()
                .filter(|n| (1..=100_000).contains(n))
                .unwrap_or_else(|| usage(&format!("{name} {v}: expected 1..=100000")))
        };
        match a.as_str() {
            "--size" => {
                let v = value("--size");
                let p: Vec<u32> = v.split('x').filter_map(|s| s.parse().ok()).collect();
                match p[..] {
                    [w, h] if (1..=8192).contains(&w) && (1..=8192).contains(&h) => o.size = (w, h),
                    _ => usage(&format!("--size {v}: expected WIDTHxHEIGHT")),
                }
            }
            "--radius" => {
                let v = value("--radius");
                o.radius = v
                    .parse()
                    .ok()
                    .filter(|r: &f32| r.is_finite() && *r > 0.0)
                    .unwrap_or_else(|| usage(&format!("--radius {v}: expected a number > 0")));
            }
            "--warmup" => o.warmup = number("--warmup", value("--warmup")),
            "--frames" => o.frames = number("--frames", value("--frames")),
            "--rounds" => o.rounds = number("--rounds", value("--rounds")),
            "--out" => o.out = PathBuf::from(value("--out")),
            "--presets" => {
                let v = value("--presets");
                o.presets = v.split(',').map(|s| s.trim().to_string()).collect();
                for p in &o.presets {
                    if preset(p).is_none() && p != "off" && p != "sun" {
                        usage(&format!(
                            "--presets: unknown preset {p} (known: off, low, medium, high, ultra, sun)"
                        ));
                    }
                }
                if !o.presets.iter().any(|p| p == "off") {
                    o.presets.insert(0, "off".into());
                }
            }
            "--sun" => {
                let v = value("--sun");
                let p: Vec<f32> = v.split(',').filter_map(|s| s.trim().parse().ok()).collect();
                match p[..] {
                    [el, az, r]
                        if (-90.0..=90.0).contains(&el)
                            && az.is_finite()
                            && r > 0.0
                            && r < 45.0 =>
                    {
                        // nearfield's angles: elevation above the horizon, azimuth
                        // atan2(x, −z) of the direction towards the sun.
                        let (el, az) = (el.to_radians(), az.to_radians());
                        let d = Vec3::new(az.sin() * el.cos(), el.sin(), -az.cos() * el.cos());
                        o.sun = Some((d, r.to_radians()));
                    }
                    _ => usage(&format!(
                        "--sun {v}: expected ELEVATION,AZIMUTH,RADIUS in degrees (radius in (0, 45))"
                    )),
                }
            }
            s if s.starts_with("--") => usage(&format!("unknown option {s}")),
            s => scene = Some(PathBuf::from(s)),
        }
    }
    if o.sun.is_some() && !o.presets.iter().any(|p| p == "sun") {
        o.presets.push("sun".into());
    }
    o.scene =
        scene.unwrap_or_else(|| usage("no scene given (a .glb or .gltf from `nearfield export`)"));
    if !o.scene.is_file() {
        usage(&format!("{}: no such file", o.scene.display()));
    }
    o
}

fn preset(name: &str) -> Option<Q> {
    Some(match name {
        "low" => Q::Low,
        "medium" => Q::Medium,
        "high" => Q::High,
        "ultra" => Q::Ultra,
        _ => return None,
    })
}

/// Slices and samples per slice side of a preset (Bevy's `sample_counts`, which is private).
fn counts(q: Q) -> (u32, u32) {
    match q {
        Q::Low => (1, 2),
        Q::Medium => (2, 2),
        Q::High => (3, 3),
        Q::Ultra => (9, 3),
        Q::Custom {
            slice_count,
            samples_per_slice_side,
        } => (slice_count, samples_per_slice_side),
    }
}

/// One primitive's positions, normals and indices (world space).
type Triangles = (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>);

/// The scene's triangles (world space) and its camera 0, read with the `gltf` crate.
#[derive(Resource)]
struct Loaded {
    meshes: Vec<Triangles>,
    eye: Vec3,
    forward: Vec3,
    up: Vec3,
    yfov: f32,
}

fn load(path: &std::path::Path) -> Result<Loaded, String> {
    let (doc, buffers, _) = gltf::import(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let scene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or("no scene")?;
    let mut out = Loaded {
        meshes: Vec::new(),
        eye: Vec3::ZERO,
        forward: Vec3::NEG_Z,
        up: Vec3::Y,
        yfov: 0.0,
    };
    fn visit(node: gltf::Node, parent: Mat4, buffers: &[gltf::buffer::Data], out: &mut Loaded) {
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                let r = prim.reader(|b| Some(&buffers[b.index()]));
                let Some(pos) = r.read_positions() else {
                    continue;
                };
                let pos: Vec<[f32; 3]> = pos
                    .map(|p| world.transform_point3(Vec3::from(p)).to_array())
                    .collect();
                let normal_m = Mat3::from_mat4(world).inverse().transpose();
                let nrm: Vec<[f32; 3]> = match r.read_normals() {
                    Some(n) => n
                        .map(|n| (normal_m * Vec3::from(n)).normalize_or_zero().to_array())
                        .collect(),
                    None => vec![[0.0, 1.0, 0.0]; pos.len()],
                };
                let idx: Vec<u32> = match r.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..pos.len() as u32).collect(),
                };
                out.meshes.push((pos, nrm, idx));
            }
        }
        if let Some(cam) = node.camera()
            && let gltf::camera::Projection::Perspective(p) = cam.projection()
            && out.yfov == 0.0
        {
            out.eye = world.transform_point3(Vec3::ZERO);
            out.forward = world.transform_vector3(Vec3::NEG_Z).normalize();
            out.up = world.transform_vector3(Vec3::Y).normalize();
            out.yfov = p.yfov();
        }
        for c in node.children() {
            visit(c, world, buffers, out);
        }
    }
    for n in scene.nodes() {
        visit(n, Mat4::IDENTITY, &buffers, &mut out);
    }
    if out.yfov == 0.0 {
        return Err(format!(
            "{}: no perspective camera (export it with `nearfield export`)",
            path.display()
        ));
    }
    Ok(out)
}

#[derive(Resource)]
struct Run {
    options: Options,
    /// (configuration, timed?) in order.
    phases: Vec<(String, bool)>,
    phase: usize,
    frame_in_phase: u32,
    last: Option<Instant>,
    times: BTreeMap<String, Vec<f64>>,
    /// Screenshots still to take, and what was captured.
    shots_todo: Vec<String>,
    waiting: Option<String>,
    shots: Arc<Mutex<BTreeMap<String, Image>>>,
    calibrated: bool,
    brightness: f32,
    done: bool,
}

fn main() {
    let options = parse_options();
    let loaded = load(&options.scene).unwrap_or_else(|e| usage(&e));
    let mut phases: Vec<(String, bool)> =
        options.presets.iter().map(|p| (p.clone(), false)).collect();
    for _ in 0..options.rounds {
        phases.extend(options.presets.iter().map(|p| (p.clone(), true)));
    }
    std::fs::create_dir_all(&options.out)
        .unwrap_or_else(|e| usage(&format!("{}: {e}", options.out.display())));
    let (w, h) = options.size;
    let mut shots_todo = vec!["off".to_string()];
    shots_todo.extend(
        options
            .presets
            .iter()
            .filter(|p| preset(p).is_some())
            .cloned(),
    );
    App::new()
        .add_plugins(DefaultPlugins.set(WindowPlugin {
            primary_window: Some(Window {
                title: "bevy ssao peer".into(),
                resolution: WindowResolution::new(w, h).with_scale_factor_override(1.0),
                present_mode: PresentMode::AutoNoVsync,
                resizable: false,
                ..default()
            }),
            ..default()
        }))
        .insert_resource(GlobalAmbientLight {
            brightness: 0.0,
            ..default()
        })
        .insert_resource(ClearColor(Color::BLACK))
        .insert_resource(Run {
            options,
            phases,
            phase: 0,
            frame_in_phase: 0,
            last: None,
            times: BTreeMap::new(),
            shots_todo,
            waiting: None,
            shots: Arc::new(Mutex::new(BTreeMap::new())),
            calibrated: false,
            brightness: 100_000.0,
            done: false,
        })
        .insert_resource(loaded)
        .add_systems(Startup, setup)
        .add_systems(Update, step)
        .run();
}

#[derive(Component)]
struct TheCamera;

/// The entity that carries the sun's `DirectionalLight` (this one) in the "sun" configuration.
#[derive(Component)]
struct TheSun(DirectionalLight);

fn setup(
    mut commands: Commands,
    loaded: Res<Loaded>,
    run: Res<Run>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let material = materials.add(StandardMaterial {
        base_color: Color::linear_rgb(ALBEDO, ALBEDO, ALBEDO),
        perceptual_roughness: 1.0,
        metallic: 0.0,
        reflectance: 0.0,
        // Single-sided walls cast shadows whichever side the sun is on, as in nearfield's
        // shadow maps (the camera sees only front faces, so the AO is unchanged).
        cull_mode: None,
        double_sided: true,
        ..default()
    });
    for (pos, nrm, idx) in &loaded.meshes {
        let mesh = Mesh::new(
            PrimitiveTopology::TriangleList,
            RenderAssetUsages::default(),
        )
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, pos.clone())
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, nrm.clone())
        .with_inserted_indices(Indices::U32(idx.clone()));
        commands.spawn((Mesh3d(meshes.add(mesh)), MeshMaterial3d(material.clone())));
    }
    if let Some((towards, angular_radius)) = run.options.sun {
        #[cfg(not(feature = "pcss"))]
        let _ = angular_radius;
        commands.spawn((
            TheSun(DirectionalLight {
                // Timing only: the value does not change the cost.
                illuminance: 10_000.0,
                shadow_maps_enabled: true,
                #[cfg(feature = "pcss")]
                soft_shadow_size: Some(angular_radius.tan()),
                ..default()
            }),
            Transform::default().looking_to(
                -towards,
                if towards.y.abs() > 0.99 {
                    Vec3::X
                } else {
                    Vec3::Y
                },
            ),
        ));
    }
    let (w, h) = run.options.size;
    commands.spawn((
        Camera3d::default(),
        TheCamera,
        Transform::from_translation(loaded.eye).looking_to(loaded.forward, loaded.up),
        Projection::Perspective(PerspectiveProjection {
            fov: loaded.yfov,
            aspect_ratio: w as f32 / h as f32,
            near: 0.01,
            ..default()
        }),
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        AmbientLight {
            brightness: run.brightness,
            ..default()
        },
    ));
}

fn configure(
    commands: &mut Commands,
    camera: Entity,
    sun: Option<(Entity, &TheSun)>,
    config: &str,
    radius: f32,
) {
    if let Some((entity, TheSun(light))) = sun {
        let mut s = commands.entity(entity);
        if config == "sun" {
            s.insert(light.clone());
        } else {
            s.remove::<DirectionalLight>();
        }
    }
    let mut c = commands.entity(camera);
    match preset(config) {
        Some(q) => {
            c.insert((
                ScreenSpaceAmbientOcclusion {
                    quality_level: q,
                    radius,
                    ..default()
                },
                DepthPrepass,
                NormalPrepass,
            ));
        }
        None => {
            c.remove::<(ScreenSpaceAmbientOcclusion, DepthPrepass, NormalPrepass)>();
        }
    }
}

fn step(
    mut commands: Commands,
    mut run: ResMut<Run>,
    camera: Single<(Entity, &mut AmbientLight), With<TheCamera>>,
    sun: Option<Single<(Entity, &TheSun)>>,
    mut exit: MessageWriter<AppExit>,
) {
    let (camera, mut ambient) = camera.into_inner();
    let sun = sun.map(|s| s.into_inner());
    let now = Instant::now();
    let dt = run.last.map(|l| (now - l).as_secs_f64() * 1e3);
    run.last = Some(now);
    let radius = run.options.radius;
    // Timing phases.
    if run.phase < run.phases.len() {
        let (config, timed) = run.phases[run.phase].clone();
        if run.frame_in_phase == 0 {
            configure(&mut commands, camera, sun, &config, radius);
        } else if timed && run.frame_in_phase > run.options.warmup + 1 {
            // Frame k's time is the interval that ends at the start of frame k + 1.
            if let Some(dt) = dt {
                run.times.entry(config.clone()).or_default().push(dt);
            }
        }
        run.frame_in_phase += 1;
        let length = run.options.warmup + 1 + if timed { run.options.frames + 1 } else { 0 };
        if run.frame_in_phase > length {
            run.phase += 1;
            run.frame_in_phase = 0;
        }
        return;
    }
    // Screenshot phases: configure, settle, capture, wait for the image.
    if let Some(name) = run.waiting.clone() {
        let done = run.shots.lock().unwrap().contains_key(&name);
        if !done {
            return;
        }
        run.waiting = None;
        if name == "off" && !run.calibrated {
            // Scale the ambient light so that the brightest pixel without SSAO is 0.85, then
            // take "off" again.
            let peak = max_linear(&run.shots.lock().unwrap()["off"]);
            run.shots.lock().unwrap().remove("off");
            if peak <= 0.0 {
                eprintln!(
                    "bevy-ssao-peer: error: the scene is black without SSAO (nothing in view?)"
                );
                std::process::exit(1);
            }
            run.brightness *= 0.85 / peak;
            ambient.brightness = run.brightness;
            run.calibrated = true;
            run.shots_todo.insert(0, "off".into());
        }
        run.frame_in_phase = 0;
        return;
    }
    if let Some(name) = run.shots_todo.first().cloned() {
        if run.frame_in_phase == 0 {
            configure(&mut commands, camera, sun, &name, radius);
        }
        run.frame_in_phase += 1;
        if run.frame_in_phase > run.options.warmup + 2 {
            run.shots_todo.remove(0);
            run.waiting = Some(name.clone());
            let shots = run.shots.clone();
            commands.spawn(Screenshot::primary_window()).observe(
                move |shot: On<ScreenshotCaptured>| {
                    shots
                        .lock()
                        .unwrap()
                        .insert(name.clone(), shot.image.clone());
                },
            );
        }
        return;
    }
    if run.done {
        return;
    }
    run.done = true;
    if let Err(e) = finish(&run) {
        eprintln!("bevy-ssao-peer: error: {e}");
        std::process::exit(1);
    }
    exit.write(AppExit::Success);
}

fn max_linear(img: &Image) -> f32 {
    let (w, h) = (img.width(), img.height());
    let mut peak = 0.0f32;
    for y in 0..h {
        for x in 0..w {
            if let Ok(c) = img.get_color_at(x, y) {
                let c = c.to_linear();
                peak = peak.max(c.red).max(c.green).max(c.blue);
            }
        }
    }
    peak
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn finish(run: &Run) -> Result<(), String> {
    let o = &run.options;
    let shots = run.shots.lock().unwrap();
    let off = &shots["off"];
    let (w, h) = (off.width(), off.height());
    if (w, h) != o.size {
        return Err(format!(
            "the window is {w}x{h}, not the requested {}x{} (a window manager resized it?)",
            o.size.0, o.size.1
        ));
    }
    let lum = |img: &Image, x, y| {
        img.get_color_at(x, y)
            .map(|c| c.to_linear().green)
            .unwrap_or(0.0)
    };
    let mut rows = Vec::new();
    let mut times = run.times.clone();
    let off_ms = times.get_mut("off").map(|v| median(v)).unwrap_or(f64::NAN);
    for name in &o.presets {
        let mut t = times.get(name).cloned().unwrap_or_default();
        let ms = median(&mut t);
        let (min, max) = (
            t.first().copied().unwrap_or(f64::NAN),
            t.last().copied().unwrap_or(f64::NAN),
        );
        let mut row = serde_json::json!({
            "preset": name,
            "frame_ms": { "median": ms, "min": min, "max": max, "frames": t.len() },
            "overhead_ms": ms - off_ms,
        });
        if let Some(q) = preset(name) {
            let (slices, side) = counts(q);
            row["slices"] = slices.into();
            row["samples_per_side"] = side.into();
            row["samples"] = (slices * side * 2).into();
            let img = &shots[name];
            let mut ao = vec![1.0f32; (w * h) as usize];
            for y in 0..h {
                for x in 0..w {
                    let a = lum(off, x, y);
                    if a > 1e-3 {
                        ao[(y * w + x) as usize] = (lum(img, x, y) / a).clamp(0.0, 1.0);
                    }
                }
            }
            let file = format!("ao-{name}.exr");
            let path = o.out.join(&file);
            let tmp = o.out.join(format!(".{file}.partial"));
            exr::prelude::write_rgba_file(&tmp, w as usize, h as usize, |x, y| {
                let v = ao[y * w as usize + x];
                (v, v, v, 1.0f32)
            })
            .map_err(|e| format!("{}: {e}", path.display()))?;
            std::fs::rename(&tmp, &path).map_err(|e| format!("{}: {e}", path.display()))?;
            row["ao"] = file.into();
        }
        rows.push(row);
    }
    let report = serde_json::json!({
        "peer": "bevy 0.20.1 ScreenSpaceAmbientOcclusion",
        "scene": o.scene.display().to_string(),
        "size": [w, h],
        "radius": o.radius,
        "warmup": o.warmup,
        "frames": o.frames,
        "rounds": o.rounds,
        "off_ms": off_ms,
        "presets": rows,
        "ao_note": "Bevy's AO (visibility bitmask, constant thickness) is not cosine-weighted; read as the ratio of ambient-only frames with and without SSAO",
    });
    let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    let path = o.out.join("peer.json");
    let tmp = o.out.join(".peer.json.partial");
    std::fs::write(&tmp, text)
        .and_then(|()| std::fs::rename(&tmp, &path))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    println!("preset   samples  frame ms  overhead ms");
    for r in &rows {
        println!(
            "{:<8} {:>7}  {:>8.1}  {:>11.1}",
            r["preset"].as_str().unwrap_or(""),
            r["samples"]
                .as_u64()
                .map(|s| s.to_string())
                .unwrap_or("-".into()),
            r["frame_ms"]["median"].as_f64().unwrap_or(f64::NAN),
            r["overhead_ms"].as_f64().unwrap_or(f64::NAN)
        );
    }
    eprintln!("bevy-ssao-peer: wrote {}", path.display());
    Ok(())
}

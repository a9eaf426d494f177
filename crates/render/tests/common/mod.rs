//! Helpers for GPU tests: an adapter (lavapipe in CI), and rendering a scene to AOVs.
#![allow(dead_code)]

use glam::{Vec2, Vec3};
use nearfield_render::{Aov, AovImage, GpuContext, RenderSettings, Renderer, TechniqueParams};
use nearfield_scene::{Camera, Environment, Mesh, Scene};

/// The test adapter, or None (test skipped) when there is none — unless `REQUIRE_GPU=1`, which
/// turns a missing adapter into a failure (CI sets it).
pub fn context() -> Option<GpuContext> {
    match GpuContext::new(None) {
        Ok(c) => Some(c),
        Err(e) => {
            if std::env::var("REQUIRE_GPU").as_deref() == Ok("1") {
                panic!("REQUIRE_GPU=1 but no adapter: {e}");
            }
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}

pub fn renderer(
    ctx: &GpuContext,
    scene: &Scene,
    env: &Environment,
    camera: Camera,
    size: (u32, u32),
) -> Renderer {
    let settings = RenderSettings {
        size,
        ..Default::default()
    };
    let mut r = Renderer::new(
        ctx,
        scene,
        env,
        None,
        camera,
        &nearfield_render::technique::Spec::resolve("none", &TechniqueParams::default()).unwrap(),
        settings,
    )
    .unwrap();
    r.render_frame();
    r
}

pub fn render_aovs(
    ctx: &GpuContext,
    scene: &Scene,
    env: &Environment,
    camera: Camera,
    size: (u32, u32),
    aovs: &[Aov],
) -> Vec<AovImage> {
    let mut r = renderer(ctx, scene, env, camera, size);
    aovs.iter().map(|&a| r.read_aov(a)).collect()
}

/// World position of pixel (x, y) from the `depth` AOV (view depth along the camera axis).
pub fn world_position(camera: &Camera, size: (u32, u32), depth: &AovImage, x: u32, y: u32) -> Vec3 {
    let d = camera.primary_ray(x, y, size);
    let t = depth.get(x, y)[0] / d.dot(camera.forward());
    camera.eye + d * t
}

/// The `wall` scene's truth: ao of a floor point at distance k·R from the wall (R the near-field
/// radius), 1 − (acos k − k√(1−k²))/π for k < 1 and 1 beyond.
pub fn wall_ao(k: f32) -> f32 {
    if k >= 1.0 {
        1.0
    } else {
        1.0 - (k.acos() - k * (1.0 - k * k).sqrt()) / std::f32::consts::PI
    }
}

/// Appends a planar quad (corners counter-clockwise seen from the front) with its flat normal.
pub fn push_quad(mesh: &mut Mesh, c: [Vec3; 4]) {
    let n = (c[1] - c[0]).cross(c[2] - c[0]).normalize();
    let b = mesh.positions.len() as u32;
    for p in c {
        mesh.positions.push(p);
        mesh.normals.push(n);
        mesh.uvs.push(Vec2::ZERO);
    }
    mesh.indices.push([b, b + 1, b + 2]);
    mesh.indices.push([b, b + 2, b + 3]);
}

/// A unit box standing at the origin on the `plane` scene.
pub fn box_on_plane() -> Scene {
    let mut scene = nearfield_scene::builtin::scene("plane").unwrap();
    for p in &mut scene.meshes[0].positions {
        *p *= 0.05;
    }
    let mut mesh = Mesh {
        name: "box".into(),
        ..Default::default()
    };
    let v = Vec3::new;
    for c in [
        [
            v(-0.5, 1.0, 0.5),
            v(0.5, 1.0, 0.5),
            v(0.5, 1.0, -0.5),
            v(-0.5, 1.0, -0.5),
        ],
        [
            v(-0.5, 0.0, 0.5),
            v(0.5, 0.0, 0.5),
            v(0.5, 1.0, 0.5),
            v(-0.5, 1.0, 0.5),
        ],
        [
            v(0.5, 0.0, -0.5),
            v(-0.5, 0.0, -0.5),
            v(-0.5, 1.0, -0.5),
            v(0.5, 1.0, -0.5),
        ],
        [
            v(0.5, 0.0, 0.5),
            v(0.5, 0.0, -0.5),
            v(0.5, 1.0, -0.5),
            v(0.5, 1.0, 0.5),
        ],
        [
            v(-0.5, 0.0, -0.5),
            v(-0.5, 0.0, 0.5),
            v(-0.5, 1.0, 0.5),
            v(-0.5, 1.0, -0.5),
        ],
    ] {
        push_quad(&mut mesh, c);
    }
    scene.meshes.push(mesh);
    scene
}

/// What to render: scene, environment, view, image size and noise seed.
pub struct Shot<'a> {
    pub scene: &'a Scene,
    pub env: &'a Environment,
    pub camera: Camera,
    pub size: (u32, u32),
    pub seed: u32,
}

/// Renders one frame of `shot` with `method`, radius `radius` and `--set` pairs.
pub fn render_shot(
    ctx: &GpuContext,
    shot: &Shot,
    method: &str,
    set: &[(&str, &str)],
    radius: f32,
) -> Renderer {
    let params = TechniqueParams {
        samples: None,
        radius: Some(radius),
        set: set
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
    };
    let settings = RenderSettings {
        size: shot.size,
        seed: shot.seed,
        ..Default::default()
    };
    let mut r = Renderer::new(
        ctx,
        shot.scene,
        shot.env,
        None,
        shot.camera,
        &nearfield_render::technique::Spec::resolve(method, &params).unwrap(),
        settings,
    )
    .unwrap();
    r.render_frame();
    r
}

/// Live objects per kind, from wgpu-core's registries.
pub fn live_objects(ctx: &GpuContext) -> Vec<(&'static str, usize)> {
    let _ = ctx.device.poll(wgpu::PollType::wait_indefinitely());
    let report = ctx
        .instance
        .generate_report()
        .expect("wgpu-core backend reports its registries");
    let hub = report.hub_report();
    vec![
        ("buffers", hub.buffers.num_kept_from_user),
        ("textures", hub.textures.num_kept_from_user),
        ("texture views", hub.texture_views.num_kept_from_user),
        ("samplers", hub.samplers.num_kept_from_user),
        ("bind groups", hub.bind_groups.num_kept_from_user),
        (
            "bind group layouts",
            hub.bind_group_layouts.num_kept_from_user,
        ),
        ("pipeline layouts", hub.pipeline_layouts.num_kept_from_user),
        ("shader modules", hub.shader_modules.num_kept_from_user),
        (
            "compute pipelines",
            hub.compute_pipelines.num_kept_from_user,
        ),
        ("render pipelines", hub.render_pipelines.num_kept_from_user),
        ("query sets", hub.query_sets.num_kept_from_user),
    ]
}

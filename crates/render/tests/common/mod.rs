//! Helpers for GPU tests: an adapter (lavapipe in CI), and rendering a scene to AOVs.
#![allow(dead_code)]

use glam::Vec3;
use nearfield_render::{Aov, AovImage, GpuContext, RenderSettings, Renderer, TechniqueParams};
use nearfield_scene::{Camera, Environment, Scene};

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
        camera,
        "none",
        &TechniqueParams::default(),
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

//! Shadow maps are drawn again only when a layer's projection changed (passes/shadow.rs): a
//! renderer whose camera moved, or whose sun turned, after its first frame lights the scene
//! exactly as a renderer made at the new camera or sun does, and a still camera keeps the frame.

mod common;

use nearfield_render::{Aov, Renderer};
use nearfield_scene::{Camera, Environment};

const SIZE: (u32, u32) = (64, 36);

fn renderer(ctx: &nearfield_render::GpuContext, env: &Environment, camera: Camera) -> Renderer {
    // Boxes has a point light (six cached layers) and, under the sky with its sun split out, a
    // disc light whose layer follows the view.
    let scene = nearfield_scene::builtin::scene("boxes").unwrap();
    common::renderer(ctx, &scene, env, camera, SIZE)
}

fn light(r: &mut Renderer) -> Vec<u32> {
    r.read_aov(Aov::LightIrradiance)
        .pixels
        .iter()
        .flatten()
        .map(|x| x.to_bits())
        .collect()
}

fn differing(a: &[u32], b: &[u32]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count()
}

/// The next frame of `r`, after a change: it must differ from `before` (the change moved the
/// light) and match `fresh`, a renderer made with the change, bit for bit. Returns its light.
fn redrawn(r: &mut Renderer, before: &[u32], mut fresh: Renderer, what: &str) -> Vec<u32> {
    r.render_frame();
    let after = light(r);
    assert!(
        differing(&after, before) > 100,
        "{what}: the change moves the light"
    );
    assert_eq!(
        differing(&after, &light(&mut fresh)),
        0,
        "{what} against a fresh renderer"
    );
    after
}

#[test]
fn moved_camera_and_turned_sun_redraw_the_maps_a_still_one_keeps_them() {
    let Some(ctx) = common::context() else { return };
    let (mut env, _) = nearfield_scene::EnvSource::Sky
        .load_split(nearfield_scene::SunMode::Auto)
        .unwrap();
    assert!(env.sun.is_some());
    let start = nearfield_scene::builtin::scene("boxes")
        .unwrap()
        .default_camera();
    let mut r = renderer(&ctx, &env, start);
    let first = light(&mut r);

    // A still camera: the cached maps give the same light.
    r.render_frame();
    assert_eq!(differing(&light(&mut r), &first), 0, "still camera");

    // The camera turns: the sun's layer is refitted and drawn again.
    let turned = start.orbit(25.0);
    r.set_camera(turned);
    let moved = redrawn(&mut r, &first, renderer(&ctx, &env, turned), "moved camera");

    // The sun turns (the environment rotates): its layer is drawn again.
    r.set_environment_rotation(40.0);
    env.rotation = 40.0;
    redrawn(&mut r, &moved, renderer(&ctx, &env, turned), "turned sun");
}

//! Moving objects (moving.rs): a renderer whose scene's clock moved poses its objects as a
//! renderer made over the scene posed at that time does, bit for bit, shadows included (the maps
//! are drawn again); the G-buffer's motion vectors carry the object's own motion; and once the
//! object stops, they are the camera's alone.

mod common;

use glam::{Vec2, Vec3};
use nearfield_render::{Aov, AovImage, Renderer};
use nearfield_scene::{Camera, Scene};

const SIZE: (u32, u32) = (96, 72);

fn bits(r: &mut Renderer, aov: Aov) -> Vec<u32> {
    r.read_aov(aov)
        .pixels
        .iter()
        .flatten()
        .map(|x| x.to_bits())
        .collect()
}

/// Where world point `p` lands on the screen (pixels, y down).
fn screen(camera: &Camera, p: Vec3) -> Vec2 {
    let aspect = SIZE.0 as f32 / SIZE.1 as f32;
    let clip = camera.clip_from_view(aspect, 0.1, 100.0) * camera.view_from_world() * p.extend(1.0);
    let ndc = clip.truncate().truncate() / clip.w;
    Vec2::new(
        (ndc.x + 1.0) * 0.5 * SIZE.0 as f32,
        (1.0 - ndc.y) * 0.5 * SIZE.1 as f32,
    )
}

/// The pixels whose albedo is the ball's.
fn ball_pixels(albedo: &AovImage) -> Vec<(u32, u32)> {
    let ball = Vec3::new(0.3, 0.55, 0.85);
    (0..SIZE.1)
        .flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            (Vec3::from_slice(&albedo.get(x, y)[..3]) - ball)
                .abs()
                .max_element()
                < 0.02
        })
        .collect()
}

#[test]
fn a_moved_clock_poses_objects_as_a_fresh_renderer_and_their_motion_reaches_the_motion_vectors() {
    let Some(ctx) = common::context() else { return };
    let scene = nearfield_scene::builtin::scene("columns-moving").unwrap();
    let (env, _) = nearfield_scene::EnvSource::Sky
        .load_split(nearfield_scene::SunMode::Auto)
        .unwrap();
    let camera = scene.default_camera();
    let mut r = common::renderer(&ctx, &scene, &env, camera, SIZE);
    let first = bits(&mut r, Aov::LightIrradiance);
    let (t0, t1) = (1.0, 1.0 + 1.0 / 30.0);
    r.set_time(t0);
    r.render_frame();
    r.set_time(t1);
    r.render_frame();

    // The same frame as a renderer made over the scene posed at t1: geometry and shadows.
    let mut posed: Scene = scene.clone();
    posed.pose(t1);
    let mut fresh = common::renderer(&ctx, &posed, &env, camera, SIZE);
    let moved = bits(&mut r, Aov::LightIrradiance);
    let changed = moved.iter().zip(&first).filter(|(a, b)| a != b).count();
    assert!(
        changed > 100,
        "the ball and its shadow moved: {changed} pixels"
    );
    for aov in [Aov::LightIrradiance, Aov::Normal, Aov::Depth] {
        let fresh = bits(&mut fresh, aov);
        let d = bits(&mut r, aov)
            .iter()
            .zip(&fresh)
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            d, 0,
            "{aov:?} differs from a fresh renderer's in {d} pixels"
        );
    }

    // Every ball pixel's motion vector points to where its surface point was at t0.
    let depth = r.read_aov(Aov::Depth);
    let motion = r.read_aov(Aov::Motion);
    let ball = ball_pixels(&r.read_aov(Aov::Albedo));
    assert!(ball.len() > 100, "{} ball pixels", ball.len());
    let node = scene
        .meshes
        .iter()
        .find_map(|m| m.motion.as_ref())
        .unwrap()
        .node;
    let back = scene.motion_at(node, t0) * scene.motion_at(node, t1).inverse();
    let mut worst: f32 = 0.0;
    let mut mean = Vec2::ZERO;
    for &(x, y) in &ball {
        let p = common::world_position(&camera, SIZE, &depth, x, y);
        let expect =
            screen(&camera, back.transform_point3(p)) - Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        let got = Vec2::from_slice(&motion.get(x, y)[..2]);
        worst = worst.max((got - expect).length());
        mean += got;
    }
    mean /= ball.len() as f32;
    // The ball rolls 3.2 m in 2 s: 5.3 cm a frame, about 1.3 pixels here, to the left.
    assert!(mean.x < -0.8, "mean motion {mean}");
    assert!(worst < 0.05, "largest motion vector error {worst} px");

    // Standing still (after 2 s): after one frame that moves it there, no motion (rounding only).
    r.set_time(2.5);
    r.render_frame();
    r.render_frame();
    let still = r.read_aov(Aov::Motion);
    let largest = still
        .pixels
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f32::max);
    assert!(
        largest < 1e-3,
        "a still camera over a still scene: {largest} px"
    );
}

//! The far field on the GPU against the CPU's reading of the same probe volume
//! (`ProbeVolume::irradiance`), and the two rooms' wall: no light leaks into the closed room.

mod common;

use glam::Vec3;
use nearfield_reference::bake::{self, BakeSettings};
use nearfield_render::{Aov, AovImage, Renderer};
use nearfield_scene::probes::{IRRADIANCE_TILE_ERROR, IRRADIANCE_TILE_MEAN_ERROR, ProbeVolume};
use nearfield_scene::sun::SunMode;
use nearfield_scene::{Camera, Environment, Scene, builtin};

/// The two rooms under their sky, and their volume (few rays: the test compares two readings
/// of one volume, not the volume with the truth).
fn two_rooms() -> (Scene, Environment, ProbeVolume) {
    let scene = builtin::scene("two-rooms").unwrap();
    let env = scene.default_env.load_split(SunMode::Auto).unwrap().0;
    let settings = BakeSettings {
        grid: bake::default_grid(&scene).unwrap(),
        rays: 128,
        bounces: 2,
    };
    let volume = bake::bake(&scene, &env, settings, false, None).expect("bake");
    (scene, env, volume)
}

fn render_none(
    ctx: &nearfield_render::GpuContext,
    scene: &Scene,
    env: &Environment,
    camera: Camera,
    volume: &ProbeVolume,
    size: (u32, u32),
) -> Renderer {
    let mut r = common::renderer(ctx, scene, env, camera, size);
    r.set_far_field(Some(volume)).unwrap();
    r.render_frame();
    r
}

/// Surface pixels' (world position, normal, GPU env-irradiance).
fn surface(r: &mut Renderer, camera: &Camera, size: (u32, u32)) -> Vec<(Vec3, Vec3, Vec3)> {
    let depth: AovImage = r.read_aov(Aov::Depth);
    let normal = r.read_aov(Aov::Normal);
    let env = r.read_aov(Aov::EnvIrradiance);
    let mut out = Vec::new();
    for y in 0..size.1 {
        for x in 0..size.0 {
            let nw = normal.get(x, y);
            if nw[3] == 0.0 {
                continue;
            }
            let p = common::world_position(camera, size, &depth, x, y);
            let e = env.get(x, y);
            out.push((
                p,
                Vec3::new(nw[0], nw[1], nw[2]).normalize(),
                Vec3::new(e[0], e[1], e[2]),
            ));
        }
    }
    out
}

/// `none` with a volume is the volume's irradiance at each pixel: the GPU's trilinear,
/// backface and Chebyshev weights and its filtered irradiance tiles against the CPU's SH
/// reading. The tiles' own error ([`IRRADIANCE_TILE_ERROR`], [`IRRADIANCE_TILE_MEAN_ERROR`] of
/// the largest E) bounds the difference.
#[test]
fn none_reads_the_volume_as_the_cpu_does() {
    let Some(ctx) = common::context() else { return };
    let (scene, env, volume) = two_rooms();
    let size = (96, 64);
    let camera = scene.default_camera();
    let mut r = render_none(&ctx, &scene, &env, camera, &volume, size);
    let pixels = surface(&mut r, &camera, size);
    let mut largest = 0.0f32;
    let mut diffs = Vec::new();
    for &(p, n, gpu) in &pixels {
        let v = (camera.eye - p).normalize();
        let cpu = volume.irradiance(p, n, v);
        largest = largest.max(cpu.max_element());
        diffs.push((gpu - cpu).abs().max_element());
    }
    let mean = diffs.iter().sum::<f32>() / diffs.len() as f32 / largest;
    diffs.sort_by(f32::total_cmp);
    let p99 = diffs[diffs.len() * 99 / 100] / largest;
    eprintln!(
        "{} pixels: GPU − CPU mean {mean:.4}, 99th percentile {p99:.4} of the largest E",
        pixels.len()
    );
    assert!(pixels.len() > size.0 as usize * size.1 as usize / 2);
    assert!(
        mean <= IRRADIANCE_TILE_MEAN_ERROR,
        "mean difference {mean:.4} of the largest E, bound {IRRADIANCE_TILE_MEAN_ERROR}"
    );
    assert!(
        p99 <= IRRADIANCE_TILE_ERROR,
        "99th percentile {p99:.4} of the largest E, bound {IRRADIANCE_TILE_ERROR}"
    );
}

/// The leak test: looking at each room's floor from inside it, the closed room's mean
/// env-irradiance with the volume is at most 2 % of the open room's (its truth is 0: no path
/// from the sky reaches it).
#[test]
fn no_light_leaks_through_the_shared_wall() {
    let Some(ctx) = common::context() else { return };
    let (scene, env, volume) = two_rooms();
    let size = (64, 48);
    let floor_mean = |eye: Vec3, target: Vec3| {
        let camera = Camera::new(eye, target, 60.0);
        let mut r = render_none(&ctx, &scene, &env, camera, &volume, size);
        let floor: Vec<Vec3> = surface(&mut r, &camera, size)
            .into_iter()
            .filter(|(p, n, _)| n.y > 0.9 && p.y < 0.01)
            .map(|(_, _, e)| e)
            .collect();
        assert!(floor.len() > 100, "the floor is in view");
        floor.iter().sum::<Vec3>().dot(Vec3::splat(1.0 / 3.0)) / floor.len() as f32
    };
    let lit = floor_mean(Vec3::new(-1.6, 2.0, 1.2), Vec3::new(-1.6, 0.0, -0.6));
    let dark = floor_mean(Vec3::new(1.6, 2.0, 1.2), Vec3::new(1.6, 0.0, -0.6));
    eprintln!("floor env-irradiance: lit room {lit:.4}, closed room {dark:.5}");
    assert!(lit > 0.05, "the open room is lit: {lit}");
    assert!(dark <= 0.02 * lit, "closed room {dark} against {lit}");
}

//! GPU results against analytic truths on tiny scenes (lavapipe in CI; REQUIRE_GPU=1 there).

mod common;

use glam::Vec3;
use nearfield_render::Aov;
use nearfield_scene::{Camera, Environment, Light, LightKind, Material, Mesh, Scene, builtin};

/// `plane` under constant:1,1,1: env-irradiance = 1 within 0.5 % on every surface pixel, ao = 1.
#[test]
fn plane_under_white_sky() {
    let Some(ctx) = common::context() else { return };
    let scene = builtin::scene("plane").unwrap();
    let env = Environment::constant(Vec3::ONE);
    let imgs = common::render_aovs(
        &ctx,
        &scene,
        &env,
        scene.default_camera(),
        (96, 64),
        &[Aov::EnvIrradiance, Aov::Ao],
    );
    let surface: Vec<_> = imgs[0].surface().collect();
    assert!(surface.len() > 96 * 64 / 3, "plane covers the lower image");
    for p in surface {
        for c in &p[..3] {
            assert!((c - 1.0).abs() < 0.005, "env-irradiance {c}");
        }
    }
    assert!(imgs[1].surface().all(|p| p[0] == 1.0));
}

/// Two vertical quads facing +X and −X in front of the camera.
fn facing_pair() -> Scene {
    let mut mesh = Mesh {
        name: "pair".into(),
        ..Default::default()
    };
    // Quad A faces +X at x = 0.5, quad B faces −X at x = −0.5, both spanning z ∈ [−1, 0].
    common::push_quad(
        &mut mesh,
        [
            Vec3::new(0.5, 0.0, 0.0),
            Vec3::new(0.5, 0.0, -1.0),
            Vec3::new(0.5, 1.0, -1.0),
            Vec3::new(0.5, 1.0, 0.0),
        ],
    );
    common::push_quad(
        &mut mesh,
        [
            Vec3::new(-0.5, 0.0, -1.0),
            Vec3::new(-0.5, 0.0, 0.0),
            Vec3::new(-0.5, 1.0, 0.0),
            Vec3::new(-0.5, 1.0, -1.0),
        ],
    );
    Scene {
        name: "pair".into(),
        meshes: vec![mesh],
        materials: vec![Material {
            double_sided: true,
            ..Material::default()
        }],
        ..Default::default()
    }
}

/// Convention: a map bright only where d.x > 0 lights a +X-facing face and leaves a −X-facing
/// face dark. Order-2 SH of max(0, d·x) gives exactly 127/192 on +X (Funk–Hecke; see
/// nearfield_scene::sh) and a clamped 0 on −X.
#[test]
fn bright_plus_x_map_lights_plus_x_faces() {
    let Some(ctx) = common::context() else { return };
    let scene = facing_pair();
    let env = Environment::from_fn("x", 256, 128, |d| Vec3::splat(d.x.max(0.0)));
    // Camera on +Z looking along −Z between the quads, seeing both obliquely.
    let camera = Camera::new(Vec3::new(0.0, 0.5, 1.0), Vec3::new(0.0, 0.5, -1.0), 90.0);
    let size = (96, 64);
    let imgs = common::render_aovs(
        &ctx,
        &scene,
        &env,
        camera,
        size,
        &[Aov::EnvIrradiance, Aov::Normal],
    );
    let (mut plus, mut minus) = (0, 0);
    for (p, n) in imgs[0].pixels.iter().zip(&imgs[1].pixels) {
        if p[3] == 0.0 {
            continue;
        }
        if n[0] > 0.9 {
            plus += 1;
            assert!((p[0] - 127.0 / 192.0).abs() < 0.005, "+X face: {}", p[0]);
        } else if n[0] < -0.9 {
            minus += 1;
            assert!(p[0] < 1e-3, "−X face: {}", p[0]);
        }
    }
    assert!(plus > 50 && minus > 50, "{plus} {minus}");
}

/// The background shows the map through the lat-long formula (docs/src/conventions.md): encode u
/// (as sin/cos, continuous across the seam) and v in a map and read it back through the centre
/// pixel looking along each axis, with and without --env-rotation.
#[test]
fn lat_long_convention_on_the_gpu() {
    let Some(ctx) = common::context() else { return };
    let tau = std::f32::consts::TAU;
    let map = Environment::from_fn("uv", 512, 256, |d| {
        let uv = nearfield_scene::environment::dir_to_uv(d);
        Vec3::new(
            0.5 + 0.5 * (tau * uv.x).sin(),
            uv.y,
            0.5 + 0.5 * (tau * uv.x).cos(),
        )
    });
    // Tiny quads far off every axis so that the scene is not empty.
    let mut scene = facing_pair();
    for p in &mut scene.meshes[0].positions {
        *p = *p * 1e-3 + Vec3::splat(300.0);
    }
    let cases = [
        (Vec3::NEG_Z, 0.0, 0.5),
        (Vec3::X, 0.25, 0.5),
        (Vec3::Z, 0.5, 0.5),
        (Vec3::NEG_X, 0.75, 0.5),
    ];
    for rotation_deg in [0.0f32, 90.0] {
        let mut env = map.clone();
        env.rotation = rotation_deg.to_radians();
        for (axis, u, v) in cases {
            // With rotation R, the map's feature at direction a appears at R·a.
            let look = nearfield_scene::environment::rotate_y(axis, env.rotation);
            let camera = Camera::new(Vec3::ZERO, look, 10.0);
            let img = &common::render_aovs(&ctx, &scene, &env, camera, (3, 3), &[Aov::Radiance])[0];
            let c = img.get(1, 1);
            assert_eq!(c[3], 0.0, "background");
            let got_u = ((c[0] - 0.5).atan2(c[2] - 0.5) / tau).rem_euclid(1.0);
            let du = (got_u - u).abs().min(1.0 - (got_u - u).abs());
            assert!(
                du < 0.01 && (c[1] - v).abs() < 0.01,
                "axis {axis} rot {rotation_deg}: u {got_u} v {}",
                c[1]
            );
        }
    }
}

/// A unit box on a plane under one directional light: ground points whose ray to the light hits
/// the box are dark, the others get exactly E cos θ / π.
#[test]
fn directional_light_casts_the_box_shadow() {
    let Some(ctx) = common::context() else { return };
    let mut scene = builtin::scene("plane").unwrap();
    // Reuse the plane; add an axis-aligned unit box at the origin from two quads per face.
    let mut mesh = Mesh {
        name: "box".into(),
        material: 0,
        ..Default::default()
    };
    let faces: [[Vec3; 4]; 5] = [
        [
            Vec3::new(-0.5, 1.0, 0.5),
            Vec3::new(0.5, 1.0, 0.5),
            Vec3::new(0.5, 1.0, -0.5),
            Vec3::new(-0.5, 1.0, -0.5),
        ],
        [
            Vec3::new(-0.5, 0.0, 0.5),
            Vec3::new(0.5, 0.0, 0.5),
            Vec3::new(0.5, 1.0, 0.5),
            Vec3::new(-0.5, 1.0, 0.5),
        ],
        [
            Vec3::new(0.5, 0.0, -0.5),
            Vec3::new(-0.5, 0.0, -0.5),
            Vec3::new(-0.5, 1.0, -0.5),
            Vec3::new(0.5, 1.0, -0.5),
        ],
        [
            Vec3::new(0.5, 0.0, 0.5),
            Vec3::new(0.5, 0.0, -0.5),
            Vec3::new(0.5, 1.0, -0.5),
            Vec3::new(0.5, 1.0, 0.5),
        ],
        [
            Vec3::new(-0.5, 0.0, -0.5),
            Vec3::new(-0.5, 0.0, 0.5),
            Vec3::new(-0.5, 1.0, 0.5),
            Vec3::new(-0.5, 1.0, -0.5),
        ],
    ];
    for c in faces {
        common::push_quad(&mut mesh, c);
    }
    // Keep the ground small so that the shadow map's texels are fine.
    for p in &mut scene.meshes[0].positions {
        *p *= 0.02;
    }
    scene.meshes.push(mesh);
    let direction = Vec3::new(1.0, -1.0, 0.3).normalize();
    scene.lights = vec![Light {
        kind: LightKind::Directional {
            direction,
            angular_radius: 0.0,
        },
        color: Vec3::ONE,
        intensity: 3.0,
        range: None,
    }];
    let env = Environment::constant(Vec3::ZERO);
    let camera = Camera {
        eye: Vec3::new(0.8, 6.0, 0.0),
        target: Vec3::new(0.8, 0.0, 0.0),
        up: Vec3::NEG_Z,
        yfov: 50f32.to_radians(),
    };
    let size = (96, 96);
    let imgs = common::render_aovs(
        &ctx,
        &scene,
        &env,
        camera,
        size,
        &[Aov::LightIrradiance, Aov::Depth, Aov::Normal],
    );
    let lit_value = 3.0 * (-direction).y / std::f32::consts::PI;
    let to_light = -direction;
    // Slab test against the box.
    let hits_box = |p: Vec3| {
        let (mut t0, mut t1) = (0.0f32, f32::INFINITY);
        for a in 0..3 {
            let (lo, hi) = ([-0.5, 0.0, -0.5][a], [0.5, 1.0, 0.5][a]);
            let (o, d) = (p[a], to_light[a]);
            if d.abs() < 1e-9 {
                if o < lo || o > hi {
                    return false;
                }
                continue;
            }
            let (mut ta, mut tb) = ((lo - o) / d, (hi - o) / d);
            if ta > tb {
                std::mem::swap(&mut ta, &mut tb);
            }
            t0 = t0.max(ta);
            t1 = t1.min(tb);
        }
        t0 <= t1
    };
    let (mut shadowed, mut lit) = (0, 0);
    for y in 0..size.1 {
        for x in 0..size.0 {
            let n = imgs[2].get(x, y);
            if n[3] == 0.0 || n[1] < 0.99 {
                continue;
            }
            let p = common::world_position(&camera, size, &imgs[1], x, y);
            if p.y > 0.01 {
                continue; // the box top
            }
            // Stay clear of the shadow's edge: the same verdict for points 4 cm around.
            let offsets = [
                Vec3::ZERO,
                Vec3::X * 0.04,
                -Vec3::X * 0.04,
                Vec3::Z * 0.04,
                -Vec3::Z * 0.04,
            ];
            let verdicts: Vec<bool> = offsets.iter().map(|o| hits_box(p + *o)).collect();
            if verdicts.iter().any(|&v| v != verdicts[0]) {
                continue;
            }
            let e = imgs[0].get(x, y)[0];
            if verdicts[0] {
                shadowed += 1;
                assert!(e < 0.02 * lit_value, "shadowed point {p} receives {e}");
            } else {
                lit += 1;
                assert!(
                    (e - lit_value).abs() < 0.01 * lit_value,
                    "lit point {p}: {e} vs {lit_value}"
                );
            }
        }
    }
    assert!(
        shadowed > 100 && lit > 500,
        "shadowed {shadowed}, lit {lit}"
    );
}

/// A point light inside the closed room (six cube-face shadow layers): floor pixels receive
/// exactly E/π = I cos θ / (π d²) where the light is unblocked, and never more. The block
/// shadows only a small part of the floor.
#[test]
fn point_light_irradiance_through_cube_shadow_maps() {
    let Some(ctx) = common::context() else { return };
    let scene = builtin::scene("closed-box").unwrap();
    let light = scene.lights[0];
    let env = Environment::constant(Vec3::ZERO);
    let camera = scene.default_camera();
    let size = (96, 64);
    let imgs = common::render_aovs(
        &ctx,
        &scene,
        &env,
        camera,
        size,
        &[Aov::LightIrradiance, Aov::Depth, Aov::Normal],
    );
    let (mut floor, mut exact) = (0, 0);
    for y in 0..size.1 {
        for x in 0..size.0 {
            let n = imgs[2].get(x, y);
            if n[3] == 0.0 || n[1] < 0.99 {
                continue;
            }
            let p = common::world_position(&camera, size, &imgs[1], x, y);
            if p.y > 0.01 {
                continue;
            }
            floor += 1;
            let want = light.irradiance(p, Vec3::Y).x / std::f32::consts::PI;
            let got = imgs[0].get(x, y)[0];
            assert!(got <= want * 1.01 + 1e-4, "{p}: {got} > {want}");
            if (got - want).abs() <= 0.01 * want {
                exact += 1;
            }
        }
    }
    assert!(floor > 1000, "{floor}");
    assert!(
        exact as f32 > 0.85 * floor as f32,
        "{exact} of {floor} floor pixels match"
    );
}

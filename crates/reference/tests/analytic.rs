//! The reference against analytic truths. Each assertion compares a number with a formula,
//! allowing 4 standard errors of the reference's own noise (plus the stated discretisation).

use glam::{Vec2, Vec3};
use nearfield_reference::{ReferenceAov, ReferenceImage, ReferenceSettings, Senders, render};
use nearfield_scene::{Camera, Environment, Material, Mesh, Scene, builtin};
use std::f32::consts::PI;

fn settings(aov: ReferenceAov, size: (u32, u32), radius: f32, spp: u32) -> ReferenceSettings {
    ReferenceSettings {
        aov,
        size,
        radius,
        spp,
        seed: 1,
        max_depth: 5,
        senders: nearfield_reference::Senders::Physical,
    }
}

/// World position of each surface pixel, from the reference's depth.
fn position(img: &ReferenceImage, camera: &Camera, x: u32, y: u32) -> Vec3 {
    let d = camera.primary_ray(x, y, (img.width, img.height));
    camera.eye + d * (img.depth[(y * img.width + x) as usize] / d.dot(camera.forward()))
}

/// Cosine-weighted near-field visibility at distance d from an infinite perpendicular plane with
/// radius R, k = d/R: 1 − (acos k − k √(1 − k²))/π for k < 1, else 1.
fn ao_near_wall(k: f32) -> f32 {
    if k >= 1.0 {
        1.0
    } else {
        1.0 - (k.acos() - k * (1.0 - k * k).sqrt()) / PI
    }
}

#[test]
fn plane_is_unoccluded_exactly() {
    let scene = builtin::scene("plane").unwrap();
    let cam = scene.default_camera();
    let env = Environment::constant(Vec3::splat(0.7));
    let ao = render(
        &scene,
        &env,
        &cam,
        &settings(ReferenceAov::Ao, (24, 16), f32::INFINITY, 64),
        false,
    );
    let e = render(
        &scene,
        &env,
        &cam,
        &settings(ReferenceAov::EnvIrradiance, (24, 16), f32::INFINITY, 64),
        false,
    );
    let mut n = 0;
    for (a, b) in ao.value.iter().zip(&e.value) {
        if a[3] > 0.0 {
            n += 1;
            assert_eq!(a[0], 1.0);
            assert!((b[0] - 0.7).abs() < 1e-5, "{}", b[0]);
        }
    }
    assert!(n > 100);
}

#[test]
fn wall_ao_follows_the_formula() {
    let scene = builtin::scene("wall").unwrap();
    let cam = Camera::new(Vec3::new(0.5, 1.2, 2.0), Vec3::new(0.0, 0.3, 0.0), 70.0);
    let env = Environment::constant(Vec3::ONE);
    let r = 1.0;
    let img = render(
        &scene,
        &env,
        &cam,
        &settings(ReferenceAov::Ao, (40, 30), r, 256),
        false,
    );
    let (mut near, mut far) = (0, 0);
    for y in 0..img.height {
        for x in 0..img.width {
            let v = img.get(x, y);
            if v[3] == 0.0 {
                continue;
            }
            let p = position(&img, &cam, x, y);
            // Distance to the other plane: floor points to the wall (z), wall points to the floor (y).
            let d = if p.y.abs() < 1e-3 { p.z } else { p.y };
            let want = ao_near_wall(d / r);
            let se = img.stderr[(y * img.width + x) as usize][0];
            // 4 standard errors, and 0.01 for rare events the sample variance cannot see (a
            // point at 0.96 R from the wall has 0.5 % of its lobe blocked: often no sample hits).
            assert!(
                (v[0] - want).abs() <= 4.0 * se + 1e-2,
                "{p}: ao {} vs {want} (se {se})",
                v[0]
            );
            if d < r {
                near += 1;
            } else {
                far += 1;
            }
        }
    }
    assert!(near > 200 && far > 50, "{near} {far}");
    // At the base of the wall (k → 0) the formula gives exactly 0.5.
    assert_eq!(ao_near_wall(0.0), 0.5);
}

#[test]
fn closed_box_sees_nothing() {
    let scene = builtin::scene("closed-box").unwrap();
    let cam = scene.default_camera();
    let env = Environment::constant(Vec3::ONE);
    for aov in [ReferenceAov::Ao, ReferenceAov::EnvIrradiance] {
        let img = render(
            &scene,
            &env,
            &cam,
            &settings(aov, (24, 16), f32::INFINITY, 32),
            false,
        );
        assert!(
            img.value.iter().all(|v| v[3] == 1.0 && v[0] == 0.0),
            "{aov:?}"
        );
    }
}

/// One quad facing `normal` at the origin, 2 m wide, no other geometry.
fn lone_quad(normal: Vec3) -> Scene {
    let (t, b) = nearfield_reference::sampling::orthonormal_basis(normal);
    let c = [-t - b, t - b, t + b, -t + b];
    let mut m = Mesh {
        name: "quad".into(),
        positions: c.to_vec(),
        normals: vec![normal; 4],
        uvs: vec![Vec2::ZERO; 4],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        material: 0,
        ..Default::default()
    };
    // Make sure the winding faces `normal`.
    let g = (c[1] - c[0]).cross(c[2] - c[0]);
    if g.dot(normal) < 0.0 {
        m.indices = vec![[0, 2, 1], [0, 3, 2]];
    }
    Scene {
        name: "quad".into(),
        meshes: vec![m],
        materials: vec![Material::default()],
        ..Default::default()
    }
}

#[test]
fn clamped_cosine_environment() {
    // Radiance max(0, d·x): E/π = 2/(3π) on an upward surface, 2/3 on a +X-facing one.
    let env = Environment::from_fn("x", 1024, 512, |d| Vec3::splat(d.x.max(0.0)));
    for (normal, want) in [(Vec3::Y, 2.0 / (3.0 * PI)), (Vec3::X, 2.0 / 3.0)] {
        let scene = lone_quad(normal);
        let cam = Camera {
            eye: normal * 3.0 + Vec3::new(0.01, 0.02, 0.03),
            target: Vec3::ZERO,
            up: if normal.y.abs() > 0.9 {
                Vec3::Z
            } else {
                Vec3::Y
            },
            yfov: 20f32.to_radians(),
        };
        let img = render(
            &scene,
            &env,
            &cam,
            &settings(ReferenceAov::EnvIrradiance, (8, 8), f32::INFINITY, 1024),
            false,
        );
        for (v, se) in img.value.iter().zip(&img.stderr) {
            assert_eq!(v[3], 1.0);
            // Bilinear lookups of the 1024×512 map are exact for this piecewise-linear
            // function except along d.x = 0: allow 0.2 %.
            assert!(
                (v[0] - want).abs() <= 4.0 * se[0] + 0.002 * want,
                "{normal}: {} vs {want}",
                v[0]
            );
        }
    }
}

/// Indirect light from the wall onto the floor (the floor/wall wedge), with radius R, at floor
/// distance d (k = d/R): the wall covers a cosine-weighted fraction 1 − ao(k) of the near
/// field, and its outgoing radiance is uniform, so indirect-irradiance = L_wall (1 − ao(k)).
/// (a) an emissive black wall (Le = 1.5) in a black world: L_wall = 1.5;
/// (b) a white wall (ρ = 0.8) under a constant sky L = 2 with physical senders: every wall
///     point sees half sky and half (unlit) floor, so its direct radiance is ρ L/2 = 0.8 — the
///     floor reaches 400 m and 200 m sideways, so the sky seen past its edges from the wall
///     points within R (height < 1 m) is below 0.3 % of the hemisphere;
/// (c) the same with `Senders::Unshadowed` (V ≡ 1 at the wall): L_wall = ρ L = 1.6.
#[test]
fn indirect_from_a_uniform_wall() {
    let r = 1.0;
    let cam = Camera::new(Vec3::new(0.3, 0.9, 2.2), Vec3::new(0.0, 0.0, 0.4), 60.0);
    for (emissive, albedo, env_l, senders, wall_l) in [
        (1.5, 0.0, 0.0, Senders::Physical, 1.5),
        (0.0, 0.8, 2.0, Senders::Physical, 0.8),
        (0.0, 0.8, 2.0, Senders::Unshadowed, 1.6),
    ] {
        let mut scene = builtin::scene("wall").unwrap();
        scene.materials[1].emissive = Vec3::splat(emissive);
        scene.materials[1].base_color = Vec3::splat(albedo).extend(1.0);
        let env = Environment::constant(Vec3::splat(env_l));
        let mut s = settings(ReferenceAov::IndirectIrradiance, (24, 18), r, 512);
        s.senders = senders;
        let img = render(&scene, &env, &cam, &s, false);
        let mut floor = 0;
        for y in 0..img.height {
            for x in 0..img.width {
                let v = img.get(x, y);
                let p = position(&img, &cam, x, y);
                if v[3] == 0.0 || p.y.abs() > 1e-3 {
                    continue;
                }
                floor += 1;
                let want = wall_l * (1.0 - ao_near_wall(p.z / r));
                let se = img.stderr[(y * img.width + x) as usize][0];
                // 0.5 %: the irradiance table's interpolation (irradiance.rs) for case (c), the
                // floor's finite extent for (b).
                assert!(
                    (v[0] - want).abs() <= 4.0 * se + 0.005 * wall_l,
                    "{p}: {} vs {want}",
                    v[0]
                );
            }
        }
        assert!(floor > 100);
    }
}

/// Two estimates agree within their noise: for every pixel that `coverage` covers and every
/// channel, `value(i, c)` = (a, b, se) has |a − b| ≤ 5 se + slack(b), and the mean of a − b is
/// zero within 4 of its standard error (printed).
fn assert_agree_within_noise(
    label: &str,
    coverage: &ReferenceImage,
    value: impl Fn(usize, usize) -> (f32, f32, f32),
    slack: impl Fn(f32) -> f32,
) {
    let (mut n, mut sum_diff, mut sum_se2) = (0, 0.0f64, 0.0f64);
    for i in 0..coverage.value.len() {
        if coverage.value[i][3] == 0.0 {
            continue;
        }
        for c in 0..3 {
            let (a, b, se) = value(i, c);
            let d = a - b;
            assert!(
                d.abs() <= 5.0 * se + slack(b),
                "{label}: pixel {i} channel {c}: {a} vs {b} (se {se})"
            );
            sum_diff += d as f64;
            sum_se2 += (se * se) as f64;
            n += 1;
        }
    }
    let mean = sum_diff / n as f64;
    let mean_se = sum_se2.sqrt() / n as f64;
    eprintln!(
        "{label}: mean difference {mean:.5} (its standard error {mean_se:.5}) over {n} values"
    );
    assert!(mean.abs() <= 4.0 * mean_se, "{label}: {mean} vs {mean_se}");
}

/// Two code paths agree: a path of at most 2 segments sees emission, one bounce of direct
/// light (lights + environment with full occlusion), so radiance(max_depth 2) equals
/// ρ (env-irradiance(R = ∞) + light-irradiance) + emission of the primary hit.
#[test]
fn radiance_depth_two_equals_direct_diffuse() {
    let scene = builtin::scene("boxes").unwrap();
    let cam = scene.default_camera();
    let env = Environment::constant(Vec3::splat(0.3));
    let size = (24, 16);
    let mut rad = settings(ReferenceAov::Radiance, size, f32::INFINITY, 256);
    rad.max_depth = 2;
    let radiance = render(&scene, &env, &cam, &rad, false);
    let env_irr = render(
        &scene,
        &env,
        &cam,
        &settings(ReferenceAov::EnvIrradiance, size, f32::INFINITY, 256),
        false,
    );
    let light = render(
        &scene,
        &env,
        &cam,
        &settings(ReferenceAov::LightIrradiance, size, f32::INFINITY, 1),
        false,
    );
    let albedo = render(
        &scene,
        &env,
        &cam,
        &settings(ReferenceAov::Albedo, size, f32::INFINITY, 1),
        false,
    );
    assert_agree_within_noise(
        "radiance (2 segments) vs direct diffuse",
        &radiance,
        |i, c| {
            let want = albedo.value[i][c] * (env_irr.value[i][c] + light.value[i][c]);
            let se = (radiance.stderr[i][c].powi(2)
                + (albedo.value[i][c] * env_irr.stderr[i][c]).powi(2))
            .sqrt();
            (radiance.value[i][c], want, se)
        },
        |_| 1e-4,
    );
}

/// `diffuse` at R = ∞ is one bounce of physical direct light: the path tracer's `radiance`
/// through camera, P, x′ and the light x′ sees (`max_depth` 3: our convention counts
/// segments) minus P's emission, per pixel within the two estimates' noise. On `boxes` (its
/// directional light) under the built-in sky with its sun split out as a disc light, so
/// punctual, disc and environment light all take part.
#[test]
fn diffuse_at_infinite_radius_is_the_three_segment_path_tracer() {
    let scene = builtin::scene("boxes").unwrap();
    let cam = scene.default_camera();
    let env = nearfield_scene::sky::Sky {
        width: 256,
        ..Default::default()
    }
    .to_split_environment();
    assert!(env.sun.is_some());
    let size = (24, 16);
    let mut rad = settings(ReferenceAov::Radiance, size, f32::INFINITY, 512);
    rad.max_depth = 3;
    let radiance = render(&scene, &env, &cam, &rad, false);
    let diffuse = render(
        &scene,
        &env,
        &cam,
        &settings(ReferenceAov::Diffuse, size, f32::INFINITY, 512),
        false,
    );
    assert_agree_within_noise(
        "3-segment radiance vs diffuse",
        &radiance,
        |i, c| {
            let se = (radiance.stderr[i][c].powi(2) + diffuse.stderr[i][c].powi(2)).sqrt();
            (radiance.value[i][c], diffuse.value[i][c], se)
        },
        |want| 1e-3 * want.abs() + 1e-4,
    );
}

/// Splitting the sky's sun into a disc light changes how it is sampled, not the physics: the
/// path-traced `radiance` of `builtin:cornell` with the split agrees with the whole map's per
/// pixel within the two estimates' noise.
#[test]
fn sun_split_keeps_the_path_traced_image() {
    let scene = builtin::scene("cornell").unwrap();
    let cam = scene.default_camera();
    let sky = nearfield_scene::sky::Sky {
        width: 256,
        ..Default::default()
    };
    let size = (24, 14);
    let mut s = settings(ReferenceAov::Radiance, size, f32::INFINITY, 1024);
    s.max_depth = 4;
    let whole = render(&scene, &sky.to_environment(), &cam, &s, false);
    let split = render(&scene, &sky.to_split_environment(), &cam, &s, false);
    assert_agree_within_noise(
        "split vs whole",
        &whole,
        |i, c| {
            let se = (whole.stderr[i][c].powi(2) + split.stderr[i][c].powi(2)).sqrt();
            (split.value[i][c], whole.value[i][c], se)
        },
        |want| 2e-3 * want,
    );
}

/// Error against a 16× spp render falls at least as fast as 1/√spp.
#[test]
fn error_falls_with_sample_count() {
    let scene = builtin::scene("cornell").unwrap();
    let cam = scene.default_camera();
    let env = Environment::constant(Vec3::ONE);
    let size = (24, 16);
    let run = |spp, seed| {
        let mut s = settings(ReferenceAov::Ao, size, 0.5, spp);
        s.seed = seed;
        render(&scene, &env, &cam, &s, false)
    };
    let truth = run(16 * 64, 99);
    let rmse = |img: &ReferenceImage| {
        let (mut s, mut n) = (0.0f64, 0);
        for (a, b) in img.value.iter().zip(&truth.value) {
            if a[3] > 0.0 {
                s += ((a[0] - b[0]) as f64).powi(2);
                n += 1;
            }
        }
        (s / n as f64).sqrt()
    };
    let e4 = rmse(&run(4, 1));
    let e16 = rmse(&run(16, 1));
    let e64 = rmse(&run(64, 1));
    eprintln!("ao RMSE vs 1024 spp: 4 spp {e4:.4}, 16 spp {e16:.4}, 64 spp {e64:.4}");
    // 1/√spp predicts a factor 2 per 4× samples.
    assert!(e4 / e16 >= 1.7 && e16 / e64 >= 1.7, "{e4} {e16} {e64}");
}

/// A pixel centre exactly on the floor/wall seam: with light only from behind the wall
/// (d.z < −0.1: the margin keeps the map's bilinear blur, a texel wide, off the directions in
/// front of the wall), nothing may leak through to it, and its visibility is one half.
#[test]
fn seam_pixels_do_not_leak() {
    let scene = builtin::scene("wall").unwrap();
    let env = Environment::from_fn("behind", 256, 128, |d| {
        Vec3::splat(if d.z < -0.1 { 10.0 } else { 0.0 })
    });
    for target_x in [0.3f32, -1.7, 12.25] {
        // A 1×1 image: the only pixel's centre ray goes exactly through the target on the seam.
        let cam = Camera::new(
            Vec3::new(target_x + 0.4, 1.0, 1.3),
            Vec3::new(target_x, 0.0, 0.0),
            30.0,
        );
        let e = render(
            &scene,
            &env,
            &cam,
            &settings(ReferenceAov::EnvIrradiance, (1, 1), f32::INFINITY, 4096),
            false,
        );
        let p = position(&e, &cam, 0, 0);
        assert!(p.y.abs() < 1e-4 && p.z.abs() < 1e-4, "not on the seam: {p}");
        assert_eq!(e.value[0][0], 0.0, "light leaked at {p}");
        let ao = render(
            &scene,
            &env,
            &cam,
            &settings(ReferenceAov::Ao, (1, 1), f32::INFINITY, 4096),
            false,
        );
        assert!(
            ao.value[0][0] <= 0.5 + 4.0 * ao.stderr[0][0],
            "{}",
            ao.value[0][0]
        );
    }
}

#[test]
fn light_irradiance_is_exact_and_shadowed() {
    // closed-box: the point light at (0, 2.6, 0); floor pixels get I cos θ / (π d²) or 0 behind
    // the block, nothing in between (exact shadow rays).
    let scene = builtin::scene("closed-box").unwrap();
    let light = scene.lights[0];
    // From the far corner, looking back at the block and the shadow it casts away from the light.
    let cam = Camera::new(Vec3::new(1.9, 2.5, -1.95), Vec3::new(0.3, 0.0, -0.5), 80.0);
    let env = Environment::constant(Vec3::ZERO);
    let img = render(
        &scene,
        &env,
        &cam,
        &settings(ReferenceAov::LightIrradiance, (48, 32), f32::INFINITY, 1),
        false,
    );
    let (mut lit, mut dark) = (0, 0);
    for y in 0..img.height {
        for x in 0..img.width {
            let p = position(&img, &cam, x, y);
            if p.y.abs() > 1e-3 {
                continue;
            }
            let want = light.irradiance(p, Vec3::Y).x / PI;
            let got = img.get(x, y)[0];
            if got == 0.0 {
                dark += 1;
            } else {
                lit += 1;
                assert!(
                    (got - want).abs() < 1e-5 * want.max(1.0),
                    "{p}: {got} vs {want}"
                );
            }
        }
    }
    assert!(lit > 300 && dark > 5, "{lit} {dark}");
}

#[test]
fn results_do_not_depend_on_thread_count() {
    let scene = builtin::scene("cornell").unwrap();
    let cam = scene.default_camera();
    let env = Environment::constant(Vec3::ONE);
    let s = settings(ReferenceAov::Ao, (16, 12), 0.5, 16);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let a = one.install(|| render(&scene, &env, &cam, &s, false));
    let b = render(&scene, &env, &cam, &s, false);
    assert_eq!(a.value, b.value);
}

//! The probe bake against analytic truths: a furnace (bounces add up as a geometric series), an
//! unoccluded plane under a constant sky, the two rooms' wall (no leak), probes out of geometry,
//! and determinism.

use glam::Vec3;
use nearfield_reference::bake::{self, BakeSettings};
use nearfield_scene::probes::{ProbeGrid, ProbeVolume};
use nearfield_scene::{Environment, Scene, builtin};

fn bake(scene: &Scene, env: &Environment, grid: ProbeGrid, rays: u32, bounces: u32) -> ProbeVolume {
    bake::bake(
        scene,
        env,
        BakeSettings {
            grid,
            rays,
            bounces,
        },
        false,
        None,
    )
    .expect("bake")
}

/// Mean of E/π over the active probes' own positions, for a normal `n`.
fn mean_irradiance(v: &ProbeVolume, n: Vec3) -> Vec3 {
    let mut sum = Vec3::ZERO;
    let mut count = 0;
    for p in v.probes.iter().filter(|p| p.active) {
        sum += nearfield_scene::sh::irradiance_over_pi(&p.sh, n);
        count += 1;
    }
    sum / count.max(1) as f32
}

#[test]
fn bounces_add_up_in_a_furnace() {
    // A closed room whose every surface emits Le = 1 and reflects ρ = 0.5, no lights: after K
    // bounces every surface leaves Le (1 − ρ^(K+1)) / (1 − ρ), so every probe receives that
    // radiance from every direction (E/π = the same).
    let mut scene = builtin::scene("closed-box").unwrap();
    scene.lights.clear();
    for m in &mut scene.materials {
        m.base_color = glam::Vec4::new(0.5, 0.5, 0.5, 1.0);
        m.base_color_texture = None;
        m.emissive = Vec3::ONE;
    }
    let env = Environment::constant(Vec3::ZERO);
    let grid = ProbeGrid::with_counts(scene.bounds(), [4, 3, 4]).unwrap();
    for k in [0u32, 1, 3, 6] {
        let v = bake(&scene, &env, grid, 512, k);
        let want = (1.0 - 0.5f32.powi(k as i32 + 1)) / 0.5;
        for n in [Vec3::Y, Vec3::X, -Vec3::Z] {
            let e = mean_irradiance(&v, n);
            // 8-bit albedo (0.5 → 128/255) and the SH projection of 512 rays: 1 %.
            assert!(
                (e.x - want).abs() < 0.01 * want,
                "K = {k}, n = {n}: {e} vs {want}"
            );
        }
    }
}

#[test]
fn open_plane_under_a_constant_sky() {
    // Above an unoccluded plane (albedo ρ) under a constant sky L = 1, a probe receives 1 from
    // above and, with at least one bounce, the plane's outgoing ρ·1 from below: E(+Y)/π = 1 and
    // E(−Y)/π = ρ. Order 2 is exact here: the radiance (1 + ρ)/2 + (1 − ρ)/2 · sign(y) has
    // irradiance (1 + ρ)/2 ± (1 − ρ)/2 from bands 0 and 1 (its band 3 does not reach irradiance).
    let scene = builtin::scene("plane").unwrap();
    let env = Environment::constant(Vec3::ONE);
    let bounds = nearfield_scene::Aabb {
        min: Vec3::new(-5.0, 0.5, -5.0),
        max: Vec3::new(5.0, 1.5, 5.0),
    };
    let grid = ProbeGrid::with_counts(bounds, [3, 1, 3]).unwrap();
    let v = bake(&scene, &env, grid, 1024, 2);
    let rho = scene.materials[0].base_color.x;
    let (up, down) = (1.0, rho);
    let e_up = mean_irradiance(&v, Vec3::Y).x;
    let e_down = mean_irradiance(&v, -Vec3::Y).x;
    // The plane is 400 m wide: seen from 1 m its edge is below the horizon by 0.3°.
    assert!((e_up - up).abs() < 0.01, "{e_up} vs {up}");
    assert!((e_down - down).abs() < 0.01, "{e_down} vs {down}");
}

#[test]
fn no_light_leaks_into_the_closed_room() {
    let scene = builtin::scene("two-rooms").unwrap();
    let env = scene
        .default_env
        .load_split(nearfield_scene::SunMode::Auto)
        .unwrap()
        .0;
    let grid = bake::default_grid(&scene).unwrap();
    let v = bake(
        &scene,
        &env,
        grid,
        bake::DEFAULT_RAYS,
        bake::DEFAULT_BOUNCES,
    );
    // Floor points of each room, away from the walls, read as the renderer reads them.
    let mean = |x0: f32, x1: f32| {
        let mut sum = Vec3::ZERO;
        let mut n = 0;
        for i in 0..12 {
            for j in 0..10 {
                let p = Vec3::new(
                    x0 + (x1 - x0) * (i as f32 + 0.5) / 12.0,
                    0.0,
                    -1.3 + 2.6 * (j as f32 + 0.5) / 10.0,
                );
                sum += v.irradiance(p, Vec3::Y, Vec3::Y);
                n += 1;
            }
        }
        (sum / n as f32).dot(Vec3::splat(1.0 / 3.0))
    };
    let lit = mean(-3.0, -0.3);
    let dark = mean(0.3, 3.0);
    assert!(lit > 0.1, "the lit room gets light: {lit}");
    assert!(dark <= 0.02 * lit, "dark {dark} vs lit {lit}");
    // Right beside the wall too.
    let near_wall = v
        .irradiance(Vec3::new(0.15, 0.0, 0.0), Vec3::Y, Vec3::Y)
        .max_element();
    assert!(
        near_wall <= 0.02 * lit,
        "beside the wall {near_wall} vs lit {lit}"
    );
}

#[test]
fn probes_leave_solids_or_switch_off() {
    // Cornell's two blocks and city's towers hold grid positions: every active probe ends where
    // few of its rays meet back faces.
    for name in ["cornell", "city"] {
        let scene = builtin::scene(name).unwrap();
        let env = Environment::constant(Vec3::ONE);
        let grid = bake::default_grid(&scene).unwrap();
        let v = bake(&scene, &env, grid, 64, 0);
        let moved = v.probes.iter().filter(|p| p.offset != Vec3::ZERO).count();
        assert!(moved > 0, "{name}: some probes stood in a block");
        let tracer = nearfield_reference::tracer::Tracer::new(&scene);
        for (i, p) in v.probes.iter().enumerate().filter(|(_, p)| p.active) {
            let o = v.probe_position(i);
            let dirs = 64;
            let back = (0..dirs)
                .filter(|&j| {
                    let z = 1.0 - (2.0 * j as f32 + 1.0) / dirs as f32;
                    let r = (1.0 - z * z).sqrt();
                    let phi = j as f32 * 2.399_963;
                    let d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                    tracer
                        .closest(o, d, f32::INFINITY, false)
                        .is_some_and(|h| !h.front)
                })
                .count();
            assert!(
                back as f32 <= 0.3 * dirs as f32,
                "{name}: probe {i} at {o} ({:?}) is inside geometry ({back}/{dirs} back faces)",
                p.offset
            );
        }
    }
}

#[test]
fn bakes_do_not_depend_on_threads() {
    let scene = builtin::scene("cornell").unwrap();
    let env = Environment::constant(Vec3::new(0.5, 0.7, 1.0));
    let grid = ProbeGrid::with_counts(scene.bounds(), [5, 5, 5]).unwrap();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| bake(&scene, &env, grid, 128, 2));
    let all = bake(&scene, &env, grid, 128, 2);
    assert_eq!(one.to_bytes(), all.to_bytes());
}

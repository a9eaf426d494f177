//! `ssao` and `ssdo` on scenes whose answer is known (lavapipe in CI).

mod common;

use glam::Vec3;
use nearfield_render::{Aov, AovImage, Renderer};
use nearfield_scene::{Camera, Environment, builtin};

fn aov(r: &mut Renderer, a: Aov) -> AovImage {
    r.read_aov(a)
}

/// No false occlusion on a flat surface at any radius: ao = 1 and env-irradiance equal to
/// `none`'s, bit for bit (visibility mode), for both techniques and both patterns.
#[test]
fn plane_has_no_false_occlusion() {
    let Some(ctx) = common::context() else { return };
    let scene = builtin::scene("plane").unwrap();
    let env = nearfield_scene::sky::Sky {
        width: 256,
        ..Default::default()
    }
    .to_environment();
    let cam = scene.default_camera();
    let size = (64, 40);
    let mut base = common::render_shot(
        &ctx,
        &common::Shot {
            scene: &scene,
            env: &env,
            camera: cam,
            size,
            seed: 0,
        },
        "none",
        &[],
        1.0,
    );
    let want = aov(&mut base, Aov::EnvIrradiance);
    for radius in [0.05, 1.0, 20.0] {
        for (method, set) in [
            ("ssao", vec![]),
            ("ssdo", vec![]),
            ("ssdo", vec![("pattern", "chapter")]),
        ] {
            let mut r = common::render_shot(
                &ctx,
                &common::Shot {
                    scene: &scene,
                    env: &env,
                    camera: cam,
                    size,
                    seed: 0,
                },
                method,
                &set,
                radius,
            );
            let ao = aov(&mut r, Aov::Ao);
            let e = aov(&mut r, Aov::EnvIrradiance);
            for i in 0..ao.pixels.len() {
                if ao.pixels[i][3] == 0.0 {
                    continue;
                }
                assert_eq!(ao.pixels[i][0], 1.0, "{method} {set:?} R {radius}: ao");
                assert_eq!(
                    e.pixels[i], want.pixels[i],
                    "{method} {set:?} R {radius}: env-irradiance"
                );
            }
        }
    }
}

/// `wall`: ao at the base of the wall within 0.1 of 0.5, rising towards 1 away from it as the
/// analytic curve 1 − (acos k − k√(1−k²))/π, k = d/R, does. The paper's point samples (one
/// random length per direction) test occupancy at one distance rather than along the whole
/// segment, so they see less of the wall than a ray within R does: the measured curve lies above
/// the analytic one by up to the printed worst error.
#[test]
fn wall_ao_follows_the_curve() {
    let Some(ctx) = common::context() else { return };
    let scene = builtin::scene("wall").unwrap();
    let env = Environment::constant(Vec3::ONE);
    let cam = Camera::new(Vec3::new(0.3, 0.6, 2.4), Vec3::new(0.0, 0.35, 0.0), 60.0);
    let size = (240, 180);
    let radius = 1.0;
    let mut r = common::render_shot(
        &ctx,
        &common::Shot {
            scene: &scene,
            env: &env,
            camera: cam,
            size,
            seed: 0,
        },
        "ssdo",
        &[("samples", "64")],
        radius,
    );
    let ao = aov(&mut r, Aov::Ao);
    let depth = aov(&mut r, Aov::Depth);
    let normal = aov(&mut r, Aov::Normal);
    let mut bands = vec![(0.0f64, 0usize); 15];
    let (mut base, mut base_n) = (0.0f64, 0usize);
    let mut worst: f32 = 0.0;
    for y in 0..size.1 {
        for x in 0..size.0 {
            if ao.get(x, y)[3] == 0.0 || normal.get(x, y)[1] < 0.99 {
                continue;
            }
            let p = common::world_position(&cam, size, &depth, x, y);
            let k = p.z / radius;
            let v = ao.get(x, y)[0];
            if k < 0.01 {
                base += v as f64;
                base_n += 1;
            }
            let band = (k * 10.0) as usize;
            if band < bands.len() {
                bands[band].0 += v as f64;
                bands[band].1 += 1;
            }
            let want = common::wall_ao(k);
            worst = worst.max((v - want).abs());
        }
    }
    let base = base / base_n.max(1) as f64;
    let means: Vec<f64> = bands.iter().map(|(s, n)| s / (*n).max(1) as f64).collect();
    eprintln!(
        "ssdo ao at the base (k < 0.01, {base_n} px): {base:.3}; by 0.1 R band: {means:.3?}; worst pixel vs the curve {worst:.3}"
    );
    assert!(base_n > 20 && (base - 0.5).abs() < 0.1, "base {base}");
    for w in means.windows(2) {
        assert!(w[1] >= w[0] - 0.02, "{means:?}");
    }
    assert!(means[12] > 0.97, "{means:?}");
    // Measured on lavapipe (64 samples, blur on): base 0.596, worst pixel 0.197 (near k = 0.2).
    assert!(worst < 0.3, "{worst}");
}

/// Coloured shadows: under an environment that is red towards −X and blue towards +X, the floor
/// just right (+X) of a box loses red light: SSDO tints it blue (towards the unblocked side),
/// SSAO only darkens it (grey).
#[test]
fn ssdo_casts_coloured_shadows_ssao_grey_ones() {
    let Some(ctx) = common::context() else { return };
    let scene = common::box_on_plane();
    let env = Environment::from_fn("red-blue", 256, 128, |d| {
        if d.x < 0.0 {
            Vec3::new(1.0, 0.05, 0.05)
        } else {
            Vec3::new(0.05, 0.05, 1.0)
        }
    });
    let cam = Camera::new(Vec3::new(0.6, 3.0, 3.0), Vec3::new(0.6, 0.0, 0.0), 50.0);
    let size = (96, 72);
    let hue = |method: &str, set: &[(&str, &str)]| {
        let mut r = common::render_shot(
            &ctx,
            &common::Shot {
                scene: &scene,
                env: &env,
                camera: cam,
                size,
                seed: 0,
            },
            method,
            set,
            1.0,
        );
        let e = aov(&mut r, Aov::EnvIrradiance);
        let depth = aov(&mut r, Aov::Depth);
        let normal = aov(&mut r, Aov::Normal);
        let (mut near, mut far) = (Vec3::ZERO, Vec3::ZERO);
        for y in 0..size.1 {
            for x in 0..size.0 {
                if e.get(x, y)[3] == 0.0 || normal.get(x, y)[1] < 0.99 {
                    continue;
                }
                let p = common::world_position(&cam, size, &depth, x, y);
                if p.y > 0.01 {
                    continue;
                }
                let c = Vec3::from_slice(&e.get(x, y)[..3]);
                if (0.52..0.6).contains(&p.x) && p.z.abs() < 0.3 {
                    near += c;
                } else if p.x > 2.5 {
                    far += c;
                }
            }
        }
        // Blue-to-red ratio next to the box relative to the open floor.
        (near.z / near.x) / (far.z / far.x)
    };
    let ssdo = hue("ssdo", &[("mode", "radiance"), ("samples", "32")]);
    let ssao = hue("ssao", &[("samples", "32")]);
    eprintln!("blue/red next to the box relative to open floor: ssdo {ssdo:.3}, ssao {ssao:.3}");
    // Measured on lavapipe: ssdo 1.108, ssao 1.000 (the bound leaves room for other adapters).
    assert!(ssdo > 1.05, "ssdo shadow not tinted: {ssdo}");
    assert!((ssao - 1.0).abs() < 0.02, "ssao shadow not grey: {ssao}");
}

/// Turning the environment changes SSDO's result at once: the same renderer and technique, only
/// the frame re-run, give what a renderer built with the turned environment gives.
#[test]
fn environment_changes_need_no_precomputation() {
    let Some(ctx) = common::context() else { return };
    let scene = common::box_on_plane();
    let mut env = Environment::from_fn("red-blue", 256, 128, |d| {
        if d.x < 0.0 {
            Vec3::new(2.0, 0.1, 0.1)
        } else {
            Vec3::new(0.1, 0.1, 0.5)
        }
    });
    let cam = Camera::new(Vec3::new(0.6, 3.0, 3.0), Vec3::new(0.6, 0.0, 0.0), 50.0);
    let size = (64, 48);
    let set = [("mode", "radiance")];
    let mut r = common::render_shot(
        &ctx,
        &common::Shot {
            scene: &scene,
            env: &env,
            camera: cam,
            size,
            seed: 0,
        },
        "ssdo",
        &set,
        1.0,
    );
    let before = aov(&mut r, Aov::EnvIrradiance);
    let turn = 2.0;
    r.set_environment_rotation(turn);
    r.render_frame();
    let after = aov(&mut r, Aov::EnvIrradiance);
    env.rotation = turn;
    let mut fresh = common::render_shot(
        &ctx,
        &common::Shot {
            scene: &scene,
            env: &env,
            camera: cam,
            size,
            seed: 0,
        },
        "ssdo",
        &set,
        1.0,
    );
    let want = aov(&mut fresh, Aov::EnvIrradiance);
    let (mut changed, mut worst) = (0.0f32, 0.0f32);
    for i in 0..after.pixels.len() {
        for c in 0..3 {
            changed = changed.max((after.pixels[i][c] - before.pixels[i][c]).abs());
            worst = worst.max((after.pixels[i][c] - want.pixels[i][c]).abs());
        }
    }
    assert!(
        changed > 0.2,
        "turning the environment changed nothing: {changed}"
    );
    assert!(
        worst < 1e-3,
        "differs from a renderer built with the turned environment: {worst}"
    );
}

/// The 4×4 interleaving: on a flat plane under the sky (radiance mode's plain sum, where every
/// pixel's 16 directions differ by its set; normalised, an open plane gets the exact irradiance
/// at every pixel and shows no pattern), the image's 4×4-periodic component — the spread of the 16
/// class means (x mod 4, y mod 4) relative to the mean — is visible without the blur and below a
/// measured bound after it.
#[test]
fn blur_hides_the_interleaving_pattern() {
    let Some(ctx) = common::context() else { return };
    let scene = builtin::scene("plane").unwrap();
    let env = nearfield_scene::sky::Sky {
        width: 256,
        ..Default::default()
    }
    .to_environment();
    let cam = Camera::new(Vec3::new(0.0, 3.0, 0.01), Vec3::ZERO, 60.0);
    let size = (96, 96);
    let periodic = |blur: &str| {
        let mut r = common::render_shot(
            &ctx,
            &common::Shot {
                scene: &scene,
                env: &env,
                camera: cam,
                size,
                seed: 0,
            },
            "ssdo",
            &[
                ("mode", "radiance"),
                ("normalise", "off"),
                ("lod", "3"),
                ("denoise", blur),
            ],
            1.0,
        );
        let e = aov(&mut r, Aov::EnvIrradiance);
        let mut class = [(0.0f64, 0usize); 16];
        for y in 8..size.1 - 8 {
            for x in 8..size.0 - 8 {
                let c = &mut class[((x % 4) + 4 * (y % 4)) as usize];
                c.0 += e.get(x, y)[1] as f64;
                c.1 += 1;
            }
        }
        let means: Vec<f64> = class.iter().map(|(s, n)| s / *n as f64).collect();
        let mean = means.iter().sum::<f64>() / 16.0;
        (means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / 16.0).sqrt() / mean
    };
    let raw = periodic("off");
    let blurred = periodic("bilateral");
    eprintln!("4x4-periodic component: unblurred {raw:.4}, blurred {blurred:.5}");
    assert!(
        raw > 0.01,
        "the pattern should show without the blur: {raw}"
    );
    // Measured on lavapipe: see the eprintln above; the bound leaves a margin of about 2×.
    assert!(
        blurred < 0.002 && blurred < raw / 10.0,
        "{blurred} vs {raw}"
    );
}

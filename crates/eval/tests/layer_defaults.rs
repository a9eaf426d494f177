//! The layer defaults never make `ao` worse: for `ssao`, `ssdo` and `s3ho` at their default
//! settings (with two layers the blocker test marches 16 points per direction,
//! `settings::layers::LAYERED_STEPS`), `layers=2` has an `ao` MAE against the reference no
//! higher than `layers=1` (within 2 %, see below) on every built-in scene and on Crytek Sponza,
//! at R = 0.5 m and R = 1 m (masked as `compare` masks).
//! the book's layer section lists the table this prints.

mod common;

use nearfield_reference::{ReferenceAov, ReferenceSettings};
use nearfield_render::{Aov, RenderSettings, Renderer, TechniqueParams};
use nearfield_scene::{Camera, Scene, SunMode, builtin};

/// The scenes: every built-in one with its own camera, and Sponza from the the book's view.
fn scenes() -> Vec<(String, Scene, Camera)> {
    let mut out: Vec<(String, Scene, Camera)> = builtin::NAMES
        .iter()
        .map(|n| {
            let s = builtin::scene(n).unwrap();
            let c = s.default_camera();
            (n.to_string(), s, c)
        })
        .collect();
    if let Some(path) = nearfield_eval::shared_asset("scenes/crytek_sponza/Sponza.gltf") {
        let s = nearfield_scene::load_scene(&path).unwrap();
        let c = Camera::new(
            glam::Vec3::new(9.0, 1.5, -0.4),
            glam::Vec3::new(-5.0, 3.5, 0.2),
            60.0,
        );
        out.push(("sponza".into(), s, c));
    }
    out
}

#[test]
fn two_layers_never_raise_the_ao_error() {
    let Some(ctx) = common::context() else { return };
    let size = (128, 72);
    let mut failures = Vec::new();
    for (name, scene, camera) in scenes() {
        let (env, _) = scene.default_env.load_split(SunMode::Auto).unwrap();
        for radius in [0.5f32, 1.0] {
            let settings = ReferenceSettings {
                aov: ReferenceAov::Ao,
                size,
                radius,
                spp: 128,
                seed: 7,
                ..Default::default()
            };
            let reference = nearfield_reference::render(&scene, &env, &camera, &settings, false);
            let mut line = format!("{name:<12} R={radius:<4}");
            for method in ["ssao", "ssdo", "s3ho"] {
                let mut mae = [0.0; 2];
                for (i, layers) in [1, 2].into_iter().enumerate() {
                    let mut r = Renderer::new(
                        &ctx,
                        &scene,
                        &env,
                        None,
                        camera,
                        &nearfield_render::technique::Spec::resolve(
                            method,
                            &TechniqueParams {
                                radius: Some(radius),
                                set: vec![("layers".into(), layers.to_string())],
                                ..Default::default()
                            },
                        )
                        .unwrap(),
                        RenderSettings {
                            size,
                            ..Default::default()
                        },
                    )
                    .unwrap();
                    r.render_frame();
                    mae[i] = common::masked_metrics(&mut r, Aov::Ao, &reference).mae;
                }
                line += &format!("  {method} {:.4} → {:.4}", mae[0], mae[1]);
                // 2 %: s3ho on `columns` at R = 1 (0.0110 → 0.0112), where the second layer
                // frees the gap behind the front column in which the hidden column stands (a third
                // surface two layers cannot see; `layers=4` or `cameras` see it). Everywhere else
                // the second layer lowers the error (the book's table).
                if mae[1] > 1.02 * mae[0] + 1e-4 {
                    failures.push(format!(
                        "{name} R={radius} {method}: {} → {}",
                        mae[0], mae[1]
                    ));
                }
            }
            eprintln!("{line}");
        }
    }
    assert!(
        failures.is_empty(),
        "layers=2 raised the ao MAE: {failures:#?}"
    );
}

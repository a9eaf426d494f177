//! Determinism: the same scene, camera path, technique, settings and seed give bit-identical
//! AOVs from two renderers made one after the other (every technique, three frames with a
//! turning camera so that the temporal ones reproject and accumulate).

mod common;

use nearfield_render::{Aov, RenderSettings, Renderer, TechniqueParams, technique};

fn run(ctx: &nearfield_render::GpuContext, name: &str, seed: u32) -> Vec<Vec<u32>> {
    let scene = nearfield_scene::builtin::scene("boxes").unwrap();
    let env = nearfield_scene::Environment::constant(glam::Vec3::new(0.6, 0.7, 0.9));
    let mut settings = RenderSettings {
        size: (40, 24),
        seed,
        ..Default::default()
    };
    settings.shadows.size = 256;
    let set = match name {
        "ssdo-vpl" | "instant-radiosity" => vec![
            ("vpls".to_string(), "4".to_string()),
            ("vpl_map".to_string(), "128".to_string()),
            ("rsm".to_string(), "16".to_string()),
        ],
        _ => Vec::new(),
    };
    let mut r = Renderer::new(
        ctx,
        &scene,
        &env,
        None,
        scene.default_camera(),
        &nearfield_render::technique::Spec::resolve(
            name,
            &TechniqueParams {
                set,
                ..Default::default()
            },
        )
        .unwrap(),
        settings,
    )
    .unwrap();
    for _ in 0..3 {
        let turned = r.camera().orbit(4.0);
        r.set_camera(turned);
        r.render_frame();
    }
    Aov::ALL
        .iter()
        .filter(|&&a| a != Aov::Final)
        .map(|&a| {
            r.read_aov(a)
                .pixels
                .iter()
                .flatten()
                .map(|x| x.to_bits())
                .collect()
        })
        .collect()
}

#[test]
fn every_technique_is_bit_identical_across_runs() {
    let Some(ctx) = common::context() else { return };
    for name in technique::names() {
        let a = run(&ctx, name, 7);
        let b = run(&ctx, name, 7);
        for (i, (x, y)) in a.iter().zip(&b).enumerate() {
            let aov = Aov::ALL
                .iter()
                .filter(|&&a| a != Aov::Final)
                .nth(i)
                .unwrap();
            let differing = x.iter().zip(y).filter(|(p, q)| p != q).count();
            assert_eq!(
                differing,
                0,
                "{name}: {} differs in {differing} values",
                aov.name()
            );
        }
    }
}

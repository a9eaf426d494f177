//! `encode` allocates nothing: 200 frames of every registered technique leave wgpu's live object
//! counts (buffers, textures, views, samplers, bind groups and their layouts, pipelines, shader
//! modules, query sets) where the first frame left them.

mod common;

use common::live_objects;
use nearfield_render::{RenderSettings, Renderer, TechniqueParams, technique};

#[test]
fn two_hundred_frames_of_every_technique_keep_the_live_object_counts() {
    let Some(ctx) = common::context() else { return };
    // Boxes has a light (shadow maps, light occlusion, instant-radiosity's VPLs); under the
    // built-in sky with its sun split out as a disc light (`--sun auto`) a second, shadow-mapped
    // light; hbil reprojects from its second frame on. With `none` the camera turns every frame,
    // so the sun's shadow map is refitted to the view every frame.
    let scene = nearfield_scene::builtin::scene("boxes").unwrap();
    let (env, _) = nearfield_scene::EnvSource::Sky
        .load_split(nearfield_scene::SunMode::Auto)
        .unwrap();
    assert!(env.sun.is_some());
    for name in technique::names() {
        let t = std::time::Instant::now();
        // Small shadow maps keep 200 frames short on a CPU adapter; what is made per frame does
        // not depend on their size.
        let set = match name {
            "ssdo-vpl" | "instant-radiosity" => vec![
                ("vpls".to_string(), "4".to_string()),
                ("vpl_map".to_string(), "128".to_string()),
                ("rsm".to_string(), "16".to_string()),
            ],
            _ => Vec::new(),
        };
        let mut settings = RenderSettings {
            size: (32, 18),
            ..Default::default()
        };
        settings.shadows.size = 256;
        let mut r = Renderer::new(
            &ctx,
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
        r.render_frame();
        let after_first = live_objects(&ctx);
        // From the second frame on the temporal techniques reproject their history.
        for _ in 1..200 {
            if name == "none" {
                let turned = r.camera().orbit(1.0);
                r.set_camera(turned);
            }
            r.render_frame();
        }
        let after_200 = live_objects(&ctx);
        eprintln!("{name}: 200 frames in {:.1} s", t.elapsed().as_secs_f32());
        assert_eq!(
            after_first, after_200,
            "{name}: live objects after frame 1 vs after frame 200"
        );
    }
}

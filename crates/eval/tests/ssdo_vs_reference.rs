//! SSDO against SSAO, measured against the reference on `builtin:cornell` (masked as `compare`
//! masks): SSDO's env-irradiance has a lower mean relative error than SSAO's, and SSDO's diffuse
//! with the bounce a lower one than without, under the analytic sky and under a real HDR map
//! (rooitou_park_1k, outdoor with sun). the book's results table lists the full numbers.

mod common;

use nearfield_reference::{ReferenceAov, ReferenceSettings};
use nearfield_render::{Aov, RenderSettings, Renderer, TechniqueParams};
use nearfield_scene::{EnvSource, builtin};

#[test]
fn ssdo_beats_ssao_and_the_bounce_helps() {
    let Some(ctx) = common::context() else { return };
    let mut envs = vec![("sky", EnvSource::Sky)];
    if let Some(hdr) = nearfield_eval::shared_asset("env/rooitou_park_1k.hdr") {
        envs.push(("rooitou_park_1k", EnvSource::File(hdr)));
    }
    let scene = builtin::scene("cornell").unwrap();
    let camera = scene.default_camera();
    let size = (128, 72);
    let radius = 0.5;
    for (env_name, source) in envs {
        let env = source.load().unwrap();
        let error = |method: &str, aov: Aov, reference: &nearfield_reference::ReferenceImage| {
            let (name, set) = nearfield_render::technique::split_spec(method);
            let params = TechniqueParams {
                samples: None,
                radius: Some(radius),
                set,
            };
            let mut r = Renderer::new(
                &ctx,
                &scene,
                &env,
                None,
                camera,
                &nearfield_render::technique::Spec::resolve(name, &params).unwrap(),
                RenderSettings {
                    size,
                    ..Default::default()
                },
            )
            .unwrap();
            r.render_frame();
            common::masked_metrics(&mut r, aov, reference).relative_error
        };
        let reference = |aov| {
            let s = ReferenceSettings {
                aov,
                size,
                radius,
                spp: 128,
                seed: 3,
                max_depth: 2,
                senders: nearfield_reference::Senders::Physical,
            };
            nearfield_reference::render(&scene, &env, &camera, &s, false)
        };
        let env_ref = reference(ReferenceAov::EnvIrradiance);
        let ssao = error("ssao", Aov::EnvIrradiance, &env_ref);
        let ssdo = error("ssdo", Aov::EnvIrradiance, &env_ref);
        let diffuse_ref = reference(ReferenceAov::Diffuse);
        let no_bounce = error("ssdo:bounce=off", Aov::Diffuse, &diffuse_ref);
        let bounce = error("ssdo", Aov::Diffuse, &diffuse_ref);
        eprintln!(
            "{env_name}: env-irradiance rel. error ssao {ssao:.4} ssdo {ssdo:.4}; diffuse ssdo {no_bounce:.4} → with bounce {bounce:.4}"
        );
        assert!(ssdo < ssao, "{env_name}: ssdo {ssdo} ≥ ssao {ssao}");
        assert!(
            bounce < no_bounce,
            "{env_name}: bounce {bounce} ≥ no bounce {no_bounce}"
        );
    }
}

//! Settings change without a rebuild: a float, toggle or choice setting goes to the GPU with
//! `write_buffer`, and the frame after it is bit for bit the frame of a technique built with that
//! setting; a count (samples, steps, slices, layers) rebuilds.

mod common;

use nearfield_render::{Aov, Renderer, TechniqueParams};

fn params(set: &[(&str, &str)]) -> TechniqueParams {
    TechniqueParams {
        set: set
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
        ..Default::default()
    }
}

#[test]
fn uniform_settings_apply_in_place_and_match_a_rebuilt_technique() {
    let Some(ctx) = common::context() else { return };
    let scene = nearfield_scene::builtin::scene("boxes").unwrap();
    let env = scene.default_env.load().unwrap();
    let settings = nearfield_render::RenderSettings {
        size: (48, 27),
        ..Default::default()
    };
    let make = |method: &str, p: &TechniqueParams| {
        Renderer::new(
            &ctx,
            &scene,
            &env,
            None,
            scene.default_camera(),
            &nearfield_render::technique::Spec::resolve(method, p).unwrap(),
            settings,
        )
        .unwrap()
    };
    let cases: [(&str, &[(&str, &str)]); 6] = [
        ("ssao", &[("radius", "0.3"), ("contrast", "2")]),
        (
            "ssdo",
            &[("radius", "0.3"), ("strength", "2"), ("blur_depth", "0.05")],
        ),
        (
            "instant-radiosity",
            &[("vpl_clamp", "0.25"), ("fade", "0.5")],
        ),
        ("s3ho", &[("radius", "0.3"), ("lambda", "2")]),
        ("gtao", &[("radius", "0.3"), ("falloff", "0.3")]),
        (
            "hbil",
            &[
                ("radius", "0.3"),
                ("fresnel", "off"),
                ("reject_normal", "0.8"),
            ],
        ),
    ];
    for (method, set) in cases {
        // In place: defaults for one frame, then the new settings.
        let mut updated = make(method, &TechniqueParams::default());
        updated.render_frame();
        updated.set_technique(method, &params(set)).unwrap();
        assert_eq!(updated.rebuilds(), 0, "{method} {set:?}: rebuilt");
        updated.render_frame();
        // Built with them, one frame, then a cut (as the in-place change makes).
        let mut built = make(method, &params(set));
        built.render_frame();
        built.cut();
        built.render_frame();
        for aov in [
            Aov::Ao,
            Aov::EnvIrradiance,
            Aov::IndirectIrradiance,
            Aov::Diffuse,
        ] {
            let (a, b) = (updated.read_aov(aov), built.read_aov(aov));
            assert!(
                a.pixels == b.pixels,
                "{method} {set:?}: {} differs from a technique built with the settings",
                aov.name()
            );
        }
        // A count rebuilds.
        let count = if method.contains("gtao") || method.contains("hbil") {
            "slices"
        } else {
            "samples"
        };
        updated
            .set_technique(method, &params(&[(count, "3")]))
            .unwrap();
        assert_eq!(updated.rebuilds(), 1, "{method}: {count} did not rebuild");
        // A bad value changes nothing.
        assert!(
            updated
                .set_technique(method, &params(&[("radius", "-1")]))
                .is_err()
        );
        assert_eq!(updated.rebuilds(), 1);
    }
}

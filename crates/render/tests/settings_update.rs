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

/// A value of `s` other than its default, within its range.
fn other_value(s: &nearfield_render::technique::Setting) -> String {
    use nearfield_render::technique::SettingKind;
    match s.kind {
        SettingKind::Number {
            lo, hi, integer, ..
        } => {
            let d: f32 = s.default.parse().unwrap();
            // Halfway to a bound (a count's neighbour), so that the frame stays cheap.
            let v = if integer {
                if d + 1.0 <= hi { d + 1.0 } else { d - 1.0 }
            } else if d != lo {
                (d + lo) / 2.0
            } else {
                (d + hi.min(d.abs().max(1.0) * 4.0)) / 2.0
            };
            assert!((lo..=hi).contains(&v), "{}: {v} outside {lo}..={hi}", s.key);
            if integer {
                format!("{}", v as i64)
            } else {
                format!("{v}")
            }
        }
        SettingKind::Toggle => if s.default == "on" { "off" } else { "on" }.into(),
        SettingKind::Choice(words) => words.iter().find(|w| **w != s.default).unwrap().to_string(),
    }
}

/// What rebuilds is what the declarations say: for every registered technique, each setting
/// that applies to it, changed alone from the defaults, rebuilds the technique exactly when its
/// role does (`Role::rebuilds`: counts, structure, the denoiser's shape) and is written in place
/// otherwise (uniforms, filters). No family keeps a list of its own.
#[test]
fn a_setting_rebuilds_exactly_when_its_role_says() {
    let Some(ctx) = common::context() else { return };
    let scene = nearfield_scene::builtin::scene("boxes").unwrap();
    let env = scene.default_env.load().unwrap();
    let settings = nearfield_render::RenderSettings {
        size: (16, 16),
        ..Default::default()
    };
    let (mut checked, mut refused) = (0, Vec::new());
    for desc in nearfield_render::technique::REGISTRY {
        let mut r = Renderer::new(
            &ctx,
            &scene,
            &env,
            None,
            scene.default_camera(),
            &nearfield_render::technique::Spec::resolve(desc.name, &TechniqueParams::default())
                .unwrap(),
            settings,
        )
        .unwrap();
        for s in desc.settings.iter().filter(|s| s.applies(desc.name)) {
            let value = other_value(s);
            let before = r.rebuilds();
            if let Err(e) = r.set_technique(desc.name, &params(&[(s.key, &value)])) {
                // A value another setting constrains (vpl_clamp ≤ R with the bounce on).
                refused.push(format!("{} {}={value}: {e}", desc.name, s.key));
                continue;
            }
            let rebuilt = r.rebuilds() > before;
            assert_eq!(
                rebuilt,
                s.role.rebuilds(),
                "{} {}={value} (role {}): rebuilt {rebuilt}",
                desc.name,
                s.key,
                s.role.word()
            );
            // Back to the defaults, rebuilt or not as the same role says.
            let before = r.rebuilds();
            r.set_technique(desc.name, &TechniqueParams::default())
                .unwrap();
            assert_eq!(
                r.rebuilds() > before,
                s.role.rebuilds(),
                "{} {}",
                desc.name,
                s.key
            );
            checked += 1;
        }
    }
    assert!(checked > 150, "{checked} settings checked");
    assert!(refused.len() <= 3, "refused: {refused:#?}");
}

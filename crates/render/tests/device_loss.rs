//! A lost device (here destroyed mid-run) neither panics nor hangs: frames after it render
//! nothing, reads give zeros, and the renderer says it was lost so that commands refuse to
//! write what they read (the CLI exits 1 with one line).

mod common;

use nearfield_render::{Aov, RenderError, RenderSettings, Renderer, TechniqueParams};

#[test]
fn a_lost_device_is_reported_not_a_panic() {
    let Some(ctx) = common::context() else { return };
    let scene = nearfield_scene::builtin::scene("boxes").unwrap();
    let env = nearfield_scene::Environment::constant(glam::Vec3::splat(0.5));
    let mut r = Renderer::new(
        &ctx,
        &scene,
        &env,
        None,
        scene.default_camera(),
        &nearfield_render::technique::Spec::resolve("hbil", &TechniqueParams::default()).unwrap(),
        RenderSettings {
            size: (32, 18),
            ..Default::default()
        },
    )
    .unwrap();
    r.render_frame();
    let before = r.read_aov(Aov::Ao);
    assert!(before.pixels.iter().any(|p| p[0] > 0.0));
    assert!(r.lost().is_none() && r.check_device().is_ok());
    ctx.device.destroy();
    r.render_frame();
    let after = r.read_aov(Aov::Ao);
    assert!(
        after.pixels.iter().all(|p| p[0] == 0.0),
        "reads after a loss are zeros"
    );
    assert!(ctx.lost().is_some(), "the context knows");
    match r.check_device() {
        Err(e @ RenderError::Lost(_)) => {
            let msg = e.to_string();
            assert!(msg.contains("lost") && !msg.contains('\n'), "{msg}");
        }
        other => panic!("expected a lost device, got {other:?}"),
    }
    // Changing the technique on a lost device fails or succeeds, but does not panic.
    let _ = r.set_technique("gtao", &TechniqueParams::default());
}

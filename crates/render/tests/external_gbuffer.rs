//! Techniques on documented inputs: `examples/external_gbuffer.rs` rasterises `boxes` into its own
//! images and runs ssdo, hbil and gtao on them (each with only the outputs it declares); nearfield's `Renderer` renders the same scene and
//! camera through its own G-buffer. Both must give the same mean `ao` over the surface pixels.

mod common;

#[allow(dead_code)]
#[path = "../examples/external_gbuffer.rs"]
mod external;

use nearfield_render::{Aov, RenderSettings, Renderer, TechniqueParams};

/// Largest difference of the mean ao allowed. Measured on lavapipe (llvmpipe 15.0.6, 160×90):
/// 0 for ssdo and hbil, per pixel too — both rasterise the same triangles with the same matrices
/// and ao depends on normal and depth alone. The bounds leave room for an adapter whose two
/// raster pipelines round a view depth differently.
const BOUND: f32 = 1e-4;
/// Largest per-pixel difference allowed.
const PIXEL_BOUND: f32 = 1e-3;

#[test]
fn a_technique_on_an_engines_own_gbuffer_matches_the_renderer() {
    let Some(ctx) = common::context() else { return };
    let scene = nearfield_scene::builtin::scene("boxes").unwrap();
    let env = scene.default_env.load().unwrap();
    for method in external::METHODS {
        let external = external::mean_ao(&ctx, method).unwrap();
        let mut r = Renderer::new(
            &ctx,
            &scene,
            &env,
            None,
            scene.default_camera(),
            &nearfield_render::technique::Spec::resolve(method, &TechniqueParams::default())
                .unwrap(),
            RenderSettings {
                size: external::SIZE,
                ..Default::default()
            },
        )
        .unwrap();
        r.render_frame();
        let ao = r.read_aov(Aov::Ao);
        // Pixel by pixel too, where both see a surface.
        let (img, depth) = external::ao_image(&ctx, method).unwrap();
        let largest = img
            .iter()
            .zip(&depth)
            .zip(&ao.pixels)
            .filter(|((_, d), p)| **d > 0.0 && p[3] > 0.0)
            .map(|((a, _), p)| (a - p[0]).abs())
            .fold(0.0f32, f32::max);
        eprintln!("{method}: largest per-pixel ao difference {largest}");
        assert!(
            largest <= PIXEL_BOUND,
            "{method}: per-pixel difference {largest}"
        );
        let covered: Vec<f32> = ao.surface().map(|p| p[0]).collect();
        let own = covered.iter().sum::<f32>() / covered.len() as f32;
        eprintln!("{method}: mean ao {external:.6} (engine's G-buffer) vs {own:.6} (Renderer)");
        assert!(
            (external - own).abs() <= BOUND,
            "{method}: {external} vs {own}"
        );
    }
}

/// gtao writes ao and the bent normal and nothing else: with only those two images handed in it
/// runs, and its bent normal is a unit vector (rgba16float: within 2e-3) with w = 1 on every
/// surface pixel and 0 on background. A technique whose declared output is left out is refused
/// with a line naming it.
#[test]
fn a_technique_writes_what_it_declares() {
    use nearfield_render::technique::Output;
    let Some(ctx) = common::context() else { return };
    let gtao = external::engine_images(&ctx, "gtao", None).unwrap();
    let bent = gtao.bent_normal.expect("gtao declares the bent normal");
    let mut surface = 0;
    for (b, d) in bent.iter().zip(&gtao.view_depth) {
        if *d > 0.0 {
            surface += 1;
            let len = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
            assert!((len - 1.0).abs() < 2e-3 && b[3] == 1.0, "bent normal {b:?}");
        } else {
            assert_eq!(*b, [0.0; 4], "background");
        }
    }
    assert!(surface > 1000, "{surface} surface pixels");
    for (method, output) in [
        ("hbil", Output::EnvIrradiance),
        ("hbil", Output::IndirectIrradiance),
        ("ssdo", Output::LightIrradiance),
    ] {
        let result = external::engine_images(&ctx, method, Some(output));
        let err = result
            .err()
            .unwrap_or_else(|| panic!("{method} without {output:?} ran"));
        assert!(
            err.contains(&format!("writes {}", output.name())) && !err.contains('\n'),
            "{method}: {err}"
        );
    }
}

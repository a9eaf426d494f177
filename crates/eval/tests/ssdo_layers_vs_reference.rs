//! SSDO Sec. 4–5 measured against the reference (masked as `compare` masks):
//! - screen-space shadow correction (`light_segment=bias`) restores the contact shadows a
//!   512² shadow map loses on `builtin:contact`: the `light-irradiance` RMSE in the band around
//!   the cube falls;
//! - depth peeling only ever frees samples (a sample is occluded with two layers only if it is
//!   with one), so `ao` with `layers=2` is never below `ao` with one layer on `builtin:gap`, and
//!   somewhere above it; with ray marching (`ssdo:steps=16`, `s3ho:steps=16`) the second layer frees the rays
//!   that pass behind the thin posts and the `ao` RMSE falls;
//! - the environment as virtual point lights (`ssdo-vpl`) on `builtin:contact` under
//!   rooitou_park_1k: the screen-space correction of their shadow maps lowers the
//!   `env-irradiance` and `diffuse` RMSE against `reference --radius inf`;
//! - Instant Radiosity on `builtin:closed-box` (no environment): `indirect-irradiance` within a
//!   written bound of the ray-traced one bounce, and lower with the screen-space near-field
//!   bounce than with the clamped VPLs alone;
//! - the layers, the additional cameras and the environment lights render without GPU errors
//!   and give finite AOVs.
//!
//! the book's "Beyond one depth layer" section lists the full numbers and the commands.

mod common;

use nearfield_eval::metrics::{self, Mask, MaskSettings};
use nearfield_reference::{ReferenceAov, ReferenceSettings};
use nearfield_render::passes::shadow::ShadowSettings;
use nearfield_render::{Aov, AovImage, GpuContext, RenderSettings, Renderer, TechniqueParams};
use nearfield_scene::builtin;

fn render(
    ctx: &GpuContext,
    scene_name: &str,
    method: &str,
    radius: f32,
    size: (u32, u32),
    shadow_size: u32,
    aov: Aov,
) -> (AovImage, Vec<f32>) {
    let scene = builtin::scene(scene_name).unwrap();
    let env = scene.default_env.load().unwrap();
    render_in(ctx, &scene, &env, method, radius, size, shadow_size, aov)
}

#[allow(clippy::too_many_arguments)]
fn render_in(
    ctx: &GpuContext,
    scene: &nearfield_scene::Scene,
    env: &nearfield_scene::Environment,
    method: &str,
    radius: f32,
    size: (u32, u32),
    shadow_size: u32,
    aov: Aov,
) -> (AovImage, Vec<f32>) {
    let (name, set) = nearfield_render::technique::split_spec(method);
    let params = TechniqueParams {
        samples: None,
        radius: Some(radius),
        set,
    };
    let mut r = Renderer::new(
        ctx,
        scene,
        env,
        None,
        scene.default_camera(),
        &nearfield_render::technique::Spec::resolve(name, &params).unwrap(),
        RenderSettings {
            size,
            shadows: ShadowSettings {
                size: shadow_size,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap();
    r.render_frame();
    let img = r.read_aov(aov);
    let depth = r.read_aov(Aov::Depth).pixels.iter().map(|p| p[0]).collect();
    (img, depth)
}

#[test]
fn shadow_correction_restores_contact_shadows() {
    let Some(ctx) = common::context() else { return };
    let size = (320, 180);
    let scene = builtin::scene("contact").unwrap();
    let env = scene.default_env.load().unwrap();
    let reference = reference(&scene, &env, ReferenceAov::LightIrradiance, size, 0.1, 64);
    let band_error = |method: &str| {
        let (img, depth) = render(
            &ctx,
            "contact",
            method,
            0.1,
            size,
            512,
            Aov::LightIrradiance,
        );
        // The band around the cube and its contact with the plane.
        masked_rmse(&img, &depth, &reference, size, Some([95, 62, 165, 100]))
    };
    let plain = band_error("ssdo:light_samples=0");
    let corrected = band_error("ssdo:light_segment=bias");
    eprintln!(
        "contact band light-irradiance RMSE: shadow map {plain:.4} → corrected {corrected:.4}"
    );
    // Measured 0.122 → 0.070 (the book); the bound leaves room for driver differences.
    assert!(
        corrected < 0.8 * plain,
        "correction {corrected} not below 0.8 × {plain}"
    );
}

#[test]
fn a_second_layer_only_frees_samples() {
    let Some(ctx) = common::context() else { return };
    let size = (160, 90);
    let (one, _) = render(&ctx, "gap", "ssdo:denoise=off", 0.5, size, 2048, Aov::Ao);
    let (two, _) = render(
        &ctx,
        "gap",
        // At the same single point per direction (two layers march 16 by default).
        "ssdo:denoise=off+layers=2+steps=1",
        0.5,
        size,
        2048,
        Aov::Ao,
    );
    let mut raised = 0;
    for (a, b) in one.pixels.iter().zip(&two.pixels) {
        assert!(
            b[0] >= a[0] - 1e-5,
            "layers=2 ao {} below one layer's {}",
            b[0],
            a[0]
        );
        if b[0] > a[0] + 1e-3 {
            raised += 1;
        }
    }
    assert!(
        raised > 50,
        "only {raised} pixels freed by the second layer"
    );
}

#[test]
fn layers_cameras_and_environment_lights_render() {
    let Some(ctx) = common::context() else { return };
    for method in [
        "ssdo:layers=4+cameras=4",
        "ssao:layers=2+cameras=1",
        "s3ho:layers=2+cameras=2",
        "ssdo-vpl:vpls=16+vpl_map=256+layers=2",
    ] {
        let (img, _) = render(&ctx, "columns", method, 0.5, (96, 54), 1024, Aov::Diffuse);
        let lit = img.pixels.iter().filter(|p| p[3] > 0.0).count();
        assert!(lit > 1000, "{method}: {lit} surface pixels");
        assert!(
            img.pixels.iter().all(|p| p.iter().all(|c| c.is_finite())),
            "{method}: non-finite diffuse"
        );
    }
}

/// The reference's `aov` from the scene's camera (seed 1).
fn reference(
    scene: &nearfield_scene::Scene,
    env: &nearfield_scene::Environment,
    aov: ReferenceAov,
    size: (u32, u32),
    radius: f32,
    spp: u32,
) -> nearfield_reference::ReferenceImage {
    let settings = ReferenceSettings {
        aov,
        size,
        radius,
        spp,
        seed: 1,
        max_depth: 1,
        senders: nearfield_reference::Senders::Physical,
    };
    nearfield_reference::render(scene, env, &scene.default_camera(), &settings, false)
}

/// RMSE of `img` against `reference` under compare's mask, optionally restricted to a region.
fn masked_rmse(
    img: &AovImage,
    depth: &[f32],
    reference: &nearfield_reference::ReferenceImage,
    size: (u32, u32),
    region: Option<[u32; 4]>,
) -> f64 {
    let alpha: Vec<f32> = img.pixels.iter().map(|p| p[3]).collect();
    let ref_alpha: Vec<f32> = reference.value.iter().map(|p| p[3]).collect();
    let mut mask = Mask::new(
        size,
        &alpha,
        depth,
        &ref_alpha,
        &reference.depth,
        MaskSettings {
            border: 3,
            depth_tolerance: 0.01,
        },
    );
    if let Some(r) = region {
        mask.restrict(r);
    }
    metrics::metrics(&img.pixels, &reference.value, &mask).rmse
}

#[test]
fn a_second_layer_lets_marched_rays_pass_behind_thin_posts() {
    let Some(ctx) = common::context() else { return };
    let size = (160, 90);
    let scene = builtin::scene("gap").unwrap();
    let env = scene.default_env.load().unwrap();
    let reference = reference(&scene, &env, ReferenceAov::Ao, size, 0.5, 64);
    let error = |method: &str| {
        let (img, depth) = render(&ctx, "gap", method, 0.5, size, 2048, Aov::Ao);
        masked_rmse(&img, &depth, &reference, size, None)
    };
    // ssdo and s3ho share the blocker test and the marching; both must gain. Measured at
    // 320×180 (the book): whole image 0.119 → 0.051 (ssdo), 0.118 → 0.050 (s3ho).
    for technique in ["ssdo", "s3ho"] {
        let one = error(&format!("{technique}:steps=16"));
        let two = error(&format!("{technique}:steps=16+layers=2"));
        eprintln!("gap ao RMSE, {technique} steps=16: 1 layer {one:.4} → 2 layers {two:.4}");
        assert!(
            two < 0.7 * one,
            "{technique}: 2 layers {two} not below 0.7 × {one}"
        );
    }
}

#[test]
fn environment_lights_with_correction_beat_their_shadow_maps_alone() {
    let Some(ctx) = common::context() else { return };
    let Some(hdr) = nearfield_eval::shared_asset("env/rooitou_park_1k.hdr") else {
        return;
    };
    let size = (320, 180);
    let scene = builtin::scene("contact").unwrap();
    let env = nearfield_scene::EnvSource::File(hdr).load().unwrap();
    let mut errors = Vec::new();
    for (aov, reference_aov) in [
        (Aov::EnvIrradiance, ReferenceAov::EnvIrradiance),
        (Aov::Diffuse, ReferenceAov::Diffuse),
    ] {
        let reference = reference(&scene, &env, reference_aov, size, f32::INFINITY, 64);
        let error = |method: &str| {
            let (img, depth) = render_in(&ctx, &scene, &env, method, 0.5, size, 2048, aov);
            masked_rmse(&img, &depth, &reference, size, None)
        };
        // Two layers: with one, the correction also finds the space behind the thin rod solid.
        let alone = error("ssdo-vpl:layers=2+light_samples=0");
        let corrected = error("ssdo-vpl:layers=2");
        eprintln!(
            "contact under rooitou, {aov:?} RMSE: VPL shadow maps {alone:.4} → + correction {corrected:.4}"
        );
        errors.push((alone, corrected));
    }
    // Measured (the book): env-irradiance 0.0474 → 0.0385, diffuse 0.0586 → 0.0578. The diffuse
    // gain is small because the screen-space bounce's error dominates it; it must still be a gain.
    let (env_alone, env_corrected) = errors[0];
    assert!(
        env_corrected < 0.9 * env_alone,
        "env-irradiance: correction {env_corrected} not below 0.9 × {env_alone}"
    );
    let (diffuse_alone, diffuse_corrected) = errors[1];
    assert!(
        diffuse_corrected < diffuse_alone,
        "diffuse: correction {diffuse_corrected} not below {diffuse_alone}"
    );
}

#[test]
fn instant_radiosity_matches_one_bounce_and_the_near_field_helps() {
    let Some(ctx) = common::context() else { return };
    let size = (160, 90);
    let scene = builtin::scene("closed-box").unwrap();
    let env = nearfield_scene::Environment::constant(glam::Vec3::ZERO);
    let reference = reference(
        &scene,
        &env,
        ReferenceAov::IndirectIrradiance,
        size,
        f32::INFINITY,
        256,
    );
    let error = |method: &str, region| {
        let (img, depth) = render_in(
            &ctx,
            &scene,
            &env,
            method,
            0.5,
            size,
            1024,
            Aov::IndirectIrradiance,
        );
        assert!(img.pixels.iter().all(|p| p.iter().all(|c| c.is_finite())));
        masked_rmse(&img, &depth, &reference, size, region)
    };
    // The band where the back wall, the floor and the block meet.
    let region = Some([20, 40, 100, 70]);
    let clamped = error("instant-radiosity:vpls=256+bounce=off", region);
    let near = error("instant-radiosity:vpls=256", region);
    let whole = error("instant-radiosity:vpls=256", None);
    eprintln!(
        "closed-box indirect RMSE: band clamped {clamped:.4} → + near field {near:.4}; whole {whole:.4}"
    );
    // Measured at 320×180: whole image 0.034 (relative error 5.6 %), band 0.044 → 0.041.
    assert!(whole < 0.06, "whole-image RMSE {whole}");
    assert!(
        near < clamped,
        "near field {near} not below clamped {clamped}"
    );
}

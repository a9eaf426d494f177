//! Direct lighting (compute): light irradiance with shadows, specular, and the direct radiance
//! that near-field techniques gather (kept for the next frame). See direct_lighting.wgsl.

use super::shadow::ShadowPass;
use super::{ComputeStep, FrameGroup, PingPong, ScreenPass};
use crate::bindings::{PassLayout, kind};
use crate::gpu_scene::GpuScene;
use crate::targets::{FrameTargets, HDR_FORMAT};
use crate::util;

pub const SHADER: &str = include_str!("direct_lighting.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        util::LIGHTS_WGSL,
        SHADER,
    ])
}

crate::bind_group! {
    /// Group 1 of the direct-lighting pass.
    pub struct DirectLightingBindings: COMPUTE {
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// Base colour ρ (rgba8unorm).
        gb_albedo: view = kind::TEXTURE,
        /// F0 / metallic / roughness (rgba8unorm).
        gb_material: view = kind::TEXTURE,
        /// Emitted radiance (rgba16float).
        gb_emissive: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// The scene's lights (lights.wgsl `GpuLight`).
        lights: buffer = kind::STORAGE_READ,
        /// clip_from_world of every shadow-map layer.
        shadow_clip_from_world: buffer = kind::STORAGE_READ,
        /// The shadow maps.
        shadow_maps: view = kind::TEXTURE_DEPTH_ARRAY,
        /// Their comparison sampler.
        shadow_sampler: sampler = kind::SAMPLER_COMPARISON,
        /// (1/π) Σ E_l with shadows (rgba16float).
        out_light_irradiance: view = kind::write(HDR_FORMAT),
        /// Specular radiance (rgba16float).
        out_specular: view = kind::write(HDR_FORMAT),
        /// This frame's direct radiance (rgba16float), one side of the ping-pong pair.
        out_direct_radiance: view = kind::write(HDR_FORMAT),
        /// The far field's E(n)/π, unoccluded (rgba16float): what the senders are lit with, left
        /// in the techniques' `env-irradiance` output on entry (`none` passes it on).
        out_env_irradiance: view = kind::write(HDR_FORMAT),
        /// The shadow maps as unfilterable floats, for the disc search's loads (GL cannot load
        /// from a depth texture).
        shadow_depths: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        /// The far field at the point (rgba16float): rgb its E(n)/π, a its own visibility within
        /// R (far.wgsl's far_ao_at; 1 for the sky).
        out_far_field: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "direct_lighting",
        source: source(),
        entry_point: "main",
        group1: DirectLightingBindings::SLOTS,
    }
}

pub fn new(
    device: &wgpu::Device,
    frame: &FrameGroup,
    targets: &FrameTargets,
    scene: &GpuScene,
    shadows: &ShadowPass,
) -> ScreenPass {
    let layout = DirectLightingBindings::layout(device);
    let module = crate::pipeline_cache::shader_module(device, "direct lighting", &source());
    let l = shadows.light_resources(&scene.lights);
    let own = PingPong::from_fn(|side| {
        DirectLightingBindings {
            gb_normal: &targets.normal.view,
            gb_albedo: &targets.albedo.view,
            gb_material: &targets.material.view,
            gb_emissive: &targets.emissive.view,
            gb_view_depth: &targets.view_depth.view,
            lights: l.lights,
            shadow_clip_from_world: l.shadow_clip_from_world,
            shadow_maps: l.shadow_maps,
            shadow_sampler: l.shadow_sampler,
            shadow_depths: l.shadow_depths,
            out_light_irradiance: &targets.light_irradiance.view,
            out_specular: &targets.specular.view,
            out_direct_radiance: &targets.direct_radiance[side].view,
            out_env_irradiance: &targets.env_irradiance.view,
            out_far_field: &targets.far_field.view,
        }
        .bind_group(device, &layout)
    });
    ScreenPass {
        step: ComputeStep::new(
            device,
            "direct",
            &module,
            "main",
            frame,
            &layout,
            &[
                constants(&scene.scene_lights),
                vec![frame.far_field_constant()],
            ]
            .concat(),
        ),
        own,
    }
}

/// The pipeline's `override` constants for a light table: whether there are lights and which
/// shadow filters they need (the kernel then holds only the code its scene runs;
/// direct_lighting.wgsl). `new` adds far.wgsl's `FAR_FIELD`.
pub fn constants(lights: &[nearfield_scene::Light]) -> Vec<(&'static str, f64)> {
    let mut c = vec![("LIGHTS", f64::from(u8::from(!lights.is_empty())))];
    c.extend(crate::contract::lights::shadow_filter_constants(lights));
    c
}

#[cfg(test)]
mod tests {
    use super::constants;
    use glam::Vec3;
    use nearfield_scene::{Light, LightKind};

    fn light(kind: LightKind) -> Light {
        Light {
            kind,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        }
    }

    fn flags(lights: &[Light]) -> Vec<(&'static str, bool)> {
        constants(lights)
            .into_iter()
            .map(|(k, v)| (k, v != 0.0))
            .collect()
    }

    #[test]
    fn the_kernel_keeps_only_what_its_lights_use() {
        let sun = light(LightKind::Directional {
            direction: -Vec3::Y,
            angular_radius: 0.00465,
        });
        let parallel = light(LightKind::Directional {
            direction: -Vec3::Y,
            angular_radius: 0.0,
        });
        let point = light(LightKind::Point { position: Vec3::Y });
        // (LIGHTS, DISC_SHADOWS, PUNCTUAL_SHADOWS)
        let expect = |l, d, p| vec![("LIGHTS", l), ("DISC_SHADOWS", d), ("PUNCTUAL_SHADOWS", p)];
        assert_eq!(flags(&[]), expect(false, false, false));
        assert_eq!(flags(&[sun]), expect(true, true, false));
        // A directional light without a disc takes the 3×3 PCF.
        assert_eq!(flags(&[parallel]), expect(true, false, true));
        assert_eq!(flags(&[point, sun]), expect(true, true, true));
    }
}

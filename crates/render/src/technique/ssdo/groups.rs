//! The bind groups of ssdo's direct and bounce passes, from the handles they read and write.

use super::{bounce, direct, resolve};

/// What the direct and bounce passes share: the parameters, the sample sets, the G-buffer and the
/// extra depth layers.
pub(super) struct Shared<'a> {
    pub params: &'a wgpu::Buffer,
    pub sample_sets: &'a wgpu::Buffer,
    pub i: &'a crate::contract::io::NearFieldInputs<'a>,
    pub layer: crate::passes::layers::LayerResources<'a>,
}

/// The direct pass's layout and group: its blocker test over the layers, the light table it shades with,
/// and its outputs (the two visibility images and light-irradiance).
pub(super) fn direct_group(
    device: &wgpu::Device,
    s: &Shared,
    lights: crate::contract::lights::LightResources,
    [out_a, out_b, out_light_irradiance]: [&wgpu::TextureView; 3],
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let layout = direct::DirectBindings::layout(device);
    let group = direct::DirectBindings {
        params: s.params,
        sample_sets: s.sample_sets,
        gb_normal: s.i.normal,
        gb_view_depth: s.i.view_depth,
        layer_views: s.layer.layer_views,
        peel_normal: s.layer.peel_normal,
        peel_depth: s.layer.peel_depth,
        cam_normal: s.layer.cam_normal,
        cam_depth: s.layer.cam_depth,
        lights: lights.lights,
        shadow_clip_from_world: lights.shadow_clip_from_world,
        shadow_maps: lights.shadow_maps,
        shadow_sampler: lights.shadow_sampler,
        shadow_depths: lights.shadow_depths,
        out_a,
        out_b,
        out_light_irradiance,
    }
    .bind_group(device, &layout);
    (layout, group)
}

/// The bounce pass's layout and group: the senders over the layers with their radiance, the light table
/// that lights them, the receiver's env- and light-irradiance, and the indirect light out.
pub(super) fn bounce_group(
    device: &wgpu::Device,
    s: &Shared,
    lights: crate::contract::lights::LightResources,
    [env_irradiance, light_irradiance, out_indirect]: [&wgpu::TextureView; 3],
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let layout = bounce::BounceBindings::layout(device);
    let group = bounce::BounceBindings {
        params: s.params,
        sample_sets: s.sample_sets,
        gb_normal: s.i.normal,
        gb_view_depth: s.i.view_depth,
        layer_views: s.layer.layer_views,
        peel_normal: s.layer.peel_normal,
        peel_depth: s.layer.peel_depth,
        cam_normal: s.layer.cam_normal,
        cam_depth: s.layer.cam_depth,
        peel_radiance: s.layer.peel_radiance,
        cam_radiance: s.layer.cam_radiance,
        lights: lights.lights,
        shadow_clip_from_world: lights.shadow_clip_from_world,
        shadow_maps: lights.shadow_maps,
        shadow_sampler: lights.shadow_sampler,
        shadow_depths: lights.shadow_depths,
        gb_albedo: s.i.albedo,
        gb_emissive: s.i.emission,
        env_irradiance,
        light_irradiance,
        out_indirect,
    }
    .bind_group(device, &layout);
    (layout, group)
}

/// The resolve pass's layout and group: the blurred visibility images in, env-irradiance and ao out.
pub(super) fn resolve_group(
    device: &wgpu::Device,
    s: &Shared,
    [in_a, in_b]: [&wgpu::TextureView; 2],
    [out_env_irradiance, out_ao]: [&wgpu::TextureView; 2],
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let layout = resolve::ResolveBindings::layout(device);
    let group = resolve::ResolveBindings {
        params: s.params,
        gb_normal: s.i.normal,
        gb_view_depth: s.i.view_depth,
        in_a,
        in_b,
        out_env_irradiance,
        out_ao,
    }
    .bind_group(device, &layout);
    (layout, group)
}

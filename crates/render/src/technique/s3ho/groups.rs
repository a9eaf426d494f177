//! The bind groups of s3ho's sample, filter and shade passes, from the handles they read and
//! write; each with its layout.

use super::{filter, sample, shade};
use crate::contract::io::NearFieldInputs;
use crate::contract::lights::LightResources;
use crate::passes::layers::LayerResources;

/// What the sample and shade passes share: the parameters, the sample sets, the G-buffer, the
/// extra depth layers and the light table.
pub(super) struct Shared<'a> {
    pub params: &'a wgpu::Buffer,
    pub sample_sets: &'a wgpu::Buffer,
    pub i: &'a NearFieldInputs<'a>,
    pub layer: LayerResources<'a>,
    pub lights: LightResources<'a>,
}

/// The sample pass: the blocker test over the layers, the senders' radiance, and its outputs
/// (the two coefficient images, the bent cone, the raw ao and the indirect light).
pub(super) fn sample_group(
    device: &wgpu::Device,
    s: &Shared,
    [out_coeffs0, out_coeffs1, out_bent, out_ao_raw, out_indirect]: [&wgpu::TextureView; 5],
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let layout = sample::SampleBindings::layout(device);
    let (layer, l) = (&s.layer, &s.lights);
    let group = sample::SampleBindings {
        params: s.params,
        sample_sets: s.sample_sets,
        gb_normal: s.i.normal,
        gb_view_depth: s.i.view_depth,
        gb_albedo: s.i.albedo,
        layer_views: layer.layer_views,
        peel_normal: layer.peel_normal,
        peel_depth: layer.peel_depth,
        cam_normal: layer.cam_normal,
        cam_depth: layer.cam_depth,
        peel_radiance: layer.peel_radiance,
        cam_radiance: layer.cam_radiance,
        lights: l.lights,
        shadow_clip_from_world: l.shadow_clip_from_world,
        shadow_maps: l.shadow_maps,
        shadow_sampler: l.shadow_sampler,
        shadow_depths: l.shadow_depths,
        out_coeffs0,
        out_coeffs1,
        out_bent,
        out_ao_raw,
        out_indirect,
    }
    .bind_group(device, &layout);
    (layout, group)
}

/// The coefficients' bilateral filter: raw in, filtered out.
pub(super) fn filter_group(
    device: &wgpu::Device,
    i: &NearFieldInputs,
    [in_coeffs0, in_coeffs1, out_coeffs0, out_coeffs1]: [&wgpu::TextureView; 4],
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let layout = filter::FilterBindings::layout(device);
    let group = filter::FilterBindings {
        gb_normal: i.normal,
        gb_view_depth: i.view_depth,
        in_coeffs0,
        in_coeffs1,
        out_coeffs0,
        out_coeffs1,
    }
    .bind_group(device, &layout);
    (layout, group)
}

/// The shade pass: the coefficients, bent cone and ao in; env- and light-irradiance and ao out.
pub(super) fn shade_group(
    device: &wgpu::Device,
    s: &Shared,
    [in_coeffs0, in_coeffs1, in_bent, in_ao_raw]: [&wgpu::TextureView; 4],
    [out_env_irradiance, out_light_irradiance, out_ao]: [&wgpu::TextureView; 3],
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let layout = shade::ShadeBindings::layout(device);
    let l = &s.lights;
    let group = shade::ShadeBindings {
        params: s.params,
        gb_normal: s.i.normal,
        gb_view_depth: s.i.view_depth,
        lights: l.lights,
        shadow_clip_from_world: l.shadow_clip_from_world,
        shadow_maps: l.shadow_maps,
        shadow_sampler: l.shadow_sampler,
        shadow_depths: l.shadow_depths,
        in_coeffs0,
        in_coeffs1,
        in_bent,
        in_ao_raw,
        out_env_irradiance,
        out_light_irradiance,
        out_ao,
    }
    .bind_group(device, &layout);
    (layout, group)
}

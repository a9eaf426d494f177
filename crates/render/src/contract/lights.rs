//! The light bindings a pass that includes shaders/lights.wgsl declares: the scene's light table
//! and shadow maps, or stand-ins for an engine without nearfield's lights.

use crate::contract::formats::DEPTH_FORMAT;
use bytemuck::Zeroable;
use glam::Mat4;
use wgpu::util::DeviceExt;

/// What a pass that includes shaders/lights.wgsl binds, under these names, in its group 1.
#[derive(Clone, Copy)]
pub struct LightResources<'a> {
    /// `array<GpuLight>`: the light table.
    pub lights: &'a wgpu::Buffer,
    /// `array<mat4x4<f32>>`: clip_from_world of every shadow-map layer.
    pub shadow_clip_from_world: &'a wgpu::Buffer,
    /// The shadow maps (depth32float array).
    pub shadow_maps: &'a wgpu::TextureView,
    /// The comparison sampler of the shadow maps.
    pub shadow_sampler: &'a wgpu::Sampler,
    /// The same maps bound as unfilterable floats (`texture_2d_array<f32>`), which
    /// `textureLoad` reads on every backend (GL cannot load from a depth texture); the same view
    /// as `shadow_maps` serves.
    pub shadow_depths: &'a wgpu::TextureView,
}

/// lights.wgsl's `override` constants for a light table: which shadow filters its lights need
/// (`DISC_SHADOWS`: a directional light with a disc, `PUNCTUAL_SHADOWS`: any other light). A
/// pipeline made with them leaves out the filter no light uses; one made without keeps both.
pub fn shadow_filter_constants(lights: &[nearfield_scene::Light]) -> [(&'static str, f64); 2] {
    let disc = |l: &nearfield_scene::Light| matches!(l.kind, nearfield_scene::LightKind::Directional { angular_radius, .. } if angular_radius > 0.0);
    let flag = |b: bool| f64::from(u8::from(b));
    [
        ("DISC_SHADOWS", flag(lights.iter().any(disc))),
        ("PUNCTUAL_SHADOWS", flag(lights.iter().any(|l| !disc(l)))),
    ]
}

/// The light bindings of a frame without nearfield's lights (an engine that hands in only its
/// images): a table of one switched-off light, one identity matrix, a 1×1 shadow map. The frame's
/// light count is then 0.
pub struct NoLights {
    table: wgpu::Buffer,
    matrices: wgpu::Buffer,
    map: wgpu::TextureView,
    sampler: wgpu::Sampler,
}

impl NoLights {
    pub fn new(device: &wgpu::Device) -> Self {
        let buffer = |label, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let map = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("no shadow map"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        NoLights {
            table: buffer(
                "no lights",
                bytemuck::bytes_of(&crate::gpu_scene::GpuLight::zeroed()),
            ),
            matrices: buffer(
                "no shadow matrices",
                bytemuck::bytes_of(&Mat4::IDENTITY.to_cols_array_2d()),
            ),
            map: map.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            }),
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            }),
        }
    }

    pub fn resources(&self) -> LightResources<'_> {
        LightResources {
            lights: &self.table,
            shadow_clip_from_world: &self.matrices,
            shadow_maps: &self.map,
            shadow_sampler: &self.sampler,
            shadow_depths: &self.map,
        }
    }
}

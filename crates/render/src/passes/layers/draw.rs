//! What draws and shades the extra layers: the raster pipeline of [`super::peel`] with one bind
//! group per layer, and the shading pass of [`super::shade`] with one bind group per set.

use super::peel::{PeelBindings, peel_source};
use super::shade::{ShadeBindings, ShadeParams, source};
use super::{CAMERA_VIEW_BASE, LayerImages, VIEW_STRIDE, array_view};
use crate::contract::lights::LightResources;
use crate::gpu_scene::GpuScene;
use crate::passes::{ComputeStep, FrameGroup};
use crate::targets;
use crate::util;
use wgpu::util::DeviceExt;

/// The raster and shading passes of the extra layers.
pub(super) struct LayerDrawing {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
    pub raster: wgpu::RenderPipeline,
    /// Per peeled layer (reading the depth of the layer before), then one for the cameras.
    pub raster_groups: Vec<wgpu::BindGroup>,
    pub shade: ComputeStep,
    pub shade_groups: [wgpu::BindGroup; 2],
}

impl LayerDrawing {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        device: &wgpu::Device,
        frame: &FrameGroup,
        scene: &GpuScene,
        l: LightResources,
        (peel, cams): (&LayerImages, &LayerImages),
        views: &wgpu::Buffer,
        gbuffer_depth: &wgpu::TextureView,
        peel_depth: &[wgpu::TextureView; 2],
    ) -> Self {
        // Raster: vs_layer / fs_layer of peel.wgsl, no culling.
        let raster_layout = PeelBindings::layout(device);
        let m = scene.material_bindings();
        let raster_group = |prev: &wgpu::TextureView| {
            PeelBindings {
                materials: m.materials,
                srgb_textures: m.srgb_textures,
                linear_textures: m.linear_textures,
                material_sampler: m.material_sampler,
                layer_view: wgpu::BufferBinding {
                    buffer: views,
                    offset: 0,
                    size: wgpu::BufferSize::new(VIEW_STRIDE),
                },
                prev_depth: prev,
            }
            .bind_group(device, &raster_layout)
        };
        // Layer 2 reads the G-buffer's depth, layer 3 depth a, layer 4 depth b; cameras read
        // nothing (any depth view will do).
        let raster_groups = vec![
            raster_group(gbuffer_depth),
            raster_group(&peel_depth[0]),
            raster_group(&peel_depth[1]),
            raster_group(gbuffer_depth),
        ];
        let module = crate::pipeline_cache::shader_module(device, "layers raster", &peel_source());
        let raster = util::raster_pipeline(
            device,
            &util::RasterPipeline {
                label: "layers raster",
                frame: None,
                layout: &raster_layout,
                module: &module,
                vertex: "vs_layer",
                fragment: "fs_layer",
                color_formats: &[
                    targets::NORMAL_FORMAT,
                    targets::ALBEDO_FORMAT,
                    targets::EMISSIVE_FORMAT,
                    targets::VIEW_DEPTH_FORMAT,
                ],
                cull: None,
                depth_bias: Default::default(),
                vertex_buffers: &[Some(crate::gpu_scene::Vertex::LAYOUT)],
            },
        );

        // Shading: direct radiance of every layer texel.
        let shade_layout = ShadeBindings::layout(device);
        let shade_group = |images: &LayerImages, first_view: u32| {
            let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("layers shade params"),
                contents: bytemuck::bytes_of(&ShadeParams {
                    first_view,
                    count: images.count,
                    _pad0: 0,
                    _pad1: 0,
                }),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let normal = array_view(&images.normal);
            let albedo = array_view(&images.albedo);
            let emissive = array_view(&images.emissive);
            let depth = array_view(&images.depth);
            let radiance = array_view(&images.radiance);
            ShadeBindings {
                shade_params: &params,
                layer_views: views,
                layer_normal: &normal,
                layer_albedo: &albedo,
                layer_emissive: &emissive,
                layer_depth: &depth,
                layer_radiance: &radiance,
                lights: l.lights,
                shadow_clip_from_world: l.shadow_clip_from_world,
                shadow_maps: l.shadow_maps,
                shadow_sampler: l.shadow_sampler,
                shadow_depths: l.shadow_depths,
            }
            .bind_group(device, &shade_layout)
        };
        let shade_groups = [shade_group(peel, 0), shade_group(cams, CAMERA_VIEW_BASE)];
        let shade_module = crate::pipeline_cache::shader_module(device, "layers shade", &source());
        let shade = ComputeStep::new(
            device,
            "layer shading",
            &shade_module,
            "shade",
            frame,
            &shade_layout,
            &[frame.far_field_constant()],
        );
        LayerDrawing {
            vertices: scene.vertices.clone(),
            indices: scene.indices.clone(),
            index_count: scene.index_count,
            raster,
            raster_groups,
            shade,
            shade_groups,
        }
    }
}

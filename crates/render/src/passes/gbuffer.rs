//! The G-buffer pass (raster): see gbuffer.wgsl for every target's meaning and
//! `crate::targets` for the formats. Single-sided geometry is drawn with back-face culling,
//! double-sided geometry without (its back faces get flipped normals).

use super::FrameGroup;
use crate::bindings::{PassLayout, kind};
use crate::gpu_scene::GpuScene;
use crate::profiler::GpuProfiler;
use crate::targets::{self, FrameTargets};
use crate::util;

pub const SHADER: &str = include_str!("gbuffer.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::GPU_MATERIAL_WGSL,
        util::MATERIALS_WGSL,
        SHADER,
    ])
}

crate::bind_group! {
    /// Group 1 of the G-buffer pass: the scene's materials (shaders/materials.wgsl).
    pub struct GBufferBindings: VERTEX | FRAGMENT {
        /// `array<GpuMaterial>` (gpu_scene.rs).
        materials: buffer = kind::STORAGE_READ,
        /// Base-colour and emissive textures (rgba8unorm-srgb array).
        srgb_textures: view = kind::TEXTURE_ARRAY,
        /// Metallic-roughness textures (rgba8unorm array).
        linear_textures: view = kind::TEXTURE_ARRAY,
        /// Repeating, trilinear.
        material_sampler: sampler = kind::SAMPLER,
    }
}

/// The binding declarations the reflection test checks (vertex and fragment stage).
pub fn pass_layouts() -> Vec<PassLayout> {
    PassLayout::entries(
        "gbuffer",
        source(),
        &["vs_main", "fs_main"],
        GBufferBindings::SLOTS,
    )
}

impl GpuScene {
    /// The material bindings of a raster pass (shaders/materials.wgsl), as the G-buffer binds
    /// them.
    pub fn material_bindings(&self) -> GBufferBindings<'_> {
        GBufferBindings {
            materials: &self.materials,
            srgb_textures: &self.srgb_textures,
            linear_textures: &self.linear_textures,
            material_sampler: &self.material_sampler,
        }
    }
}

pub struct GBufferPass {
    culled: wgpu::RenderPipeline,
    double_sided: wgpu::RenderPipeline,
    frame: wgpu::BindGroup,
    bind_group: wgpu::BindGroup,
}

impl GBufferPass {
    pub fn new(device: &wgpu::Device, frame: &FrameGroup, scene: &GpuScene) -> Self {
        let layout = GBufferBindings::layout(device);
        let bind_group = scene.material_bindings().bind_group(device, &layout);
        let module = crate::pipeline_cache::shader_module(device, "gbuffer", &source());
        let pipeline = |cull: Option<wgpu::Face>| {
            util::raster_pipeline(
                device,
                &util::RasterPipeline {
                    label: "gbuffer",
                    frame: Some(&frame.layout),
                    layout: &layout,
                    module: &module,
                    vertex: "vs_main",
                    fragment: "fs_main",
                    color_formats: &[
                        targets::NORMAL_FORMAT,
                        targets::ALBEDO_FORMAT,
                        targets::MATERIAL_FORMAT,
                        targets::EMISSIVE_FORMAT,
                        targets::MOTION_FORMAT,
                        targets::VIEW_DEPTH_FORMAT,
                    ],
                    cull,
                    depth_bias: Default::default(),
                    vertex_buffers: &[
                        Some(crate::gpu_scene::Vertex::LAYOUT),
                        Some(crate::gpu_scene::Vertex::PREVIOUS),
                    ],
                },
            )
        };
        GBufferPass {
            culled: pipeline(Some(wgpu::Face::Back)),
            double_sided: pipeline(None),
            frame: frame.bind_group.clone(),
            bind_group,
        }
    }

    /// Uses `frame` as group 0 from now on (the renderer's, after an environment change).
    pub fn set_frame(&mut self, frame: &FrameGroup) {
        self.frame = frame.bind_group.clone();
    }

    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        targets: &FrameTargets,
        scene: &GpuScene,
    ) {
        let clear = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let attachments = [
            clear(&targets.normal.view),
            clear(&targets.albedo.view),
            clear(&targets.material.view),
            clear(&targets.emissive.view),
            clear(&targets.motion.view),
            clear(&targets.view_depth.view),
        ];
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth.view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: profiler.render("gbuffer"),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.frame, &[]);
        pass.set_bind_group(1, &self.bind_group, &[]);
        pass.set_vertex_buffer(0, scene.vertices.slice(..));
        pass.set_vertex_buffer(1, scene.previous.slice(..));
        pass.set_index_buffer(scene.indices.slice(..), wgpu::IndexFormat::Uint32);
        if scene.single_sided_indices > 0 {
            pass.set_pipeline(&self.culled);
            pass.draw_indexed(0..scene.single_sided_indices, 0, 0..1);
        }
        if scene.index_count > scene.single_sided_indices {
            pass.set_pipeline(&self.double_sided);
            pass.draw_indexed(scene.single_sided_indices..scene.index_count, 0, 0..1);
        }
    }
}

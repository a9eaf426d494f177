//! The G-buffer pass (raster): see gbuffer.wgsl for every target's meaning and
//! `crate::targets` for the formats. Single-sided geometry is drawn with back-face culling,
//! double-sided geometry without (its back faces get flipped normals).

use crate::gpu_scene::GpuScene;
use crate::profiler::GpuProfiler;
use crate::targets::{self, FrameTargets};
use crate::util;

pub const SHADER: &str = include_str!("gbuffer.wgsl");

pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, SHADER])
}

pub struct GBufferPass {
    culled: wgpu::RenderPipeline,
    double_sided: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
}

impl GBufferPass {
    pub fn new(device: &wgpu::Device, frame: &wgpu::Buffer, scene: &GpuScene) -> Self {
        use wgpu::ShaderStages as S;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gbuffer"),
            entries: &[
                util::uniform(0, S::VERTEX | S::FRAGMENT),
                util::storage_buffer(1, S::FRAGMENT),
                util::texture_array(2, S::FRAGMENT),
                util::texture_array(3, S::FRAGMENT),
                util::sampler(4, S::FRAGMENT),
            ],
        });
        let bind_group = util::bind_group(
            device,
            "gbuffer",
            &layout,
            &[
                (0, frame.as_entire_binding()),
                (1, scene.materials.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(&scene.srgb_textures)),
                (
                    3,
                    wgpu::BindingResource::TextureView(&scene.linear_textures),
                ),
                (4, wgpu::BindingResource::Sampler(&scene.material_sampler)),
            ],
        );
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("gbuffer"),
            source: wgpu::ShaderSource::Wgsl(source().into()),
        });
        let pipeline = |cull: Option<wgpu::Face>| {
            util::raster_pipeline(
                device,
                &util::RasterPipeline {
                    label: "gbuffer",
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
                },
            )
        };
        GBufferPass {
            culled: pipeline(Some(wgpu::Face::Back)),
            double_sided: pipeline(None),
            bind_group,
        }
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
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_vertex_buffer(0, scene.vertices.slice(..));
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

//! Last frame's radiance seen from this frame's camera, with its holes filled (reproject.wgsl):
//! scatter with a depth test (or gather through motion vectors), then push/pull. The result is
//! [`Reprojection::output`], a full-resolution rgba16float image (alpha 1 wherever some valid
//! value was found anywhere in the image).

use super::{ComputeStep, FrameGroup, PingPong};
use crate::bindings::{PassLayout, kind};
use crate::contract::io::NearFieldInputs;
use crate::profiler::GpuProfiler;
use crate::targets::HDR_FORMAT;
use crate::util;
use wgpu::util::DeviceExt;

pub const SHADER: &str = include_str!("reproject.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        SHADER,
    ])
}

pub use crate::settings::march::ReprojectMode;

crate::gpu_struct! {
    /// `ReprojectParams` in reproject.wgsl.
    pub struct ReprojectParams {
        /// Largest distance of a reprojected point from the surface seen now, relative to its view
        /// depth.
        pub reject_depth: f32,
        /// Smallest cosine between last frame's and this frame's normal.
        pub reject_normal: f32,
        pub _pad0: f32,
        pub _pad1: f32,
    }
}

/// Last frame's inputs of one ping-pong side: its geometry (rgba32float: world normal, view
/// depth; 0 on background) and its radiance.
pub struct History<'a> {
    pub geometry: &'a wgpu::TextureView,
    pub radiance: &'a wgpu::TextureView,
}

crate::bind_group! {
    /// Group 1 of the reprojection kernels (scatter_depth, scatter_color, scatter_resolve, gather).
    pub struct ReprojectBindings: COMPUTE {
        /// `ReprojectParams`: the same-surface tolerances.
        params: buffer = kind::UNIFORM,
        /// This frame's world normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// This frame's view depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// This frame's motion (rg16float, previous − current pixel position).
        gb_motion: view = kind::TEXTURE,
        /// Last frame's geometry (rgba32float: world normal, view depth).
        prev_geometry: view = kind::TEXTURE_UNFILTERABLE,
        /// Last frame's radiance (rgba16float).
        prev_radiance: view = kind::TEXTURE,
        /// Nearest landing depth per pixel (atomic u32 bits; reset by scatter_resolve).
        zbuffer: buffer = kind::STORAGE_READ_WRITE,
        /// The winner's radiance per pixel.
        colors: buffer = kind::STORAGE_READ_WRITE,
        /// The raw reprojection, alpha 0 in holes (rgba16float, level 0 of the push chain).
        out_reprojected: view = kind::write(HDR_FORMAT),
    }
}

crate::bind_group! {
    /// Group 1 of `push`: level k → level k + 1.
    pub struct PushBindings: COMPUTE {
        /// Level k (rgba16float, alpha = coverage).
        fine: view = kind::TEXTURE,
        /// Level k + 1.
        level_out: view = kind::write(HDR_FORMAT),
    }
}

crate::bind_group! {
    /// Group 1 of `pull`: level k of the push chain and level k + 1 filled → level k filled.
    pub struct PullBindings: COMPUTE {
        /// Level k of the push chain.
        fine: view = kind::TEXTURE,
        /// Level k, filled.
        level_out: view = kind::write(HDR_FORMAT),
        /// Level k + 1, filled (or the coarsest push level).
        coarse: view = kind::TEXTURE,
        /// Bilinear.
        coarse_sampler: sampler = kind::SAMPLER,
    }
}

/// The binding declarations the reflection test checks.
pub fn pass_layouts() -> Vec<PassLayout> {
    let kernels = [
        "scatter_depth",
        "scatter_color",
        "scatter_resolve",
        "gather",
    ];
    let mut v = PassLayout::entries("reproject", source(), &kernels, ReprojectBindings::SLOTS);
    v.extend(PassLayout::entries(
        "push_pull",
        push_pull_source(),
        &["push"],
        PushBindings::SLOTS,
    ));
    v.extend(PassLayout::entries(
        "push_pull",
        push_pull_source(),
        &["pull"],
        PullBindings::SLOTS,
    ));
    v
}

pub fn push_pull_source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        include_str!("push_pull.wgsl"),
    ])
}

pub struct Reprojection {
    mode: ReprojectMode,
    size: (u32, u32),
    scatter_depth: ComputeStep,
    scatter_color: ComputeStep,
    scatter_resolve: ComputeStep,
    gather: ComputeStep,
    push: ComputeStep,
    pull: ComputeStep,
    /// What a frame on each side binds: it reads last frame's side.
    main: PingPong<wgpu::BindGroup>,
    /// Level k → k + 1, with the size of level k + 1.
    push_levels: Vec<(wgpu::BindGroup, (u32, u32))>,
    /// Level k + 1 → k for k from the coarsest down, with the size of level k.
    pull_levels: Vec<(wgpu::BindGroup, (u32, u32))>,
    /// Level 0 of the push chain: the raw reprojection, alpha 0 in holes.
    pub raw: wgpu::Texture,
    /// The filled image (level 0 of the pull chain).
    pub output: wgpu::TextureView,
    pub output_texture: wgpu::Texture,
    /// The params buffer (`write_buffer` target) and the scatter buffers.
    pub params: wgpu::Buffer,
    _keep: (wgpu::Buffer, wgpu::Buffer),
}

fn mip_view(texture: &wgpu::Texture, level: u32) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        base_mip_level: level,
        mip_level_count: Some(1),
        ..Default::default()
    })
}

fn level_size(size: (u32, u32), level: u32) -> (u32, u32) {
    ((size.0 >> level).max(1), (size.1 >> level).max(1))
}

/// The push chain's groups (each level from the finer one, with its size) and the pull chain's
/// (from the coarsest up: each level from its push level and the coarser pull level, the
/// coarsest pull reading the coarsest push level).
#[allow(clippy::type_complexity)]
fn push_pull_groups(
    device: &wgpu::Device,
    (push_layout, pull_layout): (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
    (push_tex, pull_tex): (&wgpu::Texture, &wgpu::Texture),
    sampler: &wgpu::Sampler,
) -> (
    Vec<(wgpu::BindGroup, (u32, u32))>,
    Vec<(wgpu::BindGroup, (u32, u32))>,
) {
    let levels = push_tex.mip_level_count();
    let size = (push_tex.width(), push_tex.height());
    let push_levels = (0..levels - 1)
        .map(|k| {
            let bg = PushBindings {
                fine: &mip_view(push_tex, k),
                level_out: &mip_view(push_tex, k + 1),
            }
            .bind_group(device, push_layout);
            (bg, level_size(size, k + 1))
        })
        .collect();
    let pull_levels = (0..levels - 1)
        .rev()
        .map(|k| {
            let coarse = if k + 1 == levels - 1 {
                mip_view(push_tex, k + 1)
            } else {
                mip_view(pull_tex, k + 1)
            };
            let bg = PullBindings {
                fine: &mip_view(push_tex, k),
                level_out: &mip_view(pull_tex, k),
                coarse: &coarse,
                coarse_sampler: sampler,
            }
            .bind_group(device, pull_layout);
            (bg, level_size(size, k))
        })
        .collect();
    (push_levels, pull_levels)
}

impl Reprojection {
    /// `history[s]` is what frame side `s` wrote; a frame on side `s` reads `history[1 − s]`.
    pub fn new(
        device: &wgpu::Device,
        frame: &FrameGroup,
        inputs: &NearFieldInputs,
        history: [History; 2],
        mode: ReprojectMode,
        params: ReprojectParams,
    ) -> Self {
        let size = inputs.size;
        let levels = 32 - size.0.max(size.1).leading_zeros();
        let chain = |label: &str, count: u32| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: count,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: HDR_FORMAT,
                usage: wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let push_tex = chain("reprojection push", levels);
        // The pull chain has every level but the coarsest (which the push chain holds).
        let pull_tex = chain("reprojection pull", (levels - 1).max(1));
        let pixels = (size.0 * size.1) as usize;
        let zbuffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("reprojection depth"),
            contents: bytemuck::cast_slice(&vec![u32::MAX; pixels]),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let colors = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("reprojection colours"),
            size: 16 * pixels as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let params_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("reprojection params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let main_layout = ReprojectBindings::layout(device);
        let push_layout = PushBindings::layout(device);
        let pull_layout = PullBindings::layout(device);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("pull"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let raw_view = mip_view(&push_tex, 0);
        let main_bg = |h: &History| {
            ReprojectBindings {
                params: &params_buffer,
                gb_normal: inputs.normal,
                gb_view_depth: inputs.view_depth,
                gb_motion: inputs.motion,
                prev_geometry: h.geometry,
                prev_radiance: h.radiance,
                zbuffer: &zbuffer,
                colors: &colors,
                out_reprojected: &raw_view,
            }
            .bind_group(device, &main_layout)
        };
        let main = PingPong::new(main_bg(&history[1]), main_bg(&history[0]));
        let (push_levels, pull_levels) = push_pull_groups(
            device,
            (&push_layout, &pull_layout),
            (&push_tex, &pull_tex),
            &sampler,
        );
        let module = crate::pipeline_cache::shader_module(device, "reproject", &source());
        let push_pull =
            crate::pipeline_cache::shader_module(device, "push/pull", &push_pull_source());
        let step = |module, entry: &'static str, layout| {
            ComputeStep::new(device, entry, module, entry, frame, layout, &[])
        };
        // A 1×1 image has nothing to fill: the raw level is the output.
        let (output_texture, output) = if levels > 1 {
            (pull_tex.clone(), mip_view(&pull_tex, 0))
        } else {
            (push_tex.clone(), mip_view(&push_tex, 0))
        };
        Reprojection {
            mode,
            size,
            scatter_depth: step(&module, "scatter_depth", &main_layout),
            scatter_color: step(&module, "scatter_color", &main_layout),
            scatter_resolve: step(&module, "scatter_resolve", &main_layout),
            gather: step(&module, "gather", &main_layout),
            push: step(&push_pull, "push", &push_layout),
            pull: step(&push_pull, "pull", &pull_layout),
            main,
            push_levels,
            pull_levels,
            raw: push_tex,
            output,
            output_texture,
            params: params_buffer,
            _keep: (zbuffer, colors),
        }
    }

    /// Records reprojection ("reproject") and hole filling ("push/pull") for frame
    /// `frame_index`; allocates nothing.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        frame_index: u32,
    ) {
        let groups = {
            let (gx, gy) = util::groups_8x8(self.size);
            (gx, gy, 1)
        };
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("reproject"),
                timestamp_writes: profiler.compute("reproject"),
            });
            let main = self.main.current(frame_index);
            match self.mode {
                ReprojectMode::Scatter => {
                    for step in [
                        &self.scatter_depth,
                        &self.scatter_color,
                        &self.scatter_resolve,
                    ] {
                        step.dispatch(&mut pass, main, groups);
                    }
                }
                ReprojectMode::Gather => self.gather.dispatch(&mut pass, main, groups),
            }
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("push/pull"),
            timestamp_writes: profiler.compute("push/pull"),
        });
        for (bg, size) in &self.push_levels {
            let (x, y) = util::groups_8x8(*size);
            self.push.dispatch(&mut pass, bg, (x, y, 1));
        }
        for (bg, size) in &self.pull_levels {
            let (x, y) = util::groups_8x8(*size);
            self.pull.dispatch(&mut pass, bg, (x, y, 1));
        }
    }
}

//! Last frame's radiance seen from this frame's camera, with its holes filled (reproject.wgsl):
//! scatter with a depth test (or gather through motion vectors), then push/pull. The result is
//! [`Reprojection::output`], a full-resolution rgba16float image (alpha 1 wherever some valid
//! value was found anywhere in the image).

use crate::profiler::GpuProfiler;
use crate::targets::{FrameTargets, HDR_FORMAT};
use crate::util;
use bytemuck::{Pod, Zeroable};
use wgpu::BindingResource as R;
use wgpu::util::DeviceExt;

pub const SHADER: &str = include_str!("reproject.wgsl");

pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, SHADER])
}

/// How last frame's pixels reach this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReprojectMode {
    /// Forward: last frame's pixels move to their new place (depth-tested, atomics).
    Scatter,
    /// Backward: this frame's pixels fetch through their motion vectors.
    Gather,
}

impl ReprojectMode {
    /// `scatter|gather`.
    pub fn parse(key: &str, v: &str) -> Result<Self, String> {
        match v {
            "scatter" => Ok(ReprojectMode::Scatter),
            "gather" => Ok(ReprojectMode::Gather),
            _ => Err(format!("{key}={v}: expected scatter or gather")),
        }
    }
}

/// `ReprojectParams` in reproject.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ReprojectParams {
    /// Largest distance of a reprojected point from the surface seen now, relative to its view
    /// depth.
    pub reject_depth: f32,
    /// Smallest cosine between last frame's and this frame's normal.
    pub reject_normal: f32,
    pub _pad: [f32; 2],
}

/// Last frame's inputs of one ping-pong side: its geometry (rgba32float: world normal, view
/// depth; 0 on background) and its radiance.
pub struct History<'a> {
    pub geometry: &'a wgpu::TextureView,
    pub radiance: &'a wgpu::TextureView,
}

pub struct Reprojection {
    mode: ReprojectMode,
    size: (u32, u32),
    scatter_depth: wgpu::ComputePipeline,
    scatter_color: wgpu::ComputePipeline,
    scatter_resolve: wgpu::ComputePipeline,
    gather: wgpu::ComputePipeline,
    push: wgpu::ComputePipeline,
    pull: wgpu::ComputePipeline,
    /// Indexed by this frame's side: reads last frame's side.
    main: [wgpu::BindGroup; 2],
    /// Level k → k + 1, with the size of level k + 1.
    push_levels: Vec<(wgpu::BindGroup, (u32, u32))>,
    /// Level k + 1 → k for k from the coarsest down, with the size of level k.
    pull_levels: Vec<(wgpu::BindGroup, (u32, u32))>,
    /// Level 0 of the push chain: the raw reprojection, alpha 0 in holes.
    pub raw: wgpu::Texture,
    /// The filled image (level 0 of the pull chain).
    pub output: wgpu::TextureView,
    pub output_texture: wgpu::Texture,
    _keep: (wgpu::Buffer, wgpu::Buffer, wgpu::Buffer),
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

impl Reprojection {
    /// `history[s]` is what frame side `s` wrote; a frame on side `s` reads `history[1 − s]`.
    pub fn new(
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        targets: &FrameTargets,
        history: [History; 2],
        mode: ReprojectMode,
        params: ReprojectParams,
    ) -> Self {
        let size = targets.size;
        let c = wgpu::ShaderStages::COMPUTE;
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
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let rw_buffer = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: c,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let main_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("reprojection"),
            entries: &[
                util::uniform(0, c),
                util::uniform(5, c),
                util::texture(8, c, true),
                util::texture(9, c, false),
                util::texture(10, c, false),
                util::texture(11, c, true),
                rw_buffer(12),
                rw_buffer(13),
                util::storage_texture(14, HDR_FORMAT),
                util::texture(15, c, true),
            ],
        });
        let push_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("push"),
            entries: &[
                util::uniform(0, c),
                util::texture(16, c, true),
                util::storage_texture(17, HDR_FORMAT),
            ],
        });
        let pull_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("pull"),
            entries: &[
                util::uniform(0, c),
                util::texture(16, c, true),
                util::storage_texture(17, HDR_FORMAT),
                util::texture(18, c, true),
                util::sampler(19, c),
            ],
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("pull"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let raw_view = mip_view(&push_tex, 0);
        let main_bg = |h: &History| {
            util::bind_group(
                device,
                "reprojection",
                &main_layout,
                &[
                    (0, frame.as_entire_binding()),
                    (5, params_buffer.as_entire_binding()),
                    (8, R::TextureView(&targets.normal.view)),
                    (9, R::TextureView(&targets.view_depth.view)),
                    (10, R::TextureView(h.geometry)),
                    (11, R::TextureView(h.radiance)),
                    (12, zbuffer.as_entire_binding()),
                    (13, colors.as_entire_binding()),
                    (14, R::TextureView(&raw_view)),
                    (15, R::TextureView(&targets.motion.view)),
                ],
            )
        };
        let main = [main_bg(&history[1]), main_bg(&history[0])];
        let push_levels = (0..levels - 1)
            .map(|k| {
                let bg = util::bind_group(
                    device,
                    "push",
                    &push_layout,
                    &[
                        (0, frame.as_entire_binding()),
                        (16, R::TextureView(&mip_view(&push_tex, k))),
                        (17, R::TextureView(&mip_view(&push_tex, k + 1))),
                    ],
                );
                (bg, level_size(size, k + 1))
            })
            .collect();
        let pull_levels = (0..levels - 1)
            .rev()
            .map(|k| {
                let coarse = if k + 1 == levels - 1 {
                    mip_view(&push_tex, k + 1)
                } else {
                    mip_view(&pull_tex, k + 1)
                };
                let bg = util::bind_group(
                    device,
                    "pull",
                    &pull_layout,
                    &[
                        (0, frame.as_entire_binding()),
                        (16, R::TextureView(&mip_view(&push_tex, k))),
                        (17, R::TextureView(&mip_view(&pull_tex, k))),
                        (18, R::TextureView(&coarse)),
                        (19, R::Sampler(&sampler)),
                    ],
                );
                (bg, level_size(size, k))
            })
            .collect();
        let src = source();
        let pipeline = |entry: &str, layout: &wgpu::BindGroupLayout| {
            util::compute_pipeline(device, entry, &src, entry, layout)
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
            scatter_depth: pipeline("scatter_depth", &main_layout),
            scatter_color: pipeline("scatter_color", &main_layout),
            scatter_resolve: pipeline("scatter_resolve", &main_layout),
            gather: pipeline("gather", &main_layout),
            push: pipeline("push", &push_layout),
            pull: pipeline("pull", &pull_layout),
            main,
            push_levels,
            pull_levels,
            raw: push_tex,
            output,
            output_texture,
            _keep: (zbuffer, colors, params_buffer),
        }
    }

    /// Records reprojection ("reproject") and hole filling ("push/pull") for a frame on `side`.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        side: usize,
    ) {
        let (gx, gy) = util::groups_8x8(self.size);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("reproject"),
                timestamp_writes: profiler.compute("reproject"),
            });
            pass.set_bind_group(0, &self.main[side], &[]);
            let pipelines = match self.mode {
                ReprojectMode::Scatter => {
                    vec![
                        &self.scatter_depth,
                        &self.scatter_color,
                        &self.scatter_resolve,
                    ]
                }
                ReprojectMode::Gather => vec![&self.gather],
            };
            for p in pipelines {
                pass.set_pipeline(p);
                pass.dispatch_workgroups(gx, gy, 1);
            }
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("push/pull"),
            timestamp_writes: profiler.compute("push/pull"),
        });
        pass.set_pipeline(&self.push);
        for (bg, size) in &self.push_levels {
            pass.set_bind_group(0, bg, &[]);
            let (x, y) = util::groups_8x8(*size);
            pass.dispatch_workgroups(x, y, 1);
        }
        pass.set_pipeline(&self.pull);
        for (bg, size) in &self.pull_levels {
            pass.set_bind_group(0, bg, &[]);
            let (x, y) = util::groups_8x8(*size);
            pass.dispatch_workgroups(x, y, 1);
        }
    }
}

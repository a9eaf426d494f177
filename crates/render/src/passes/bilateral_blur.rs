//! Separable geometry-aware (depth + normal) bilateral blur of rgba16float images. See
//! bilateral_blur.wgsl. A `BilateralBlur` holds the pipeline; each blurred image gets a
//! `BlurChain` (horizontal into a scratch texture, then vertical into the destination), recorded
//! as two dispatches inside the caller's compute pass.

use crate::targets::{FrameTargets, HDR_FORMAT};
use crate::util;
use bytemuck::{Pod, Zeroable};
use wgpu::BindingResource as R;
use wgpu::util::DeviceExt;

pub const SHADER: &str = include_str!("bilateral_blur.wgsl");

pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, SHADER])
}

/// `BlurParams` in bilateral_blur.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct BlurParams {
    pub direction: [i32; 2],
    pub radius: i32,
    pub enabled: u32,
    pub depth_sigma: f32,
    pub normal_power: f32,
    pub _pad: [f32; 2],
}

/// Blur settings.
#[derive(Clone, Copy, Debug)]
pub struct BlurSettings {
    pub enabled: bool,
    /// Half width in pixels, 0..=16.
    pub radius: u32,
    /// Tangent-plane distance (relative to view depth) at which a tap's weight falls by e, > 0.
    pub depth_sigma: f32,
    /// Exponent on the normals' cosine, ≥ 0.
    pub normal_power: f32,
}

pub struct BilateralBlur {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    horizontal: wgpu::Buffer,
    vertical: wgpu::Buffer,
}

/// One image's two dispatches.
pub struct BlurChain {
    horizontal: wgpu::BindGroup,
    vertical: wgpu::BindGroup,
}

impl BilateralBlur {
    pub fn new(device: &wgpu::Device, settings: BlurSettings) -> Self {
        let c = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("bilateral blur"),
            entries: &[
                util::uniform(0, c),
                util::uniform(5, c),
                util::texture(8, c, true),
                util::texture(9, c, false),
                util::texture(10, c, true),
                util::storage_texture(11, HDR_FORMAT),
            ],
        });
        let params = |direction: [i32; 2]| BlurParams {
            direction,
            radius: settings.radius as i32,
            enabled: settings.enabled as u32,
            depth_sigma: settings.depth_sigma,
            normal_power: settings.normal_power,
            _pad: [0.0; 2],
        };
        let buffer = |p: BlurParams| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("blur params"),
                contents: bytemuck::bytes_of(&p),
                usage: wgpu::BufferUsages::UNIFORM,
            })
        };
        BilateralBlur {
            pipeline: util::compute_pipeline(device, "bilateral blur", &source(), "main", &layout),
            horizontal: buffer(params([1, 0])),
            vertical: buffer(params([0, 1])),
            layout,
        }
    }

    /// Binds `source` → `scratch` (horizontal) → `destination` (vertical).
    pub fn chain(
        &self,
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        targets: &FrameTargets,
        source: &wgpu::TextureView,
        scratch: &wgpu::TextureView,
        destination: &wgpu::TextureView,
    ) -> BlurChain {
        let bg = |params: &wgpu::Buffer, from: &wgpu::TextureView, to: &wgpu::TextureView| {
            util::bind_group(
                device,
                "bilateral blur",
                &self.layout,
                &[
                    (0, frame.as_entire_binding()),
                    (5, params.as_entire_binding()),
                    (8, R::TextureView(&targets.normal.view)),
                    (9, R::TextureView(&targets.view_depth.view)),
                    (10, R::TextureView(from)),
                    (11, R::TextureView(to)),
                ],
            )
        };
        BlurChain {
            horizontal: bg(&self.horizontal, source, scratch),
            vertical: bg(&self.vertical, scratch, destination),
        }
    }

    /// Records both dispatches of `chain` into an open compute pass.
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass, chain: &BlurChain, size: (u32, u32)) {
        let (gx, gy) = util::groups_8x8(size);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &chain.horizontal, &[]);
        pass.dispatch_workgroups(gx, gy, 1);
        pass.set_bind_group(0, &chain.vertical, &[]);
        pass.dispatch_workgroups(gx, gy, 1);
    }
}

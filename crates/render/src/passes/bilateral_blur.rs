//! Separable geometry-aware (depth + normal) bilateral blur of rgba16float images. See
//! bilateral_blur.wgsl. A `BilateralBlur` holds the pipeline; each blurred image gets a
//! `BlurChain` (horizontal into a scratch texture, then vertical into the destination), recorded
//! as two dispatches inside the caller's compute pass.

use super::{ComputeStep, FrameGroup};
use crate::bindings::{PassLayout, kind};
use crate::contract::io::NearFieldInputs;
use crate::targets::HDR_FORMAT;
use crate::util;
use wgpu::util::DeviceExt;

pub const SHADER: &str = include_str!("bilateral_blur.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        SHADER,
    ])
}

crate::gpu_struct! {
    /// `BlurParams` in bilateral_blur.wgsl.
    pub struct BlurParams {
        pub direction: [i32; 2],
        pub radius: i32,
        pub enabled: u32,
        pub depth_sigma: f32,
        pub normal_power: f32,
        pub _pad0: f32,
        pub _pad1: f32,
    }
}

crate::bind_group! {
    /// Group 1 of one direction of the blur.
    pub struct BlurBindings: COMPUTE {
        /// [`BlurParams`]: direction, radius and tolerances.
        blur: buffer = kind::UNIFORM,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// The image blurred (rgba16float).
        source: view = kind::TEXTURE,
        /// The blurred image (rgba16float).
        destination: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "bilateral_blur",
        source: source(),
        entry_point: "main",
        group1: BlurBindings::SLOTS,
    }
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

/// The GPU constants of one direction (pure).
pub fn blur_params(settings: BlurSettings, direction: [i32; 2]) -> BlurParams {
    BlurParams {
        direction,
        radius: settings.radius as i32,
        enabled: settings.enabled as u32,
        depth_sigma: settings.depth_sigma,
        normal_power: settings.normal_power,
        _pad0: 0.0,
        _pad1: 0.0,
    }
}

pub struct BilateralBlur {
    step: ComputeStep,
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
    pub fn new(device: &wgpu::Device, frame: &FrameGroup, settings: BlurSettings) -> Self {
        let layout = BlurBindings::layout(device);
        let module = crate::pipeline_cache::shader_module(device, "bilateral blur", &source());
        let params = |direction: [i32; 2]| blur_params(settings, direction);
        let buffer = |p: BlurParams| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("blur params"),
                contents: bytemuck::bytes_of(&p),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            })
        };
        BilateralBlur {
            step: ComputeStep::new(device, "blur", &module, "main", frame, &layout, &[]),
            horizontal: buffer(params([1, 0])),
            vertical: buffer(params([0, 1])),
            layout,
        }
    }

    /// Writes new settings into both directions' parameters (no rebuild).
    pub fn write(&self, queue: &wgpu::Queue, settings: BlurSettings) {
        for (buffer, direction) in [(&self.horizontal, [1, 0]), (&self.vertical, [0, 1])] {
            queue.write_buffer(
                buffer,
                0,
                bytemuck::bytes_of(&blur_params(settings, direction)),
            );
        }
    }

    /// Binds `source` → `scratch` (horizontal) → `destination` (vertical).
    pub fn chain(
        &self,
        device: &wgpu::Device,
        inputs: &NearFieldInputs,
        source: &wgpu::TextureView,
        scratch: &wgpu::TextureView,
        destination: &wgpu::TextureView,
    ) -> BlurChain {
        let bg = |params: &wgpu::Buffer, from: &wgpu::TextureView, to: &wgpu::TextureView| {
            BlurBindings {
                blur: params,
                gb_normal: inputs.normal,
                gb_view_depth: inputs.view_depth,
                source: from,
                destination: to,
            }
            .bind_group(device, &self.layout)
        };
        BlurChain {
            horizontal: bg(&self.horizontal, source, scratch),
            vertical: bg(&self.vertical, scratch, destination),
        }
    }

    /// Records both dispatches of `chain` into an open compute pass.
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass, chain: &BlurChain, size: (u32, u32)) {
        let (gx, gy) = util::groups_8x8(size);
        self.step.dispatch(pass, &chain.horizontal, (gx, gy, 1));
        self.step.dispatch(pass, &chain.vertical, (gx, gy, 1));
    }
}

//! Tonemap (compute): `radiance` × 2^exposure through a named operator, sRGB-encoded into the
//! `final` image. See tonemap.wgsl.

use super::{ComputeStep, FrameGroup, ScreenPass};
use crate::bindings::{PassLayout, kind};
use crate::targets::{FINAL_FORMAT, FrameTargets};
use crate::util;

pub const SHADER: &str = include_str!("tonemap.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::TONEMAP_OPS_WGSL,
        SHADER,
    ])
}

crate::bind_group! {
    /// Group 1 of the tonemap pass.
    pub struct TonemapBindings: COMPUTE {
        /// The linear HDR frame (rgba16float).
        radiance: view = kind::TEXTURE,
        /// The tonemapped, sRGB-encoded image (rgba8unorm): the `final` AOV.
        out_final: view = kind::write(FINAL_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "tonemap",
        source: source(),
        entry_point: "main",
        group1: TonemapBindings::SLOTS,
    }
}

pub fn new(device: &wgpu::Device, frame: &FrameGroup, targets: &FrameTargets) -> ScreenPass {
    let layout = TonemapBindings::layout(device);
    let module = crate::pipeline_cache::shader_module(device, "tonemap", &source());
    let own = TonemapBindings {
        radiance: &targets.radiance.view,
        out_final: &targets.final_ldr.view,
    }
    .bind_group(device, &layout);
    ScreenPass::single(
        ComputeStep::new(device, "tonemap", &module, "main", frame, &layout, &[]),
        own,
    )
}

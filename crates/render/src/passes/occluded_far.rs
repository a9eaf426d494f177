//! The env-irradiance and indirect-irradiance of a technique that writes only ao (gtao):
//! nearfield's frame runs this after such a technique. See occluded_far.wgsl.

use super::{ComputeStep, FrameGroup, ScreenPass};
use crate::bindings::{PassLayout, kind};
use crate::targets::{FrameTargets, HDR_FORMAT};
use crate::util;

pub const SHADER: &str = include_str!("occluded_far.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        SHADER,
    ])
}

crate::bind_group! {
    /// Group 1 of the occluded far field.
    pub struct OccludedFarBindings: COMPUTE {
        /// World normal (rgba16float, xyz unit; a = 0 on background).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// The technique's `ao` (r32float).
        in_ao: view = kind::TEXTURE_UNFILTERABLE,
        /// `env-irradiance` (rgba16float): ao × E_far(n)/π.
        out_env: view = kind::write(HDR_FORMAT),
        /// `indirect-irradiance` (rgba16float): 0.
        out_indirect: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "occluded_far",
        source: source(),
        entry_point: "main",
        group1: OccludedFarBindings::SLOTS,
    }
}

pub fn new(device: &wgpu::Device, frame: &FrameGroup, targets: &FrameTargets) -> ScreenPass {
    let layout = OccludedFarBindings::layout(device);
    let module = crate::pipeline_cache::shader_module(device, "occluded_far", &source());
    let own = OccludedFarBindings {
        gb_normal: &targets.normal.view,
        gb_view_depth: &targets.view_depth.view,
        in_ao: &targets.ao.view,
        out_env: &targets.env_irradiance.view,
        out_indirect: &targets.indirect_irradiance.view,
    }
    .bind_group(device, &layout);
    ScreenPass::single(
        ComputeStep::new(device, "occluded far", &module, "main", frame, &layout, &[]),
        own,
    )
}

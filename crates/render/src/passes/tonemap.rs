//! Tonemap (compute): `radiance` × 2^exposure through a named operator, sRGB-encoded into the
//! `final` image. See tonemap.wgsl.

use super::ScreenPass;
use crate::targets::{FINAL_FORMAT, FrameTargets};
use crate::util;
use wgpu::BindingResource as R;

pub const SHADER: &str = include_str!("tonemap.wgsl");

pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, util::TONEMAP_OPS_WGSL, SHADER])
}

pub fn new(device: &wgpu::Device, frame: &wgpu::Buffer, targets: &FrameTargets) -> ScreenPass {
    let c = wgpu::ShaderStages::COMPUTE;
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("tonemap"),
        entries: &[
            util::uniform(0, c),
            util::texture(8, c, true),
            util::storage_texture(9, FINAL_FORMAT),
        ],
    });
    let r = [
        (0, frame.as_entire_binding()),
        (8, R::TextureView(&targets.radiance.view)),
        (9, R::TextureView(&targets.final_ldr.view)),
    ];
    ScreenPass {
        label: "tonemap",
        pipeline: util::compute_pipeline(device, "tonemap", &source(), "main", &layout),
        bind_groups: vec![util::bind_group(device, "tonemap", &layout, &r)],
    }
}

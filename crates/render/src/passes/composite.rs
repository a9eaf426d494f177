//! Composite (compute): assembles the linear HDR `radiance` from the G-buffer, direct lighting
//! and the near-field technique's outputs. See composite.wgsl.

use super::ScreenPass;
use crate::gpu_env::GpuEnvironment;
use crate::targets::{FrameTargets, HDR_FORMAT};
use crate::util;
use wgpu::BindingResource as R;

pub const SHADER: &str = include_str!("composite.wgsl");

pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, util::ENV_WGSL, SHADER])
}

pub fn new(
    device: &wgpu::Device,
    frame: &wgpu::Buffer,
    targets: &FrameTargets,
    env: &GpuEnvironment,
) -> ScreenPass {
    let c = wgpu::ShaderStages::COMPUTE;
    let mut entries = vec![util::uniform(0, c)];
    entries.extend(GpuEnvironment::layout_entries());
    entries.extend((8..=15).map(|b| util::texture(b, c, true)));
    entries.push(util::storage_texture(16, HDR_FORMAT));
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("composite"),
        entries: &entries,
    });
    let mut r = vec![(0, frame.as_entire_binding())];
    r.extend(env.bindings());
    r.extend([
        (8, R::TextureView(&targets.normal.view)),
        (9, R::TextureView(&targets.albedo.view)),
        (10, R::TextureView(&targets.material.view)),
        (11, R::TextureView(&targets.emissive.view)),
        (12, R::TextureView(&targets.light_irradiance.view)),
        (13, R::TextureView(&targets.specular.view)),
        (14, R::TextureView(&targets.env_irradiance.view)),
        (15, R::TextureView(&targets.indirect_irradiance.view)),
        (16, R::TextureView(&targets.radiance.view)),
    ]);
    ScreenPass {
        label: "composite",
        pipeline: util::compute_pipeline(device, "composite", &source(), "main", &layout),
        bind_groups: vec![util::bind_group(device, "composite", &layout, &r)],
    }
}

//! AOV extraction (compute): writes one AOV as float RGBA (alpha = surface coverage) into the
//! readback image. See aov.wgsl and `crate::Aov`.

use super::ScreenPass;
use crate::targets::{AOV_FORMAT, FrameTargets};
use crate::util;
use wgpu::BindingResource as R;

pub const SHADER: &str = include_str!("aov.wgsl");

pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, SHADER])
}

pub fn new(device: &wgpu::Device, frame: &wgpu::Buffer, targets: &FrameTargets) -> ScreenPass {
    let c = wgpu::ShaderStages::COMPUTE;
    let mut entries = vec![util::uniform(0, c)];
    // view depth (10) and ao (13) are r32float: unfilterable.
    entries.extend((8..=18).map(|b| util::texture(b, c, b != 10 && b != 13)));
    entries.push(util::storage_texture(19, AOV_FORMAT));
    entries.push(util::texture(20, c, true));
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("aov"),
        entries: &entries,
    });
    let bind_groups = targets
        .direct_radiance
        .iter()
        .map(|direct| {
            let r = [
                (0, frame.as_entire_binding()),
                (8, R::TextureView(&targets.normal.view)),
                (9, R::TextureView(&targets.albedo.view)),
                (10, R::TextureView(&targets.view_depth.view)),
                (11, R::TextureView(&targets.motion.view)),
                (12, R::TextureView(&targets.radiance.view)),
                (13, R::TextureView(&targets.ao.view)),
                (14, R::TextureView(&targets.env_irradiance.view)),
                (15, R::TextureView(&targets.light_irradiance.view)),
                (16, R::TextureView(&targets.indirect_irradiance.view)),
                (17, R::TextureView(&targets.specular.view)),
                (18, R::TextureView(&direct.view)),
                (19, R::TextureView(&targets.aov.view)),
                (20, R::TextureView(&targets.emissive.view)),
            ];
            util::bind_group(device, "aov", &layout, &r)
        })
        .collect();
    ScreenPass {
        label: "aov",
        pipeline: util::compute_pipeline(device, "aov", &source(), "main", &layout),
        bind_groups,
    }
}

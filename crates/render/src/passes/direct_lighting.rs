//! Direct lighting (compute): light irradiance with shadows, specular (lights + prefiltered
//! environment) and the direct radiance kept for the next frame. See direct_lighting.wgsl.

use super::ScreenPass;
use super::shadow::ShadowPass;
use crate::gpu_env::GpuEnvironment;
use crate::gpu_scene::GpuScene;
use crate::targets::{FrameTargets, HDR_FORMAT};
use crate::util;
use wgpu::BindingResource as R;

pub const SHADER: &str = include_str!("direct_lighting.wgsl");

pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, util::ENV_WGSL, util::LIGHTS_WGSL, SHADER])
}

pub fn new(
    device: &wgpu::Device,
    frame: &wgpu::Buffer,
    targets: &FrameTargets,
    scene: &GpuScene,
    env: &GpuEnvironment,
    shadows: &ShadowPass,
) -> ScreenPass {
    use wgpu::ShaderStages as S;
    let c = S::COMPUTE;
    let mut entries = vec![util::uniform(0, c)];
    entries.extend(GpuEnvironment::layout_entries());
    entries.extend([
        util::texture(8, c, true),
        util::texture(9, c, true),
        util::texture(10, c, true),
        util::texture(11, c, true),
        util::texture(12, c, false),
    ]);
    entries.extend(ShadowPass::layout_entries());
    entries.extend([
        util::storage_texture(17, HDR_FORMAT),
        util::storage_texture(18, HDR_FORMAT),
        util::storage_texture(19, HDR_FORMAT),
    ]);
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("direct lighting"),
        entries: &entries,
    });
    let bind_groups = targets
        .direct_radiance
        .iter()
        .map(|out| {
            let mut r = vec![(0, frame.as_entire_binding())];
            r.extend(env.bindings());
            r.extend(shadows.bindings(scene));
            r.extend([
                (8, R::TextureView(&targets.normal.view)),
                (9, R::TextureView(&targets.albedo.view)),
                (10, R::TextureView(&targets.material.view)),
                (11, R::TextureView(&targets.emissive.view)),
                (12, R::TextureView(&targets.view_depth.view)),
                (17, R::TextureView(&targets.light_irradiance.view)),
                (18, R::TextureView(&targets.specular.view)),
                (19, R::TextureView(&out.view)),
            ]);
            util::bind_group(device, "direct lighting", &layout, &r)
        })
        .collect();
    ScreenPass {
        label: "direct",
        pipeline: util::compute_pipeline(device, "direct lighting", &source(), "main", &layout),
        bind_groups,
    }
}

//! Group 0 of every pass: the view and the frame's uniforms, the environment and the far field
//! ([`crate::bindings::FrameBindings`]), one bind group made by the renderer (docs/src/architecture.md).

use crate::bindings::FrameBindings;
use crate::far::GpuFarField;
use crate::gpu_env::GpuEnvironment;

/// Group 0 of every pass of the frame ([`FrameBindings`]): its layout and bind group, made once
/// per environment and far field by the renderer.
pub struct FrameGroup {
    pub layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
}

impl FrameGroup {
    pub fn new(
        device: &wgpu::Device,
        view: &wgpu::Buffer,
        frame: &wgpu::Buffer,
        env: &GpuEnvironment,
        far: &GpuFarField,
    ) -> Self {
        let layout = FrameBindings::layout(device);
        let bind_group = FrameBindings {
            view,
            env_radiance: &env.radiance_view,
            env_specular: &env.specular_view,
            env_sampler: &env.sampler,
            env_sh: &env.sh_buffer,
            env_irradiance_map: &env.irradiance_view,
            far_probes: &far.probes_view,
            far_visibility: &far.visibility_view,
            far_irradiance_atlas: &far.irradiance_view,
            frame,
        }
        .bind_group(device, &layout);
        FrameGroup { layout, bind_group }
    }
}

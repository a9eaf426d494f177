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
    /// The zeroed `Frame` made when none was handed in (kept alive with the bind group).
    _own_frame: Option<wgpu::Buffer>,
    /// Whether the far field bound is a probe volume (far.wgsl's `far_volume()`).
    far_volume: bool,
}

impl FrameGroup {
    /// Group 0 over `view` ([`crate::frame::ViewUniforms`]), the environment and the far field.
    /// `frame` ([`crate::frame::FrameUniforms`]) is nearfield's own frame; a host that runs only
    /// gtao, hbil or vbgi (which read none of it) passes `None`, and a zeroed one is bound.
    pub fn new(
        device: &wgpu::Device,
        view: &wgpu::Buffer,
        frame: Option<&wgpu::Buffer>,
        env: &GpuEnvironment,
        far: &GpuFarField,
    ) -> Self {
        let mut own_frame = None;
        let frame = match frame {
            Some(f) => f,
            None => &*own_frame.insert(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("frame (unused)"),
                size: std::mem::size_of::<crate::frame::FrameUniforms>() as u64,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })),
        };
        let layout = FrameBindings::layout(device);
        let bind_group = FrameBindings {
            view,
            env_radiance: &env.radiance_view,
            env_specular: &env.specular_view,
            env_sampler: &env.sampler,
            env: &env.uniform_buffer,
            env_irradiance_map: &env.irradiance_view,
            far_probes: &far.probes_view,
            far_visibility: &far.visibility_view,
            far_irradiance_atlas: &far.irradiance_view,
            frame,
        }
        .bind_group(device, &layout);
        FrameGroup {
            layout,
            bind_group,
            _own_frame: own_frame,
            far_volume: far.mode == crate::far::FarMode::Volume,
        }
    }

    /// Whether the far field this group binds is a probe volume (else the sky).
    pub fn far_volume(&self) -> bool {
        self.far_volume
    }

    /// far.wgsl's `FAR_FIELD` for a pipeline over this group: the far field it binds, a probe
    /// volume or the sky, so that `far_volume()` is a constant and the branch the frame does not
    /// take is left out of the kernel. Every pass that includes far.wgsl sets it.
    pub fn far_field_constant(&self) -> (&'static str, f64) {
        ("FAR_FIELD", if self.far_volume { 1.0 } else { 0.0 })
    }
}

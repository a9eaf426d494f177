//! The slice march as a strategy: the horizon machinery (split, reprojection, accumulate,
//! outputs: `super::build`) runs one [`March`] per technique. gtao and hbil march for the
//! horizon ([`HorizonMarch`], search.wgsl + march.wgsl); vbgi fills a bitmask of sectors
//! (`technique/vbgi`'s march). A march owns its kernel, its group 1 and whatever resources the
//! kernel reads beyond the machinery's (vbgi: its uniforms and the second depth layer).

use super::params::FAR_SLICES;
use super::{Hidden, HorizonParams, Settings, search};
use crate::RenderError;
use crate::contract::technique::{TechniqueContext, TechniqueParams};
use crate::profiler::GpuProfiler;

/// One of the techniques the horizon machinery runs.
#[derive(Clone, Copy)]
pub struct Flavor {
    pub name: &'static str,
    /// The march gathers near-field light (hbil, vbgi; params.wgsl's `NEAR`), not only
    /// occlusion (gtao).
    pub near: bool,
    /// The machinery's settings, from the technique's parameters (pure; refuses bad values).
    pub settings: fn(&TechniqueParams) -> Result<Settings, String>,
    /// Makes the march.
    pub march: fn(&MarchContext) -> Result<Box<dyn March>, RenderError>,
}

/// What a march is made from.
pub struct MarchContext<'a> {
    pub ctx: &'a TechniqueContext<'a>,
    pub tp: &'a TechniqueParams,
    pub name: &'static str,
    pub settings: &'a Settings,
    /// The machinery's constants (`HorizonParams`, with the deinterleaved layers' size) and
    /// their buffer.
    pub params: &'a HorizonParams,
    pub params_buffer: &'a wgpu::Buffer,
}

/// The images a march's kernel reads and writes in one bind group: full-resolution arrays of one
/// layer, or the 16 deinterleaved layers.
pub struct MarchIo<'a> {
    /// `HorizonParams`.
    pub params: &'a wgpu::Buffer,
    pub depth: &'a wgpu::TextureView,
    pub normal: &'a wgpu::TextureView,
    pub radiance: &'a wgpu::TextureView,
    /// The G-buffer's albedo and material.
    pub albedo: &'a wgpu::TextureView,
    pub material: &'a wgpu::TextureView,
    /// Raw bent cone, near-field irradiance, far field.
    pub out: [&'a wgpu::TextureView; 3],
}

/// A slice march: the kernel that fills the raw cone, near-field and far-field images.
pub trait March: Send + Sync {
    /// Group 1 of the kernel.
    fn layout(&self) -> &wgpu::BindGroupLayout;
    fn bind_group(&self, device: &wgpu::Device, io: MarchIo) -> wgpu::BindGroup;
    /// The kernel's WGSL, its entry point, and its override constants besides the machinery's
    /// counts (`SLICES`, `STEPS`) and `HALF`.
    fn kernel(&self) -> (String, &'static str, Vec<(String, f64)>);
    /// Uploads per-frame data before the frame is recorded (the peeled layer's cameras).
    fn prepare(&self, _queue: &wgpu::Queue, _camera: &nearfield_scene::Camera) {}
    /// Records passes the march needs before the split (vbgi's second depth layer).
    fn encode_before(&self, _encoder: &mut wgpu::CommandEncoder, _profiler: &mut GpuProfiler) {}
    /// Dispatches in the split's compute pass, after the split (vbgi's back depth).
    fn dispatch_after_split(&self, _pass: &mut wgpu::ComputePass) {}
    /// New settings in place; `Ok(false)` when what shapes the march's pipelines changed.
    fn update(&mut self, _queue: &wgpu::Queue, _tp: &TechniqueParams) -> Result<bool, String> {
        Ok(true)
    }
}

/// The horizon search of gtao and hbil (search.wgsl).
pub struct HorizonMarch {
    layout: wgpu::BindGroupLayout,
    /// params.wgsl's `NEAR` and `FAR`: near-field light, the far field over the slices' arcs.
    work: [(&'static str, f64); 2],
    /// params.wgsl's `HIDDEN`: 0 `last`, 1 `volume`, 2 `unbaked` (0 where the scene has no
    /// mesh the bake never saw, or is another engine's).
    hidden: u8,
}

impl HorizonMarch {
    pub fn create(m: &MarchContext, near: bool) -> Box<dyn March> {
        Box::new(HorizonMarch {
            layout: search::SearchBindings::layout(m.ctx.device),
            work: work(near, m.params),
            hidden: match m.settings.hidden {
                _ if !near => 0,
                Hidden::Last => 0,
                Hidden::Volume => 1,
                Hidden::Unbaked if m.ctx.scene.is_some_and(|s| s.scene.has_dynamic) => 2,
                Hidden::Unbaked => 0,
            },
        })
    }
}

/// params.wgsl's `NEAR` and `FAR` of a technique: what its kernels compute besides the cone.
pub fn work(near: bool, p: &HorizonParams) -> [(&'static str, f64); 2] {
    [
        ("NEAR", f64::from(u8::from(near))),
        ("FAR", f64::from(u8::from(p.far == FAR_SLICES))),
    ]
}

impl March for HorizonMarch {
    fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    fn bind_group(&self, device: &wgpu::Device, io: MarchIo) -> wgpu::BindGroup {
        search::SearchBindings {
            params: io.params,
            in_depth: io.depth,
            in_normal: io.normal,
            in_radiance: io.radiance,
            out_cone: io.out[0],
            out_near: io.out[1],
            out_far: io.out[2],
            in_albedo: io.albedo,
            in_material: io.material,
        }
        .bind_group(device, &self.layout)
    }

    fn kernel(&self) -> (String, &'static str, Vec<(String, f64)>) {
        let mut constants: Vec<_> = self.work.iter().map(|&(k, v)| (k.to_string(), v)).collect();
        constants.push(("HIDDEN".to_string(), f64::from(self.hidden)));
        (search::source(), "horizon", constants)
    }
}

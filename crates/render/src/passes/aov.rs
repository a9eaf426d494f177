//! AOV extraction (compute): one AOV of the last frame into `targets.aov` (rgba32float), as
//! docs/src/aovs.md defines it. See aov.wgsl.

use super::{ComputeStep, FrameGroup, PingPong, ScreenPass};
use crate::bindings::{PassLayout, kind};
use crate::targets::{AOV_FORMAT, FrameTargets};
use crate::util;

pub const SHADER: &str = include_str!("aov.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        util::IRRADIANCE_TERMS_WGSL,
        SHADER,
    ])
}

crate::bind_group! {
    /// Group 1 of the AOV pass: every image an AOV is made of.
    pub struct AovBindings: COMPUTE {
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// Base colour ρ (rgba8unorm).
        gb_albedo: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// Motion (rgba16float: previous − current pixel position in rg).
        gb_motion: view = kind::TEXTURE,
        /// The linear HDR frame (rgba16float).
        radiance: view = kind::TEXTURE,
        /// `ao` (r32float).
        ao: view = kind::TEXTURE_UNFILTERABLE,
        /// `env-irradiance` (rgba16float).
        env_irradiance: view = kind::TEXTURE,
        /// `light-irradiance` (rgba16float).
        light_irradiance: view = kind::TEXTURE,
        /// `indirect-irradiance` (rgba16float).
        indirect_irradiance: view = kind::TEXTURE,
        /// Specular radiance (rgba16float).
        specular: view = kind::TEXTURE,
        /// The frame's direct radiance (rgba16float).
        direct_radiance: view = kind::TEXTURE,
        /// Emitted radiance (rgba16float).
        gb_emissive: view = kind::TEXTURE,
        /// The extracted AOV (rgba32float).
        out_aov: view = kind::write(AOV_FORMAT),
        /// The far field at the point (rgba16float: rgb E_far(n)/π, a its visibility within R).
        far_field: view = kind::TEXTURE,
        /// Which AOV ([`AovSelection`]).
        selection: buffer = kind::UNIFORM,
    }
}

crate::gpu_struct! {
    /// `AovSelection` in aov.wgsl: the AOV the pass copies ([`crate::aov::Aov::shader_id`]).
    pub struct AovSelection {
        pub aov: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

/// The AOV pass and its selector.
pub struct AovPass {
    pass: ScreenPass,
    selection: wgpu::Buffer,
}

impl AovPass {
    /// Records the copy of `aov` from the images of frame `frame_index` (whose uniforms group 0
    /// still holds).
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut crate::profiler::GpuProfiler,
        size: (u32, u32),
        frame_index: u32,
        aov: crate::aov::Aov,
    ) {
        let selection = AovSelection {
            aov: aov.shader_id(),
            _pad0: 0,
            _pad1: 0,
            _pad2: 0,
        };
        queue.write_buffer(&self.selection, 0, bytemuck::bytes_of(&selection));
        self.pass.encode(encoder, profiler, size, frame_index);
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "aov",
        source: source(),
        entry_point: "main",
        group1: AovBindings::SLOTS,
    }
}

/// `ao_scales_far` as [`super::composite::new`]'s.
pub fn new(
    device: &wgpu::Device,
    frame: &FrameGroup,
    targets: &FrameTargets,
    ao_scales_far: bool,
    far_rule: crate::contract::technique::FarRule,
) -> AovPass {
    let layout = AovBindings::layout(device);
    let selection = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("aov selection"),
        size: std::mem::size_of::<AovSelection>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let module = crate::pipeline_cache::shader_module(device, "aov", &source());
    let own = PingPong::from_fn(|side| {
        AovBindings {
            gb_normal: &targets.normal.view,
            gb_albedo: &targets.albedo.view,
            gb_view_depth: &targets.view_depth.view,
            gb_motion: &targets.motion.view,
            radiance: &targets.radiance.view,
            ao: &targets.ao.view,
            env_irradiance: &targets.env_irradiance.view,
            light_irradiance: &targets.light_irradiance.view,
            indirect_irradiance: &targets.indirect_irradiance.view,
            specular: &targets.specular.view,
            direct_radiance: &targets.direct_radiance[side].view,
            gb_emissive: &targets.emissive.view,
            out_aov: &targets.aov.view,
            far_field: &targets.far_field.view,
            selection: &selection,
        }
        .bind_group(device, &layout)
    });
    let pass = ScreenPass {
        step: ComputeStep::new(
            device,
            "aov",
            &module,
            "main",
            frame,
            &layout,
            &super::irradiance_terms_constants(ao_scales_far, far_rule, frame),
        ),
        own,
    };
    AovPass { pass, selection }
}

//! The frame's passes, one `.rs` + one `.wgsl` each, in frame order:
//! [`gbuffer`] → [`shadow`] → [`direct_lighting`] → (technique) → [`composite`] → [`tonemap`],
//! and [`aov`] for output, [`display`] for a window. The environment's mip chains come from `env_prefilter.wgsl`
//! (driven by `crate::gpu_env`).

pub mod aov;
pub mod bilateral_blur;
pub mod composite;
pub mod denoise;
pub mod direct_lighting;
pub mod display;
pub mod gbuffer;
pub mod layers;
pub mod reproject;
pub mod rsm;
pub mod shadow;
pub mod tonemap;

use crate::profiler::GpuProfiler;
use crate::util;

pub use crate::contract::frame::FrameGroup;

/// The pipeline constant of the passes that read the technique's irradiance images (composite,
/// aov; passes/irradiance_terms.wgsl): `AO_SCALES_FAR`, whether the technique writes only ao.
/// `FAR_RULE`: how the technique's near field is counted against a probe volume
/// ([`crate::contract::technique::FarRule`]); and far.wgsl's `FAR_FIELD` of the frame.
pub fn irradiance_terms_constants(
    ao_scales_far: bool,
    far_rule: crate::contract::technique::FarRule,
    frame: &FrameGroup,
) -> [(&'static str, f64); 3] {
    [
        ("AO_SCALES_FAR", f64::from(u8::from(ao_scales_far))),
        ("FAR_RULE", far_rule.constant()),
        frame.far_field_constant(),
    ]
}

/// Two of a thing a pass keeps across frames: this frame writes one side and reads the other.
pub struct PingPong<T> {
    sides: [T; 2],
}

impl<T> PingPong<T> {
    /// Side 0 and side 1.
    pub fn new(side0: T, side1: T) -> Self {
        PingPong {
            sides: [side0, side1],
        }
    }

    /// Builds each side from its index (0, 1).
    pub fn from_fn(mut f: impl FnMut(usize) -> T) -> Self {
        PingPong {
            sides: [f(0), f(1)],
        }
    }

    /// The side that frame `index` writes.
    pub fn current(&self, index: u32) -> &T {
        &self.sides[(index % 2) as usize]
    }

    /// The side that frame `index` reads (what frame `index − 1` wrote).
    pub fn previous(&self, index: u32) -> &T {
        &self.sides[((index + 1) % 2) as usize]
    }
}

/// A compute pipeline of `module`'s `entry_point` over groups 0 and 1, specialised by the WGSL
/// `override` constants `constants`.
fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entry_point: &str,
    groups: [Option<&wgpu::BindGroupLayout>; 2],
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    crate::pipeline_cache::compute_pipeline(device, label, module, entry_point, groups, constants)
}

/// One compute kernel of a pass: its pipeline (group 0 = frame, group 1 = `layout`), built once;
/// the bind groups it runs with are the pass's.
pub struct ComputeStep {
    pub label: &'static str,
    pub pipeline: wgpu::ComputePipeline,
    frame: wgpu::BindGroup,
}

impl ComputeStep {
    /// `constants` are the WGSL `override` constants (counts) the pipeline is specialised for.
    pub fn new(
        device: &wgpu::Device,
        label: &'static str,
        module: &wgpu::ShaderModule,
        entry_point: &str,
        frame: &FrameGroup,
        layout: &wgpu::BindGroupLayout,
        constants: &[(&str, f64)],
    ) -> Self {
        let groups = [Some(&frame.layout), Some(layout)];
        ComputeStep {
            label,
            pipeline: compute_pipeline(device, label, module, entry_point, groups, constants),
            frame: frame.bind_group.clone(),
        }
    }

    /// The kernel `entry` of the WGSL `source` (its module labelled `label`), specialised by the
    /// counts it declares (`override KEY`: [`crate::settings::count_constants`] of `counts`, a
    /// family's [`crate::settings::Declared::counts`]) and by `constants`.
    pub fn counted(
        device: &wgpu::Device,
        frame: &FrameGroup,
        (label, source, entry_point): (&'static str, &str, &str),
        layout: &wgpu::BindGroupLayout,
        counts: &[(&'static str, f64)],
        constants: &[(&str, f64)],
    ) -> Self {
        let module = crate::pipeline_cache::shader_module(device, label, source);
        let counted = crate::settings::count_constants(source, counts);
        let mut all: Vec<(&str, f64)> = counted.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        all.extend_from_slice(constants);
        Self::new(device, label, &module, entry_point, frame, layout, &all)
    }

    /// Records this kernel over `size` pixels (8×8 groups) as its own timed pass.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        own: &wgpu::BindGroup,
        size: (u32, u32),
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.label),
            timestamp_writes: profiler.compute(self.label),
        });
        let (gx, gy) = util::groups_8x8(size);
        self.dispatch(&mut pass, own, (gx, gy, 1));
    }

    /// Records this kernel inside an open pass, over `groups` workgroups.
    pub fn dispatch(
        &self,
        pass: &mut wgpu::ComputePass,
        own: &wgpu::BindGroup,
        groups: (u32, u32, u32),
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.frame, &[]);
        pass.set_bind_group(1, own, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, groups.2);
    }
}

/// A pass of one kernel over the screen (8×8 workgroups) with its group 1 built once, one
/// bind group per ping-pong side of the direct radiance (the same one twice where it reads
/// none).
pub struct ScreenPass {
    pub step: ComputeStep,
    pub own: PingPong<wgpu::BindGroup>,
}

impl ScreenPass {
    /// A pass whose group 1 does not depend on the frame's side.
    pub fn single(step: ComputeStep, own: wgpu::BindGroup) -> Self {
        ScreenPass {
            step,
            own: PingPong::new(own.clone(), own),
        }
    }

    /// Records the dispatch of frame `frame_index`; allocates nothing.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        size: (u32, u32),
        frame_index: u32,
    ) {
        self.step
            .encode(encoder, profiler, self.own.current(frame_index), size);
    }
}

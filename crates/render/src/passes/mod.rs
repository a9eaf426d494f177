//! The frame's passes, one `.rs` + one `.wgsl` each, in frame order:
//! [`gbuffer`] → [`shadow`] → [`direct_lighting`] → (technique) → [`composite`] → [`tonemap`],
//! and [`aov`] for output, [`display`] for a window. The environment's mip chains come from `env_prefilter.wgsl`
//! (driven by `crate::gpu_env`).

pub mod aov;
pub mod bilateral_blur;
pub mod composite;
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

/// A compute pass over the screen (8×8 workgroups) with prebuilt bind groups: variant `i`
/// usually selects the direct-radiance ping-pong side.
pub struct ScreenPass {
    pub label: &'static str,
    pub pipeline: wgpu::ComputePipeline,
    pub bind_groups: Vec<wgpu::BindGroup>,
}

impl ScreenPass {
    /// Records the dispatch; allocates nothing.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        size: (u32, u32),
        variant: usize,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(self.label),
            timestamp_writes: profiler.compute(self.label),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_groups[variant % self.bind_groups.len()], &[]);
        let (gx, gy) = util::groups_8x8(size);
        pass.dispatch_workgroups(gx, gy, 1);
    }
}

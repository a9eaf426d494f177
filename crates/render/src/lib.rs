//! nearfield's wgpu renderer: a deferred frame (G-buffer, shadow maps, direct lighting), the
//! near-field techniques that estimate occlusion and indirect light from it, composite and
//! tonemap, per-pass GPU timings, and AOV readback.
//!
//! Every screen-space pass is a compute shader (8×8 workgroups); raster is used for the G-buffer
//! and shadow maps only. One pass is one `.rs` + one `.wgsl` under `passes/` (techniques under
//! `technique/`); the shared WGSL preludes are in `shaders/`.

pub mod aov;
pub mod bindings;
pub mod context;
pub mod contract;
pub mod error;
pub mod far;
pub mod frame;
pub mod gpu_env;
pub mod gpu_scene;
pub mod moving;
pub mod passes;
pub mod pipeline_cache;
pub mod profiler;
pub mod reflect;
pub mod renderer;
pub mod settings;
pub mod targets;
pub mod technique;
pub mod util;
pub mod vertex;
pub mod vpl;

pub use aov::{Aov, AovImage};
pub use context::GpuContext;
pub use error::RenderError;
pub use frame::Tonemap;
pub use renderer::{FramePass, RenderSettings, Renderer};
pub use technique::TechniqueParams;
/// The wgpu this crate is built on (for adapter information and the like).
pub use wgpu;

/// Every pass's binding declaration (WGSL as compiled, entry point, group-1 slots): what the
/// reflection test compares with naga's view of the WGSL. The techniques' come from the
/// registry (each declares its own).
pub fn pass_layouts() -> Vec<bindings::PassLayout> {
    let mut v = vec![
        passes::tonemap::pass_layout(),
        passes::composite::pass_layout(),
        passes::aov::pass_layout(),
        passes::direct_lighting::pass_layout(),
        passes::bilateral_blur::pass_layout(),
        passes::display::pass_layout(),
    ];
    v.extend(technique::pass_layouts());
    v.extend(passes::gbuffer::pass_layouts());
    v.extend(passes::shadow::pass_layouts());
    v.extend(passes::rsm::pass_layouts());
    v.extend(passes::layers::pass_layouts());
    v.extend(passes::reproject::pass_layouts());
    v.extend(gpu_env::pass_layouts());
    v.extend(passes::denoise::pass_layouts());
    v
}

/// Every WGSL program as compiled (preludes included): (name, source). Tests validate each with
/// naga.
pub fn shader_sources() -> Vec<(&'static str, String)> {
    let mut seen = std::collections::BTreeMap::new();
    for p in pass_layouts() {
        seen.entry(p.name).or_insert(p.source);
    }
    seen.into_iter().collect()
}

//! nearfield's wgpu renderer: a deferred frame (G-buffer, shadow maps, direct lighting), the
//! near-field techniques that estimate occlusion and indirect light from it, composite and
//! tonemap, per-pass GPU timings, and AOV readback.
//!
//! Every screen-space pass is a compute shader (8×8 workgroups); raster is used for the G-buffer
//! and shadow maps only. One pass is one `.rs` + one `.wgsl` under `passes/` (techniques under
//! `technique/`); the shared WGSL preludes are in `shaders/`.

pub mod aov;
pub mod context;
pub mod error;
pub mod frame;
pub mod gpu_env;
pub mod gpu_scene;
pub mod passes;
pub mod profiler;
pub mod renderer;
pub mod targets;
pub mod technique;
pub mod util;
pub mod vpl;

pub use aov::{Aov, AovImage};
pub use context::GpuContext;
pub use error::RenderError;
pub use frame::Tonemap;
pub use renderer::{RenderSettings, Renderer};
pub use technique::TechniqueParams;
/// The wgpu this crate is built on (for adapter information and the like).
pub use wgpu;

/// Every WGSL program as compiled (preludes included): (name, source). Tests validate each with
/// naga.
pub fn shader_sources() -> Vec<(&'static str, String)> {
    vec![
        ("gbuffer", passes::gbuffer::source()),
        ("shadow", passes::shadow::SHADER.to_string()),
        ("direct_lighting", passes::direct_lighting::source()),
        ("composite", passes::composite::source()),
        ("tonemap", passes::tonemap::source()),
        ("aov", passes::aov::source()),
        ("display", passes::display::source()),
        (
            "env_prefilter",
            include_str!("passes/env_prefilter.wgsl").to_string(),
        ),
        ("technique/none", technique::none::source()),
        ("technique/ssdo", technique::ssdo::source()),
        ("technique/s3ho", technique::s3ho::source()),
        ("technique/horizon", technique::horizon::source()),
        ("bilateral_blur", passes::bilateral_blur::source()),
        ("reproject", passes::reproject::source()),
    ]
}

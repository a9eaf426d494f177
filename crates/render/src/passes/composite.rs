//! Composite (compute): assembles the linear HDR `radiance` from the G-buffer, direct lighting
//! and the near-field technique's outputs. See composite.wgsl.

use super::{ComputeStep, FrameGroup, ScreenPass};
use crate::bindings::{PassLayout, kind};
use crate::targets::{FrameTargets, HDR_FORMAT};
use crate::util;

pub const SHADER: &str = include_str!("composite.wgsl");

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
    /// Group 1 of the composite pass.
    pub struct CompositeBindings: COMPUTE {
        /// World normal (rgba16float, xyz unit; a = 0 on background).
        gb_normal: view = kind::TEXTURE,
        /// Base colour ρ, linear (rgba8unorm).
        gb_albedo: view = kind::TEXTURE,
        /// F0 / metallic / roughness (rgba8unorm).
        gb_material: view = kind::TEXTURE,
        /// Emitted radiance (rgba16float).
        gb_emissive: view = kind::TEXTURE,
        /// (1/π) Σ E_l with shadows (rgba16float).
        light_irradiance: view = kind::TEXTURE,
        /// Specular radiance (rgba16float).
        specular: view = kind::TEXTURE,
        /// The technique's `env-irradiance` (rgba16float).
        env_irradiance: view = kind::TEXTURE,
        /// The technique's `indirect-irradiance` (rgba16float).
        indirect_irradiance: view = kind::TEXTURE,
        /// The linear HDR frame (rgba16float).
        out_radiance: view = kind::write(HDR_FORMAT),
        /// The technique's `ao` (r32float).
        ao: view = kind::TEXTURE_UNFILTERABLE,
        /// The far field at the point (rgba16float: rgb E_far(n)/π, a its visibility within R).
        far_field: view = kind::TEXTURE,
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "composite",
        source: source(),
        entry_point: "main",
        group1: CompositeBindings::SLOTS,
    }
}

/// `ao_scales_far`: the technique writes only ao (gtao); its env-irradiance is then ao times the
/// far field the direct pass left, and its indirect-irradiance 0 (composite.wgsl).
pub fn new(
    device: &wgpu::Device,
    frame: &FrameGroup,
    targets: &FrameTargets,
    ao_scales_far: bool,
    far_rule: crate::contract::technique::FarRule,
) -> ScreenPass {
    let layout = CompositeBindings::layout(device);
    let module = crate::pipeline_cache::shader_module(device, "composite", &source());
    let own = CompositeBindings {
        gb_normal: &targets.normal.view,
        gb_albedo: &targets.albedo.view,
        gb_material: &targets.material.view,
        gb_emissive: &targets.emissive.view,
        light_irradiance: &targets.light_irradiance.view,
        specular: &targets.specular.view,
        env_irradiance: &targets.env_irradiance.view,
        indirect_irradiance: &targets.indirect_irradiance.view,
        out_radiance: &targets.radiance.view,
        ao: &targets.ao.view,
        far_field: &targets.far_field.view,
    }
    .bind_group(device, &layout);
    ScreenPass::single(
        ComputeStep::new(
            device,
            "composite",
            &module,
            "main",
            frame,
            &layout,
            &super::irradiance_terms_constants(ao_scales_far, far_rule, frame),
        ),
        own,
    )
}

//! The `outputs` kernel of gtao/hbil (outputs.wgsl): the AOVs.

use crate::bindings::{PassLayout, kind};
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        include_str!("params.wgsl"),
        include_str!("outputs.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `outputs`.
    pub struct OutputsBindings: COMPUTE {
        /// `HorizonParams`.
        params: buffer = kind::UNIFORM,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// Base colour ρ (rgba8unorm).
        gb_albedo: view = kind::TEXTURE,
        /// F0 / metallic / roughness (rgba8unorm).
        gb_material: view = kind::TEXTURE,
        /// Emitted radiance (rgba16float).
        gb_emissive: view = kind::TEXTURE,
        /// (1/π) Σ E_l with shadows (rgba16float).
        light_irradiance: view = kind::TEXTURE,
        /// Accumulated bent cone.
        final_cone: view = kind::TEXTURE,
        /// Accumulated near-field irradiance.
        final_near: view = kind::TEXTURE,
        /// Accumulated far field.
        final_far: view = kind::TEXTURE,
        /// `ao` (r32float).
        out_ao: view = kind::write(AO_FORMAT),
        /// `env-irradiance` (rgba16float).
        out_env: view = kind::write(HDR_FORMAT),
        /// `indirect-irradiance` (rgba16float).
        out_indirect: view = kind::write(HDR_FORMAT),
        /// The diffuse radiance the next frame gathers (rgba16float).
        out_feedback: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "horizon/outputs",
        source: source(),
        entry_point: "outputs",
        group1: OutputsBindings::SLOTS,
    }
}

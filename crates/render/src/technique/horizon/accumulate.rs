//! The `accumulate` kernel of gtao/hbil/vbgi (accumulate.wgsl): the temporal running mean and
//! the AOVs from it.

use super::GEOMETRY_FORMAT;
use crate::bindings::{PassLayout, kind};
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        include_str!("params.wgsl"),
        include_str!("half.wgsl"),
        include_str!("accumulate.wgsl"),
        include_str!("resolve.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `accumulate`.
    pub struct AccumulateBindings: COMPUTE {
        /// `HorizonParams`.
        params: buffer = kind::UNIFORM,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// This frame's (blurred) bent cone; with `HALF` the search's, one texel per 2×2 block.
        raw_cone: view = kind::TEXTURE,
        /// This frame's near-field irradiance.
        raw_near: view = kind::TEXTURE,
        /// This frame's far field.
        raw_far: view = kind::TEXTURE,
        /// Last frame's accumulated bent cone.
        prev_cone: view = kind::TEXTURE,
        /// Last frame's accumulated near field.
        prev_near: view = kind::TEXTURE,
        /// Last frame's accumulated far field.
        prev_far: view = kind::TEXTURE,
        /// Last frame's geometry (rgba32float: normal, view depth).
        prev_geometry: view = kind::TEXTURE_UNFILTERABLE,
        /// This frame's accumulated bent cone.
        acc_cone: view = kind::write(HDR_FORMAT),
        /// … near field.
        acc_near: view = kind::write(HDR_FORMAT),
        /// … far field.
        acc_far: view = kind::write(HDR_FORMAT),
        /// This frame's geometry, for the next frame.
        acc_geometry: view = kind::write(GEOMETRY_FORMAT),
        /// Base colour ρ (rgba8unorm).
        gb_albedo: view = kind::TEXTURE,
        /// F0 / metallic / roughness (rgba8unorm).
        gb_material: view = kind::TEXTURE,
        /// Emitted radiance (rgba16float).
        gb_emissive: view = kind::TEXTURE,
        /// (1/π) Σ E_l with shadows (rgba16float).
        light_irradiance: view = kind::TEXTURE,
        /// `ao` (r32float).
        out_ao: view = kind::write(AO_FORMAT),
        /// `env-irradiance` (rgba16float).
        out_env: view = kind::write(HDR_FORMAT),
        /// `indirect-irradiance` (rgba16float).
        out_indirect: view = kind::write(HDR_FORMAT),
        /// The diffuse radiance the next frame gathers (rgba16float).
        out_feedback: view = kind::write(HDR_FORMAT),
        /// The bent normal (rgba16float, xyz unit world, w = 1), where the host handed one in.
        out_bent: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "horizon/accumulate",
        source: source(),
        entry_point: "accumulate",
        group1: AccumulateBindings::SLOTS,
    }
}

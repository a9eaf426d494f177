//! The `shade_pass` kernel of s3ho/ssbn (shade.wgsl): SH lighting of the environment and lights.

use crate::bindings::{PassLayout, kind};
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        util::LIGHTS_WGSL,
        util::SURFACE_WGSL,
        include_str!("sh.wgsl"),
        include_str!("shade.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `shade_pass`.
    pub struct ShadeBindings: COMPUTE {
        /// `S3hoParams`.
        params: buffer = kind::UNIFORM,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// The scene's lights (shaders/lights.wgsl).
        lights: buffer = kind::STORAGE_READ,
        shadow_clip_from_world: buffer = kind::STORAGE_READ,
        shadow_maps: view = kind::TEXTURE_DEPTH_ARRAY,
        shadow_sampler: sampler = kind::SAMPLER_COMPARISON,
        /// Coefficients 0..8 (filtered, or raw with blur off).
        in_coeffs0: view = kind::TEXTURE_UINT,
        /// Coefficients 8..16.
        in_coeffs1: view = kind::TEXTURE_UINT,
        /// ssbn: blurred bent cone.
        in_bent: view = kind::TEXTURE,
        /// ssbn: blurred ao.
        in_ao_raw: view = kind::TEXTURE,
        /// `env-irradiance` (rgba16float).
        out_env_irradiance: view = kind::write(HDR_FORMAT),
        /// `light-irradiance` (rgba16float).
        out_light_irradiance: view = kind::write(HDR_FORMAT),
        /// `ao` (r32float).
        out_ao: view = kind::write(AO_FORMAT),
        /// The shadow maps as unfilterable floats, for the disc search's loads (GL cannot load
        /// from a depth texture).
        shadow_depths: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "s3ho/shade",
        source: source(),
        entry_point: "shade_pass",
        group1: ShadeBindings::SLOTS,
    }
}

//! The `sample_pass` kernel of s3ho/ssbn (sample.wgsl): the SH coefficients and the raw indirect light.

use super::COEFFS_FORMAT;
use crate::bindings::{PassLayout, kind};
use crate::targets::HDR_FORMAT;
use crate::technique::samples;
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        util::LIGHTS_WGSL,
        util::SURFACE_WGSL,
        samples::SAMPLES_WGSL,
        samples::SENDERS_WGSL,
        include_str!("sh.wgsl"),
        samples::LAYERS_GLUE_WGSL,
        include_str!("sample.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `sample_pass`.
    pub struct SampleBindings: COMPUTE {
        /// `S3hoParams`.
        params: buffer = kind::UNIFORM,
        /// The interleaved sample sets.
        sample_sets: buffer = kind::STORAGE_READ,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// Base colour ρ (rgba8unorm).
        gb_albedo: view = kind::TEXTURE,
        /// Extra layers (passes/layers/ `LayerResources`).
        layer_views: buffer = kind::STORAGE_READ,
        peel_normal: view = kind::TEXTURE_ARRAY,
        peel_depth: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        cam_normal: view = kind::TEXTURE_ARRAY,
        cam_depth: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        peel_radiance: view = kind::TEXTURE_ARRAY,
        cam_radiance: view = kind::TEXTURE_ARRAY,
        /// The scene's lights (shaders/lights.wgsl).
        lights: buffer = kind::STORAGE_READ,
        shadow_clip_from_world: buffer = kind::STORAGE_READ,
        shadow_maps: view = kind::TEXTURE_DEPTH_ARRAY,
        shadow_sampler: sampler = kind::SAMPLER_COMPARISON,
        /// Coefficients 0..8 as half floats (rgba32uint).
        out_coeffs0: view = kind::write(COEFFS_FORMAT),
        /// Coefficients 8..16.
        out_coeffs1: view = kind::write(COEFFS_FORMAT),
        /// ssbn: bent normal xyz, cos α (rgba16float).
        out_bent: view = kind::write(HDR_FORMAT),
        /// ssbn: ao in r (rgba16float).
        out_ao_raw: view = kind::write(HDR_FORMAT),
        /// Raw indirect irradiance (rgba16float).
        out_indirect: view = kind::write(HDR_FORMAT),
        /// The shadow maps as unfilterable floats, for the disc search's loads (GL cannot load
        /// from a depth texture).
        shadow_depths: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "s3ho/sample",
        source: source(),
        entry_point: "sample_pass",
        group1: SampleBindings::SLOTS,
    }
}

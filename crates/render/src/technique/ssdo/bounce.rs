//! The `bounce` pass of ssdo (bounce.wgsl): one indirect bounce from sender patches, and
//! instant-radiosity's virtual point lights.

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
        include_str!("params.wgsl"),
        include_str!("segment.wgsl"),
        samples::LAYERS_GLUE_WGSL,
        include_str!("segment_glue.wgsl"),
        include_str!("bounce.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `bounce`.
    pub struct BounceBindings: COMPUTE {
        /// `SsdoParams`.
        params: buffer = kind::UNIFORM,
        /// The interleaved sample sets.
        sample_sets: buffer = kind::STORAGE_READ,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// Extra layers (passes/layers/ `LayerResources`).
        layer_views: buffer = kind::STORAGE_READ,
        peel_normal: view = kind::TEXTURE_ARRAY,
        peel_depth: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        cam_normal: view = kind::TEXTURE_ARRAY,
        cam_depth: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        peel_radiance: view = kind::TEXTURE_ARRAY,
        cam_radiance: view = kind::TEXTURE_ARRAY,
        /// The light table: the scene's lights, or instant-radiosity's virtual point lights.
        lights: buffer = kind::STORAGE_READ,
        shadow_clip_from_world: buffer = kind::STORAGE_READ,
        shadow_maps: view = kind::TEXTURE_DEPTH_ARRAY,
        shadow_sampler: sampler = kind::SAMPLER_COMPARISON,
        /// Base colour ρ (rgba8unorm).
        gb_albedo: view = kind::TEXTURE,
        /// Emitted radiance (rgba16float).
        gb_emissive: view = kind::TEXTURE,
        /// The resolved env-irradiance of senders (rgba16float).
        env_irradiance: view = kind::TEXTURE,
        /// Their light irradiance (rgba16float).
        light_irradiance: view = kind::TEXTURE,
        /// Raw indirect-irradiance before the blur (rgba16float).
        out_indirect: view = kind::write(HDR_FORMAT),
        /// The shadow maps as unfilterable floats, for the disc search's loads (GL cannot load
        /// from a depth texture).
        shadow_depths: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "ssdo/bounce",
        source: source(),
        entry_point: "bounce",
        group1: BounceBindings::SLOTS,
    }
}

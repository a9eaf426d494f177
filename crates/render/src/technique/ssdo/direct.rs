//! The `direct` pass of ssao/ssdo (direct.wgsl): samples, visibility, directional occlusion of
//! the environment, the lights' screen-space occlusion.

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
        include_str!("params.wgsl"),
        include_str!("segment.wgsl"),
        samples::LAYERS_GLUE_WGSL,
        include_str!("segment_glue.wgsl"),
        include_str!("direct.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `direct`.
    pub struct DirectBindings: COMPUTE {
        /// `SsdoParams`.
        params: buffer = kind::UNIFORM,
        /// The interleaved sample sets (`samples::interleaved_sets`).
        sample_sets: buffer = kind::STORAGE_READ,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// Extra layers' views (passes/layers/ `LayerResources`).
        layer_views: buffer = kind::STORAGE_READ,
        peel_normal: view = kind::TEXTURE_ARRAY,
        peel_depth: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        cam_normal: view = kind::TEXTURE_ARRAY,
        cam_depth: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        /// The light table: the scene's lights, or ssdo-vpl's environment lights.
        lights: buffer = kind::STORAGE_READ,
        shadow_clip_from_world: buffer = kind::STORAGE_READ,
        shadow_maps: view = kind::TEXTURE_DEPTH_ARRAY,
        shadow_sampler: sampler = kind::SAMPLER_COMPARISON,
        /// (L_dir rgb, visibility) before the blur (rgba16float).
        out_a: view = kind::write(HDR_FORMAT),
        /// (ao, 0, 0, 1) before the blur (rgba16float).
        out_b: view = kind::write(HDR_FORMAT),
        /// Light irradiance with screen-space light occlusion (rgba16float; ssdo only).
        out_light_irradiance: view = kind::write(HDR_FORMAT),
        /// The shadow maps as unfilterable floats, for the disc search's loads (GL cannot load
        /// from a depth texture).
        shadow_depths: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "ssdo/direct",
        source: source(),
        entry_point: "direct",
        group1: DirectBindings::SLOTS,
    }
}

//! The shading pass of the extra layers (shade.wgsl): the direct radiance of every texel of the
//! peeled layers and additional cameras.

use crate::bindings::{PassLayout, kind};
use crate::targets;
use crate::util;

/// Shader text of the shading pass.
pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        util::LIGHTS_WGSL,
        include_str!("shade.wgsl"),
    ])
}

crate::gpu_struct! {
    /// `ShadeParams` in shade.wgsl.
    pub struct ShadeParams {
        /// Index in the views buffer of this set's first layer.
        pub first_view: u32,
        pub count: u32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

crate::bind_group! {
    /// Group 1 of the layers' shading pass (shade.wgsl).
    pub struct ShadeBindings: COMPUTE {
        /// `ShadeParams`: this set's first view and layer count.
        shade_params: buffer = kind::UNIFORM,
        /// Every layer's `LayerView`.
        layer_views: buffer = kind::STORAGE_READ,
        /// The set's normals (rgba16float array), base colours (rgba8unorm-srgb array),
        /// emission (rgba16float array), view depths (r32float array).
        layer_normal: view = kind::TEXTURE_ARRAY,
        layer_albedo: view = kind::TEXTURE_ARRAY,
        layer_emissive: view = kind::TEXTURE_ARRAY,
        layer_depth: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        /// Their direct radiance (rgba16float array).
        layer_radiance: view = kind::write_array(targets::HDR_FORMAT),
        /// The scene's lights (shaders/lights.wgsl).
        lights: buffer = kind::STORAGE_READ,
        shadow_clip_from_world: buffer = kind::STORAGE_READ,
        shadow_maps: view = kind::TEXTURE_DEPTH_ARRAY,
        shadow_sampler: sampler = kind::SAMPLER_COMPARISON,
        /// The shadow maps as unfilterable floats, for the disc search's loads (GL cannot load
        /// from a depth texture).
        shadow_depths: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "layers shade",
        source: source(),
        entry_point: "shade",
        group1: ShadeBindings::SLOTS,
    }
}

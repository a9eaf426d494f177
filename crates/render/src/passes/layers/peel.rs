//! The raster pass of the extra layers (peel.wgsl): depth peeling of the main view and the
//! additional cameras, normal, albedo, emission and view depth of every layer.

use super::VIEW_STRIDE;
use crate::bindings::{PassLayout, kind};
use crate::util;

/// Shader text of the raster pass (depth peeling, additional cameras).
pub fn peel_source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::GPU_MATERIAL_WGSL,
        util::MATERIALS_WGSL,
        include_str!("peel.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of the layers' raster pass (peel.wgsl; group 0 is not read).
    pub struct PeelBindings: VERTEX | FRAGMENT {
        /// The scene's materials (shaders/materials.wgsl).
        materials: buffer = kind::STORAGE_READ,
        srgb_textures: view = kind::TEXTURE_ARRAY,
        linear_textures: view = kind::TEXTURE_ARRAY,
        material_sampler: sampler = kind::SAMPLER,
        /// This layer's `LayerView`, at a dynamic offset into the views buffer.
        layer_view: buffer_range = kind::uniform_dynamic(VIEW_STRIDE),
        /// The depth buffer of the layer before (peeling), read as an unfilterable float (GL
        /// cannot load from a depth texture).
        prev_depth: view = kind::TEXTURE_UNFILTERABLE,
    }
}

/// The binding declarations the reflection test checks (vertex and fragment stage).
pub fn pass_layouts() -> Vec<PassLayout> {
    PassLayout::entries(
        "layers raster",
        peel_source(),
        &["vs_layer", "fs_layer"],
        PeelBindings::SLOTS,
    )
}

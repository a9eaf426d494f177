//! The `horizon` kernel of gtao/hbil (search.wgsl): the horizon search.

use crate::bindings::{PassLayout, kind};
use crate::targets::HDR_FORMAT;
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        include_str!("params.wgsl"),
        include_str!("half.wgsl"),
        include_str!("search.wgsl"),
        include_str!("march.wgsl"),
        include_str!("slice.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `horizon`.
    pub struct SearchBindings: COMPUTE {
        /// `HorizonParams`.
        params: buffer = kind::UNIFORM,
        /// View depth (r32float; read without interleaving).
        in_depth: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        /// Normal: the split geometry (rgba32float array) or the G-buffer's normal.
        in_normal: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        /// Radiance source (rgba16float array).
        in_radiance: view = kind::TEXTURE_ARRAY,
        /// Raw bent cone (xyz bent normal, w ao).
        out_cone: view = kind::write(HDR_FORMAT),
        /// Raw near-field irradiance.
        out_near: view = kind::write(HDR_FORMAT),
        /// Raw far field through the slices' visible arcs.
        out_far: view = kind::write(HDR_FORMAT),
        /// The G-buffer's albedo (full resolution).
        in_albedo: view = kind::TEXTURE,
        /// The G-buffer's material (full resolution): b = 1 on surfaces the bake never saw.
        in_material: view = kind::TEXTURE,
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "horizon/search",
        source: source(),
        entry_point: "horizon",
        group1: SearchBindings::SLOTS,
    }
}

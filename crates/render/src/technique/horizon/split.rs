//! The `split` kernel of gtao/hbil (split.wgsl): the 4×4 deinterleave.

use super::GEOMETRY_FORMAT;
use crate::bindings::{PassLayout, kind};
use crate::targets::HDR_FORMAT;
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        include_str!("params.wgsl"),
        include_str!("split.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `split`.
    pub struct SplitBindings: COMPUTE {
        /// `HorizonParams`.
        params: buffer = kind::UNIFORM,
        /// View depth (r32float, m).
        full_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// World normal (rgba16float).
        full_normal: view = kind::TEXTURE,
        /// The near-field radiance source (rgba16float): this frame's direct radiance or last frame's reprojected.
        full_radiance: view = kind::TEXTURE,
        /// 16 layers of (normal xyz, view depth) (rgba32float array).
        split_geometry: view = kind::write_array(GEOMETRY_FORMAT),
        /// 16 layers of radiance (rgba16float array).
        split_radiance: view = kind::write_array(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "horizon/split",
        source: source(),
        entry_point: "split",
        group1: SplitBindings::SLOTS,
    }
}

//! The `merge` kernel of gtao/hbil (merge.wgsl): the layers back to full resolution.

use crate::bindings::{PassLayout, kind};
use crate::targets::HDR_FORMAT;
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        include_str!("params.wgsl"),
        include_str!("merge.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `merge`.
    pub struct MergeBindings: COMPUTE {
        /// The 16 layers' bent cones.
        layered_cone: view = kind::TEXTURE_ARRAY,
        /// … near-field irradiance.
        layered_near: view = kind::TEXTURE_ARRAY,
        /// … far field.
        layered_far: view = kind::TEXTURE_ARRAY,
        /// Full-resolution bent cone.
        merged_cone: view = kind::write(HDR_FORMAT),
        /// Full-resolution near-field irradiance.
        merged_near: view = kind::write(HDR_FORMAT),
        /// Full-resolution far field.
        merged_far: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "horizon/merge",
        source: source(),
        entry_point: "merge",
        group1: MergeBindings::SLOTS,
    }
}

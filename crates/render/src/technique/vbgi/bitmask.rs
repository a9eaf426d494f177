//! The `bitmask` kernel of vbgi (bitmask.wgsl): the slice march with a visibility bitmask.

use crate::bindings::{PassLayout, kind};
use crate::targets::HDR_FORMAT;
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        include_str!("../horizon/params.wgsl"),
        include_str!("../horizon/half.wgsl"),
        include_str!("bitmask.wgsl"),
        include_str!("../horizon/slice.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `bitmask`.
    pub struct BitmaskBindings: COMPUTE {
        /// `HorizonParams`.
        params: buffer = kind::UNIFORM,
        /// `VbgiParams`: thickness.
        vbgi: buffer = kind::UNIFORM,
        /// View depth (r32float; read without interleaving).
        in_depth: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        /// Normal: the split geometry (rgba32float array) or the G-buffer's normal.
        in_normal: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        /// Radiance source (rgba16float array).
        in_radiance: view = kind::TEXTURE_ARRAY,
        /// View depth of the second depth layer (r32float array; 0 where there is none).
        in_back: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        /// Direct radiance of the second depth layer (rgba16float array): the surface behind a
        /// sample's front, which a receiver behind the sample sees.
        in_back_radiance: view = kind::TEXTURE_ARRAY,
        /// Raw bent cone (xyz bent normal, w ao).
        out_cone: view = kind::write(HDR_FORMAT),
        /// Raw near-field irradiance.
        out_near: view = kind::write(HDR_FORMAT),
        /// Raw far field through the unoccupied sectors.
        out_far: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "vbgi/bitmask",
        source: source(),
        entry_point: "bitmask",
        group1: BitmaskBindings::SLOTS,
    }
}

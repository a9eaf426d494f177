//! The `upsample` kernel of gtao, hbil and vbgi (upsample.wgsl): `resolution=half`'s results
//! brought to every pixel before the bilateral blur.

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
        include_str!("upsample.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `upsample`.
    pub struct UpsampleBindings: COMPUTE {
        /// `HorizonParams`.
        params: buffer = kind::UNIFORM,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// The search's bent cone, one texel per 2×2 block.
        half_cone: view = kind::TEXTURE,
        /// … near-field irradiance.
        half_near: view = kind::TEXTURE,
        /// … far field.
        half_far: view = kind::TEXTURE,
        /// The bent cone at every pixel.
        out_cone: view = kind::write(HDR_FORMAT),
        /// … near-field irradiance.
        out_near: view = kind::write(HDR_FORMAT),
        /// … far field.
        out_far: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "horizon/upsample",
        source: source(),
        entry_point: "upsample",
        group1: UpsampleBindings::SLOTS,
    }
}

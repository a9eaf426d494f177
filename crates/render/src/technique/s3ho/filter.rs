//! The `filter_pass` kernel of s3ho/ssbn (filter.wgsl): the 8×8 bilateral filter on the coefficients.

use super::COEFFS_FORMAT;
use crate::bindings::{PassLayout, kind};
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::SURFACE_WGSL,
        include_str!("sh.wgsl"),
        include_str!("filter.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `filter_pass`.
    pub struct FilterBindings: COMPUTE {
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// Raw coefficients 0..8 (rgba32uint).
        in_coeffs0: view = kind::TEXTURE_UINT,
        /// Raw coefficients 8..16.
        in_coeffs1: view = kind::TEXTURE_UINT,
        /// Filtered coefficients 0..8.
        out_coeffs0: view = kind::write(COEFFS_FORMAT),
        /// Filtered coefficients 8..16.
        out_coeffs1: view = kind::write(COEFFS_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "s3ho/filter",
        source: source(),
        entry_point: "filter_pass",
        group1: FilterBindings::SLOTS,
    }
}

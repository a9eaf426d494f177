//! The `variance` kernel of svgf (variance.wgsl): the per-pixel variance estimate.

use super::source_of;
use crate::bindings::{PassLayout, kind};
use crate::targets::HDR_FORMAT;

pub fn source() -> String {
    source_of(include_str!("variance.wgsl"))
}

crate::bind_group! {
    /// Group 1 of `variance`.
    pub struct VarianceBindings: COMPUTE {
        /// `SvgfParams`.
        params: buffer = kind::UNIFORM,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// The accumulated moments (rgba32float).
        acc_moments: view = kind::TEXTURE_UNFILTERABLE,
        /// The accumulated env-irradiance (w: frames in the mean).
        acc_env: view = kind::TEXTURE,
        /// ao, Var(ao), Var(luminance), count (rgba16float).
        out_signal: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "denoise/variance",
        source: source(),
        entry_point: "variance",
        group1: VarianceBindings::SLOTS,
    }
}

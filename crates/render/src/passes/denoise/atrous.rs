//! The `atrous` kernel of svgf (atrous.wgsl): one edge-aware à-trous iteration.

use super::source_of;
use crate::bindings::{PassLayout, kind};
use crate::targets::HDR_FORMAT;

pub fn source() -> String {
    source_of(include_str!("atrous.wgsl"))
}

crate::bind_group! {
    /// Group 1 of `atrous`.
    pub struct AtrousBindings: COMPUTE {
        /// `SvgfParams` of this iteration (its `step`).
        params: buffer = kind::UNIFORM,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// ao, Var(ao), Var(luminance), count (rgba16float).
        in_signal: view = kind::TEXTURE,
        /// env-irradiance.
        in_env: view = kind::TEXTURE,
        /// indirect-irradiance.
        in_indirect: view = kind::TEXTURE,
        /// Filtered ao and variances.
        out_signal: view = kind::write(HDR_FORMAT),
        /// Filtered env-irradiance.
        out_env: view = kind::write(HDR_FORMAT),
        /// Filtered indirect-irradiance.
        out_indirect: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "denoise/atrous",
        source: source(),
        entry_point: "atrous",
        group1: AtrousBindings::SLOTS,
    }
}

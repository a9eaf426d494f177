//! The `temporal` kernel of svgf (temporal.wgsl): the running means and moments.

use super::source_of;
use crate::bindings::{PassLayout, kind};
use crate::targets::HDR_FORMAT;

pub fn source() -> String {
    source_of(include_str!("temporal.wgsl"))
}

crate::bind_group! {
    /// Group 1 of `temporal`.
    pub struct TemporalBindings: COMPUTE {
        /// `SvgfParams`.
        params: buffer = kind::UNIFORM,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m).
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// Motion (rg16float): previous − current pixel position.
        gb_motion: view = kind::TEXTURE,
        /// This frame's ao (r32float).
        raw_ao: view = kind::TEXTURE_UNFILTERABLE,
        /// This frame's env-irradiance.
        raw_env: view = kind::TEXTURE,
        /// This frame's indirect-irradiance.
        raw_indirect: view = kind::TEXTURE,
        /// Last frame's moments (rgba32float: ao, ao², luminance, luminance²).
        prev_moments: view = kind::TEXTURE_UNFILTERABLE,
        /// Last frame's env-irradiance mean (w: frames in the mean).
        prev_env: view = kind::TEXTURE,
        /// Last frame's indirect-irradiance mean.
        prev_indirect: view = kind::TEXTURE,
        /// Last frame's geometry (rgba32float: normal, view depth).
        prev_geometry: view = kind::TEXTURE_UNFILTERABLE,
        /// This frame's moments.
        acc_moments: view = kind::write(wgpu::TextureFormat::Rgba32Float),
        /// This frame's env-irradiance mean and count.
        acc_env: view = kind::write(HDR_FORMAT),
        /// This frame's indirect-irradiance mean.
        acc_indirect: view = kind::write(HDR_FORMAT),
        /// This frame's geometry, for the next frame.
        acc_geometry: view = kind::write(wgpu::TextureFormat::Rgba32Float),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "denoise/temporal",
        source: source(),
        entry_point: "temporal",
        group1: TemporalBindings::SLOTS,
    }
}

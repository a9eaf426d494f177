//! The `resolve` kernel of svgf (resolve.wgsl): the filtered results into the AOVs.

use crate::bindings::{PassLayout, kind};
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        include_str!("resolve.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `resolve`.
    pub struct ResolveBindings: COMPUTE {
        /// The last iteration's ao and variances.
        final_signal: view = kind::TEXTURE,
        /// The last iteration's env-irradiance.
        final_env: view = kind::TEXTURE,
        /// The last iteration's indirect-irradiance.
        final_indirect: view = kind::TEXTURE,
        /// `ao` (r32float).
        out_ao: view = kind::write(AO_FORMAT),
        /// `env-irradiance` (rgba16float).
        out_env: view = kind::write(HDR_FORMAT),
        /// `indirect-irradiance` (rgba16float).
        out_indirect: view = kind::write(HDR_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "denoise/resolve",
        source: source(),
        entry_point: "resolve",
        group1: ResolveBindings::SLOTS,
    }
}

//! The `resolve` pass of ssao/ssdo (resolve.wgsl): blurred visibility → env-irradiance and ao.

use crate::bindings::{PassLayout, kind};
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::FAR_WGSL,
        include_str!("params.wgsl"),
        include_str!("resolve.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `resolve`.
    pub struct ResolveBindings: COMPUTE {
        /// `SsdoParams`.
        params: buffer = kind::UNIFORM,
        /// World normal (rgba16float).
        gb_normal: view = kind::TEXTURE,
        /// View depth (r32float, m): where the probe volume is read.
        gb_view_depth: view = kind::TEXTURE_UNFILTERABLE,
        /// Blurred (L_dir, visibility) (rgba16float).
        in_a: view = kind::TEXTURE,
        /// Blurred (ao, 0, 0, 1) (rgba16float).
        in_b: view = kind::TEXTURE,
        /// `env-irradiance` (rgba16float).
        out_env_irradiance: view = kind::write(HDR_FORMAT),
        /// `ao` (r32float).
        out_ao: view = kind::write(AO_FORMAT),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "ssdo/resolve",
        source: source(),
        entry_point: "resolve",
        group1: ResolveBindings::SLOTS,
    }
}

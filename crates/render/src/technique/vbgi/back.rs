//! The `back` kernel of vbgi (back.wgsl): the second layer's depth, deinterleaved.

use crate::bindings::{PassLayout, kind};
use crate::util;

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        include_str!("../horizon/params.wgsl"),
        include_str!("back.wgsl"),
    ])
}

crate::bind_group! {
    /// Group 1 of `back`.
    pub struct BackBindings: COMPUTE {
        /// `HorizonParams`.
        params: buffer = kind::UNIFORM,
        /// The peeled layers' view depth (r32float array; layer 0 is the second layer).
        full_back: view = kind::TEXTURE_ARRAY_UNFILTERABLE,
        /// 16 layers of the second layer's view depth (r32float array).
        split_back: view = kind::write_array(wgpu::TextureFormat::R32Float),
        /// The peeled layers' direct radiance (rgba16float array; layer 0 is the second layer).
        full_back_radiance: view = kind::TEXTURE_ARRAY,
        /// 16 layers of the second layer's direct radiance (rgba16float array).
        split_back_radiance: view = kind::write_array(wgpu::TextureFormat::Rgba16Float),
    }
}

/// The binding declaration the reflection test checks.
pub fn pass_layout() -> PassLayout {
    PassLayout {
        name: "vbgi/back",
        source: source(),
        entry_point: "back",
        group1: BackBindings::SLOTS,
    }
}

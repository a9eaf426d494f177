//! What the hemisphere-sampling techniques (ssdo's and s3ho's families) share: the sample
//! pattern and the `quality` presets (directions per pixel).

use super::Preset;
use crate::choice;

choice! {
    /// Sample pattern.
    pub enum Pattern {
        /// The chapter's stratified elevation, golden-ratio azimuth, IGN rotation, random λ.
        Chapter = "chapter",
        /// The paper's M×N texture: 4×4 sets of N low-discrepancy samples, one set per pixel.
        Interleaved = "interleaved",
    }
}

/// `quality` presets of the sampling techniques: directions per pixel.
pub const PRESETS: &[Preset] = &[
    Preset {
        name: "low",
        set: &[("samples", "8")],
    },
    Preset {
        name: "medium",
        set: &[("samples", "16")],
    },
    Preset {
        name: "high",
        set: &[("samples", "32")],
    },
    Preset {
        name: "ultra",
        set: &[("samples", "64")],
    },
];

//! The denoiser choice every technique with a blur takes, and the settings of the shared
//! spatio-temporal denoiser (`passes/denoise`, SVGF-style).

use crate::{choice, declare_settings};

choice! {
    /// What removes the noise and the 4×4 interleaving pattern of a technique's results.
    pub enum Denoise {
        /// The shared spatio-temporal denoiser (passes/denoise: temporal accumulation through
        /// motion vectors with disocclusion rejection, per-pixel variance, edge-aware à-trous).
        Svgf = "svgf",
        /// The technique's own geometry-aware bilateral blur.
        Bilateral = "bilateral",
        /// Nothing: the raw per-pixel results.
        Off = "off",
    }
}

declare_settings! {
    /// Settings of the `svgf` denoiser (used where `denoise=svgf`).
    pub struct SvgfSettings {
        svgf_iterations: u32 = "4", integer(1, 6), denoiser, "", "svgf: à-trous iterations; iteration k spaces its 3×3 taps 2^k pixels apart (4: ±15 pixels)";
        svgf_luminance: f32 = "4", number(0, 64), filter, "", "svgf: σ_l, a tap's value may differ from the centre's by this many standard deviations before its weight falls by e (0: no value term)";
        svgf_depth: f32 = "0.02", log(1e-4, 10), filter, "", "svgf: tangent-plane distance, relative to view depth, at which a tap's weight falls by e";
        svgf_normal: f32 = "64", number(0, 256), filter, "", "svgf: exponent σ_n on the normals' cosine";
        svgf_motion: f32 = "0.1", log(1e-3, 100), filter, "m", "svgf: a surface that moves in the world (its motion vector beyond the camera's) keeps the history of its last this many metres of travel, so that the light of a moving object follows it (large: no limit)";
        svgf_reach: f32 = "1", log(1e-2, 1e6), filter, "R", "svgf: ao's and env-irradiance's taps this many R (the technique's radius) from the centre in the world have their weight fall by e (taps within 3 pixels keep theirs), so that the filter does not mix the occlusion of separate neighbourhoods (large: no limit)";
        svgf_clamp: f32 = "0", number(0, 8), filter, "", "svgf: the history's ao and light are clamped to this frame's 5×5 neighbourhood mean ± this many of its standard deviations before the new frame joins them, so that light follows a moving object within frames (0: no clamp; not yet with resolution=half)";
    }
}

/// What the denoiser is run with: the technique's own temporal settings and svgf's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SvgfConfig {
    pub temporal: bool,
    pub history: u32,
    pub reject_depth: f32,
    pub reject_normal: f32,
    /// The technique's radius R (m).
    pub radius: f32,
    pub svgf: SvgfSettings,
}

impl SvgfConfig {
    /// svgf's settings with the running mean on (32 frames) and the history tests of the
    /// horizon techniques' defaults: for techniques without temporal settings of their own.
    pub fn with_defaults(svgf: SvgfSettings, radius: f32) -> Self {
        SvgfConfig {
            temporal: true,
            history: 32,
            reject_depth: 0.02,
            reject_normal: 0.9,
            radius,
            svgf,
        }
    }
}

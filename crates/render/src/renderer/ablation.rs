//! The passes of a frame that a timing run may leave out one at a time (`nearfield bench
//! --ablate`): on a CPU adapter, whose per-pass timestamps are unreliable, the wall time a pass
//! saves when it is left out is its cost. A frame with a pass left out is wrong; it is for
//! timing only.

/// One pass of nearfield's frame, in frame order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FramePass {
    /// The G-buffer raster pass.
    Gbuffer,
    /// The shadow maps (raster), the sun's cascade included.
    Shadows,
    /// Direct lighting (compute): lights with their shadows, the far field, specular.
    Direct,
    /// The near-field technique's passes (and nearfield's own step after an ao-only one).
    Technique,
    /// The composite of the linear HDR frame.
    Composite,
    /// Tone mapping into the `final` image.
    Tonemap,
}

impl FramePass {
    pub const ALL: [FramePass; 6] = [
        FramePass::Gbuffer,
        FramePass::Shadows,
        FramePass::Direct,
        FramePass::Technique,
        FramePass::Composite,
        FramePass::Tonemap,
    ];

    pub fn name(self) -> &'static str {
        match self {
            FramePass::Gbuffer => "gbuffer",
            FramePass::Shadows => "shadows",
            FramePass::Direct => "direct",
            FramePass::Technique => "technique",
            FramePass::Composite => "composite",
            FramePass::Tonemap => "tonemap",
        }
    }
}

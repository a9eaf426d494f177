//! Depth peeling and additional cameras in the blocker test (`passes/layers/`): the settings
//! every technique with the shared blocker test takes.

use crate::declare_settings;

/// Depth layers of the main view at most.
pub const MAX_LAYERS: u32 = 4;
/// Additional cameras at most.
pub const MAX_CAMERAS: u32 = 4;

declare_settings! {
    /// What the extra layers hold.
    pub struct LayerSettings {
        layers: u32 = "1", values("1", "2", "4"), structural, "", "depth layers of the main view in the blocker test (depth peeling; 1 = the G-buffer only; layers come in entry/exit pairs)";
        cameras: u32 = "0", integer(0, MAX_CAMERAS), count, "", "additional cameras in the blocker test";
        camera_scale: u32 = "2", integer(1, 8), structural, "", "resolution divisor of the additional cameras";
        camera_spread: f32 = "0.5", number(0, 4), structural, "", "camera displacement as a fraction of the scene's bounding-sphere radius";
    }
}

/// Points per direction of the blocker test with two or four layers, unless `steps` is set:
/// a single point per direction frees the samples behind thin objects that the ray towards
/// them cannot reach, so peeling alone raised the `ao` error (MAE against the reference,
/// 128×72, R = 0.5 and 1, `tests/layer_defaults.rs`: cornell 0.087 → 0.097 and 0.180 →
/// 0.200, Sponza 0.082 → 0.088 and 0.115 → 0.129 for ssdo); marched in 16 points it falls on
/// them (cornell 0.073 and 0.103, Sponza 0.052 and 0.066).
pub const LAYERED_STEPS: u32 = 16;

/// `steps` after `--set`: as set, else [`LAYERED_STEPS`] with two or four layers, else
/// `default_steps`.
pub fn resolve_steps(params: &super::TechniqueParams, layers: u32, steps: u32) -> u32 {
    let explicit = params.set.iter().any(|(k, _)| k == "steps");
    if !explicit && layers > 1 {
        LAYERED_STEPS
    } else {
        steps
    }
}

impl LayerSettings {
    /// Whether anything beyond the G-buffer is drawn.
    pub fn active(&self) -> bool {
        self.layers > 1 || self.cameras > 0
    }
}

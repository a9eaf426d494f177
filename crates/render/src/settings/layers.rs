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
        layers: u32 = "1", values("1", "2", "4"), "", "depth layers of the main view in the blocker test (depth peeling; 1 = the G-buffer only; layers come in entry/exit pairs)";
        cameras: u32 = "0", integer(0, MAX_CAMERAS), "", "additional cameras in the blocker test";
        camera_scale: u32 = "2", integer(1, 8), "", "resolution divisor of the additional cameras";
        camera_spread: f32 = "0.5", number(0, 4), "", "camera displacement as a fraction of the scene's bounding-sphere radius";
    }
}

impl LayerSettings {
    /// Whether anything beyond the G-buffer is drawn.
    pub fn active(&self) -> bool {
        self.layers > 1 || self.cameras > 0
    }
}

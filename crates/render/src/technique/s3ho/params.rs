//! `S3hoParams`: the GPU constants of every s3ho pass, a pure function of the settings.

use super::Settings;
use crate::settings::sampling::Pattern;

impl Settings {
    /// The GPU constants (pure).
    pub fn params(&self, ssbn: bool) -> S3hoParams {
        S3hoParams {
            radius: self.radius,
            _pad0: 0,
            pattern: (self.pattern == Pattern::Interleaved) as u32,
            fade: self.fade,
            _pad1: 0,
            lambda: self.lambda,
            technique: ssbn as u32,
            indirect: (!ssbn && self.indirect) as u32,
            strength: self.strength,
            distance_clamp: self.distance_clamp,
            layers: self.layers.layers,
            cameras: self.layers.cameras,
        }
    }
}

crate::gpu_struct! {
    /// `S3hoParams` in sh.wgsl.
    pub struct S3hoParams {
        pub radius: f32,
        /// (Directions per pixel: the override `SAMPLES`.)
        pub _pad0: u32,
        pub pattern: u32,
        pub fade: f32,
        /// (Points per direction: the override `STEPS`.)
        pub _pad1: u32,
        pub lambda: f32,
        pub technique: u32,
        pub indirect: u32,
        pub strength: f32,
        pub distance_clamp: f32,
        pub layers: u32,
        pub cameras: u32,
    }
}

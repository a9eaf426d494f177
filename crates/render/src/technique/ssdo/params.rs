//! `SsdoParams`: the GPU constants of every ssdo pass, a pure function of the settings.

use super::settings::SampleLight;
use super::{LightSegment, Mode, Pattern, Settings};

impl Settings {
    /// The GPU constants (pure).
    pub fn params(&self, ssdo: bool) -> SsdoParams {
        SsdoParams {
            radius: self.radius,
            sample_light: (self.sample_light == SampleLight::Mip) as u32,
            mode: (self.mode == Mode::Radiance) as u32,
            technique: ssdo as u32,
            lod: self.lod,
            contrast: self.contrast,
            scale: self.scale,
            fade: self.fade,
            strength: self.strength,
            distance_clamp: self.distance_clamp,
            pattern: (self.pattern == Pattern::Interleaved) as u32,
            light_samples: if ssdo { self.light_samples } else { 0 },
            layers: self.layers.layers,
            cameras: self.layers.cameras,
            light_segment: (self.light_segment == LightSegment::Bias) as u32,
            vpl_mode: 0,
            vpl_count: 0,
            vpl_clamp: self.vpl_clamp,
            near: (ssdo && self.bounce) as u32,
            normalise: self.normalise as u32,
        }
    }
}

crate::gpu_struct! {
    /// `SsdoParams` in params.wgsl.
    pub struct SsdoParams {
        pub radius: f32,
        /// Radiance mode's L_in: 0 the environment's SH, 1 the mip at `lod`. (Directions per pixel
        /// are the override `SAMPLES`.)
        pub sample_light: u32,
        pub mode: u32,
        pub technique: u32,
        pub lod: f32,
        pub contrast: f32,
        pub scale: f32,
        pub fade: f32,
        pub strength: f32,
        pub distance_clamp: f32,
        pub pattern: u32,
        pub light_samples: u32,
        pub layers: u32,
        pub cameras: u32,
        pub light_segment: u32,
        /// 0 none, 1 the environment as VPLs (direct pass), 2 Instant Radiosity (bounce pass).
        pub vpl_mode: u32,
        pub vpl_count: u32,
        pub vpl_clamp: f32,
        /// 1: the bounce pass gathers sender pixels.
        pub near: u32,
        /// Radiance mode: 1 self-normalised per channel (direct.wgsl), 0 the paper's plain sum.
        /// (Points per direction: the override `STEPS`.)
        pub normalise: u32,
    }
}

//! `HorizonParams`: the GPU constants of every horizon pass, a pure function of the settings.

use super::{Aperture, Far, Settings};
use crate::passes::denoise::Denoise;

/// `HorizonParams::far`: what the far field is (params.wgsl's constants of the same names).
/// gtao: ao only, the far field from the direct pass's irradiance.
pub const FAR_AO: u32 = 0;
/// SH irradiance through the bent cone.
pub const FAR_SH: u32 = 1;
/// The pre-convolved diffuse map at the bent normal × F0(ao).
pub const FAR_ENVMAP: u32 = 2;
/// The environment (or the probe volume) over the slices' visible arcs.
pub const FAR_SLICES: u32 = 3;

impl Settings {
    /// The GPU constants (pure). `size` is the image size; `near`: the technique gathers
    /// near-field light (hbil, vbgi), not only occlusion (gtao).
    pub fn params(&self, near: bool, size: (u32, u32)) -> HorizonParams {
        let scale = if self.march.interleaved { 4 } else { 1 };
        HorizonParams {
            radius: self.march.radius,
            bent_normal: 0,
            falloff: self.falloff,
            max_pixels: self.march.max_pixels,
            scale,
            indirect: near as u32,
            step_power: self.march.step_power,
            reject_a: self.march.reject_a,
            reject_b: self.march.reject_b,
            layer_width: size.0.div_ceil(scale),
            layer_height: size.1.div_ceil(scale),
            // With svgf the denoiser keeps the running mean.
            temporal: (self.march.temporal && self.denoise != Denoise::Svgf) as u32,
            max_history: self.march.history as f32,
            far: match (near, self.far) {
                (false, _) => FAR_AO,
                (true, Far::Sh) => FAR_SH,
                (true, Far::Envmap) => FAR_ENVMAP,
                (true, Far::Slices) => FAR_SLICES,
            },
            fresnel: (near && self.march.fresnel) as u32,
            reject_depth: self.march.reject_depth,
            reject_normal: self.march.reject_normal,
            aperture: (self.aperture == Aperture::Matched) as u32,
            far_steps: 8,
        }
    }
}

crate::gpu_struct! {
    /// `HorizonParams` in params.wgsl.
    pub struct HorizonParams {
        /// R (m). (Slices and steps are the overrides `SLICES` and `STEPS`.)
        pub radius: f32,
        /// 1: write the bent normal (the host handed one in).
        pub bent_normal: u32,
        pub falloff: f32,
        pub max_pixels: f32,
        pub scale: u32,
        pub indirect: u32,
        pub step_power: f32,
        pub reject_a: f32,
        pub reject_b: f32,
        pub layer_width: u32,
        pub layer_height: u32,
        pub temporal: u32,
        pub max_history: f32,
        pub far: u32,
        pub fresnel: u32,
        pub reject_depth: f32,
        pub reject_normal: f32,
        pub aperture: u32,
        pub far_steps: u32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `const NAME: u32 = Nu;` of params.wgsl.
    fn wgsl_constant(name: &str) -> u32 {
        let src = include_str!("params.wgsl");
        let line = src
            .lines()
            .find(|l| l.starts_with(&format!("const {name}: u32 = ")))
            .unwrap_or_else(|| panic!("params.wgsl has no {name}"));
        let value = line.rsplit("= ").next().unwrap().trim_end_matches(';');
        value.trim_end_matches('u').parse().unwrap()
    }

    #[test]
    fn the_far_constants_match_params_wgsl() {
        for (name, value) in [
            ("FAR_AO", FAR_AO),
            ("FAR_SH", FAR_SH),
            ("FAR_ENVMAP", FAR_ENVMAP),
            ("FAR_SLICES", FAR_SLICES),
        ] {
            assert_eq!(wgsl_constant(name), value, "{name}");
        }
    }
}

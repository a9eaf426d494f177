//! `HorizonParams`: the GPU constants of every horizon pass, a pure function of the settings.

use super::{Aperture, Far, Settings};
use crate::passes::denoise::Denoise;
use bytemuck::{Pod, Zeroable};

impl Settings {
    /// The GPU constants (pure). `size` is the image size.
    pub fn params(&self, hbil: bool, size: (u32, u32)) -> HorizonParams {
        let scale = if self.interleaved { 4 } else { 1 };
        HorizonParams {
            radius: self.radius,
            _pad0: 0,
            _pad1: 0,
            falloff: self.falloff,
            max_pixels: self.max_pixels,
            scale,
            indirect: hbil as u32,
            step_power: self.step_power,
            reject_a: self.reject_a,
            reject_b: self.reject_b,
            layer_width: size.0.div_ceil(scale),
            layer_height: size.1.div_ceil(scale),
            // With svgf the denoiser keeps the running mean.
            temporal: (self.temporal && self.denoise != Denoise::Svgf) as u32,
            max_history: self.history as f32,
            far: match (hbil, self.far) {
                (false, _) => 0,
                (true, Far::Sh) => 1,
                (true, Far::Envmap) => 2,
                (true, Far::Slices) => 3,
            },
            fresnel: (hbil && self.fresnel) as u32,
            reject_depth: self.reject_depth,
            reject_normal: self.reject_normal,
            aperture: (self.aperture == Aperture::Matched) as u32,
            far_steps: 8,
        }
    }
}

/// `HorizonParams` in params.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct HorizonParams {
    pub radius: f32,
    /// (Slices and steps: the overrides `SLICES` and `STEPS`.)
    pub _pad0: u32,
    pub _pad1: u32,
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

//! Reading the frame back: AOVs, the technique's own images, the final image.

use super::Renderer;
use crate::aov::{Aov, AovImage};
use crate::technique;

impl Renderer {
    /// Writes one float AOV of the last rendered frame into `targets.aov` (rgba32float; see
    /// aov.wgsl) and submits the work; nothing is read back. Group 0 still holds the uniforms the
    /// last frame was rendered with.
    pub fn extract_aov(&mut self, aov: Aov) {
        let mut encoder = self.device.create_command_encoder(&Default::default());
        self.passes.aov.encode(
            &self.queue,
            &mut encoder,
            &mut self.quiet,
            self.settings.size,
            self.last_frame.index,
            aov,
        );
        self.queue.submit([encoder.finish()]);
    }

    /// Reads one float AOV of the last rendered frame.
    pub fn read_aov(&mut self, aov: Aov) -> AovImage {
        self.extract_aov(aov);
        let encoder = self.device.create_command_encoder(&Default::default());
        let bytes = self.read_texture(encoder, &self.targets.aov.texture, 16);
        let (w, h) = self.settings.size;
        AovImage {
            width: w,
            height: h,
            pixels: bytemuck::cast_slice::<u8, [f32; 4]>(&bytes).to_vec(),
        }
    }

    /// The technique's extra image `name` of the last rendered frame, if it has one.
    pub fn extra_texture(&self, name: &str) -> Option<&wgpu::Texture> {
        self.passes
            .technique
            .extras(self.last_frame_info())
            .into_iter()
            .find(|(n, _)| *n == name)
            .map(|(_, t)| t)
    }

    /// Names of the technique's extra images ([`Technique::extras`]).
    pub fn extra_names(&self) -> Vec<&'static str> {
        self.passes
            .technique
            .extras(self.last_frame_info())
            .into_iter()
            .map(|(n, _)| n)
            .collect()
    }

    /// Reads one of the technique's extra images of the last rendered frame (all four channels
    /// as stored), or `None` when the technique has no image of that name.
    pub fn read_extra(&self, name: &str) -> Option<AovImage> {
        let texture = self.extra_texture(name)?;
        let (w, h) = self.settings.size;
        let encoder = self.device.create_command_encoder(&Default::default());
        let pixels: Vec<[f32; 4]> = match texture.format() {
            wgpu::TextureFormat::Rgba16Float => {
                let bytes = self.read_texture(encoder, texture, 8);
                bytemuck::cast_slice::<u8, [u16; 4]>(&bytes)
                    .iter()
                    .map(|p| p.map(|b| half::f16::from_bits(b).to_f32()))
                    .collect()
            }
            wgpu::TextureFormat::Rgba32Float => {
                let bytes = self.read_texture(encoder, texture, 16);
                bytemuck::cast_slice::<u8, [f32; 4]>(&bytes).to_vec()
            }
            wgpu::TextureFormat::R32Float => {
                let bytes = self.read_texture(encoder, texture, 4);
                bytemuck::cast_slice::<u8, f32>(&bytes)
                    .iter()
                    .map(|&v| [v, 0.0, 0.0, 1.0])
                    .collect()
            }
            _ => return None,
        };
        Some(AovImage {
            width: w,
            height: h,
            pixels,
        })
    }

    fn last_frame_info(&self) -> technique::FrameInfo {
        self.last_frame
    }

    /// Reads the tonemapped sRGB image of the last rendered frame.
    pub fn read_final(&mut self) -> image::RgbaImage {
        let encoder = self.device.create_command_encoder(&Default::default());
        let bytes = self.read_texture(encoder, &self.targets.final_ldr.texture, 4);
        let (w, h) = self.settings.size;
        image::RgbaImage::from_raw(w, h, bytes).expect("readback size matches the image")
    }

    /// Copies a whole texture into host memory (tightly packed rows).
    fn read_texture(
        &self,
        encoder: wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        texel_bytes: u32,
    ) -> Vec<u8> {
        crate::util::read_texture(&self.device, &self.queue, encoder, texture, texel_bytes)
    }
}

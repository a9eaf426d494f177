//! Materials (glTF 2.0 metallic-roughness) and decoded textures.

use glam::{Vec3, Vec4};

/// How a material's alpha is used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Alpha ignored.
    Opaque,
    /// Fragments with alpha below the cutoff are discarded (foliage, chains).
    Mask { cutoff: f32 },
    /// glTF `BLEND`: rendered opaque (a deferred renderer has one surface per pixel); the loader
    /// warns.
    Blend,
}

/// A surface material. Colours are linear Rec.709.
#[derive(Clone, Debug)]
pub struct Material {
    pub name: String,
    /// Base colour factor (RGBA, linear); multiplied with the base colour texture.
    pub base_color: Vec4,
    /// Index into [`crate::Scene::textures`]; sRGB-encoded RGBA.
    pub base_color_texture: Option<usize>,
    /// Metallic factor in [0,1]; multiplied with the texture's blue channel.
    pub metallic: f32,
    /// Perceptual roughness in [0,1]; multiplied with the texture's green channel.
    pub roughness: f32,
    /// Index into [`crate::Scene::textures`]; linear, G = roughness, B = metallic.
    pub metallic_roughness_texture: Option<usize>,
    /// Emitted radiance factor (linear RGB, already multiplied by `KHR_materials_emissive_strength`).
    pub emissive: Vec3,
    /// Index into [`crate::Scene::textures`]; sRGB-encoded RGB, multiplied with `emissive`.
    pub emissive_texture: Option<usize>,
    pub alpha_mode: AlphaMode,
    /// Rendered without back-face culling.
    pub double_sided: bool,
}

impl Default for Material {
    /// A rough white dielectric (albedo 0.8).
    fn default() -> Self {
        Material {
            name: "default".into(),
            base_color: Vec4::new(0.8, 0.8, 0.8, 1.0),
            base_color_texture: None,
            metallic: 0.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
        }
    }
}

impl Material {
    /// A rough diffuse material of the given linear albedo.
    pub fn diffuse(name: &str, albedo: Vec3) -> Self {
        Material {
            name: name.into(),
            base_color: albedo.extend(1.0),
            ..Default::default()
        }
    }
}

/// How a texture's texels are to be decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureColorSpace {
    /// sRGB transfer function (base colour, emissive).
    Srgb,
    /// Raw values (metallic-roughness).
    Linear,
}

/// A decoded RGBA8 texture.
#[derive(Clone, Debug)]
pub struct Texture {
    pub width: u32,
    pub height: u32,
    /// `width * height * 4` bytes, row 0 at the top (glTF uv (0,0) is the top-left corner).
    pub rgba8: Vec<u8>,
    pub color_space: TextureColorSpace,
}

impl Texture {
    /// The texel nearest to `uv`, wrapping (glTF `REPEAT`), as linear RGBA in [0,1].
    pub fn sample_nearest(&self, u: f32, v: f32) -> Vec4 {
        let x = ((u - u.floor()) * self.width as f32) as u32 % self.width;
        let y = ((v - v.floor()) * self.height as f32) as u32 % self.height;
        let i = 4 * (y * self.width + x) as usize;
        let t = &self.rgba8[i..i + 4];
        let c = |b: u8| b as f32 / 255.0;
        match self.color_space {
            TextureColorSpace::Linear => Vec4::new(c(t[0]), c(t[1]), c(t[2]), c(t[3])),
            TextureColorSpace::Srgb => Vec4::new(
                srgb_to_linear(c(t[0])),
                srgb_to_linear(c(t[1])),
                srgb_to_linear(c(t[2])),
                c(t[3]),
            ),
        }
    }
}

impl Texture {
    /// Bilinear lookup of level 0 at `uv`, wrapping (glTF `REPEAT`), as linear RGBA. Texels are
    /// decoded before they are blended, as a GPU does for sRGB formats.
    pub fn sample_bilinear(&self, u: f32, v: f32) -> Vec4 {
        let x = u * self.width as f32 - 0.5;
        let y = v * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |xi: i64, yi: i64| {
            let xw = xi.rem_euclid(self.width as i64) as f32;
            let yw = yi.rem_euclid(self.height as i64) as f32;
            self.sample_nearest(
                (xw + 0.5) / self.width as f32,
                (yw + 0.5) / self.height as f32,
            )
        };
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = texel(x0, y0).lerp(texel(x0 + 1, y0), fx);
        let bottom = texel(x0, y0 + 1).lerp(texel(x0 + 1, y0 + 1), fx);
        top.lerp(bottom, fy)
    }
}

/// The sRGB electro-optical transfer function (IEC 61966-2-1).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The inverse of [`srgb_to_linear`].
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.0031308 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

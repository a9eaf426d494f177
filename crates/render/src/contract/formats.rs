//! The formats of the images a technique reads and writes, and of the frame's own targets: the
//! contract with the shaders (docs/src/aovs.md gives every image's meaning).

/// G-buffer formats (see gbuffer.wgsl for the meaning of every channel).
pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const ALBEDO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub const MATERIAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub const EMISSIVE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub const MOTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;
pub const VIEW_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Lighting buffers: HDR radiance or irradiance/π, linear RGB.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Ambient occlusion in [0, 1].
pub const AO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Display image, sRGB-encoded by the tonemapper.
pub const FINAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// AOV readback image.
pub const AOV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Largest image side accepted (pixels).
pub const MAX_SIZE: u32 = 8192;

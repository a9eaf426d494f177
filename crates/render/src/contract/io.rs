//! What every near-field technique reads and writes (NearFieldInputs; docs/src/architecture.md,
//! "Lifting a pass into another engine"): the images of a deferred frame, each with its format
//! and meaning. An engine that renders these images can run any technique without nearfield's
//! G-buffer pass (`examples/external_gbuffer.rs`); nearfield's own [`crate::Renderer`] is one
//! provider of them.
//!
//! Besides these images a technique binds group 0 ([`crate::contract::frame::FrameGroup`]: the
//! `View` uniform of [`crate::frame::ViewUniforms`], camera matrices of this and last frame, the
//! environment of [`crate::gpu_env::GpuEnvironment`] with its own uniform
//! ([`crate::gpu_env::EnvUniforms`]), and the far field; nearfield's own `Frame` only where the
//! technique shades with the light table).

use crate::contract::lights::LightResources;
use crate::gpu_scene::GpuScene;

/// The images a technique reads. Every one is `size` pixels, row 0 at the top, bound as a
/// sampled texture (`TEXTURE_BINDING`); the ones named "storage" are also written by some
/// technique's passes.
#[derive(Clone, Copy)]
pub struct NearFieldInputs<'a> {
    /// Image size in pixels.
    pub size: (u32, u32),
    /// View depth: r32float, metres along the camera's view direction (positive), 0 on
    /// background.
    pub view_depth: &'a wgpu::TextureView,
    /// World-space unit normal: rgba16float, xyz, w = 1 on surfaces and 0 on background.
    pub normal: &'a wgpu::TextureView,
    /// Base colour ρ, linear: rgba8unorm (or rgba8unorm-srgb), a = 1.
    pub albedo: &'a wgpu::TextureView,
    /// r = metallic, g = perceptual roughness: rgba8unorm.
    pub material: &'a wgpu::TextureView,
    /// Emitted radiance, linear: rgba16float.
    pub emission: &'a wgpu::TextureView,
    /// The outgoing diffuse radiance of direct light (emission + ρ (light irradiance +
    /// unoccluded environment irradiance)): rgba16float, one image per frame parity — frame `i`
    /// reads `[i % 2]` as this frame's and `[(i + 1) % 2]` as last frame's.
    pub direct_radiance: [&'a wgpu::TextureView; 2],
    /// Motion: rg16float, previous − current pixel position of the surface seen (pixels).
    pub motion: &'a wgpu::TextureView,
    /// The raster depth buffer of the image (depth32float), for depth peeling: techniques with
    /// `layers` > 1 need it (with [`SceneInputs`]).
    pub depth: Option<&'a wgpu::TextureView>,
}

/// The images a technique writes (storage textures of `size`).
#[derive(Clone, Copy)]
pub struct NearFieldOutputs<'a> {
    /// `ao`: r32float, (1/π) ∫ V_R cos θ dω.
    pub ao: &'a wgpu::TextureView,
    /// `env-irradiance`: rgba16float, (1/π) ∫ L_env V_R cos θ dω. It holds the direct pass's
    /// unoccluded far field E_far(n)/π on entry (the sky's SH irradiance or the probe volume's):
    /// `none` passes it on, every other technique overwrites it. An engine that runs `none`
    /// writes its own unoccluded irradiance there first.
    pub env_irradiance: &'a wgpu::TextureView,
    /// `indirect-irradiance`: rgba16float, (1/π) ∫ (1 − V_R) L_o(x′) cos θ dω.
    pub indirect_irradiance: &'a wgpu::TextureView,
    /// `light-irradiance`: rgba16float, (1/π) Σ E_l with shadows. It holds the direct pass's
    /// value on entry (the bounce reads it for senders); techniques that occlude lights in screen
    /// space (ssdo, s3ho) write their own.
    pub light_irradiance: &'a wgpu::TextureView,
}

/// nearfield's own scene, for what only it can give: the lights and their shadow maps (the
/// screen-space light occlusion of ssdo and s3ho), the geometry for depth peeling and additional
/// cameras, and virtual point lights. An engine that hands in only the images passes `None`:
/// lights are then absent and the settings that need the scene are refused.
#[derive(Clone, Copy)]
pub struct SceneInputs<'a> {
    pub scene: &'a GpuScene,
    /// The scene's light table with its shadow maps.
    pub lights: LightResources<'a>,
}

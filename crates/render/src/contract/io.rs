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
    /// r = metallic, g = perceptual roughness, b = 1 on a surface the far field's bake never
    /// saw (a dynamic mesh; hbil's `hidden=unbaked` reads it), else 0: rgba8unorm.
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

/// One image a technique writes ([`crate::contract::technique::TechniqueDesc::writes`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    Ao,
    BentNormal,
    EnvIrradiance,
    IndirectIrradiance,
    LightIrradiance,
}

impl Output {
    /// The output's name (the AOV's, where it is one).
    pub fn name(self) -> &'static str {
        match self {
            Output::Ao => "ao",
            Output::BentNormal => "bent-normal",
            Output::EnvIrradiance => "env-irradiance",
            Output::IndirectIrradiance => "indirect-irradiance",
            Output::LightIrradiance => "light-irradiance",
        }
    }
}

/// The images a technique writes (storage textures of `size`). A technique writes the ones its
/// descriptor declares (`TechniqueDesc::writes`) and no other: a host hands in those (the bent
/// normal where it wants it) and may leave the rest `None`. nearfield's own frame hands in all
/// but the bent normal, and fills env-irradiance and indirect-irradiance itself after a
/// technique that writes only ao (gtao): env-irradiance = ao × E_far(n), indirect = 0.
#[derive(Clone, Copy)]
pub struct NearFieldOutputs<'a> {
    /// `ao`: r32float, (1/π) ∫ V_R cos θ dω. Every technique writes it.
    pub ao: &'a wgpu::TextureView,
    /// The bent normal: rgba16float, xyz the unit world direction of the cosine-weighted mean
    /// unoccluded direction within R, w = 1; (0, 0, 0, 0) on background. Written by gtao, hbil
    /// and vbgi where it is given.
    pub bent_normal: Option<&'a wgpu::TextureView>,
    /// `env-irradiance`: rgba16float, (1/π) ∫ L_env V_R cos θ dω. It holds the direct pass's
    /// unoccluded far field E_far(n)/π on entry (the sky's SH irradiance or the probe volume's):
    /// `none` passes it on, every technique that declares it overwrites it. An engine that runs
    /// `none` writes its own unoccluded irradiance there first.
    pub env_irradiance: Option<&'a wgpu::TextureView>,
    /// `indirect-irradiance`: rgba16float, (1/π) ∫ (1 − V_R) L_o(x′) cos θ dω.
    pub indirect_irradiance: Option<&'a wgpu::TextureView>,
    /// `light-irradiance`: rgba16float, (1/π) Σ E_l with shadows. It holds the direct pass's
    /// value on entry (the bounce reads it for senders); techniques that occlude lights in screen
    /// space (ssdo, s3ho) write their own.
    pub light_irradiance: Option<&'a wgpu::TextureView>,
}

impl<'a> NearFieldOutputs<'a> {
    /// The image of `output`, if the host handed it in.
    pub fn get(&self, output: Output) -> Option<&'a wgpu::TextureView> {
        match output {
            Output::Ao => Some(self.ao),
            Output::BentNormal => self.bent_normal,
            Output::EnvIrradiance => self.env_irradiance,
            Output::IndirectIrradiance => self.indirect_irradiance,
            Output::LightIrradiance => self.light_irradiance,
        }
    }

    /// The image of `output`, or an error naming the technique that writes it.
    pub fn require(
        &self,
        technique: &str,
        output: Output,
    ) -> Result<&'a wgpu::TextureView, crate::RenderError> {
        self.get(output).ok_or_else(|| crate::RenderError::Setting {
            technique: technique.into(),
            msg: format!(
                "writes {}, which the host did not hand in (NearFieldOutputs)",
                output.name()
            ),
        })
    }
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

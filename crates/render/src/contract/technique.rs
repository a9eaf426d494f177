//! The technique API: what a technique is made from ([`TechniqueContext`]), what it does each
//! frame ([`Technique`]), how it is registered ([`TechniqueDesc`]), and the textures it owns.
//! A technique family imports this module, the passes it reuses and its settings; the registry
//! (`crate::technique`) imports the families.

use crate::RenderError;
use crate::bindings::PassLayout;
use crate::contract::frame::FrameGroup;
pub use crate::contract::io::Output;
use crate::contract::io::{NearFieldInputs, NearFieldOutputs, SceneInputs};
use crate::contract::lights::{LightResources, NoLights};
use crate::gpu_env::GpuEnvironment;
use crate::profiler::GpuProfiler;
use crate::settings::denoise::{Denoise, SvgfConfig};
pub use crate::settings::{Preset, Setting, TechniqueParams};

/// What a technique may bind when it is created.
pub struct TechniqueContext<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    /// Group 0 of every pass: the frame's uniforms and the environment.
    pub frame_group: &'a FrameGroup,
    /// The images the technique reads.
    pub inputs: &'a NearFieldInputs<'a>,
    /// The images it writes.
    pub outputs: &'a NearFieldOutputs<'a>,
    /// The environment (its CPU map: ssdo-vpl's lights come from it).
    pub env: &'a GpuEnvironment,
    /// nearfield's scene where there is one (lights, shadow maps, geometry for depth peeling
    /// and virtual point lights); `None` for images from another engine.
    pub scene: Option<SceneInputs<'a>>,
    /// The device may use pack2x16float / unpack2x16float.
    pub pack_half: bool,
}

impl<'a> TechniqueContext<'a> {
    /// The scene's light bindings, or `fallback`'s where there is no scene (make it with
    /// `ctx.scene.is_none().then(|| NoLights::new(device))`).
    pub fn lights<'b>(&'b self, fallback: Option<&'b NoLights>) -> LightResources<'b>
    where
        'a: 'b,
    {
        match (self.scene, fallback) {
            (Some(s), _) => s.lights,
            (None, Some(f)) => f.resources(),
            (None, None) => panic!("TechniqueContext::lights: no scene and no fallback"),
        }
    }

    /// The scene, or an error naming what needs it.
    pub fn require_scene(
        &self,
        technique: &str,
        what: &str,
    ) -> Result<SceneInputs<'a>, RenderError> {
        self.scene.ok_or_else(|| RenderError::Setting {
            technique: technique.into(),
            msg: format!("{what} needs nearfield's scene (lights, shadow maps, geometry)"),
        })
    }
}

/// What a technique learns about the frame it records.
#[derive(Clone, Copy, Debug)]
pub struct FrameInfo {
    /// Frame number since the renderer was made; `index % 2` selects the ping-pong side: this
    /// frame's direct radiance is `targets.direct_radiance[index % 2]`, last frame's the other.
    pub index: u32,
    /// Last frame's buffers may be reused (false on the first frame and after a camera cut).
    pub history: bool,
}

impl FrameInfo {
    /// This frame's side of every ping-pong pair (0 or 1).
    pub fn side(&self) -> usize {
        (self.index % 2) as usize
    }
}

/// A created technique: records its passes each frame.
pub trait Technique: Send + Sync {
    fn name(&self) -> &'static str;
    /// Uploads what this frame needs from the CPU (e.g. the additional cameras' matrices, which
    /// follow the main camera) before [`Self::encode`].
    fn prepare(&self, _queue: &wgpu::Queue, _camera: &nearfield_scene::Camera) {}
    /// Records this frame's passes. Allocates nothing.
    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        frame: FrameInfo,
    );
    /// Applies new settings in place where they change only what the passes read from their
    /// uniforms (floats, toggles, choices): the parameter buffers are written with
    /// `write_buffer` and the result is `Ok(true)`. `Ok(false)` when a count or another setting
    /// that shapes pipelines or resources changed: the technique must be rebuilt. On error
    /// (settings out of range) nothing changes.
    fn update(
        &mut self,
        _queue: &wgpu::Queue,
        _params: &TechniqueParams,
    ) -> Result<bool, RenderError> {
        Ok(false)
    }
    /// Technique-specific images of the frame `frame` (full resolution, level 0), by name, for
    /// inspection and tests (e.g. hbil's reprojected radiance before and after hole filling).
    fn extras(&self, _frame: FrameInfo) -> Vec<(&'static str, &wgpu::Texture)> {
        Vec::new()
    }
}

/// Builds a technique's pipelines and bind groups.
/// (The denoiser, where the technique declares one, is applied by the registry around it.)
pub type CreateFn =
    fn(&TechniqueContext, &TechniqueParams) -> Result<Box<dyn Technique>, RenderError>;

/// Parses a technique's settings without building anything.
pub type CheckFn = fn(&TechniqueParams) -> Result<(), String>;

/// A registry entry.
pub struct TechniqueDesc {
    pub name: &'static str,
    /// The family whose settings it shares (its folder `technique/<family>/`; the book's page
    /// `settings-<family>.md`).
    pub family: &'static str,
    /// One line for `--help` and the book.
    pub summary: &'static str,
    pub create: CreateFn,
    /// Parses the settings as `create` does, without a device: what a command checks before it
    /// loads anything. `create` may still refuse a combination that depends on the image size.
    pub check: CheckFn,
    /// Every `--set` key with its documented range and default (what the viewer shows as
    /// sliders, checkboxes and lists; a test checks that the parser agrees with it).
    pub settings: &'static [Setting],
    /// Named `quality` presets (`--set quality=NAME`): the settings each one stands for.
    pub presets: &'static [Preset],
    /// The technique's choice of the shared denoiser (`denoise=svgf`) and svgf's configuration,
    /// parsed from its settings; `None` for a technique without one. The registry wraps the
    /// technique that `create` makes in the denoiser where this says `svgf`.
    pub denoise: Option<DenoiseFn>,
    /// Every pass's binding declaration (what the reflection test checks against naga); passes
    /// shared within a family appear under one name.
    pub pass_layouts: fn() -> Vec<PassLayout>,
    /// The outputs it writes (`NearFieldOutputs`), and no other. Each must be handed in, except
    /// the bent normal, which is written where it is given.
    pub writes: &'static [Output],
    /// How its light is counted against a probe volume, once (the book, "Near and far").
    pub far_rule: FarRule,
    /// Settings it takes over its defaults where the frame has a probe volume, unless the first
    /// one's key is given ([`crate::technique::Spec::params_for`]): what keeps it from taking
    /// away light the volume already holds (the book, "Near and far").
    pub with_volume: &'static [(&'static str, &'static str)],
}

/// How nearfield's frame counts a technique's near field against the probe volume's irradiance,
/// which already holds the occlusion its probes see and the light of those occluders
/// (passes/irradiance_terms.wgsl). Nothing changes under the open sky.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FarRule {
    /// Scalar occlusion (ssao, gtao, ssdo, ssbn, instant-radiosity): of the volume's irradiance,
    /// what its visibility v keeps beyond the volume's own visibility within R, the occluders lit
    /// as the receiver is (its albedo, its direct light and GTAO's multi-bounce fit):
    /// min(E_far, E(v)) with E(ao_far) = E_far (irradiance_terms.wgsl's `occluded_light`), its
    /// far part E_open · v and the rest near light; its own bounce (ssdo's senders,
    /// instant-radiosity's VPLs within R) keeps the share of the occlusion the volume does not
    /// hold, (1 − h) · indirect.
    Occlusion,
    /// Directional occlusion with its own near light (s3ho): the share h of the occlusion the
    /// technique finds that the volume holds takes the volume's light — the image's
    /// mix(env, E_far, h), env its far part and the rest near, with (1 − h) · indirect;
    /// h = min(1, (1 − ao_far) / (1 − ao)).
    Directional,
    /// Near-field light that replaces the volume's in the directions the technique finds
    /// occluded (hbil, vbgi): as written.
    Replace,
    /// Its own environment (ssdo-vpl, `none`): as written.
    Own,
}

impl TechniqueDesc {
    /// Whether its `with_volume` settings apply where the frame has a probe volume: it has some,
    /// and the first one's key is not among those `given`.
    pub fn takes_with_volume(&self, given: impl Fn(&str) -> bool) -> bool {
        self.with_volume
            .first()
            .is_some_and(|(switch, _)| !given(switch))
    }
}

impl FarRule {
    /// The value of irradiance_terms.wgsl's `FAR_RULE`.
    pub fn constant(self) -> f64 {
        match self {
            FarRule::Own | FarRule::Replace => 0.0,
            FarRule::Occlusion => 1.0,
            FarRule::Directional => 2.0,
        }
    }
}

/// Parses a technique's denoiser choice and svgf configuration from its settings.
pub type DenoiseFn = fn(&TechniqueParams) -> Result<(Denoise, SvgfConfig), String>;

/// Rejects `--set` keys a technique does not know, naming the ones it does.
pub fn reject_unknown_keys(
    technique: &str,
    params: &TechniqueParams,
    known: &[&str],
) -> Result<(), RenderError> {
    for (k, _) in &params.set {
        if !known.contains(&k.as_str()) {
            return Err(RenderError::Setting {
                technique: technique.into(),
                msg: if known.is_empty() {
                    format!("unknown setting '{k}' (this technique has no settings)")
                } else {
                    format!("unknown setting '{k}' (known: {})", known.join(", "))
                },
            });
        }
    }
    Ok(())
}

/// A screen-sized texture a technique owns (storage + sampled + copy source).
pub fn screen_texture(
    device: &wgpu::Device,
    size: (u32, u32),
    label: &str,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    layered_texture(device, size, 1, label, format)
}

/// A texture array (`layers` layers of `size`) a technique owns (storage + sampled + copy
/// source).
pub fn layered_texture(
    device: &wgpu::Device,
    size: (u32, u32),
    layers: u32,
    label: &str,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

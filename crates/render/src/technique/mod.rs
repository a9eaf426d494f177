//! Near-field techniques and their registry.
//!
//! A technique reads the G-buffer, the direct radiance (this frame's and last frame's) and the
//! environment, and writes `ao`, `env_irradiance` and `indirect_irradiance` (DESIGN.md's AOV
//! definitions; `crate::targets`). The registry is the one list that the command line, the
//! viewer, `bench` and `compare` enumerate.

pub mod horizon;
pub mod none;
pub mod s3ho;
pub mod samples;
pub mod ssdo;
pub mod vbgi;

use crate::RenderError;
use crate::gpu_env::GpuEnvironment;
use crate::inputs::{NearFieldInputs, NearFieldOutputs, SceneInputs};
use crate::passes::FrameGroup;
use crate::passes::shadow::{LightResources, NoLights};
use crate::profiler::GpuProfiler;
pub use crate::settings::{
    Preset, Setting, SettingKind, TechniqueParams, keys, parse_integer, parse_number, parse_on_off,
};

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
            (Some(s), _) => s.shadows.light_resources(&s.scene.lights),
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
pub trait Technique {
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
pub type CreateFn =
    fn(&TechniqueContext, &TechniqueParams) -> Result<Box<dyn Technique>, RenderError>;

/// Parses a technique's settings without building anything.
pub type CheckFn = fn(&TechniqueParams) -> Result<(), String>;

/// A registry entry.
pub struct TechniqueDesc {
    pub name: &'static str,
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
}

/// Replaces `quality=NAME` in `params.set` by the preset's settings, placed first so that
/// explicit settings (and `--samples`, `--radius`) refine it. A technique without presets keeps
/// the key (and rejects it as unknown).
pub fn expand_presets(
    desc: &TechniqueDesc,
    params: &TechniqueParams,
) -> Result<TechniqueParams, RenderError> {
    if desc.presets.is_empty() {
        return Ok(params.clone());
    }
    let mut preset_set = Vec::new();
    let mut rest = Vec::new();
    for (k, v) in &params.set {
        if k != "quality" {
            rest.push((k.clone(), v.clone()));
            continue;
        }
        let preset =
            desc.presets
                .iter()
                .find(|p| p.name == v)
                .ok_or_else(|| RenderError::Setting {
                    technique: desc.name.into(),
                    msg: format!(
                        "quality={v}: expected {}",
                        desc.presets
                            .iter()
                            .map(|p| p.name)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                })?;
        preset_set.clear();
        for (pk, pv) in preset.set {
            // `--samples` is `steps` for the horizon techniques.
            let overridden = (matches!(*pk, "samples" | "steps") && params.samples.is_some())
                || (*pk == "radius" && params.radius.is_some());
            if !overridden {
                preset_set.push((pk.to_string(), pv.to_string()));
            }
        }
    }
    preset_set.extend(rest);
    Ok(TechniqueParams {
        samples: params.samples,
        radius: params.radius,
        set: preset_set,
    })
}

/// Every technique, in the order shown to users.
pub const REGISTRY: &[TechniqueDesc] = &[
    none::DESC,
    ssdo::SSAO,
    ssdo::SSDO,
    ssdo::SSDO_VPL,
    ssdo::INSTANT_RADIOSITY,
    s3ho::S3HO,
    s3ho::SSBN,
    horizon::GTAO,
    horizon::HBIL,
    vbgi::VBGI,
];

/// Names of all registered techniques.
pub fn names() -> Vec<&'static str> {
    REGISTRY.iter().map(|t| t.name).collect()
}

/// Splits a method spec `name` or `name:key=value+key=value` (a technique with settings, as
/// `bench` and `compare` accept in `--methods`) into the name and its settings.
pub fn split_spec(spec: &str) -> (&str, Vec<(String, String)>) {
    match spec.split_once(':') {
        None => (spec, Vec::new()),
        Some((name, rest)) => (
            name,
            rest.split('+')
                .map(|kv| match kv.split_once('=') {
                    Some((k, v)) => (k.trim().to_string(), v.trim().to_string()),
                    None => (kv.trim().to_string(), String::new()),
                })
                .collect(),
        ),
    }
}

/// The parameters a technique is made with from a spec (`name` or `name:key=value+…`) and the
/// command line's: the spec's settings after the others, `quality` expanded first.
pub fn resolve_params(
    spec: &str,
    params: &TechniqueParams,
) -> Result<(&'static TechniqueDesc, TechniqueParams), RenderError> {
    let desc = find(spec)?;
    let mut params = params.clone();
    params.set.extend(split_spec(spec).1);
    let params = expand_presets(desc, &params)?;
    Ok((desc, params))
}

/// Resolves a spec against the command line's parameters and parses its settings without a
/// device: the error `create` would give for a refused setting, before anything is loaded.
pub fn check_spec(spec: &str, params: &TechniqueParams) -> Result<(), RenderError> {
    let (desc, resolved) = resolve_params(spec, params)?;
    (desc.check)(&resolved).map_err(RenderError::setting(desc.name))
}

/// Looks a technique up by name (or by a `name:key=value` spec).
pub fn find(spec: &str) -> Result<&'static TechniqueDesc, RenderError> {
    let name = split_spec(spec).0;
    REGISTRY
        .iter()
        .find(|t| t.name == name)
        .ok_or_else(|| RenderError::UnknownTechnique {
            name: name.to_string(),
            known: names().join(", "),
        })
}

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

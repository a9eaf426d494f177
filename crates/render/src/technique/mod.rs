//! Near-field techniques and their registry.
//!
//! A technique reads the G-buffer, the direct radiance (this frame's and last frame's) and the
//! environment, and writes `ao`, `env_irradiance` and `indirect_irradiance` (DESIGN.md's AOV
//! definitions; `crate::targets`). The registry is the one list that the command line, the
//! viewer, `bench` and `compare` enumerate.

pub mod horizon;
pub mod none;
pub mod s3ho;
pub mod ssdo;

use crate::RenderError;
use crate::gpu_env::GpuEnvironment;
use crate::gpu_scene::GpuScene;
use crate::passes::shadow::ShadowPass;
use crate::profiler::GpuProfiler;
use crate::targets::FrameTargets;

/// Generic settings from the command line, interpreted by each technique: `--samples`,
/// `--radius` and `--set key=value`.
#[derive(Clone, Debug, Default)]
pub struct TechniqueParams {
    /// Samples per pixel (`--samples`); `None` = the technique's default.
    pub samples: Option<u32>,
    /// Near-field radius in metres (`--radius`, `inf` allowed); `None` = default.
    pub radius: Option<f32>,
    /// `--set key=value` pairs, in order.
    pub set: Vec<(String, String)>,
}

/// What a technique may bind when it is created.
pub struct TechniqueContext<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub frame: &'a wgpu::Buffer,
    pub targets: &'a FrameTargets,
    pub env: &'a GpuEnvironment,
    pub scene: &'a GpuScene,
    pub shadows: &'a ShadowPass,
    /// The device may use pack2x16float / unpack2x16float.
    pub pack_half: bool,
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
    /// Records this frame's passes. Allocates nothing.
    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        frame: FrameInfo,
    );
    /// Technique-specific images of the frame `frame` (full resolution, level 0), by name, for
    /// inspection and tests (e.g. hbil's reprojected radiance before and after hole filling).
    fn extras(&self, _frame: FrameInfo) -> Vec<(&'static str, &wgpu::Texture)> {
        Vec::new()
    }
}

/// Builds a technique's pipelines and bind groups.
pub type CreateFn =
    fn(&TechniqueContext, &TechniqueParams) -> Result<Box<dyn Technique>, RenderError>;

/// A registry entry.
pub struct TechniqueDesc {
    pub name: &'static str,
    /// One line for `--help` and the README.
    pub summary: &'static str,
    pub create: CreateFn,
}

/// Every technique, in the order shown to users.
pub const REGISTRY: &[TechniqueDesc] = &[
    none::DESC,
    ssdo::SSAO,
    ssdo::SSDO,
    s3ho::S3HO,
    s3ho::SSBN,
    horizon::GTAO,
    horizon::HBIL,
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

/// `key=on|off` (also true/false, 1/0).
pub fn parse_on_off(key: &str, v: &str) -> Result<bool, String> {
    match v {
        "on" | "true" | "1" => Ok(true),
        "off" | "false" | "0" => Ok(false),
        _ => Err(format!("{key}={v}: expected on or off")),
    }
}

/// `key=number` within `lo..=hi`.
pub fn parse_number(key: &str, v: &str, lo: f32, hi: f32) -> Result<f32, String> {
    let x: f32 = v
        .parse()
        .map_err(|_| format!("{key}={v}: expected a number"))?;
    if !(x.is_finite() && x >= lo && x <= hi) {
        return Err(format!("{key}={v}: must be in {lo}..={hi}"));
    }
    Ok(x)
}

/// Records one full-screen compute dispatch (8×8 groups over `size`) as its own timed pass.
pub fn dispatch_screen(
    encoder: &mut wgpu::CommandEncoder,
    profiler: &mut GpuProfiler,
    label: &'static str,
    pipeline: &wgpu::ComputePipeline,
    bind_group: &wgpu::BindGroup,
    size: (u32, u32),
) {
    let (gx, gy) = crate::util::groups_8x8(size);
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: profiler.compute(label),
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, bind_group, &[]);
    pass.dispatch_workgroups(gx, gy, 1);
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

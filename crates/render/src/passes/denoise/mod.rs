//! `svgf`: the shared spatio-temporal denoiser of the techniques' AOVs (`denoise=svgf` on
//! ssdo, s3ho, gtao, hbil and vbgi; vbgi's default).
//!
//! The model is SVGF (Schied et al. 2017, "Spatiotemporal Variance-Guided Filtering: Real-Time
//! Reconstruction for Path-Traced Global Illumination"). A technique made with
//! [`create_denoised`] writes its `ao`, `env-irradiance` and `indirect-irradiance` into the
//! denoiser's own images. The denoiser then writes the AOVs, of the last two only those the
//! technique declares (gtao declares neither; the host's images keep what they hold):
//!   temporal   running means of the three through the motion vectors, with last frame's taps
//!              rejected by `history_taps` (common.wgsl: tangent plane, normal, footprint), and
//!              the first two moments of ao and of the indirect light's luminance
//!   variance   Var = E[v²] − E[v]² per pixel; under 4 frames of history, from the 5×5
//!              geometry-weighted neighbourhood's moments, scaled by 4/count
//!   atrous     `svgf_iterations` edge-aware à-trous iterations (spacing 1, 2, 4, …): weights
//!              from tangent-plane distance (σ_z), normals (σ_n) and the value difference in
//!              units of the filtered standard deviation (σ_l); variance filtered with the squared
//!              weights
//!   resolve    the last iteration into the AOVs
//! Deviations from the paper, and why:
//! - The signals are the technique's irradiance AOVs, which carry no albedo (nothing to
//!   demodulate); ao and env-irradiance share ao's value term, indirect-irradiance has its own.
//! - The running mean weighs the new frame by 1/min(count, history) (the paper: a constant
//!   α = 0.2): our scenes are static or slowly moving and the techniques' per-frame patterns
//!   rotate, so a long mean converges where α = 0.2 would keep 20 % of a frame's pattern.
//! - The history holds the unfiltered mean (the paper feeds the first à-trous iteration back):
//!   the history stays an unbiased mean, and the spatial filter never compounds over frames.
//! - 3×3 taps (¼, ½, ¼) per iteration instead of 5×5 B3-spline taps: a third of the cost; four
//!   iterations reach ±15 pixels, beyond the 4×4 interleaving period.
//! - The variance's 3×3 prefilter uses the iteration's own taps (spacing = step).
//! - Depth is compared by distance from the tangent plane relative to view depth (as the
//!   bilateral blur), not by the screen-space depth gradient.
//! - ao's and env-irradiance's taps also fall with their distance from the centre in the world,
//!   by e at `svgf_reach` × R (taps within 3 pixels exempt): where the view is deep the four
//!   iterations' ±15 pixels span metres, and averaging the visibility within R over several R
//!   mixed separate neighbourhoods' occlusion (Sponza at 160×90: vbgi 0.321 → 0.288; the book,
//!   "vbgi"). The near light keeps the whole span.

pub mod atrous;
pub mod resolve;
pub mod temporal;
pub mod variance;

use crate::RenderError;
use crate::bindings::PassLayout;
use crate::contract::formats::{AO_FORMAT, HDR_FORMAT};
use crate::contract::io::{NearFieldInputs, NearFieldOutputs, Output};
use crate::contract::technique::{
    FrameInfo, Technique, TechniqueContext, TechniqueParams, screen_texture,
};
use crate::passes::{ComputeStep, PingPong};
use crate::profiler::GpuProfiler;
use crate::settings::Declared;
pub use crate::settings::denoise::{Denoise, SvgfConfig, SvgfSettings};
use crate::util::{self, view};
use wgpu::util::DeviceExt;

/// Composes a denoise kernel's source.
fn source_of(kernel: &str) -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        include_str!("params.wgsl"),
        kernel,
    ])
}

/// The binding declarations the reflection test checks.
pub fn pass_layouts() -> Vec<PassLayout> {
    vec![
        temporal::pass_layout(),
        variance::pass_layout(),
        atrous::pass_layout(),
        resolve::pass_layout(),
    ]
}

pub use crate::contract::technique::DenoiseFn as ConfigFn;

crate::gpu_struct! {
    /// `SvgfParams` in params.wgsl.
    pub struct SvgfParams {
        pub temporal: u32,
        pub max_history: f32,
        pub reject_depth: f32,
        pub reject_normal: f32,
        pub sigma_l: f32,
        pub sigma_z: f32,
        pub sigma_n: f32,
        pub step: i32,
        pub clamp: f32,
        pub motion: f32,
        pub reach: f32,
        pub _pad2: f32,
    }
}

/// The uniforms of à-trous iteration spacing `step` (the first also serves temporal and
/// variance).
fn svgf_params(c: &SvgfConfig, step: i32) -> SvgfParams {
    SvgfParams {
        temporal: c.temporal as u32,
        max_history: c.history as f32,
        reject_depth: c.reject_depth,
        reject_normal: c.reject_normal,
        sigma_l: c.svgf.svgf_luminance,
        sigma_z: c.svgf.svgf_depth,
        sigma_n: c.svgf.svgf_normal,
        step,
        clamp: c.svgf.svgf_clamp,
        motion: c.svgf.svgf_motion,
        reach: c.svgf.svgf_reach * c.radius,
        _pad2: 0.0,
    }
}

/// A technique whose AOVs pass through svgf.
struct Denoised {
    inner: Box<dyn Technique>,
    config_fn: ConfigFn,
    config: SvgfConfig,
    size: (u32, u32),
    /// One `SvgfParams` per à-trous iteration (its `step`); the first also serves temporal and
    /// variance.
    params: Vec<wgpu::Buffer>,
    temporal: ComputeStep,
    variance: ComputeStep,
    atrous: ComputeStep,
    resolve: ComputeStep,
    temporal_bg: PingPong<wgpu::BindGroup>,
    variance_bg: PingPong<wgpu::BindGroup>,
    /// Per iteration, per side.
    atrous_bg: Vec<PingPong<wgpu::BindGroup>>,
    resolve_bg: wgpu::BindGroup,
    extras: PingPong<Vec<(&'static str, wgpu::Texture)>>,
    _textures: Vec<wgpu::Texture>,
}

/// Makes the technique `inner` builds; with `denoise=svgf` (by `config`) its AOVs are written
/// into the denoiser's images and the denoiser writes `ctx.outputs` (light-irradiance passes
/// through untouched). `writes`: what the technique declares; env-irradiance and
/// indirect-irradiance that it does not declare are left as the host handed them in (gtao's
/// env-irradiance holds the direct pass's unoccluded far field, which ao scales).
pub fn create_denoised(
    ctx: &TechniqueContext,
    tp: &TechniqueParams,
    name: &str,
    writes: &[Output],
    config_fn: ConfigFn,
    inner: impl FnOnce(&TechniqueContext) -> Result<Box<dyn Technique>, RenderError>,
) -> Result<Box<dyn Technique>, RenderError> {
    let (denoise, config) = config_fn(tp).map_err(RenderError::setting(name))?;
    if denoise != Denoise::Svgf {
        return inner(ctx);
    }
    let device = ctx.device;
    let i = ctx.inputs;
    let iterations = config.svgf.svgf_iterations;
    let images = SvgfImages::new(device, i.size, writes, iterations as usize);
    let view = |t: &wgpu::Texture| t.create_view(&Default::default());
    let raw_views = images.raw.each_ref().map(view);
    let spare_views = images.spare.each_ref().map(|t| t.as_ref().map(view));
    let out_env = match &spare_views[0] {
        Some(v) => v,
        None => ctx.outputs.require(name, Output::EnvIrradiance)?,
    };
    let out_indirect = match &spare_views[1] {
        Some(v) => v,
        None => ctx.outputs.require(name, Output::IndirectIrradiance)?,
    };
    let inner = inner(&TechniqueContext {
        outputs: &NearFieldOutputs {
            ao: &raw_views[0],
            bent_normal: ctx.outputs.bent_normal,
            env_irradiance: Some(&raw_views[1]),
            indirect_irradiance: Some(&raw_views[2]),
            light_irradiance: ctx.outputs.light_irradiance,
        },
        ..*ctx
    })?;
    let params: Vec<wgpu::Buffer> = (0..iterations)
        .map(|k| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("svgf params"),
                contents: bytemuck::bytes_of(&svgf_params(&config, 1 << k)),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            })
        })
        .collect();
    let layouts = [
        temporal::TemporalBindings::layout(device),
        variance::VarianceBindings::layout(device),
        atrous::AtrousBindings::layout(device),
        resolve::ResolveBindings::layout(device),
    ];
    let step = |label: &'static str, source: String, entry: &str, layout| {
        let module = crate::pipeline_cache::shader_module(device, label, &source);
        ComputeStep::new(device, label, &module, entry, ctx.frame_group, layout, &[])
    };
    Ok(Box::new(Denoised {
        inner,
        config_fn,
        config,
        size: i.size,
        temporal: step("svgf temporal", temporal::source(), "temporal", &layouts[0]),
        variance: step("svgf variance", variance::source(), "variance", &layouts[1]),
        atrous: step("svgf atrous", atrous::source(), "atrous", &layouts[2]),
        resolve: step("svgf resolve", resolve::source(), "resolve", &layouts[3]),
        temporal_bg: temporal_groups(device, &layouts[0], &params[0], i, &images),
        variance_bg: variance_groups(device, &layouts[1], &params[0], i, &images),
        atrous_bg: atrous_groups(device, &layouts[2], &params, i, &images),
        resolve_bg: resolve::ResolveBindings {
            final_signal: &view(&images.last()[0]),
            final_env: &view(&images.last()[1]),
            final_indirect: &view(&images.last()[2]),
            out_ao: ctx.outputs.ao,
            out_env,
            out_indirect,
        }
        .bind_group(device, &layouts[3]),
        extras: images.extras(),
        params,
        _textures: images.into_textures(),
    }))
}

/// The denoiser's images.
struct SvgfImages {
    /// The technique's raw ao, env- and indirect-irradiance (what it writes instead of the
    /// outputs).
    raw: [wgpu::Texture; 3],
    /// Where the filtered env- and indirect-irradiance go when the technique does not declare
    /// them (their filtered zeros), instead of the host's outputs.
    spare: [Option<wgpu::Texture>; 2],
    /// The temporal images, each a pair (this frame's, last frame's; swapped by frame parity):
    /// the luminance moments, the running means of env and indirect, the geometry they belong to.
    moments: [wgpu::Texture; 2],
    env: [wgpu::Texture; 2],
    indirect: [wgpu::Texture; 2],
    geometry: [wgpu::Texture; 2],
    /// Two sets of (signal, env, indirect) for the à-trous ping-pong.
    work: [[wgpu::Texture; 3]; 2],
    iterations: usize,
}

impl SvgfImages {
    fn new(device: &wgpu::Device, size: (u32, u32), writes: &[Output], iterations: usize) -> Self {
        let full = |label: &str, format| screen_texture(device, size, label, format);
        let unwritten = |output: Output, label: &str| {
            (!writes.contains(&output)).then(|| full(label, HDR_FORMAT))
        };
        let pair = |label: &str, format| {
            [
                full(&format!("{label} 0"), format),
                full(&format!("{label} 1"), format),
            ]
        };
        let f32x4 = wgpu::TextureFormat::Rgba32Float;
        SvgfImages {
            raw: [
                full("svgf raw ao", AO_FORMAT),
                full("svgf raw env", HDR_FORMAT),
                full("svgf raw indirect", HDR_FORMAT),
            ],
            spare: [
                unwritten(Output::EnvIrradiance, "svgf env (not declared)"),
                unwritten(Output::IndirectIrradiance, "svgf indirect (not declared)"),
            ],
            moments: pair("svgf moments", f32x4),
            env: pair("svgf env history", HDR_FORMAT),
            indirect: pair("svgf indirect history", HDR_FORMAT),
            geometry: pair("svgf geometry", f32x4),
            work: [0, 1].map(|k| {
                [
                    full(&format!("svgf signal {k}"), HDR_FORMAT),
                    full(&format!("svgf env {k}"), HDR_FORMAT),
                    full(&format!("svgf indirect {k}"), HDR_FORMAT),
                ]
            }),
            iterations,
        }
    }

    /// The set the last à-trous iteration wrote.
    fn last(&self) -> &[wgpu::Texture; 3] {
        &self.work[self.iterations % 2]
    }

    /// The denoiser's images by name, per frame parity.
    fn extras(&self) -> PingPong<Vec<(&'static str, wgpu::Texture)>> {
        PingPong::from_fn(|side| {
            vec![
                ("denoise-history", self.env[side].clone()),
                ("denoise-moments", self.moments[side].clone()),
                ("denoise-raw-ao", self.raw[0].clone()),
                ("denoise-raw-indirect", self.raw[2].clone()),
            ]
        })
    }

    fn into_textures(self) -> Vec<wgpu::Texture> {
        let mut textures: Vec<wgpu::Texture> = Vec::new();
        textures.extend(self.raw);
        textures.extend(self.moments);
        textures.extend(self.env);
        textures.extend(self.indirect);
        textures.extend(self.geometry);
        textures.extend(self.work.into_iter().flatten());
        textures.extend(self.spare.into_iter().flatten());
        textures
    }
}

/// Temporal accumulation's groups, per frame parity: the raw AOVs and last frame's means in,
/// this frame's means out.
fn temporal_groups(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    i: &NearFieldInputs,
    m: &SvgfImages,
) -> PingPong<wgpu::BindGroup> {
    PingPong::from_fn(|side| {
        let prev = 1 - side;
        temporal::TemporalBindings {
            params,
            gb_normal: i.normal,
            gb_view_depth: i.view_depth,
            gb_motion: i.motion,
            raw_ao: &view(&m.raw[0]),
            raw_env: &view(&m.raw[1]),
            raw_indirect: &view(&m.raw[2]),
            prev_moments: &view(&m.moments[prev]),
            prev_env: &view(&m.env[prev]),
            prev_indirect: &view(&m.indirect[prev]),
            prev_geometry: &view(&m.geometry[prev]),
            acc_moments: &view(&m.moments[side]),
            acc_env: &view(&m.env[side]),
            acc_indirect: &view(&m.indirect[side]),
            acc_geometry: &view(&m.geometry[side]),
        }
        .bind_group(device, layout)
    })
}

/// The variance estimate's groups, per frame parity: the signal à-trous starts from.
fn variance_groups(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    i: &NearFieldInputs,
    m: &SvgfImages,
) -> PingPong<wgpu::BindGroup> {
    PingPong::from_fn(|side| {
        variance::VarianceBindings {
            params,
            gb_normal: i.normal,
            gb_view_depth: i.view_depth,
            acc_moments: &view(&m.moments[side]),
            acc_env: &view(&m.env[side]),
            out_signal: &view(&m.work[0][0]),
        }
        .bind_group(device, layout)
    })
}

/// The à-trous groups, per iteration and frame parity: iteration k reads set k % 2 and writes
/// set (k + 1) % 2; iteration 0 reads the variance pass's signal (set 0) with this frame's env
/// and indirect means.
fn atrous_groups(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    params: &[wgpu::Buffer],
    i: &NearFieldInputs,
    m: &SvgfImages,
) -> Vec<PingPong<wgpu::BindGroup>> {
    (0..params.len())
        .map(|k| {
            let (from, to) = (&m.work[k % 2], &m.work[(k + 1) % 2]);
            PingPong::from_fn(|side| {
                let (in_env, in_indirect) = if k == 0 {
                    (view(&m.env[side]), view(&m.indirect[side]))
                } else {
                    (view(&from[1]), view(&from[2]))
                };
                atrous::AtrousBindings {
                    params: &params[k],
                    gb_normal: i.normal,
                    gb_view_depth: i.view_depth,
                    in_signal: &view(&from[0]),
                    in_env: &in_env,
                    in_indirect: &in_indirect,
                    out_signal: &view(&to[0]),
                    out_env: &view(&to[1]),
                    out_indirect: &view(&to[2]),
                }
                .bind_group(device, layout)
            })
        })
        .collect()
}

impl Technique for Denoised {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn prepare(&self, queue: &wgpu::Queue, camera: &nearfield_scene::Camera) {
        self.inner.prepare(queue, camera);
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        frame: FrameInfo,
    ) {
        self.inner.encode(encoder, profiler, frame);
        let groups = util::groups_8x8(self.size);
        let groups = (groups.0, groups.1, 1);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("denoise"),
            timestamp_writes: profiler.compute("denoise"),
        });
        self.temporal
            .dispatch(&mut pass, self.temporal_bg.current(frame.index), groups);
        self.variance
            .dispatch(&mut pass, self.variance_bg.current(frame.index), groups);
        for bg in &self.atrous_bg {
            self.atrous
                .dispatch(&mut pass, bg.current(frame.index), groups);
        }
        self.resolve.dispatch(&mut pass, &self.resolve_bg, groups);
    }

    fn update(&mut self, queue: &wgpu::Queue, tp: &TechniqueParams) -> Result<bool, RenderError> {
        let (denoise, config) =
            (self.config_fn)(tp).map_err(RenderError::setting(self.inner.name()))?;
        if denoise != Denoise::Svgf || !config.svgf.same_build(&self.config.svgf) {
            return Ok(false);
        }
        if !self.inner.update(queue, tp)? {
            return Ok(false);
        }
        for (k, buffer) in self.params.iter().enumerate() {
            queue.write_buffer(buffer, 0, bytemuck::bytes_of(&svgf_params(&config, 1 << k)));
        }
        self.config = config;
        Ok(true)
    }

    fn extras(&self, frame: FrameInfo) -> Vec<(&'static str, &wgpu::Texture)> {
        let mut e = self.inner.extras(frame);
        e.extend(
            self.extras
                .current(frame.index)
                .iter()
                .map(|(n, t)| (*n, t)),
        );
        e
    }
}

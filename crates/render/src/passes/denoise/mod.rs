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

pub mod atrous;
pub mod resolve;
pub mod temporal;
pub mod variance;

use crate::RenderError;
use crate::bindings::PassLayout;
use crate::contract::formats::{AO_FORMAT, HDR_FORMAT};
use crate::contract::io::{NearFieldOutputs, Output};
use crate::contract::technique::{
    FrameInfo, Technique, TechniqueContext, TechniqueParams, screen_texture,
};
use crate::passes::{ComputeStep, PingPong};
use crate::profiler::GpuProfiler;
pub use crate::settings::denoise::{Denoise, SvgfConfig, SvgfSettings};
use crate::util;
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
    let size = i.size;
    let full = |label: &str, format| screen_texture(device, size, label, format);
    let view = |t: &wgpu::Texture| t.create_view(&Default::default());
    let raw = [
        full("svgf raw ao", AO_FORMAT),
        full("svgf raw env", HDR_FORMAT),
        full("svgf raw indirect", HDR_FORMAT),
    ];
    let raw_views = [view(&raw[0]), view(&raw[1]), view(&raw[2])];
    // The denoiser writes ao, and env-irradiance and indirect-irradiance where the technique
    // declares them; the others' filtered zeros go to images of its own.
    let unwritten =
        |output: Output, label: &str| (!writes.contains(&output)).then(|| full(label, HDR_FORMAT));
    let spare_env = unwritten(Output::EnvIrradiance, "svgf env (not declared)");
    let spare_indirect = unwritten(Output::IndirectIrradiance, "svgf indirect (not declared)");
    let spare_views = [
        spare_env.as_ref().map(view),
        spare_indirect.as_ref().map(view),
    ];
    let out_env = match &spare_views[0] {
        Some(v) => v,
        None => ctx.outputs.require(name, Output::EnvIrradiance)?,
    };
    let out_indirect = match &spare_views[1] {
        Some(v) => v,
        None => ctx.outputs.require(name, Output::IndirectIrradiance)?,
    };
    let inner_outputs = NearFieldOutputs {
        ao: &raw_views[0],
        bent_normal: ctx.outputs.bent_normal,
        env_irradiance: Some(&raw_views[1]),
        indirect_irradiance: Some(&raw_views[2]),
        light_irradiance: ctx.outputs.light_irradiance,
    };
    let inner_ctx = TechniqueContext {
        device: ctx.device,
        queue: ctx.queue,
        frame_group: ctx.frame_group,
        inputs: ctx.inputs,
        outputs: &inner_outputs,
        env: ctx.env,
        scene: ctx.scene,
        pack_half: ctx.pack_half,
    };
    let inner = inner(&inner_ctx)?;

    let pair = |label: &str, format| {
        [
            full(&format!("{label} 0"), format),
            full(&format!("{label} 1"), format),
        ]
    };
    let f32x4 = wgpu::TextureFormat::Rgba32Float;
    let moments = pair("svgf moments", f32x4);
    let env = pair("svgf env history", HDR_FORMAT);
    let indirect = pair("svgf indirect history", HDR_FORMAT);
    let geometry = pair("svgf geometry", f32x4);
    // Two sets of (signal, env, indirect) for the à-trous ping-pong.
    let work: Vec<[wgpu::Texture; 3]> = (0..2)
        .map(|k| {
            [
                full(&format!("svgf signal {k}"), HDR_FORMAT),
                full(&format!("svgf env {k}"), HDR_FORMAT),
                full(&format!("svgf indirect {k}"), HDR_FORMAT),
            ]
        })
        .collect();
    let iterations = config.svgf.svgf_iterations;
    let params: Vec<wgpu::Buffer> = (0..iterations)
        .map(|k| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("svgf params"),
                contents: bytemuck::bytes_of(&svgf_params(&config, 1 << k)),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            })
        })
        .collect();

    let temporal_layout = temporal::TemporalBindings::layout(device);
    let temporal_bg = PingPong::from_fn(|side| {
        let prev = 1 - side;
        temporal::TemporalBindings {
            params: &params[0],
            gb_normal: i.normal,
            gb_view_depth: i.view_depth,
            gb_motion: i.motion,
            raw_ao: &raw_views[0],
            raw_env: &raw_views[1],
            raw_indirect: &raw_views[2],
            prev_moments: &view(&moments[prev]),
            prev_env: &view(&env[prev]),
            prev_indirect: &view(&indirect[prev]),
            prev_geometry: &view(&geometry[prev]),
            acc_moments: &view(&moments[side]),
            acc_env: &view(&env[side]),
            acc_indirect: &view(&indirect[side]),
            acc_geometry: &view(&geometry[side]),
        }
        .bind_group(device, &temporal_layout)
    });
    let variance_layout = variance::VarianceBindings::layout(device);
    let variance_bg = PingPong::from_fn(|side| {
        variance::VarianceBindings {
            params: &params[0],
            gb_normal: i.normal,
            gb_view_depth: i.view_depth,
            acc_moments: &view(&moments[side]),
            acc_env: &view(&env[side]),
            out_signal: &view(&work[0][0]),
        }
        .bind_group(device, &variance_layout)
    });
    // Iteration k reads set k % 2 and writes set (k + 1) % 2; iteration 0 reads the variance
    // pass's signal (set 0) with this frame's env and indirect means.
    let atrous_layout = atrous::AtrousBindings::layout(device);
    let atrous_bg = (0..iterations as usize)
        .map(|k| {
            let (from, to) = (&work[k % 2], &work[(k + 1) % 2]);
            PingPong::from_fn(|side| {
                let (in_env, in_indirect) = if k == 0 {
                    (view(&env[side]), view(&indirect[side]))
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
                .bind_group(device, &atrous_layout)
            })
        })
        .collect();
    let last = &work[iterations as usize % 2];
    let resolve_layout = resolve::ResolveBindings::layout(device);
    let resolve_bg = resolve::ResolveBindings {
        final_signal: &view(&last[0]),
        final_env: &view(&last[1]),
        final_indirect: &view(&last[2]),
        out_ao: ctx.outputs.ao,
        out_env,
        out_indirect,
    }
    .bind_group(device, &resolve_layout);
    let step = |label: &'static str, source: String, entry: &str, layout| {
        let module = crate::pipeline_cache::shader_module(device, label, &source);
        ComputeStep::new(device, label, &module, entry, ctx.frame_group, layout, &[])
    };
    let extras = PingPong::from_fn(|side| {
        vec![
            ("denoise-history", env[side].clone()),
            ("denoise-moments", moments[side].clone()),
            ("denoise-raw-ao", raw[0].clone()),
            ("denoise-raw-indirect", raw[2].clone()),
        ]
    });
    let mut textures: Vec<wgpu::Texture> = Vec::new();
    textures.extend(raw);
    textures.extend(moments);
    textures.extend(env);
    textures.extend(indirect);
    textures.extend(geometry);
    textures.extend(work.into_iter().flatten());
    textures.extend(spare_env);
    textures.extend(spare_indirect);
    Ok(Box::new(Denoised {
        inner,
        config_fn,
        config,
        size,
        params,
        temporal: step(
            "svgf temporal",
            temporal::source(),
            "temporal",
            &temporal_layout,
        ),
        variance: step(
            "svgf variance",
            variance::source(),
            "variance",
            &variance_layout,
        ),
        atrous: step("svgf atrous", atrous::source(), "atrous", &atrous_layout),
        resolve: step(
            "svgf resolve",
            resolve::source(),
            "resolve",
            &resolve_layout,
        ),
        temporal_bg,
        variance_bg,
        atrous_bg,
        resolve_bg,
        extras,
        _textures: textures,
    }))
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
        if denoise != Denoise::Svgf
            || config.svgf.svgf_iterations != self.config.svgf.svgf_iterations
        {
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

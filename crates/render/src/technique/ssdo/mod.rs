//! screen-space ambient occlusion (`ssao`) and screen-space directional occlusion with
//! one indirect bounce (`ssdo`). Sources: Ritschel, Grosch & Seidel 2009, "Approximating Dynamic
//! Global Illumination in Image Space" (seed 003: Sec. 3 directional occlusion and indirect
//! bounce, Sec. 4 light segments, M×N interleaved sample sets) and the SSDO chapter of seed 001
//! (tangent frame, stratified elevation + golden-ratio azimuth, interleaved gradient noise, three
//! "visible" conditions, visibility and radiance modes, environment at a blurred mip, bounce from
//! the blurred direct radiance, distance clamp, falloff, strength).
//!
//! Entry points, in frame order: `direct` → (bilateral blur) → `resolve` → `bounce` → (blur).
//! SSAO runs `direct` and `resolve` only; the two techniques share sample generation and the
//! visibility test and differ in what they do with the samples.
//!
//! Deviations, and why:
//! - Visibility test. The paper's rule — a sample point is an occluder when projecting it onto the
//!   surface seen at its pixel moves it towards the viewer — is evaluated against that surface's
//!   tangent plane (position and normal from the G-buffer) rather than its depth at the pixel
//!   centre: the same verdict for curved surfaces at pixel scale, but exact on planes whatever the
//!   view angle (no false occlusion on a flat floor at any radius).
//! - Sample lengths: the paper draws λ ∈ [0, r_max] at random without naming the distribution;
//!   we take λ = r_max·u^(1/3), points uniform in the hemisphere's volume. Uniform λ leaves most
//!   points close to P and misses planar occluders a ray within R would meet (ao 0.78 instead of
//!   0.56 at a tenth of R from a wall); volume-uniform points halve that gap.
//! - The paper's smooth-step fade acts on the blocker's distance from P, from `fade`·R to R: where
//!   the segment from P to the sample crosses the tangent plane of the surface seen (when P is in
//!   front of that plane), else the distance to that surface point (so surfaces far in front of P,
//!   whose pixels a sample may project onto, fade out instead of casting halos).
//! - The bounce's sender cosine uses the direction from the sender to the receiver (the chapter's
//!   listing dots the sender normal with receiver→sender, which rejects front-facing senders).
//!
//! Frame: `direct` (sampling: ao, visibility, L_dir, screen-space light occlusion) → bilateral
//! blur → `resolve` (env-irradiance = visibility × SH irradiance in visibility mode, L_dir in
//! radiance mode; ao) → `bounce` (sender patches from the blurred direct light) → bilateral blur →
//! `indirect-irradiance`. `ssao` stops after `resolve`, with A = pow(max(0, 1 − scale·S), contrast)
//! in place of the visibility. Specular light is never occluded (composite.wgsl).
//! One pass = one `.rs` + one `.wgsl` here: [`direct`], [`resolve`], [`bounce`]; `params.wgsl`
//! and `segment.wgsl` are shared by them, [`vpls`] holds the virtual point lights.

pub mod bounce;
pub mod direct;
mod groups;
pub mod params;
pub mod resolve;
pub mod settings;
pub mod vpls;

use crate::RenderError;
use crate::contract::technique::FarRule;
use crate::contract::technique::{
    Output, Technique, TechniqueContext, TechniqueDesc, TechniqueParams,
};
use crate::passes::ComputeStep;
use crate::passes::bilateral_blur::{BilateralBlur, BlurChain, BlurSettings};
use crate::passes::denoise::{Denoise, SvgfConfig};
use crate::passes::layers::LayerStack;
use crate::passes::shadow::NoLights;
use crate::profiler::GpuProfiler;
use crate::settings::Declared;
use crate::targets::HDR_FORMAT;
use groups::{Shared, bounce_group, direct_group, resolve_group};
use vpls::Vpls;

pub use params::SsdoParams;
pub use settings::{LightSegment, Mode, PRESETS, Pattern, Settings};

/// Most memory the virtual point lights' shadow maps may take.
pub const VPL_SHADOW_BUDGET: u64 = 1 << 30;

const SSAO_PRESETS: [crate::settings::Preset; 5] =
    crate::settings::fitted::with_fitted(PRESETS, crate::settings::fitted::SSAO);
const SSDO_PRESETS: [crate::settings::Preset; 5] =
    crate::settings::fitted::with_fitted(PRESETS, crate::settings::fitted::SSDO);
const SSDO_VPL_PRESETS: [crate::settings::Preset; 5] =
    crate::settings::fitted::with_fitted(PRESETS, crate::settings::fitted::SSDO_VPL);
const INSTANT_RADIOSITY_PRESETS: [crate::settings::Preset; 5] =
    crate::settings::fitted::with_fitted(PRESETS, crate::settings::fitted::INSTANT_RADIOSITY);

pub const SSAO: TechniqueDesc = TechniqueDesc {
    family: "ssdo",
    name: "ssao",
    summary: "normal-oriented hemisphere SSAO (same samples and visibility test as ssdo): ao × SH irradiance",
    create: |ctx, tp| create(ctx, tp, Variant::Ssao),
    check: |tp| Variant::Ssao.check(tp),
    settings: <Settings as Declared>::TABLE,
    presets: &SSAO_PRESETS,
    denoise: Some(denoise_config),
    pass_layouts,
    writes: &[
        Output::Ao,
        Output::EnvIrradiance,
        Output::IndirectIrradiance,
        Output::LightIrradiance,
    ],
    far_rule: FarRule::Occlusion,
    with_volume: &[],
};

/// `ssdo` and `instant-radiosity` with a probe volume: a second depth layer. The thin occluders
/// that one layer takes for solids (SSDO Fig. 5) would darken light the volume already holds
/// behind them; 4 points per direction cost +39 % of ssdo's frame at 640×360 where the 16 of
/// `layers::LAYERED_STEPS` cost +131 %, for the same image error with the volume (the book,
/// "Near and far").
const PEELED_WITH_VOLUME: &[(&str, &str)] = &[("layers", "2"), ("steps", "4")];

pub const SSDO: TechniqueDesc = TechniqueDesc {
    family: "ssdo",
    name: "ssdo",
    summary: "screen-space directional occlusion of environment and lights, plus one indirect bounce",
    create: |ctx, tp| create(ctx, tp, Variant::Ssdo),
    check: |tp| Variant::Ssdo.check(tp),
    settings: <Settings as Declared>::TABLE,
    presets: &SSDO_PRESETS,
    denoise: Some(denoise_config),
    pass_layouts,
    writes: &[
        Output::Ao,
        Output::EnvIrradiance,
        Output::IndirectIrradiance,
        Output::LightIrradiance,
    ],
    far_rule: FarRule::Occlusion,
    with_volume: PEELED_WITH_VOLUME,
};

pub const SSDO_VPL: TechniqueDesc = TechniqueDesc {
    family: "ssdo",
    name: "ssdo-vpl",
    summary: "the environment as shadow-mapped virtual point lights, their lost small-scale shadows restored in screen space (ssdo Sec. 5)",
    create: |ctx, tp| create(ctx, tp, Variant::SsdoVpl),
    check: |tp| Variant::SsdoVpl.check(tp),
    settings: <Settings as Declared>::TABLE,
    presets: &SSDO_VPL_PRESETS,
    denoise: Some(denoise_config),
    pass_layouts,
    writes: &[
        Output::Ao,
        Output::EnvIrradiance,
        Output::IndirectIrradiance,
        Output::LightIrradiance,
    ],
    far_rule: FarRule::Own,
    with_volume: &[],
};

pub const INSTANT_RADIOSITY: TechniqueDesc = TechniqueDesc {
    family: "ssdo",
    name: "instant-radiosity",
    summary: "one bounce of the lights from virtual point lights drawn from reflective shadow maps (shadow-mapped, clamped), plus the screen-space near-field bounce the clamp removes and screen-space shadow correction (ssdo Sec. 5)",
    create: |ctx, tp| create(ctx, tp, Variant::InstantRadiosity),
    check: |tp| Variant::InstantRadiosity.check(tp),
    settings: <Settings as Declared>::TABLE,
    presets: &INSTANT_RADIOSITY_PRESETS,
    denoise: Some(denoise_config),
    pass_layouts,
    writes: &[
        Output::Ao,
        Output::EnvIrradiance,
        Output::IndirectIrradiance,
        Output::LightIrradiance,
    ],
    far_rule: FarRule::Occlusion,
    with_volume: PEELED_WITH_VOLUME,
};

/// Which technique of this file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Variant {
    Ssao,
    Ssdo,
    /// ssdo with the environment as VPLs (Sec. 5).
    SsdoVpl,
    /// ssdo with the lights' bounce from VPLs of reflective shadow maps (Sec. 5).
    InstantRadiosity,
}

/// The denoiser choice and svgf's configuration (the running mean at its defaults).
fn denoise_config(tp: &TechniqueParams) -> Result<(Denoise, SvgfConfig), String> {
    let s = Settings::from_params(tp)?;
    Ok((s.denoise, SvgfConfig::with_defaults(s.svgf, s.radius)))
}

/// A created ssao/ssdo/ssdo-vpl/instant-radiosity: its passes with their bind groups, built once.
struct Ssdo {
    name: &'static str,
    variant: Variant,
    /// The settings the parameter buffers hold.
    settings: Settings,
    params: wgpu::Buffer,
    size: (u32, u32),
    bounce_on: bool,
    direct: (ComputeStep, wgpu::BindGroup),
    resolve: (ComputeStep, wgpu::BindGroup),
    bounce: (ComputeStep, wgpu::BindGroup),
    blur: BilateralBlur,
    blur_a: BlurChain,
    blur_b: BlurChain,
    blur_indirect: BlurChain,
    layers: LayerStack,
    vpls: Option<Vpls>,
    // Keep the technique's own textures alive.
    _textures: Vec<wgpu::Texture>,
}

/// The technique's own images: the direct pass's two visibility images, the blur's scratch,
/// both blurred, and the bounce's raw indirect light.
const IMAGES: [&str; 6] = [
    "ssdo a",
    "ssdo b",
    "ssdo blur scratch",
    "ssdo a blurred",
    "ssdo b blurred",
    "ssdo indirect",
];

fn create(
    ctx: &TechniqueContext,
    tp: &TechniqueParams,
    variant: Variant,
) -> Result<Box<dyn Technique>, RenderError> {
    let name = variant.name();
    let settings = variant.settings(tp)?;
    let vpls = vpls_of(ctx, variant, &settings)?;
    let device = ctx.device;
    let (i, o) = (ctx.inputs, ctx.outputs);
    let textures =
        IMAGES.map(|l| crate::contract::technique::screen_texture(device, i.size, l, HDR_FORMAT));
    let [raw_a, raw_b, scratch, blurred_a, blurred_b, raw_indirect] = &textures
        .each_ref()
        .map(|t| t.create_view(&Default::default()));
    let gpu_params = variant.params(&settings, vpls.as_ref().map_or(0, |v| v.count));
    let (params, sample_sets) = crate::technique::samples::buffers(
        device,
        "ssdo",
        bytemuck::bytes_of(&gpu_params),
        settings.samples,
    );
    let stack = LayerStack::new(device, i, ctx.scene, ctx.frame_group, settings.layers)
        .map_err(RenderError::setting(name))?;
    let layer = stack.resources();
    let no_lights = ctx.scene.is_none().then(|| NoLights::new(device));
    let scene_lights = ctx.lights(no_lights.as_ref());
    // The light table of each pass: the VPLs where it uses them, else the scene's lights.
    let vpl_lights = vpls.as_ref().map(|v| v.light_resources());
    let (direct_lights, bounce_lights) = match variant {
        Variant::SsdoVpl => (vpl_lights.unwrap_or(scene_lights), scene_lights),
        Variant::InstantRadiosity => (scene_lights, vpl_lights.unwrap_or(scene_lights)),
        _ => (scene_lights, scene_lights),
    };
    let frame = ctx.frame_group;
    let shared = Shared {
        params: &params,
        sample_sets: &sample_sets,
        i,
        layer,
    };
    let (env_out, light_out) = (
        o.require(name, Output::EnvIrradiance)?,
        o.require(name, Output::LightIrradiance)?,
    );
    let (direct_layout, direct_bg) =
        direct_group(device, &shared, direct_lights, [raw_a, raw_b, light_out]);
    let (resolve_layout, resolve_bg) =
        resolve_group(device, &shared, [blurred_a, blurred_b], [env_out, o.ao]);
    let (bounce_layout, bounce_bg) = bounce_group(
        device,
        &shared,
        bounce_lights,
        [env_out, light_out, raw_indirect],
    );
    let blur = BilateralBlur::new(device, frame, blur_settings(&settings));
    let far_field = frame.far_field_constant();
    let counts = settings.counts();
    // (label, entry point), the kernel's WGSL; specialised by the counts it declares (`SAMPLES`,
    // `STEPS`) and the far field.
    let step = |(label, entry), source: String, layout| {
        let kernel = (label, source.as_str(), entry);
        ComputeStep::counted(device, frame, kernel, layout, &counts, &[far_field])
    };
    Ok(Box::new(Ssdo {
        name,
        variant,
        settings,
        params,
        size: i.size,
        bounce_on: variant.bounce_on(&settings),
        direct: (
            step((name, "direct"), direct::source(), &direct_layout),
            direct_bg,
        ),
        resolve: (
            step(("resolve", "resolve"), resolve::source(), &resolve_layout),
            resolve_bg,
        ),
        bounce: (
            step(("bounce", "bounce"), bounce::source(), &bounce_layout),
            bounce_bg,
        ),
        blur_a: blur.chain(device, i, raw_a, scratch, blurred_a),
        blur_b: blur.chain(device, i, raw_b, scratch, blurred_b),
        blur_indirect: blur.chain(
            device,
            i,
            raw_indirect,
            scratch,
            o.require(name, Output::IndirectIrradiance)?,
        ),
        blur,
        layers: stack,
        vpls,
        _textures: textures.into(),
    }))
}

/// The virtual point lights of ssdo-vpl (the environment's) and instant-radiosity (the lights'
/// bounce); none for the others.
fn vpls_of(
    ctx: &TechniqueContext,
    variant: Variant,
    settings: &Settings,
) -> Result<Option<Vpls>, RenderError> {
    let scene = || ctx.require_scene(variant.name(), "virtual point lights");
    Ok(match variant {
        Variant::SsdoVpl => Some(Vpls::environment(ctx, scene()?, settings)),
        Variant::InstantRadiosity => Some(Vpls::radiosity(ctx, scene()?, settings)),
        _ => None,
    })
}

impl Variant {
    fn name(self) -> &'static str {
        match self {
            Variant::Ssao => "ssao",
            Variant::Ssdo => "ssdo",
            Variant::SsdoVpl => "ssdo-vpl",
            Variant::InstantRadiosity => "instant-radiosity",
        }
    }

    /// [`Self::settings`] as `TechniqueDesc::check` wants it.
    fn check(self, tp: &TechniqueParams) -> Result<(), String> {
        match self.settings(tp) {
            Ok(_) => Ok(()),
            Err(RenderError::Setting { msg, .. }) => Err(msg),
            Err(e) => Err(e.to_string()),
        }
    }

    /// The settings of `tp`, checked (instant-radiosity's clamp against R too).
    fn settings(self, tp: &TechniqueParams) -> Result<Settings, RenderError> {
        let error = RenderError::setting(self.name());
        let mut settings = Settings::from_params(tp).map_err(&error)?;
        // The default clamp follows a smaller R (`--radius auto` from a fine volume); a clamp
        // set by hand is the user's, and checked.
        let clamp_given = tp
            .set
            .iter()
            .any(|(k, _)| k == "vpl_clamp" || k == "quality");
        if !clamp_given {
            settings.vpl_clamp = settings.vpl_clamp.min(settings.radius);
        }
        if self == Variant::InstantRadiosity
            && settings.bounce
            && settings.vpl_clamp > settings.radius
        {
            return Err(error(format!(
                "vpl_clamp {} > radius {}: the screen-space bounce cannot add back what the clamp removes beyond R; set vpl_clamp ≤ radius or bounce=off",
                settings.vpl_clamp, settings.radius
            )));
        }
        if matches!(self, Variant::SsdoVpl | Variant::InstantRadiosity) {
            // One depth layer of vpl_map² per light.
            let bytes = settings.vpls as u64 * (settings.vpl_map as u64).pow(2) * 4;
            if bytes > VPL_SHADOW_BUDGET {
                return Err(error(format!(
                    "vpls={} with vpl_map={} needs {} MiB of shadow maps, beyond the {} MiB \
                     budget; lower vpls or vpl_map",
                    settings.vpls,
                    settings.vpl_map,
                    bytes >> 20,
                    VPL_SHADOW_BUDGET >> 20
                )));
            }
        }
        Ok(settings)
    }

    /// The GPU constants of `settings` with `vpl_count` virtual point lights (pure).
    fn params(self, settings: &Settings, vpl_count: u32) -> SsdoParams {
        let mut p = settings.params(self != Variant::Ssao);
        if matches!(self, Variant::SsdoVpl | Variant::InstantRadiosity) {
            p.vpl_mode = if self == Variant::SsdoVpl { 1 } else { 2 };
            p.vpl_count = vpl_count;
            // Screen-space correction of the shadow maps' bias (ssdo-vpl: the VPLs take the
            // direct pass's light table; the scene's lights keep their shadow-mapped light
            // irradiance).
            p.light_segment = 1;
        }
        p
    }

    /// Whether the bounce pass runs.
    fn bounce_on(self, settings: &Settings) -> bool {
        (self != Variant::Ssao && settings.bounce) || self == Variant::InstantRadiosity
    }
}

fn blur_settings(settings: &Settings) -> BlurSettings {
    BlurSettings {
        enabled: settings.denoise == Denoise::Bilateral,
        radius: settings.blur_radius,
        depth_sigma: settings.blur_depth,
        normal_power: settings.blur_normal,
    }
}

impl Technique for Ssdo {
    fn name(&self) -> &'static str {
        self.name
    }

    fn update(&mut self, queue: &wgpu::Queue, tp: &TechniqueParams) -> Result<bool, RenderError> {
        let settings = self.variant.settings(tp)?;
        if !settings.same_build(&self.settings) {
            return Ok(false);
        }
        let vpl_count = self.vpls.as_ref().map_or(0, |v| v.count);
        let p = self.variant.params(&settings, vpl_count);
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        self.blur.write(queue, blur_settings(&settings));
        self.bounce_on = self.variant.bounce_on(&settings);
        self.settings = settings;
        Ok(true)
    }

    fn prepare(&self, queue: &wgpu::Queue, camera: &nearfield_scene::Camera) {
        self.layers.prepare(queue, camera);
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        _frame: crate::contract::technique::FrameInfo,
    ) {
        if let Some(v) = &self.vpls {
            v.shadows.encode(encoder, profiler);
        }
        self.layers.encode(encoder, profiler);
        self.direct
            .0
            .encode(encoder, profiler, &self.direct.1, self.size);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("blur"),
                timestamp_writes: profiler.compute("blur"),
            });
            self.blur.dispatch(&mut pass, &self.blur_a, self.size);
            self.blur.dispatch(&mut pass, &self.blur_b, self.size);
        }
        self.resolve
            .0
            .encode(encoder, profiler, &self.resolve.1, self.size);
        if self.bounce_on {
            self.bounce
                .0
                .encode(encoder, profiler, &self.bounce.1, self.size);
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("blur indirect"),
                timestamp_writes: profiler.compute("blur indirect"),
            });
            self.blur
                .dispatch(&mut pass, &self.blur_indirect, self.size);
        }
    }
}

/// The family's passes (`TechniqueDesc::pass_layouts`).
fn pass_layouts() -> Vec<crate::bindings::PassLayout> {
    vec![
        direct::pass_layout(),
        resolve::pass_layout(),
        bounce::pass_layout(),
    ]
}

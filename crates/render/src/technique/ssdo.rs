//! `ssao` and `ssdo`: screen-space ambient occlusion, and screen-space directional occlusion with
//! one indirect bounce (Ritschel et al. 2009 and the SSDO chapter; see ssdo.wgsl for the formulas,
//! the sources and the deviations).
//!
//! Frame: `direct` (sampling: ao, visibility, L_dir, screen-space light occlusion) → bilateral
//! blur → `resolve` (env-irradiance = visibility × SH irradiance in visibility mode, L_dir in
//! radiance mode; ao) → `bounce` (sender patches from the blurred direct light) → bilateral blur →
//! `indirect-irradiance`. `ssao` stops after `resolve`, with A = pow(max(0, 1 − scale·S), contrast)
//! in place of the visibility. Specular light is never occluded (composite.wgsl).

use super::{Preset, Setting, Technique, TechniqueContext, TechniqueDesc, TechniqueParams};
use crate::RenderError;
use crate::gpu_env::GpuEnvironment;
use crate::passes::bilateral_blur::{BilateralBlur, BlurChain, BlurSettings};
use crate::passes::layers::{self, LayerSettings, LayerStack};
use crate::passes::shadow::ShadowPass;
use crate::profiler::GpuProfiler;
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;
use bytemuck::{Pod, Zeroable};
use wgpu::BindingResource as R;
use wgpu::util::DeviceExt;

pub const SHADER: &str = include_str!("ssdo.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::LIGHTS_WGSL,
        util::SCREEN_SAMPLES_WGSL,
        SHADER,
    ])
}

pub const SSAO: TechniqueDesc = TechniqueDesc {
    name: "ssao",
    summary: "normal-oriented hemisphere SSAO (same samples and visibility test as ssdo): ao × SH irradiance",
    create: create_ssao,
    settings: SETTINGS,
    presets: PRESETS,
};

pub const SSDO: TechniqueDesc = TechniqueDesc {
    name: "ssdo",
    summary: "screen-space directional occlusion of environment and lights, plus one indirect bounce",
    create: create_ssdo,
    settings: SETTINGS,
    presets: PRESETS,
};

pub const SSDO_VPL: TechniqueDesc = TechniqueDesc {
    name: "ssdo-vpl",
    summary: "the environment as shadow-mapped virtual point lights, their lost small-scale shadows restored in screen space (ssdo Sec. 5)",
    create: create_ssdo_vpl,
    settings: SETTINGS,
    presets: PRESETS,
};

pub const INSTANT_RADIOSITY: TechniqueDesc = TechniqueDesc {
    name: "instant-radiosity",
    summary: "one bounce of the lights from virtual point lights drawn from reflective shadow maps (shadow-mapped, clamped), plus the screen-space near-field bounce the clamp removes and screen-space shadow correction (ssdo Sec. 5)",
    create: create_instant_radiosity,
    settings: SETTINGS,
    presets: PRESETS,
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

/// How the environment term is formed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Luminance-weighted visible fraction × SH irradiance (the chapter's visibility mode).
    Visibility,
    /// Σ (1/π) L_in V cos θ Δω from the environment at `lod` (radiance mode).
    Radiance,
}

/// Sample pattern.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// The chapter's stratified elevation, golden-ratio azimuth, IGN rotation, random λ.
    Chapter,
    /// The paper's M×N texture: 4×4 sets of N low-discrepancy samples, one set per pixel.
    Interleaved,
}

impl Pattern {
    /// `pattern=chapter|interleaved`.
    pub fn parse(v: &str) -> Result<Self, String> {
        match v {
            "chapter" => Ok(Pattern::Chapter),
            "interleaved" => Ok(Pattern::Interleaved),
            _ => Err(format!("pattern={v}: expected chapter or interleaved")),
        }
    }
}

/// Checks the sampling settings every screen-space sampling technique shares.
pub fn check_sampling(samples: u32, radius: f32) -> Result<(), String> {
    if !(1..=256).contains(&samples) {
        return Err(format!("samples {samples}: must be in 1..=256"));
    }
    if !(radius.is_finite() && radius > 0.0) {
        return Err(format!(
            "radius {radius}: screen-space sampling needs a finite radius > 0"
        ));
    }
    Ok(())
}

/// Settings of `ssao` and `ssdo` (`--samples`, `--radius`, `--set key=value`).
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// `samples`: directions per pixel N, 1..=256. Default 16.
    pub samples: u32,
    /// `steps`: points tested per direction at λ·k/steps (ray marching; the first occluded one
    /// decides), 1..=16. Default 1 (the paper's single point at λ).
    pub steps: u32,
    /// `radius`: hemisphere radius R in metres, > 0 and finite. Default 0.5.
    pub radius: f32,
    /// `mode`: visibility | radiance. Default visibility.
    pub mode: Mode,
    /// `bounce`: on | off (ssdo only). Default on.
    pub bounce: bool,
    /// `pattern`: chapter | interleaved. Default interleaved.
    pub pattern: Pattern,
    /// `lod`: mip of the environment read per sample, 0..=16. Default 5 (32×16 for a 1k map).
    pub lod: f32,
    /// `contrast`: exponent on the visibility, 0.1..=8. Default 1.
    pub contrast: f32,
    /// `scale`: SSAO's factor on the occluded fraction S, 0..=4. Default 1.
    pub scale: f32,
    /// `strength`: bounce strength, 0..=16. Default 1.
    pub strength: f32,
    /// `distance_clamp`: smallest sender distance in 1/d² (m), 0..=R. Default 0.1.
    pub distance_clamp: f32,
    /// `fade`: where the occluder fade starts, as a fraction of R, 0..=1. Default 0.75.
    pub fade: f32,
    /// `light_samples`: points per light segment (0: no screen-space light occlusion), 0..=64.
    /// Default 8.
    pub light_samples: u32,
    /// `blur`: on | off. Default on.
    pub blur: bool,
    /// `blur_radius`: half width in pixels, 0..=16. Default 4 (covers the 4×4 interleaving).
    pub blur_radius: u32,
    /// `blur_depth`: distance of a blur tap from the centre's tangent plane, relative to the
    /// centre's view depth, at which the tap's weight falls by e. Default 0.01.
    pub blur_depth: f32,
    /// `blur_normal`: exponent on the normals' cosine in the blur. Default 8.
    pub blur_normal: f32,
    /// `light_segment`: radius | bias — the segment towards each light tested in screen space:
    /// length R (Sec. 4) or the shadow map's bias (Sec. 5 shadow correction). Default radius.
    pub light_segment: LightSegment,
    /// `layers`, `cameras`, `camera_scale`, `camera_spread`: depth peeling and additional
    /// cameras in the blocker test (passes/layers.rs). Default 1 layer, no cameras.
    pub layers: LayerSettings,
    /// `vpls` (ssdo-vpl, instant-radiosity): virtual point lights, 1..=256. Default 64.
    pub vpls: u32,
    /// `vpl_map` (ssdo-vpl, instant-radiosity): side of each virtual point light's shadow map,
    /// 128..=2048. Default 512.
    pub vpl_map: u32,
    /// `rsm` (instant-radiosity): side of each reflective shadow map view, 16..=1024. Default 256.
    pub rsm: u32,
    /// `vpl_clamp` (instant-radiosity): smallest distance in a virtual point light's 1/d² (m),
    /// ≥ 0. With `bounce=on` it must not exceed R: the screen-space bounce adds back what the
    /// clamp removes. Default 0.5 (the default R).
    pub vpl_clamp: f32,
}

/// What part of the ray towards a light is tested in screen space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightSegment {
    /// Length R, on top of the shadow map (paper Sec. 4, Fig. 6).
    Radius,
    /// The length the shadow map's bias hides (paper Sec. 5, Fig. 8–9).
    Bias,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            samples: 16,
            steps: 1,
            radius: 0.5,
            mode: Mode::Visibility,
            bounce: true,
            pattern: Pattern::Interleaved,
            lod: 5.0,
            contrast: 1.0,
            scale: 1.0,
            strength: 1.0,
            distance_clamp: 0.1,
            fade: 0.75,
            light_samples: 8,
            blur: true,
            blur_radius: 4,
            blur_depth: 0.01,
            blur_normal: 8.0,
            light_segment: LightSegment::Radius,
            layers: LayerSettings::default(),
            vpls: 64,
            vpl_map: 512,
            rsm: 256,
            vpl_clamp: 0.5,
        }
    }
}

/// Every `--set` key with its range and default (the fields of [`Settings`]).
pub const SETTINGS: &[Setting] = &[
    Setting::integer("samples", 1.0, 256.0, "16", "directions per pixel N"),
    Setting::integer(
        "steps",
        1.0,
        16.0,
        "1",
        "points tested per direction (ray marching; 1: one point at λ)",
    ),
    Setting::log("radius", 1e-6, 1e6, "0.5", "hemisphere radius R (m)"),
    Setting::choice(
        "mode",
        &["visibility", "radiance"],
        "visibility",
        "what a direction carries",
    ),
    Setting::toggle("bounce", "on", "one indirect bounce from occluders (ssdo)"),
    Setting::choice(
        "pattern",
        &["chapter", "interleaved"],
        "interleaved",
        "sample sets",
    ),
    Setting::number("lod", 0.0, 16.0, "5", "environment mip read per sample"),
    Setting::number("contrast", 0.1, 8.0, "1", "exponent on the visibility"),
    Setting::number(
        "scale",
        0.0,
        4.0,
        "1",
        "SSAO's factor on the occluded fraction",
    ),
    Setting::number("strength", 0.0, 16.0, "1", "bounce strength"),
    Setting::log(
        "distance_clamp",
        0.0,
        1e6,
        "0.1",
        "smallest sender distance in 1/d² (m)",
    ),
    Setting::number(
        "fade",
        0.0,
        1.0,
        "0.75",
        "occluder fade start (fraction of R)",
    ),
    Setting::integer(
        "light_samples",
        0.0,
        64.0,
        "8",
        "points per light segment (0: off)",
    ),
    Setting::choice(
        "light_segment",
        &["radius", "bias"],
        "radius",
        "light segment tested in screen space: R, or the shadow map's bias (shadow correction)",
    ),
    layers::SETTINGS[0],
    layers::SETTINGS[1],
    layers::SETTINGS[2],
    layers::SETTINGS[3],
    Setting::integer(
        "vpls",
        1.0,
        256.0,
        "64",
        "virtual point lights (ssdo-vpl, instant-radiosity; light_samples = correction points per light)",
    ),
    Setting::integer(
        "vpl_map",
        128.0,
        2048.0,
        "512",
        "shadow map side per virtual point light (ssdo-vpl, instant-radiosity)",
    ),
    Setting::integer(
        "rsm",
        16.0,
        1024.0,
        "256",
        "reflective shadow map side per light view (instant-radiosity)",
    ),
    Setting::log(
        "vpl_clamp",
        0.0,
        1e6,
        "0.5",
        "smallest distance in a VPL's 1/d² (m; instant-radiosity, ≤ R with bounce=on)",
    ),
    Setting::toggle("blur", "on", "geometry-aware blur"),
    Setting::integer("blur_radius", 0.0, 16.0, "4", "blur half width (pixels)"),
    Setting::log(
        "blur_depth",
        1e-4,
        10.0,
        "0.01",
        "blur depth tolerance (× view depth)",
    ),
    Setting::number(
        "blur_normal",
        0.0,
        128.0,
        "8",
        "exponent on the normals' cosine in the blur",
    ),
];

/// `quality` presets: directions per pixel.
pub const PRESETS: &[Preset] = &[
    Preset {
        name: "low",
        set: &[("samples", "8")],
    },
    Preset {
        name: "medium",
        set: &[("samples", "16")],
    },
    Preset {
        name: "high",
        set: &[("samples", "32")],
    },
    Preset {
        name: "ultra",
        set: &[("samples", "64")],
    },
];

impl Settings {
    /// Applies `--samples`, `--radius` and `--set` on top of the defaults.
    pub fn from_params(params: &TechniqueParams) -> Result<Self, String> {
        let mut s = Settings::default();
        if let Some(n) = params.samples {
            s.samples = n;
        }
        if let Some(r) = params.radius {
            s.radius = r;
        }
        for (k, v) in &params.set {
            match k.as_str() {
                "mode" => {
                    s.mode = match v.as_str() {
                        "visibility" => Mode::Visibility,
                        "radiance" => Mode::Radiance,
                        _ => return Err(format!("mode={v}: expected visibility or radiance")),
                    }
                }
                "pattern" => s.pattern = Pattern::parse(v)?,
                "bounce" => s.bounce = super::parse_on_off(k, v)?,
                "blur" => s.blur = super::parse_on_off(k, v)?,
                "lod" => s.lod = super::parse_number(k, v, 0.0, 16.0)?,
                "contrast" => s.contrast = super::parse_number(k, v, 0.1, 8.0)?,
                "scale" => s.scale = super::parse_number(k, v, 0.0, 4.0)?,
                "strength" => s.strength = super::parse_number(k, v, 0.0, 16.0)?,
                "distance_clamp" => s.distance_clamp = super::parse_number(k, v, 0.0, 1e6)?,
                "fade" => s.fade = super::parse_number(k, v, 0.0, 1.0)?,
                "light_samples" => s.light_samples = super::parse_integer(k, v, 0, 64)?,
                "blur_radius" => s.blur_radius = super::parse_integer(k, v, 0, 16)?,
                "blur_depth" => s.blur_depth = super::parse_number(k, v, 1e-4, 10.0)?,
                "blur_normal" => s.blur_normal = super::parse_number(k, v, 0.0, 128.0)?,
                "samples" => s.samples = super::parse_integer(k, v, 1, 256)?,
                "steps" => s.steps = super::parse_integer(k, v, 1, 16)?,
                "radius" => s.radius = super::parse_number(k, v, 1e-6, 1e6)?,
                "light_segment" => {
                    s.light_segment = match v.as_str() {
                        "radius" => LightSegment::Radius,
                        "bias" => LightSegment::Bias,
                        _ => return Err(format!("light_segment={v}: expected radius or bias")),
                    }
                }
                "vpls" => s.vpls = super::parse_integer(k, v, 1, crate::vpl::MAX_VPLS)?,
                "vpl_map" => s.vpl_map = super::parse_integer(k, v, 128, 2048)?,
                "rsm" => s.rsm = super::parse_integer(k, v, 16, 1024)?,
                "vpl_clamp" => s.vpl_clamp = super::parse_number(k, v, 0.0, 1e6)?,
                _ if layers::parse_setting(&mut s.layers, k, v)? => {}
                _ => {
                    return Err(format!(
                        "unknown setting '{k}' (known: quality, {})",
                        super::keys(SETTINGS)
                    ));
                }
            }
        }
        check_sampling(s.samples, s.radius)?;
        Ok(s)
    }

    /// The GPU constants (pure).
    pub fn params(&self, ssdo: bool) -> SsdoParams {
        SsdoParams {
            radius: self.radius,
            samples: self.samples,
            mode: (self.mode == Mode::Radiance) as u32,
            technique: ssdo as u32,
            lod: self.lod,
            contrast: self.contrast,
            scale: self.scale,
            fade: self.fade,
            strength: self.strength,
            distance_clamp: self.distance_clamp,
            pattern: (self.pattern == Pattern::Interleaved) as u32,
            light_samples: if ssdo { self.light_samples } else { 0 },
            layers: self.layers.layers,
            cameras: self.layers.cameras,
            light_segment: (self.light_segment == LightSegment::Bias) as u32,
            vpl_mode: 0,
            vpl_count: 0,
            vpl_clamp: self.vpl_clamp,
            near: (ssdo && self.bounce) as u32,
            steps: self.steps,
        }
    }
}

/// `SsdoParams` in ssdo.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct SsdoParams {
    pub radius: f32,
    pub samples: u32,
    pub mode: u32,
    pub technique: u32,
    pub lod: f32,
    pub contrast: f32,
    pub scale: f32,
    pub fade: f32,
    pub strength: f32,
    pub distance_clamp: f32,
    pub pattern: u32,
    pub light_samples: u32,
    pub layers: u32,
    pub cameras: u32,
    pub light_segment: u32,
    /// 0 none, 1 the environment as VPLs (direct pass), 2 Instant Radiosity (bounce pass).
    pub vpl_mode: u32,
    pub vpl_count: u32,
    pub vpl_clamp: f32,
    /// 1: the bounce pass gathers sender pixels.
    pub near: u32,
    pub steps: u32,
}

/// The paper's M×N sample texture with M = 4×4 sets: set m, sample i has a stratified elevation
/// cos θ = 1 − (i + ½)/N (uniform solid angle, so every sample stands for Δω = 2π/N), an azimuth
/// from the base-2 radical inverse and a length λ/R = v^(1/3) (points uniform in the hemisphere's
/// volume, as in ssdo.wgsl) from the base-3 radical inverse v of i, each rotated
/// (Cranley–Patterson) by the m-th point of the R2 sequence so that the 16 sets differ.
pub fn interleaved_sets(n: u32) -> Vec<[f32; 4]> {
    fn radical_inverse(mut i: u32, base: u32) -> f32 {
        let (mut f, mut r) = (1.0 / base as f64, 0.0f64);
        while i > 0 {
            r += f * (i % base) as f64;
            i /= base;
            f /= base as f64;
        }
        r as f32
    }
    let g = 1.324_717_957_244_746f64;
    let mut out = Vec::with_capacity(16 * n as usize);
    for m in 0..16u32 {
        let o1 = ((m as f64 + 1.0) / g).fract() as f32;
        let o2 = ((m as f64 + 1.0) / (g * g)).fract() as f32;
        for i in 0..n {
            let cos_e = 1.0 - (i as f32 + 0.5) / n as f32;
            let sin_e = (1.0 - cos_e * cos_e).max(0.0).sqrt();
            let phi = std::f32::consts::TAU * (radical_inverse(i, 2) + o1).fract();
            let lambda = ((radical_inverse(i, 3) + o2).fract())
                .max(0.5 / n as f32)
                .cbrt();
            out.push([sin_e * phi.cos(), sin_e * phi.sin(), cos_e, lambda]);
        }
    }
    out
}

struct Ssdo {
    name: &'static str,
    size: (u32, u32),
    bounce: bool,
    direct: wgpu::ComputePipeline,
    resolve: wgpu::ComputePipeline,
    bounce_pipeline: wgpu::ComputePipeline,
    direct_bg: wgpu::BindGroup,
    resolve_bg: wgpu::BindGroup,
    bounce_bg: wgpu::BindGroup,
    blur: BilateralBlur,
    blur_a: BlurChain,
    blur_b: BlurChain,
    blur_indirect: BlurChain,
    layers: LayerStack,
    vpls: Option<Vpls>,
    // Keep the technique's own textures alive.
    _textures: Vec<wgpu::Texture>,
}

fn create_ssao(
    ctx: &TechniqueContext,
    params: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    create(ctx, params, Variant::Ssao)
}

fn create_ssdo(
    ctx: &TechniqueContext,
    params: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    create(ctx, params, Variant::Ssdo)
}

fn create_ssdo_vpl(
    ctx: &TechniqueContext,
    params: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    create(ctx, params, Variant::SsdoVpl)
}

fn create_instant_radiosity(
    ctx: &TechniqueContext,
    params: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    create(ctx, params, Variant::InstantRadiosity)
}

/// The virtual point lights of ssdo-vpl or instant-radiosity: their table (`GpuLight`s with
/// their shadow layers) and shadow maps.
struct Vpls {
    table: wgpu::Buffer,
    count: u32,
    shadows: ShadowPass,
}

impl Vpls {
    /// ssdo-vpl: the environment as directional lights.
    fn environment(ctx: &TechniqueContext, settings: &Settings) -> Self {
        let env = ctx.env;
        let lights = crate::vpl::environment_lights(
            env.source(),
            env.rotation,
            env.intensity,
            settings.vpls,
        );
        Self::new(ctx, settings, &lights, "environment lights")
    }

    /// instant-radiosity: cosine emitters drawn from the reflective shadow maps of the scene's
    /// lights, as spot lights about their normals (shadow maps over 160°; shadow_visibility
    /// counts receivers beyond 80° from the normal, where cos θ < 0.18, as unshadowed), with
    /// colour Φ/π (ssdo.wgsl `radiosity_bounce`).
    fn radiosity(ctx: &TechniqueContext, settings: &Settings) -> Self {
        let texels = crate::passes::rsm::render(
            ctx.device,
            ctx.queue,
            ctx.scene,
            &ctx.scene.scene_lights,
            settings.rsm,
        );
        // Lift each light off its surface by a thousandth of the scene's radius.
        let lift = 1e-3 * ctx.scene.bounds.radius();
        let lights: Vec<nearfield_scene::Light> =
            crate::vpl::radiosity_lights(&texels, settings.vpls)
                .iter()
                .map(|v| nearfield_scene::Light {
                    kind: nearfield_scene::LightKind::Spot {
                        position: v.position + v.normal * lift,
                        direction: v.normal,
                        inner_cone: std::f32::consts::FRAC_PI_2,
                        outer_cone: std::f32::consts::FRAC_PI_2,
                    },
                    color: v.flux / std::f32::consts::PI,
                    intensity: 1.0,
                    range: None,
                })
                .collect();
        log::info!(
            "instant-radiosity: {} virtual point lights from {} lit reflective-shadow-map texels",
            lights.len(),
            texels.len()
        );
        Self::new(ctx, settings, &lights, "radiosity lights")
    }

    /// Bindings 13..=16 (lights.wgsl) with the VPLs as the light table.
    fn bindings(&self) -> [(u32, R<'_>); 4] {
        [
            (13, self.table.as_entire_binding()),
            (14, self.shadows.matrices.as_entire_binding()),
            (15, R::TextureView(&self.shadows.array_view)),
            (16, R::Sampler(&self.shadows.compare_sampler)),
        ]
    }

    fn new(
        ctx: &TechniqueContext,
        settings: &Settings,
        lights: &[nearfield_scene::Light],
        label: &'static str,
    ) -> Self {
        let kinds: Vec<_> = lights.iter().map(|l| l.kind).collect();
        let shadows = ShadowPass::for_lights(
            ctx.device,
            ctx.scene,
            &kinds,
            crate::passes::shadow::ShadowSettings {
                size: settings.vpl_map,
                max_layers: crate::vpl::MAX_VPLS,
                ..Default::default()
            },
            "vpl shadows",
        );
        let table: Vec<crate::gpu_scene::GpuLight> = lights
            .iter()
            .zip(&shadows.light_layers)
            .map(|(l, &(layer, texel))| crate::gpu_scene::gpu_light(l, layer, texel))
            .collect();
        let table = if table.is_empty() {
            vec![crate::gpu_scene::GpuLight::zeroed()]
        } else {
            table
        };
        Vpls {
            table: ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytemuck::cast_slice(&table),
                    usage: wgpu::BufferUsages::STORAGE,
                }),
            count: lights.len() as u32,
            shadows,
        }
    }
}

fn create(
    ctx: &TechniqueContext,
    tp: &TechniqueParams,
    variant: Variant,
) -> Result<Box<dyn Technique>, RenderError> {
    let name = match variant {
        Variant::Ssao => "ssao",
        Variant::Ssdo => "ssdo",
        Variant::SsdoVpl => "ssdo-vpl",
        Variant::InstantRadiosity => "instant-radiosity",
    };
    let ssdo = variant != Variant::Ssao;
    let settings = Settings::from_params(tp).map_err(|msg| RenderError::Setting {
        technique: name.into(),
        msg,
    })?;
    if variant == Variant::InstantRadiosity
        && settings.bounce
        && settings.vpl_clamp > settings.radius
    {
        return Err(RenderError::Setting {
            technique: name.into(),
            msg: format!(
                "vpl_clamp {} > radius {}: the screen-space bounce cannot add back what the clamp removes beyond R; set vpl_clamp ≤ radius or bounce=off",
                settings.vpl_clamp, settings.radius
            ),
        });
    }
    let vpls = match variant {
        Variant::SsdoVpl => Some(Vpls::environment(ctx, &settings)),
        Variant::InstantRadiosity => Some(Vpls::radiosity(ctx, &settings)),
        _ => None,
    };
    let device = ctx.device;
    let t = ctx.targets;
    let c = wgpu::ShaderStages::COMPUTE;
    let texture = |label: &str| super::screen_texture(device, t.size, label, HDR_FORMAT);
    let textures: Vec<wgpu::Texture> = [
        "ssdo a",
        "ssdo b",
        "ssdo blur scratch",
        "ssdo a blurred",
        "ssdo b blurred",
        "ssdo indirect",
    ]
    .iter()
    .map(|l| texture(l))
    .collect();
    let views: Vec<wgpu::TextureView> = textures
        .iter()
        .map(|t| t.create_view(&Default::default()))
        .collect();
    let (raw_a, raw_b, scratch, blurred_a, blurred_b, raw_indirect) = (
        &views[0], &views[1], &views[2], &views[3], &views[4], &views[5],
    );

    let mut gpu_params = settings.params(ssdo);
    if let Some(v) = &vpls {
        gpu_params.vpl_mode = if variant == Variant::SsdoVpl { 1 } else { 2 };
        gpu_params.vpl_count = v.count;
        // Screen-space correction of the shadow maps' bias (ssdo-vpl: the VPLs take the direct
        // pass's light table; the scene's lights keep their shadow-mapped light irradiance).
        gpu_params.light_segment = 1;
    }
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("ssdo params"),
        contents: bytemuck::bytes_of(&gpu_params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let sets = interleaved_sets(settings.samples);
    let sample_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("ssdo sample sets"),
        contents: bytemuck::cast_slice(&sets),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let source = source();
    let layout = |label: &str, entries: &[wgpu::BindGroupLayoutEntry]| {
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries,
        })
    };
    let mut direct_entries = vec![
        util::uniform(0, c),
        util::uniform(5, c),
        util::storage_buffer(6, c),
        util::texture(8, c, true),
        util::texture(9, c, false),
    ];
    direct_entries.extend(GpuEnvironment::layout_entries());
    direct_entries.extend(ShadowPass::layout_entries());
    direct_entries.extend(LayerStack::layout_entries(false));
    direct_entries.extend([
        util::storage_texture(20, HDR_FORMAT),
        util::storage_texture(21, HDR_FORMAT),
        util::storage_texture(22, HDR_FORMAT),
    ]);
    let direct_layout = layout("ssdo direct", &direct_entries);
    let mut resolve_entries = vec![
        util::uniform(0, c),
        util::uniform(5, c),
        util::texture(8, c, true),
    ];
    resolve_entries.extend(GpuEnvironment::layout_entries());
    resolve_entries.extend([
        util::texture(24, c, true),
        util::texture(25, c, true),
        util::storage_texture(26, HDR_FORMAT),
        util::storage_texture(27, AO_FORMAT),
    ]);
    let resolve_layout = layout("ssdo resolve", &resolve_entries);
    let mut bounce_entries = vec![
        util::uniform(0, c),
        util::uniform(5, c),
        util::storage_buffer(6, c),
        util::texture(8, c, true),
        util::texture(9, c, false),
        util::texture(10, c, true),
        util::texture(11, c, true),
        util::texture(28, c, true),
        util::texture(29, c, true),
        util::storage_texture(30, HDR_FORMAT),
    ];
    bounce_entries.extend(LayerStack::layout_entries(true));
    bounce_entries.extend(ShadowPass::layout_entries());
    let bounce_layout = layout("ssdo bounce", &bounce_entries);
    let shadows = ctx.shadows;
    let stack = LayerStack::new(
        device,
        t,
        ctx.scene,
        ctx.env,
        shadows,
        ctx.frame,
        settings.layers,
    );
    let mut direct_res = vec![
        (0, ctx.frame.as_entire_binding()),
        (5, params.as_entire_binding()),
        (6, sample_buffer.as_entire_binding()),
        (8, R::TextureView(&t.normal.view)),
        (9, R::TextureView(&t.view_depth.view)),
        (20, R::TextureView(raw_a)),
        (21, R::TextureView(raw_b)),
        (22, R::TextureView(&t.light_irradiance.view)),
    ];
    direct_res.extend(ctx.env.bindings());
    // Bindings 13..=16: the VPLs where the pass uses them, else the scene's lights.
    match (&vpls, variant) {
        (Some(v), Variant::SsdoVpl) => direct_res.extend(v.bindings()),
        _ => direct_res.extend(shadows.bindings(ctx.scene)),
    }
    direct_res.extend(stack.bindings(false));
    let mut resolve_res = vec![
        (0, ctx.frame.as_entire_binding()),
        (5, params.as_entire_binding()),
        (8, R::TextureView(&t.normal.view)),
        (24, R::TextureView(blurred_a)),
        (25, R::TextureView(blurred_b)),
        (26, R::TextureView(&t.env_irradiance.view)),
        (27, R::TextureView(&t.ao.view)),
    ];
    resolve_res.extend(ctx.env.bindings());
    let mut bounce_res = vec![
        (0, ctx.frame.as_entire_binding()),
        (5, params.as_entire_binding()),
        (6, sample_buffer.as_entire_binding()),
        (8, R::TextureView(&t.normal.view)),
        (9, R::TextureView(&t.view_depth.view)),
        (10, R::TextureView(&t.albedo.view)),
        (11, R::TextureView(&t.emissive.view)),
        (28, R::TextureView(&t.env_irradiance.view)),
        (29, R::TextureView(&t.light_irradiance.view)),
        (30, R::TextureView(raw_indirect)),
    ];
    bounce_res.extend(stack.bindings(true));
    match (&vpls, variant) {
        (Some(v), Variant::InstantRadiosity) => bounce_res.extend(v.bindings()),
        _ => bounce_res.extend(shadows.bindings(ctx.scene)),
    }
    let blur = BilateralBlur::new(
        device,
        BlurSettings {
            enabled: settings.blur,
            radius: settings.blur_radius,
            depth_sigma: settings.blur_depth,
            normal_power: settings.blur_normal,
        },
    );
    Ok(Box::new(Ssdo {
        name,
        size: t.size,
        bounce: (ssdo && settings.bounce) || variant == Variant::InstantRadiosity,
        direct: util::compute_pipeline(device, "ssdo direct", &source, "direct", &direct_layout),
        resolve: util::compute_pipeline(
            device,
            "ssdo resolve",
            &source,
            "resolve",
            &resolve_layout,
        ),
        bounce_pipeline: util::compute_pipeline(
            device,
            "ssdo bounce",
            &source,
            "bounce",
            &bounce_layout,
        ),
        direct_bg: util::bind_group(device, "ssdo direct", &direct_layout, &direct_res),
        resolve_bg: util::bind_group(device, "ssdo resolve", &resolve_layout, &resolve_res),
        bounce_bg: util::bind_group(device, "ssdo bounce", &bounce_layout, &bounce_res),
        blur_a: blur.chain(device, ctx.frame, t, raw_a, scratch, blurred_a),
        blur_b: blur.chain(device, ctx.frame, t, raw_b, scratch, blurred_b),
        blur_indirect: blur.chain(
            device,
            ctx.frame,
            t,
            raw_indirect,
            scratch,
            &t.indirect_irradiance.view,
        ),
        blur,
        layers: stack,
        vpls,
        _textures: textures,
    }))
}

impl Technique for Ssdo {
    fn name(&self) -> &'static str {
        self.name
    }

    fn prepare(&self, queue: &wgpu::Queue, camera: &nearfield_scene::Camera) {
        self.layers.prepare(queue, camera);
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        _frame: super::FrameInfo,
    ) {
        if let Some(v) = &self.vpls {
            v.shadows.encode(encoder, profiler);
        }
        self.layers.encode(encoder, profiler);
        super::dispatch_screen(
            encoder,
            profiler,
            self.name,
            &self.direct,
            &self.direct_bg,
            self.size,
        );
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("blur"),
                timestamp_writes: profiler.compute("blur"),
            });
            self.blur.dispatch(&mut pass, &self.blur_a, self.size);
            self.blur.dispatch(&mut pass, &self.blur_b, self.size);
        }
        super::dispatch_screen(
            encoder,
            profiler,
            "resolve",
            &self.resolve,
            &self.resolve_bg,
            self.size,
        );
        if self.bounce {
            super::dispatch_screen(
                encoder,
                profiler,
                "bounce",
                &self.bounce_pipeline,
                &self.bounce_bg,
                self.size,
            );
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("blur indirect"),
                timestamp_writes: profiler.compute("blur indirect"),
            });
            self.blur
                .dispatch(&mut pass, &self.blur_indirect, self.size);
        }
    }
}

//! `s3ho` (screen-space spherical-harmonic occlusion, Herholz et al. 2012, with its indirect
//! extension) and `ssbn` (screen-space bent normals and cones, Klehm et al. 2011, the paper's
//! comparison). See s3ho.wgsl for the equations, the storage and the deviations.
//!
//! Frame: `sample_pass` (16 packed SH coefficients, bent normal/cone, raw ao, raw indirect) →
//! s3ho: 8×8 bilateral filter of the coefficients; ssbn: bilateral blur of bent cone and ao →
//! `shade_pass` (env-irradiance, light-irradiance, ao) → s3ho indirect: bilateral blur →
//! `indirect-irradiance`.

use super::ssdo::{Pattern, check_sampling, interleaved_sets};
use super::{Setting, Technique, TechniqueContext, TechniqueDesc, TechniqueParams};
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

pub const SHADER: &str = include_str!("s3ho.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::LIGHTS_WGSL,
        util::SCREEN_SAMPLES_WGSL,
        SHADER,
    ])
}

pub const S3HO: TechniqueDesc = TechniqueDesc {
    name: "s3ho",
    summary: "screen-space SH occlusion (16 coefficients), SH lighting of environment and lights, indirect extension",
    create: create_s3ho,
    settings: SETTINGS,
    presets: super::ssdo::PRESETS,
};

pub const SSBN: TechniqueDesc = TechniqueDesc {
    name: "ssbn",
    summary: "screen-space bent normals and cones: environment through the cone around the bent normal",
    create: create_ssbn,
    settings: SETTINGS,
    presets: super::ssdo::PRESETS,
};

/// Settings of `s3ho` and `ssbn`.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// `samples`: directions per pixel N, 1..=256. Default 16.
    pub samples: u32,
    /// `radius`: d_max in metres, > 0 and finite. Default 0.5.
    pub radius: f32,
    /// `steps`: ray-marching points per direction, 1..=16. Default 2 (the paper's).
    pub steps: u32,
    /// `lambda`: smooth visibility 1 − 1/(1 + λd) for occluded directions, 0 = off, 0..=1000.
    /// Default 0.
    pub lambda: f32,
    /// `indirect`: the indirect extension (Eq. 5), s3ho only. Default on.
    pub indirect: bool,
    /// `pattern`: chapter | interleaved (4×4 sets). Default interleaved.
    pub pattern: Pattern,
    /// `fade`: blocker fade start as a fraction of d_max. Default 0.75.
    pub fade: f32,
    /// `strength`: indirect strength. Default 1.
    pub strength: f32,
    /// `distance_clamp`: smallest sender distance in 1/d² (m). Default 0.1.
    pub distance_clamp: f32,
    /// `blur`: the bilateral filter (s3ho: 8×8 on the coefficients; ssbn: on bent cone and ao).
    /// Default on.
    pub blur: bool,
    /// `layers`, `cameras`, `camera_scale`, `camera_spread`: depth peeling and additional
    /// cameras in the blocker test (passes/layers.rs). Default 1 layer, no cameras.
    pub layers: LayerSettings,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            samples: 16,
            radius: 0.5,
            steps: 2,
            lambda: 0.0,
            indirect: true,
            pattern: Pattern::Interleaved,
            fade: 0.75,
            strength: 1.0,
            distance_clamp: 0.1,
            blur: true,
            layers: LayerSettings::default(),
        }
    }
}

/// Every `--set` key with its range and default (the fields of [`Settings`]).
pub const SETTINGS: &[Setting] = &[
    Setting::integer("samples", 1.0, 256.0, "16", "directions per pixel"),
    Setting::log("radius", 1e-6, 1e6, "0.5", "hemisphere radius d_max (m)"),
    Setting::integer("steps", 1.0, 16.0, "2", "ray-march steps per direction"),
    Setting::number(
        "lambda",
        0.0,
        1000.0,
        "0",
        "smooth visibility 1 − 1/(1 + λd), 0 = off",
    ),
    Setting::toggle("indirect", "on", "the indirect extension (s3ho)"),
    Setting::choice(
        "pattern",
        &["chapter", "interleaved"],
        "interleaved",
        "sample sets",
    ),
    Setting::number(
        "fade",
        0.0,
        1.0,
        "0.75",
        "blocker fade start (fraction of d_max)",
    ),
    Setting::number("strength", 0.0, 16.0, "1", "indirect strength"),
    Setting::log(
        "distance_clamp",
        0.0,
        1e6,
        "0.1",
        "smallest sender distance in 1/d² (m)",
    ),
    Setting::toggle("blur", "on", "bilateral filter"),
    layers::SETTINGS[0],
    layers::SETTINGS[1],
    layers::SETTINGS[2],
    layers::SETTINGS[3],
];

impl Settings {
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
                "indirect" => s.indirect = super::parse_on_off(k, v)?,
                "blur" => s.blur = super::parse_on_off(k, v)?,
                "steps" => s.steps = super::parse_integer(k, v, 1, 16)?,
                "lambda" => s.lambda = super::parse_number(k, v, 0.0, 1000.0)?,
                "fade" => s.fade = super::parse_number(k, v, 0.0, 1.0)?,
                "strength" => s.strength = super::parse_number(k, v, 0.0, 16.0)?,
                "distance_clamp" => s.distance_clamp = super::parse_number(k, v, 0.0, 1e6)?,
                "samples" => s.samples = super::parse_integer(k, v, 1, 256)?,
                "radius" => s.radius = super::parse_number(k, v, 1e-6, 1e6)?,
                "pattern" => s.pattern = Pattern::parse(v)?,
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
    pub fn params(&self, ssbn: bool) -> S3hoParams {
        S3hoParams {
            radius: self.radius,
            samples: self.samples,
            pattern: (self.pattern == Pattern::Interleaved) as u32,
            fade: self.fade,
            steps: self.steps,
            lambda: self.lambda,
            technique: ssbn as u32,
            indirect: (!ssbn && self.indirect) as u32,
            strength: self.strength,
            distance_clamp: self.distance_clamp,
            layers: self.layers.layers,
            cameras: self.layers.cameras,
        }
    }
}

/// `S3hoParams` in s3ho.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct S3hoParams {
    pub radius: f32,
    pub samples: u32,
    pub pattern: u32,
    pub fade: f32,
    pub steps: u32,
    pub lambda: f32,
    pub technique: u32,
    pub indirect: u32,
    pub strength: f32,
    pub distance_clamp: f32,
    pub layers: u32,
    pub cameras: u32,
}

struct S3ho {
    name: &'static str,
    size: (u32, u32),
    ssbn: bool,
    indirect: bool,
    blur_on: bool,
    sample: wgpu::ComputePipeline,
    filter: wgpu::ComputePipeline,
    shade: wgpu::ComputePipeline,
    sample_bg: wgpu::BindGroup,
    filter_bg: wgpu::BindGroup,
    shade_bg: wgpu::BindGroup,
    blur: BilateralBlur,
    blur_bent: BlurChain,
    blur_ao: BlurChain,
    blur_indirect: BlurChain,
    layers: LayerStack,
    _textures: Vec<wgpu::Texture>,
}

fn create_s3ho(
    ctx: &TechniqueContext,
    p: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    create(ctx, p, false)
}

fn create_ssbn(
    ctx: &TechniqueContext,
    p: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    create(ctx, p, true)
}

fn uint_texture(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

fn create(
    ctx: &TechniqueContext,
    tp: &TechniqueParams,
    ssbn: bool,
) -> Result<Box<dyn Technique>, RenderError> {
    let name = if ssbn { "ssbn" } else { "s3ho" };
    let settings = Settings::from_params(tp).map_err(|msg| RenderError::Setting {
        technique: name.into(),
        msg,
    })?;
    if !ctx.pack_half {
        return Err(RenderError::Setting {
            technique: name.into(),
            msg: "this adapter cannot run pack2x16float (DownlevelFlags::SHADER_F16_IN_F32), which stores the SH coefficients".into(),
        });
    }
    let device = ctx.device;
    let t = ctx.targets;
    let c = wgpu::ShaderStages::COMPUTE;
    let texture = |label: &str, format| super::screen_texture(device, t.size, label, format);
    let u32x4 = wgpu::TextureFormat::Rgba32Uint;
    let textures = vec![
        texture("s3ho coefficients 0", u32x4),
        texture("s3ho coefficients 1", u32x4),
        texture("s3ho filtered 0", u32x4),
        texture("s3ho filtered 1", u32x4),
        texture("s3ho bent cone", HDR_FORMAT),
        texture("s3ho bent cone blurred", HDR_FORMAT),
        texture("s3ho ao", HDR_FORMAT),
        texture("s3ho ao blurred", HDR_FORMAT),
        texture("s3ho indirect", HDR_FORMAT),
        texture("s3ho scratch", HDR_FORMAT),
    ];
    let v: Vec<wgpu::TextureView> = textures
        .iter()
        .map(|t| t.create_view(&Default::default()))
        .collect();
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("s3ho params"),
        contents: bytemuck::bytes_of(&settings.params(ssbn)),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let sets = interleaved_sets(settings.samples);
    let sample_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("s3ho sample sets"),
        contents: bytemuck::cast_slice(&sets),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let layout = |label: &str, entries: &[wgpu::BindGroupLayoutEntry]| {
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries,
        })
    };
    let base = |extra: &[wgpu::BindGroupLayoutEntry]| {
        let mut e = vec![
            util::uniform(0, c),
            util::uniform(5, c),
            util::storage_buffer(6, c),
            util::texture(8, c, true),
            util::texture(9, c, false),
            util::texture(10, c, true),
        ];
        e.extend(GpuEnvironment::layout_entries());
        e.extend(ShadowPass::layout_entries());
        e.extend(LayerStack::layout_entries(true));
        e.extend_from_slice(extra);
        e
    };
    let sample_layout = layout(
        "s3ho sample",
        &base(&[
            util::storage_texture(20, u32x4),
            util::storage_texture(21, u32x4),
            util::storage_texture(22, HDR_FORMAT),
            util::storage_texture(23, HDR_FORMAT),
            util::storage_texture(30, HDR_FORMAT),
        ]),
    );
    let filter_layout = layout(
        "s3ho filter",
        &base(&[
            util::storage_texture(20, u32x4),
            util::storage_texture(21, u32x4),
            uint_texture(24),
            uint_texture(25),
        ]),
    );
    let shade_layout = layout(
        "s3ho shade",
        &base(&[
            uint_texture(24),
            uint_texture(25),
            util::texture(26, c, true),
            util::texture(31, c, true),
            util::storage_texture(27, HDR_FORMAT),
            util::storage_texture(28, HDR_FORMAT),
            util::storage_texture(29, AO_FORMAT),
        ]),
    );
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
    let mut common: Vec<(u32, R<'_>)> = vec![
        (0, ctx.frame.as_entire_binding()),
        (5, params.as_entire_binding()),
        (6, sample_buffer.as_entire_binding()),
        (8, R::TextureView(&t.normal.view)),
        (9, R::TextureView(&t.view_depth.view)),
        (10, R::TextureView(&t.albedo.view)),
    ];
    common.extend(ctx.env.bindings());
    common.extend(shadows.bindings(ctx.scene));
    common.extend(stack.bindings(true));
    fn with<'a>(common: &[(u32, R<'a>)], extra: &[(u32, R<'a>)]) -> Vec<(u32, R<'a>)> {
        common.iter().chain(extra).cloned().collect()
    }
    let sample_bg = util::bind_group(
        device,
        "s3ho sample",
        &sample_layout,
        &with(
            &common,
            &[
                (20, R::TextureView(&v[0])),
                (21, R::TextureView(&v[1])),
                (22, R::TextureView(&v[4])),
                (23, R::TextureView(&v[8])),
                (30, R::TextureView(&v[6])),
            ],
        ),
    );
    let filter_bg = util::bind_group(
        device,
        "s3ho filter",
        &filter_layout,
        &with(
            &common,
            &[
                (20, R::TextureView(&v[2])),
                (21, R::TextureView(&v[3])),
                (24, R::TextureView(&v[0])),
                (25, R::TextureView(&v[1])),
            ],
        ),
    );
    // With the filter off, shade reads the raw coefficients (and the raw bent cone and ao).
    let (c0, c1) = if settings.blur {
        (&v[2], &v[3])
    } else {
        (&v[0], &v[1])
    };
    let shade_bg = util::bind_group(
        device,
        "s3ho shade",
        &shade_layout,
        &with(
            &common,
            &[
                (24, R::TextureView(c0)),
                (25, R::TextureView(c1)),
                (26, R::TextureView(&v[5])),
                (31, R::TextureView(&v[7])),
                (27, R::TextureView(&t.env_irradiance.view)),
                (28, R::TextureView(&t.light_irradiance.view)),
                (29, R::TextureView(&t.ao.view)),
            ],
        ),
    );
    let source = source();
    let blur = BilateralBlur::new(
        device,
        BlurSettings {
            enabled: settings.blur,
            radius: 4,
            depth_sigma: 0.01,
            normal_power: 8.0,
        },
    );
    Ok(Box::new(S3ho {
        name,
        size: t.size,
        ssbn,
        indirect: !ssbn && settings.indirect,
        blur_on: settings.blur,
        sample: util::compute_pipeline(
            device,
            "s3ho sample",
            &source,
            "sample_pass",
            &sample_layout,
        ),
        filter: util::compute_pipeline(
            device,
            "s3ho filter",
            &source,
            "filter_pass",
            &filter_layout,
        ),
        shade: util::compute_pipeline(device, "s3ho shade", &source, "shade_pass", &shade_layout),
        sample_bg,
        filter_bg,
        shade_bg,
        blur_bent: blur.chain(device, ctx.frame, t, &v[4], &v[9], &v[5]),
        blur_ao: blur.chain(device, ctx.frame, t, &v[6], &v[9], &v[7]),
        blur_indirect: blur.chain(
            device,
            ctx.frame,
            t,
            &v[8],
            &v[9],
            &t.indirect_irradiance.view,
        ),
        blur,
        layers: stack,
        _textures: textures,
    }))
}

impl Technique for S3ho {
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
        self.layers.encode(encoder, profiler);
        super::dispatch_screen(
            encoder,
            profiler,
            self.name,
            &self.sample,
            &self.sample_bg,
            self.size,
        );
        if !self.ssbn && self.blur_on {
            super::dispatch_screen(
                encoder,
                profiler,
                "sh filter",
                &self.filter,
                &self.filter_bg,
                self.size,
            );
        }
        if self.ssbn {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("blur"),
                timestamp_writes: profiler.compute("blur"),
            });
            self.blur.dispatch(&mut pass, &self.blur_bent, self.size);
            self.blur.dispatch(&mut pass, &self.blur_ao, self.size);
        }
        super::dispatch_screen(
            encoder,
            profiler,
            "shade",
            &self.shade,
            &self.shade_bg,
            self.size,
        );
        if self.indirect {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("blur indirect"),
                timestamp_writes: profiler.compute("blur indirect"),
            });
            self.blur
                .dispatch(&mut pass, &self.blur_indirect, self.size);
        }
    }
}

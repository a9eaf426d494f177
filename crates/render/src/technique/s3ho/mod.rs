//! `s3ho` (screen-space spherical-harmonic occlusion, Herholz, Schairer, Schilling & Straßer,
//! "Screen Space Spherical Harmonic Occlusion", seed 002/000: Eq. 2–5, with its indirect
//! extension) and `ssbn` (screen-space bent normals and cones, Klehm et al. 2011, the paper's
//! comparison). Both use the samples and visibility test of technique/samples.wgsl.
//!
//! Frame: `sample_pass` (16 packed SH coefficients, bent normal/cone, raw ao, raw indirect) →
//! s3ho: 8×8 bilateral filter of the coefficients; ssbn: bilateral blur of bent cone and ao →
//! `shade_pass` (env-irradiance, light-irradiance, ao) → s3ho indirect: bilateral blur →
//! `indirect-irradiance`.
//!
//! One pass = one `.rs` + one `.wgsl` here: [`sample`], [`filter`], [`shade`] (`sh.wgsl` is
//! shared by them). The equations, the storage and the deviations from the paper head the WGSL
//! that computes them: the SH basis and packing in sh.wgsl, Eq. 2, the indirect extension (Eq.
//! 5) and ssbn's cone in sample.wgsl, the filter in filter.wgsl, Eq. 3–4 and the lights in
//! shade.wgsl.

pub mod filter;
mod groups;
pub mod params;
pub mod sample;
pub mod settings;
pub mod shade;

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
use groups::{Shared, filter_group, sample_group, shade_group};

pub use params::S3hoParams;
pub use settings::Settings;

/// 16 SH coefficients as half floats, 8 per texel (pack2x16float).
pub const COEFFS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;

const S3HO_PRESETS: [crate::settings::Preset; 5] = crate::settings::fitted::with_fitted(
    crate::settings::sampling::PRESETS,
    crate::settings::fitted::S3HO,
);
const SSBN_PRESETS: [crate::settings::Preset; 5] = crate::settings::fitted::with_fitted(
    crate::settings::sampling::PRESETS,
    crate::settings::fitted::SSBN,
);

pub const S3HO: TechniqueDesc = TechniqueDesc {
    family: "s3ho",
    name: "s3ho",
    summary: "screen-space SH occlusion (16 coefficients), SH lighting of environment and lights, indirect extension",
    create: |ctx, tp| create(ctx, tp, false),
    check,
    settings: <Settings as Declared>::TABLE,
    presets: &S3HO_PRESETS,
    denoise: Some(denoise_config),
    pass_layouts,
    writes: &[
        Output::Ao,
        Output::EnvIrradiance,
        Output::IndirectIrradiance,
        Output::LightIrradiance,
    ],
    far_rule: FarRule::Directional,
    // With a volume each blocker's occlusion fades with its distance d (1 − 1/(1 + λd): half at
    // 10 cm): the blockers further away are the probes' to hold. One layer's SH visibility took
    // `gap`'s 4 cm posts, and the Cornell box's walls, for more occlusion than the volume leaves
    // to the near field (the book, "Near and far").
    with_volume: &[("lambda", "10")],
};

pub const SSBN: TechniqueDesc = TechniqueDesc {
    family: "s3ho",
    name: "ssbn",
    summary: "screen-space bent normals and cones: environment through the cone around the bent normal",
    create: |ctx, tp| create(ctx, tp, true),
    check,
    settings: <Settings as Declared>::TABLE,
    presets: &SSBN_PRESETS,
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

struct S3ho {
    name: &'static str,
    /// The settings the parameter buffer holds.
    settings: Settings,
    params: wgpu::Buffer,
    size: (u32, u32),
    ssbn: bool,
    indirect: bool,
    blur_on: bool,
    sample: (ComputeStep, wgpu::BindGroup),
    filter: (ComputeStep, wgpu::BindGroup),
    shade: (ComputeStep, wgpu::BindGroup),
    blur: BilateralBlur,
    blur_bent: BlurChain,
    blur_ao: BlurChain,
    blur_indirect: BlurChain,
    layers: LayerStack,
    _textures: Vec<wgpu::Texture>,
}

/// The settings parsed without a device (`TechniqueDesc::check`).
fn check(tp: &TechniqueParams) -> Result<(), String> {
    denoise_config(tp).map(|_| ())
}

/// The denoiser choice and svgf's configuration (the running mean at its defaults).
fn denoise_config(tp: &TechniqueParams) -> Result<(Denoise, SvgfConfig), String> {
    let s = Settings::from_params(tp)?;
    Ok((s.denoise, SvgfConfig::with_defaults(s.svgf, s.radius)))
}

/// The technique's own images: the SH coefficients (two images) raw and filtered, the bent
/// cone and ao raw and blurred, the raw indirect light and the blur's scratch.
const IMAGES: [(&str, wgpu::TextureFormat); 10] = [
    ("s3ho coefficients 0", COEFFS_FORMAT),
    ("s3ho coefficients 1", COEFFS_FORMAT),
    ("s3ho filtered 0", COEFFS_FORMAT),
    ("s3ho filtered 1", COEFFS_FORMAT),
    ("s3ho bent cone", HDR_FORMAT),
    ("s3ho bent cone blurred", HDR_FORMAT),
    ("s3ho ao", HDR_FORMAT),
    ("s3ho ao blurred", HDR_FORMAT),
    ("s3ho indirect", HDR_FORMAT),
    ("s3ho scratch", HDR_FORMAT),
];

fn create(
    ctx: &TechniqueContext,
    tp: &TechniqueParams,
    ssbn: bool,
) -> Result<Box<dyn Technique>, RenderError> {
    let name = if ssbn { "ssbn" } else { "s3ho" };
    let settings = Settings::from_params(tp).map_err(RenderError::setting(name))?;
    if !ctx.pack_half {
        return Err(RenderError::Setting {
            technique: name.into(),
            msg: "this adapter cannot run pack2x16float (DownlevelFlags::SHADER_F16_IN_F32), which stores the SH coefficients".into(),
        });
    }
    let device = ctx.device;
    let frame = ctx.frame_group;
    let (i, o) = (ctx.inputs, ctx.outputs);
    let textures = IMAGES.map(|(label, format)| {
        crate::contract::technique::screen_texture(device, i.size, label, format)
    });
    let v = textures
        .each_ref()
        .map(|t| t.create_view(&Default::default()));
    let (params, sample_sets) = crate::technique::samples::buffers(
        device,
        "s3ho",
        bytemuck::bytes_of(&settings.params(ssbn)),
        settings.samples,
    );
    let stack = LayerStack::new(device, i, ctx.scene, frame, settings.layers)
        .map_err(RenderError::setting(name))?;
    let no_lights = ctx.scene.is_none().then(|| NoLights::new(device));
    let shared = Shared {
        params: &params,
        sample_sets: &sample_sets,
        i,
        layer: stack.resources(),
        lights: ctx.lights(no_lights.as_ref()),
    };
    let sample_pass = sample_group(device, &shared, [&v[0], &v[1], &v[4], &v[6], &v[8]]);
    let filter_pass = filter_group(device, i, [&v[0], &v[1], &v[2], &v[3]]);
    // With the filter off, shade reads the raw coefficients (and the raw bent cone and ao).
    let blurred = settings.denoise == Denoise::Bilateral;
    let coefficients = if blurred {
        [&v[2], &v[3]]
    } else {
        [&v[0], &v[1]]
    };
    let shade_pass = shade_group(
        device,
        &shared,
        [coefficients[0], coefficients[1], &v[5], &v[7]],
        [
            o.require(name, Output::EnvIrradiance)?,
            o.require(name, Output::LightIrradiance)?,
            o.ao,
        ],
    );
    let blur = BilateralBlur::new(
        device,
        frame,
        BlurSettings {
            enabled: blurred,
            radius: 4,
            depth_sigma: 0.01,
            normal_power: 8.0,
        },
    );
    let far_field = frame.far_field_constant();
    let counts = settings.counts();
    // A compute step over a (layout, group) pair, specialised by the counts its kernel declares
    // (`SAMPLES`, `STEPS`) and `extra`: the step and its group.
    let pass = |label: &'static str, source: String, entry: &str, (layout, group), extra: &[_]| {
        let kernel = (label, source.as_str(), entry);
        let step = ComputeStep::counted(device, frame, kernel, &layout, &counts, extra);
        (step, group)
    };
    Ok(Box::new(S3ho {
        name,
        settings,
        params,
        size: i.size,
        ssbn,
        indirect: !ssbn && settings.indirect,
        blur_on: blurred,
        sample: pass(
            name,
            sample::source(),
            "sample_pass",
            sample_pass,
            &[far_field],
        ),
        filter: pass(
            "sh filter",
            filter::source(),
            "filter_pass",
            filter_pass,
            &[],
        ),
        shade: pass(
            "shade",
            shade::source(),
            "shade_pass",
            shade_pass,
            &[far_field],
        ),
        blur_bent: blur.chain(device, i, &v[4], &v[9], &v[5]),
        blur_ao: blur.chain(device, i, &v[6], &v[9], &v[7]),
        blur_indirect: blur.chain(
            device,
            i,
            &v[8],
            &v[9],
            o.require(name, Output::IndirectIrradiance)?,
        ),
        blur,
        layers: stack,
        _textures: textures.into(),
    }))
}

impl Technique for S3ho {
    fn name(&self) -> &'static str {
        self.name
    }

    fn update(&mut self, queue: &wgpu::Queue, tp: &TechniqueParams) -> Result<bool, RenderError> {
        let settings = Settings::from_params(tp).map_err(RenderError::setting(self.name))?;
        if !settings.same_build(&self.settings) {
            return Ok(false);
        }
        let p = settings.params(self.ssbn);
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        self.indirect = !self.ssbn && settings.indirect;
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
        self.layers.encode(encoder, profiler);
        self.sample
            .0
            .encode(encoder, profiler, &self.sample.1, self.size);
        if !self.ssbn && self.blur_on {
            self.filter
                .0
                .encode(encoder, profiler, &self.filter.1, self.size);
        }
        if self.ssbn {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("blur"),
                timestamp_writes: profiler.compute("blur"),
            });
            self.blur.dispatch(&mut pass, &self.blur_bent, self.size);
            self.blur.dispatch(&mut pass, &self.blur_ao, self.size);
        }
        self.shade
            .0
            .encode(encoder, profiler, &self.shade.1, self.size);
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

/// The family's passes (`TechniqueDesc::pass_layouts`).
fn pass_layouts() -> Vec<crate::bindings::PassLayout> {
    vec![
        sample::pass_layout(),
        filter::pass_layout(),
        shade::pass_layout(),
    ]
}

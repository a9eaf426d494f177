//! `s3ho` (screen-space spherical-harmonic occlusion, Herholz et al. 2012, with its indirect
//! extension) and `ssbn` (screen-space bent normals and cones, Klehm et al. 2011, the paper's
//! comparison). The equations, the storage and the deviations follow below.
//!
//! Frame: `sample_pass` (16 packed SH coefficients, bent normal/cone, raw ao, raw indirect) →
//! s3ho: 8×8 bilateral filter of the coefficients; ssbn: bilateral blur of bent cone and ao →
//! `shade_pass` (env-irradiance, light-irradiance, ao) → s3ho indirect: bilateral blur →
//! `indirect-irradiance`.
//!
//! The derivations. Screen-space spherical-harmonic occlusion (`s3ho`, Herholz, Schairer,
//! Schilling & Straßer, "Screen Space Spherical Harmonic Occlusion", seed 002/000: Eq. 2–5) and
//! screen-space bent normals and cones (`ssbn`, Klehm et al. 2011) as its baseline. Both use the samples and
//! visibility test of technique/samples.wgsl.
//!
//! SH: real basis of nearfield_scene::sh (Sloan's "Stupid SH Tricks" polynomials without the
//! Condon–Shortley phase, polar axis world z, index l(l+1)+m, orthonormality tested there), 4
//! bands = 16 coefficients.
//!
//! `sample_pass` (s3ho): c[S3HO]_i(p) = (4π/2N) Σ_j V_SS(p, p_j, d_max) y_i(s_j)(n·s_j)   (Eq. 2),
//!   written as c[cos n] − (2π/N) Σ_j (1 − V_j) y_i(s_j)(n·s_j): the unoccluded part, the SH of the
//!   clamped cosine about n, is exact (Funk–Hecke: A_l y_i(n), A = π, 2π/3, π/4, 0), and only the
//!   occluded part is sampled. Same expectation as Eq. 2 with less noise, and exact (no false
//!   occlusion) on a plane. V_j: `steps` ray-marching points along each direction at λ_j·k/steps;
//!   an occluded direction keeps 1 − 1/(1 + lambda·d) of its weight (d: blocker distance) when
//!   `lambda` > 0. Storage: 16 half floats, pack2x16float into two rgba32uint targets (the WGSL
//!   form of the paper's pack_half into two 32-bit-per-channel targets).
//! `filter_pass`: the paper's geometry-aware 8×8 bilateral filter (offsets −3..4) on the coefficients,
//!   weights from the distance to the centre's tangent plane and the normals' agreement.
//! `shade_pass`: c[Lin] = c[env] + Σ_l c[l] (Eq. 4), E_diff = c[Lin]·c[S3HO] (Eq. 3):
//!   env-irradiance = c[env]·c[S3HO]/π; light-irradiance = Σ_l E_l/π · (n·l − h·c_occ(l)) · shadow
//!   where c_occ = c[cos n] − c[S3HO] and h(l) is the light's Hanning-windowed SH lobe (Sloan 2008,
//!   window (1 + cos(π l/4))/2): the unoccluded part exact, the occluded part through the SH lobe;
//!   ao = c[S3HO]_0 / (π y_0) (the DC term is y_0 ∫V cos dω).
//! Indirect (Eq. 5): every occluded sample's pixel is a patch with form factor f (SSDO's: πR²/N ·
//!   cos θ_s cos θ_r / max(d, distance_clamp)², falloff 1 − d/R) and radiance (ρ_o/π)·(c[cos n_o]·
//!   c[Lin]); the sum is computed per colour channel directly (the dot with c[Lin] is linear, so
//!   this equals storing 3×16 coefficients and dotting after the filter) and blurred.
//! `ssbn`: bent normal b = normalised mean of unoccluded directions, cone cos α = 1 − (visible
//!   fraction); env-irradiance = Σ c[env]_lm λ_l(α) y_lm(b)/π with the cone-limited cosine kernel
//!   λ_l(α) = 2π ∫_{cos α}^1 t P_l(t) dt; lights weighted by a soft cone test around b. Known
//!   failure: the two faces of a 90° corner get the same bent normal and cone, hence one colour.
//!
//! One pass = one `.rs` + one `.wgsl` here: [`sample`], [`filter`], [`shade`] (`sh.wgsl` is
//! shared by them).

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
use crate::settings::{Declared, count_constants};
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
    Ok((s.denoise, SvgfConfig::with_defaults(s.svgf)))
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
        let module = crate::pipeline_cache::shader_module(device, label, &source);
        let counted = count_constants(&source, &counts);
        let mut constants: Vec<(&str, f64)> =
            counted.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        constants.extend_from_slice(extra);
        let step = ComputeStep::new(device, label, &module, entry, frame, &layout, &constants);
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

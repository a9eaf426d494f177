//! `gtao` and `hbil`: horizon-based ambient occlusion (Jimenez et al. 2016) and horizon-based
//! indirect lighting (Mayaux 2018). See horizon.wgsl for the formulas, sources and deviations.
//!
//! Frame (hbil; gtao skips the radiance steps):
//!   reproject (scatter or gather last frame's diffuse radiance) → push/pull (fill holes) →
//!   split (4×4 deinterleave, with interleaving) → horizon search → merge → bilateral blur →
//!   accumulate (temporal, disocclusion-rejected) → outputs (ao, env-irradiance through the bent
//!   cone, indirect-irradiance, and the diffuse radiance the next frame gathers).
//! On the first frame and after a camera cut the source radiance is this frame's direct
//! radiance (DESIGN.md's L_o: one bounce); afterwards it is last frame's diffuse radiance, so
//! bounces add up over frames (HBIL Eq. 17).

use super::{
    FrameInfo, Preset, Setting, Technique, TechniqueContext, TechniqueDesc, TechniqueParams,
};
use crate::RenderError;
use crate::gpu_env::GpuEnvironment;
use crate::passes::bilateral_blur::{BilateralBlur, BlurChain, BlurSettings};
use crate::passes::reproject::{History, ReprojectMode, ReprojectParams, Reprojection};
use crate::profiler::GpuProfiler;
use crate::targets::{AO_FORMAT, HDR_FORMAT};
use crate::util;
use bytemuck::{Pod, Zeroable};
use wgpu::BindingResource as R;
use wgpu::util::DeviceExt;

pub const SHADER: &str = include_str!("horizon.wgsl");

pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, util::ENV_WGSL, SHADER])
}

pub const GTAO: TechniqueDesc = TechniqueDesc {
    name: "gtao",
    summary: "ground-truth AO: horizon search in slices, cosine-weighted AO, bent normal; ao × SH irradiance",
    create: create_gtao,
    settings: SETTINGS,
    presets: PRESETS,
};

pub const HBIL: TechniqueDesc = TechniqueDesc {
    name: "hbil",
    summary: "horizon-based indirect lighting: bent cones, far field through the cone, near-field bounces from reprojected radiance",
    create: create_hbil,
    settings: SETTINGS,
    presets: PRESETS,
};

/// Far-field estimate through the bent cone (hbil).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Far {
    /// SH irradiance with the cone's reduced aperture (HBIL Sec. 2.2.4).
    Sh,
    /// Pre-convolved diffuse map at the bent normal × F0(ao) (HBIL Sec. 2.2.3).
    Envmap,
    /// The environment integrated over every slice's visible arcs (directional; beyond the
    /// paper, see horizon.wgsl).
    Slices,
}

/// How the bent cone's aperture follows from the (cosine-weighted) ao (hbil, `far=sh`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aperture {
    /// cos α = 1 − ao (HBIL Eq. 12).
    Eq12,
    /// cos α = √(1 − ao): the cone whose cosine-weighted visibility is ao (see horizon.wgsl).
    Matched,
}

/// Where the near-field radiance comes from (hbil).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Last frame's diffuse radiance, reprojected (bounces accumulate, HBIL Eq. 17); this
    /// frame's direct radiance on the first frame and after a cut.
    Previous,
    /// This frame's direct radiance every frame (exactly one bounce, DESIGN.md's L_o).
    Direct,
}

/// Settings of `gtao` and `hbil` (`--samples` = steps, `--radius`, `--set key=value`).
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// `slices`: slices per pixel S, 1..=32. Default 2 (with 4×4 interleaving: 32 directions
    /// per 4×4 block).
    pub slices: u32,
    /// `steps` (or `--samples`): samples per side of a slice, 1..=128. Default 16.
    pub steps: u32,
    /// `radius`: near-field radius R in metres, > 0 and finite. Default 0.5.
    pub radius: f32,
    /// `interleaved`: on | off — 4×4 deinterleaved quarter-resolution layers. Default on.
    pub interleaved: bool,
    /// `reprojection`: scatter | gather. Default scatter (hbil).
    pub reprojection: ReprojectMode,
    /// `far`: sh | envmap | slices. Default slices (hbil).
    pub far: Far,
    /// `aperture`: eq12 | matched. Default matched (hbil, far=sh).
    pub aperture: Aperture,
    /// `source`: previous | direct. Default previous (hbil).
    pub source: Source,
    /// `temporal`: on | off — accumulation over frames. Default on.
    pub temporal: bool,
    /// `history`: frames in the running mean at most, 1..=1024. Default 32.
    pub history: u32,
    /// `fresnel`: on | off — (1 − F0) on near-field light (HBIL Eq. 19). Default on.
    pub fresnel: bool,
    /// `falloff`: fraction of R over which an occluder's rise fades out before R, 0..=1.
    /// Default 0.1.
    pub falloff: f32,
    /// `step_power`: exponent of the step distribution t_j ∝ ((j + ξ)/steps)^p, 1..=4.
    /// Default 2 (denser near the pixel).
    pub step_power: f32,
    /// `max_pixels`: longest march in full-resolution pixels, 1..=8192. Default 256.
    pub max_pixels: f32,
    /// `reject_a`, `reject_b`: smoothstep edges on −n′·ω of the radiance rejection (HBIL
    /// Sec. 3.4), −1..=1, a < b. Defaults −0.1, 0.1.
    pub reject_a: f32,
    pub reject_b: f32,
    /// `blur`: on | off — geometry-aware blur of the raw results (merges the 4×4 block's
    /// directions). Default on.
    pub blur: bool,
    /// `blur_radius`: half width in pixels, 0..=16. Default 4 (Gaussian σ = 2: weighs a 4×4
    /// block nearly evenly, so its 16 interleaved direction sets merge).
    pub blur_radius: u32,
    /// `reject_depth`: history and reprojection reject a point farther than this × view depth
    /// from the current tangent plane, 1e-4..=1. Default 0.02.
    pub reject_depth: f32,
    /// `reject_normal`: … or whose normal's cosine with the current one is below this, −1..=1.
    /// Default 0.9.
    pub reject_normal: f32,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            slices: 2,
            steps: 16,
            radius: 0.5,
            interleaved: true,
            reprojection: ReprojectMode::Scatter,
            far: Far::Slices,
            aperture: Aperture::Matched,
            source: Source::Previous,
            temporal: true,
            history: 32,
            fresnel: true,
            falloff: 0.1,
            step_power: 2.0,
            max_pixels: 256.0,
            reject_a: -0.1,
            reject_b: 0.1,
            blur: true,
            blur_radius: 4,
            reject_depth: 0.02,
            reject_normal: 0.9,
        }
    }
}

/// `quality` presets: slices and steps.
pub const PRESETS: &[Preset] = &[
    Preset {
        name: "low",
        set: &[("slices", "1"), ("steps", "8")],
    },
    Preset {
        name: "medium",
        set: &[("slices", "2"), ("steps", "16")],
    },
    Preset {
        name: "high",
        set: &[("slices", "4"), ("steps", "16")],
    },
    Preset {
        name: "ultra",
        set: &[("slices", "8"), ("steps", "32")],
    },
];

/// Every `--set` key with its range and default (the fields of [`Settings`]; `samples` is
/// another name for `steps`).
pub const SETTINGS: &[Setting] = &[
    Setting::integer("slices", 1.0, 32.0, "2", "slices per pixel"),
    Setting::integer("steps", 1.0, 128.0, "16", "samples per side of a slice"),
    Setting::log("radius", 1e-6, 1e6, "0.5", "near-field radius R (m)"),
    Setting::toggle(
        "interleaved",
        "on",
        "4×4 deinterleaved quarter-resolution layers",
    ),
    Setting::choice(
        "reprojection",
        &["scatter", "gather"],
        "scatter",
        "last frame's radiance (hbil)",
    ),
    Setting::choice(
        "far",
        &["sh", "envmap", "slices"],
        "slices",
        "far-field light (hbil)",
    ),
    Setting::choice(
        "aperture",
        &["eq12", "matched"],
        "matched",
        "bent-cone aperture (far=sh)",
    ),
    Setting::choice(
        "source",
        &["previous", "direct"],
        "previous",
        "near-field radiance (hbil)",
    ),
    Setting::toggle("temporal", "on", "accumulation over frames"),
    Setting::integer(
        "history",
        1.0,
        1024.0,
        "32",
        "frames in the running mean at most",
    ),
    Setting::toggle("fresnel", "on", "(1 − F0) on near-field light"),
    Setting::number(
        "falloff",
        0.0,
        1.0,
        "0.1",
        "fade of an occluder's rise before R (fraction)",
    ),
    Setting::number(
        "step_power",
        1.0,
        4.0,
        "2",
        "exponent of the step distribution",
    ),
    Setting::log("max_pixels", 1.0, 8192.0, "256", "longest march (pixels)"),
    Setting::number(
        "reject_a",
        -1.0,
        1.0,
        "-0.1",
        "radiance rejection, lower edge (< reject_b)",
    ),
    Setting::number(
        "reject_b",
        -1.0,
        1.0,
        "0.1",
        "radiance rejection, upper edge",
    ),
    Setting::toggle("blur", "on", "geometry-aware blur of the raw results"),
    Setting::integer("blur_radius", 0.0, 16.0, "4", "blur half width (pixels)"),
    Setting::log(
        "reject_depth",
        1e-4,
        1.0,
        "0.02",
        "history depth tolerance (× view depth)",
    ),
    Setting::number(
        "reject_normal",
        -1.0,
        1.0,
        "0.9",
        "history normal tolerance (cosine)",
    ),
];

impl Settings {
    /// Applies `--samples` (steps), `--radius` and `--set` on top of the defaults (`quality`
    /// was expanded by [`super::expand_presets`] before).
    pub fn from_params(params: &TechniqueParams) -> Result<Self, String> {
        let mut s = Settings::default();
        if let Some(n) = params.samples {
            s.steps = n;
        }
        if let Some(r) = params.radius {
            s.radius = r;
        }
        use super::{parse_number as num, parse_on_off as on_off};
        for (k, v) in &params.set {
            match k.as_str() {
                "slices" => s.slices = super::parse_integer(k, v, 1, 32)?,
                "steps" | "samples" => s.steps = super::parse_integer(k, v, 1, 128)?,
                "radius" => s.radius = num(k, v, 1e-6, 1e6)?,
                "interleaved" => s.interleaved = on_off(k, v)?,
                "reprojection" => s.reprojection = ReprojectMode::parse(k, v)?,
                "far" => {
                    s.far = match v.as_str() {
                        "sh" => Far::Sh,
                        "envmap" => Far::Envmap,
                        "slices" => Far::Slices,
                        _ => return Err(format!("{k}={v}: expected sh, envmap or slices")),
                    }
                }
                "aperture" => {
                    s.aperture = match v.as_str() {
                        "eq12" => Aperture::Eq12,
                        "matched" => Aperture::Matched,
                        _ => return Err(format!("{k}={v}: expected eq12 or matched")),
                    }
                }
                "source" => {
                    s.source = match v.as_str() {
                        "previous" => Source::Previous,
                        "direct" => Source::Direct,
                        _ => return Err(format!("{k}={v}: expected previous or direct")),
                    }
                }
                "temporal" => s.temporal = on_off(k, v)?,
                "history" => s.history = super::parse_integer(k, v, 1, 1024)?,
                "fresnel" => s.fresnel = on_off(k, v)?,
                "falloff" => s.falloff = num(k, v, 0.0, 1.0)?,
                "step_power" => s.step_power = num(k, v, 1.0, 4.0)?,
                "max_pixels" => s.max_pixels = num(k, v, 1.0, 8192.0)?,
                "reject_a" => s.reject_a = num(k, v, -1.0, 1.0)?,
                "reject_b" => s.reject_b = num(k, v, -1.0, 1.0)?,
                "blur" => s.blur = on_off(k, v)?,
                "blur_radius" => s.blur_radius = super::parse_integer(k, v, 0, 16)?,
                "reject_depth" => s.reject_depth = num(k, v, 1e-4, 1.0)?,
                "reject_normal" => s.reject_normal = num(k, v, -1.0, 1.0)?,
                _ => {
                    return Err(format!(
                        "unknown setting '{k}' (known: quality, samples, {})",
                        super::keys(SETTINGS)
                    ));
                }
            }
        }
        if !(s.radius.is_finite() && s.radius > 0.0) {
            return Err(format!(
                "radius {}: the horizon search needs a finite radius > 0",
                s.radius
            ));
        }
        if !(1..=128).contains(&s.steps) {
            return Err(format!("steps {}: must be in 1..=128", s.steps));
        }
        if s.reject_a >= s.reject_b {
            return Err(format!(
                "reject_a {} must be below reject_b {}",
                s.reject_a, s.reject_b
            ));
        }
        Ok(s)
    }

    /// The GPU constants (pure). `size` is the image size.
    pub fn params(&self, hbil: bool, size: (u32, u32)) -> HorizonParams {
        let scale = if self.interleaved { 4 } else { 1 };
        HorizonParams {
            radius: self.radius,
            slices: self.slices,
            steps: self.steps,
            falloff: self.falloff,
            max_pixels: self.max_pixels,
            scale,
            indirect: hbil as u32,
            step_power: self.step_power,
            reject_a: self.reject_a,
            reject_b: self.reject_b,
            layer_width: size.0.div_ceil(scale),
            layer_height: size.1.div_ceil(scale),
            temporal: self.temporal as u32,
            max_history: self.history as f32,
            far: match (hbil, self.far) {
                (false, _) => 0,
                (true, Far::Sh) => 1,
                (true, Far::Envmap) => 2,
                (true, Far::Slices) => 3,
            },
            fresnel: (hbil && self.fresnel) as u32,
            reject_depth: self.reject_depth,
            reject_normal: self.reject_normal,
            aperture: (self.aperture == Aperture::Matched) as u32,
            far_steps: 8,
        }
    }
}

/// `HorizonParams` in horizon.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct HorizonParams {
    pub radius: f32,
    pub slices: u32,
    pub steps: u32,
    pub falloff: f32,
    pub max_pixels: f32,
    pub scale: u32,
    pub indirect: u32,
    pub step_power: f32,
    pub reject_a: f32,
    pub reject_b: f32,
    pub layer_width: u32,
    pub layer_height: u32,
    pub temporal: u32,
    pub max_history: f32,
    pub far: u32,
    pub fresnel: u32,
    pub reject_depth: f32,
    pub reject_normal: f32,
    pub aperture: u32,
    pub far_steps: u32,
}

/// Texture arrays of the 4×4 deinterleaved layers.
struct Split {
    split_bg: [wgpu::BindGroup; 3],
    merge_bg: wgpu::BindGroup,
    horizon_bg: wgpu::BindGroup,
    layer_size: (u32, u32),
}

struct Horizon {
    name: &'static str,
    hbil: bool,
    size: (u32, u32),
    source: Source,
    split_pipeline: wgpu::ComputePipeline,
    horizon_pipeline: wgpu::ComputePipeline,
    merge_pipeline: wgpu::ComputePipeline,
    accumulate_pipeline: wgpu::ComputePipeline,
    outputs_pipeline: wgpu::ComputePipeline,
    /// With interleaving.
    split: Option<Split>,
    /// Without interleaving, by radiance source (direct side 0, side 1, reprojected).
    full_bg: Vec<wgpu::BindGroup>,
    reprojection: Option<Reprojection>,
    blur: Option<(BilateralBlur, Vec<BlurChain>)>,
    accumulate_bg: [wgpu::BindGroup; 2],
    outputs_bg: [wgpu::BindGroup; 2],
    extras: [Vec<(&'static str, wgpu::Texture)>; 2],
    _textures: Vec<wgpu::Texture>,
    _params: wgpu::Buffer,
}

fn create_gtao(
    ctx: &TechniqueContext,
    params: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    create(ctx, params, false)
}

fn create_hbil(
    ctx: &TechniqueContext,
    params: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    create(ctx, params, true)
}

fn array_view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

fn array_texture(binding: u32, filterable: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable },
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        count: None,
    }
}

fn array_storage(binding: u32, format: wgpu::TextureFormat) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2Array,
        },
        count: None,
    }
}

fn create(
    ctx: &TechniqueContext,
    tp: &TechniqueParams,
    hbil: bool,
) -> Result<Box<dyn Technique>, RenderError> {
    let name = if hbil { "hbil" } else { "gtao" };
    let settings = Settings::from_params(tp).map_err(|msg| RenderError::Setting {
        technique: name.into(),
        msg,
    })?;
    let device = ctx.device;
    let t = ctx.targets;
    let size = t.size;
    let c = wgpu::ShaderStages::COMPUTE;
    let p = settings.params(hbil, size);
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("horizon params"),
        contents: bytemuck::bytes_of(&p),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let full = |label: &str, format| super::screen_texture(device, size, label, format);
    let raw_cone = full("horizon cone", HDR_FORMAT);
    let raw_near = full("horizon near", HDR_FORMAT);
    let raw_far = full("horizon far", HDR_FORMAT);
    let hist_far = [
        full("far history 0", HDR_FORMAT),
        full("far history 1", HDR_FORMAT),
    ];
    let hist_cone = [
        full("cone history 0", HDR_FORMAT),
        full("cone history 1", HDR_FORMAT),
    ];
    let hist_near = [
        full("near history 0", HDR_FORMAT),
        full("near history 1", HDR_FORMAT),
    ];
    let geo_format = wgpu::TextureFormat::Rgba32Float;
    let hist_geo = [
        full("geometry history 0", geo_format),
        full("geometry history 1", geo_format),
    ];
    let feedback = [
        full("diffuse radiance 0", HDR_FORMAT),
        full("diffuse radiance 1", HDR_FORMAT),
    ];
    let view = |t: &wgpu::Texture| t.create_view(&Default::default());
    let hist_geo_views = [view(&hist_geo[0]), view(&hist_geo[1])];
    let feedback_views = [view(&feedback[0]), view(&feedback[1])];

    let reprojection = (hbil && settings.source == Source::Previous).then(|| {
        Reprojection::new(
            device,
            ctx.frame,
            t,
            [
                History {
                    geometry: &hist_geo_views[0],
                    radiance: &feedback_views[0],
                },
                History {
                    geometry: &hist_geo_views[1],
                    radiance: &feedback_views[1],
                },
            ],
            settings.reprojection,
            ReprojectParams {
                reject_depth: settings.reject_depth,
                reject_normal: settings.reject_normal,
                _pad: [0.0; 2],
            },
        )
    });
    // Radiance sources by index: this frame's direct radiance (side 0, side 1), reprojected.
    let direct_views = [&t.direct_radiance[0].view, &t.direct_radiance[1].view];
    let reprojected_view = reprojection
        .as_ref()
        .map(|r| &r.output)
        .unwrap_or(direct_views[0]);
    let source_views = [direct_views[0], direct_views[1], reprojected_view];

    let src = source();
    let layout = |label: &str, entries: &[wgpu::BindGroupLayoutEntry]| {
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries,
        })
    };
    let mut horizon_entries = vec![
        util::uniform(0, c),
        util::uniform(5, c),
        array_texture(8, false),
        array_texture(9, false),
        array_texture(10, true),
        array_storage(20, HDR_FORMAT),
        array_storage(21, HDR_FORMAT),
        array_storage(43, HDR_FORMAT),
    ];
    horizon_entries.extend(GpuEnvironment::layout_entries());
    let horizon_layout = layout("horizon", &horizon_entries);
    let horizon_bg = |depth: &wgpu::TextureView,
                      normal: &wgpu::TextureView,
                      radiance: &wgpu::TextureView,
                      out: [&wgpu::TextureView; 3]| {
        let mut res = vec![
            (0, ctx.frame.as_entire_binding()),
            (5, params.as_entire_binding()),
            (8, R::TextureView(depth)),
            (9, R::TextureView(normal)),
            (10, R::TextureView(radiance)),
            (20, R::TextureView(out[0])),
            (21, R::TextureView(out[1])),
            (43, R::TextureView(out[2])),
        ];
        res.extend(ctx.env.bindings());
        util::bind_group(device, name, &horizon_layout, &res)
    };
    let mut textures = Vec::new();
    let split_layout = layout(
        "split",
        &[
            util::uniform(0, c),
            util::uniform(5, c),
            util::texture(11, c, false),
            util::texture(12, c, true),
            util::texture(13, c, true),
            array_storage(23, geo_format),
            array_storage(24, HDR_FORMAT),
        ],
    );
    let merge_layout = layout(
        "merge",
        &[
            util::uniform(0, c),
            array_texture(14, true),
            array_texture(15, true),
            util::storage_texture(25, HDR_FORMAT),
            util::storage_texture(26, HDR_FORMAT),
            array_texture(44, true),
            util::storage_texture(45, HDR_FORMAT),
        ],
    );
    let mut full_bg = Vec::new();
    let split = if settings.interleaved {
        let layer_size = (p.layer_width, p.layer_height);
        let layered =
            |label: &str, format| super::layered_texture(device, layer_size, 16, label, format);
        let s_geometry = layered("split geometry", geo_format);
        let s_radiance = layered("split radiance", HDR_FORMAT);
        let l_cone = layered("split cone", HDR_FORMAT);
        let l_near = layered("split near", HDR_FORMAT);
        let l_far = layered("split far", HDR_FORMAT);
        let (vg, vr, vc, vnear, vfar) = (
            array_view(&s_geometry),
            array_view(&s_radiance),
            array_view(&l_cone),
            array_view(&l_near),
            array_view(&l_far),
        );
        let split_bg = |radiance: &wgpu::TextureView| {
            util::bind_group(
                device,
                "split",
                &split_layout,
                &[
                    (0, ctx.frame.as_entire_binding()),
                    (5, params.as_entire_binding()),
                    (11, R::TextureView(&t.view_depth.view)),
                    (12, R::TextureView(&t.normal.view)),
                    (13, R::TextureView(radiance)),
                    (23, R::TextureView(&vg)),
                    (24, R::TextureView(&vr)),
                ],
            )
        };
        let s = Split {
            split_bg: [
                split_bg(source_views[0]),
                split_bg(source_views[1]),
                split_bg(source_views[2]),
            ],
            merge_bg: util::bind_group(
                device,
                "merge",
                &merge_layout,
                &[
                    (0, ctx.frame.as_entire_binding()),
                    (14, R::TextureView(&vc)),
                    (15, R::TextureView(&vnear)),
                    (25, R::TextureView(&view(&raw_cone))),
                    (26, R::TextureView(&view(&raw_near))),
                    (44, R::TextureView(&vfar)),
                    (45, R::TextureView(&view(&raw_far))),
                ],
            ),
            // Depth is read from the geometry's w; binding 8 only has to be present.
            horizon_bg: horizon_bg(&vg, &vg, &vr, [&vc, &vnear, &vfar]),
            layer_size,
        };
        textures.extend([s_geometry, s_radiance, l_cone, l_near, l_far]);
        Some(s)
    } else {
        let as_array = |t: &wgpu::Texture| array_view(t);
        let (depth, normal) = (as_array(&t.view_depth.texture), as_array(&t.normal.texture));
        let (cone, near, far) = (as_array(&raw_cone), as_array(&raw_near), as_array(&raw_far));
        let source_textures = [
            &t.direct_radiance[0].texture,
            &t.direct_radiance[1].texture,
            reprojection
                .as_ref()
                .map(|r| &r.output_texture)
                .unwrap_or(&t.direct_radiance[0].texture),
        ];
        for s in source_textures {
            let radiance = s.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                base_mip_level: 0,
                mip_level_count: Some(1),
                ..Default::default()
            });
            full_bg.push(horizon_bg(&depth, &normal, &radiance, [&cone, &near, &far]));
        }
        None
    };

    let blur = settings.blur.then(|| {
        let b = BilateralBlur::new(
            device,
            BlurSettings {
                enabled: true,
                radius: settings.blur_radius,
                depth_sigma: 0.01,
                normal_power: 8.0,
            },
        );
        let scratch = full("horizon blur scratch", HDR_FORMAT);
        let cone_out = full("horizon cone blurred", HDR_FORMAT);
        let near_out = full("horizon near blurred", HDR_FORMAT);
        let far_out = full("horizon far blurred", HDR_FORMAT);
        let chain = |from: &wgpu::Texture, to: &wgpu::Texture| {
            b.chain(
                device,
                ctx.frame,
                t,
                &view(from),
                &view(&scratch),
                &view(to),
            )
        };
        let mut chains = vec![chain(&raw_cone, &cone_out)];
        if hbil {
            chains.push(chain(&raw_near, &near_out));
        }
        if p.far == 3 {
            chains.push(chain(&raw_far, &far_out));
        }
        (b, chains, [scratch, cone_out, near_out, far_out])
    });
    let (cone_in, near_in, far_in) = match &blur {
        Some((_, _, tex)) => (
            view(&tex[1]),
            if hbil { view(&tex[2]) } else { view(&raw_near) },
            if p.far == 3 {
                view(&tex[3])
            } else {
                view(&raw_far)
            },
        ),
        None => (view(&raw_cone), view(&raw_near), view(&raw_far)),
    };

    let accumulate_layout = layout(
        "accumulate",
        &[
            util::uniform(0, c),
            util::uniform(5, c),
            util::texture(16, c, true),
            util::texture(17, c, false),
            util::texture(18, c, true),
            util::texture(19, c, true),
            util::texture(27, c, true),
            util::texture(28, c, true),
            util::texture(29, c, false),
            util::storage_texture(30, HDR_FORMAT),
            util::storage_texture(31, HDR_FORMAT),
            util::storage_texture(32, geo_format),
            util::texture(46, c, true),
            util::texture(47, c, true),
            util::storage_texture(48, HDR_FORMAT),
        ],
    );
    let accumulate_bg = |side: usize| {
        let prev = 1 - side;
        util::bind_group(
            device,
            "accumulate",
            &accumulate_layout,
            &[
                (0, ctx.frame.as_entire_binding()),
                (5, params.as_entire_binding()),
                (16, R::TextureView(&t.normal.view)),
                (17, R::TextureView(&t.view_depth.view)),
                (18, R::TextureView(&cone_in)),
                (19, R::TextureView(&near_in)),
                (27, R::TextureView(&view(&hist_cone[prev]))),
                (28, R::TextureView(&view(&hist_near[prev]))),
                (29, R::TextureView(&hist_geo_views[prev])),
                (30, R::TextureView(&view(&hist_cone[side]))),
                (31, R::TextureView(&view(&hist_near[side]))),
                (32, R::TextureView(&hist_geo_views[side])),
                (46, R::TextureView(&far_in)),
                (47, R::TextureView(&view(&hist_far[prev]))),
                (48, R::TextureView(&view(&hist_far[side]))),
            ],
        )
    };
    let mut outputs_entries = vec![util::uniform(0, c), util::uniform(5, c)];
    outputs_entries.extend(GpuEnvironment::layout_entries());
    outputs_entries.extend([
        util::texture(6, c, true),
        util::texture(16, c, true),
        util::texture(33, c, true),
        util::texture(34, c, true),
        util::texture(35, c, true),
        util::texture(36, c, true),
        util::texture(37, c, true),
        util::texture(38, c, true),
        util::storage_texture(39, AO_FORMAT),
        util::storage_texture(40, HDR_FORMAT),
        util::storage_texture(41, HDR_FORMAT),
        util::storage_texture(42, HDR_FORMAT),
        util::texture(49, c, true),
    ]);
    let outputs_layout = layout("outputs", &outputs_entries);
    let outputs_bg = |side: usize| {
        let cone = view(&hist_cone[side]);
        let near = view(&hist_near[side]);
        let far = view(&hist_far[side]);
        let mut res = vec![
            (0, ctx.frame.as_entire_binding()),
            (5, params.as_entire_binding()),
            (6, R::TextureView(&ctx.env.irradiance_view)),
            (16, R::TextureView(&t.normal.view)),
            (33, R::TextureView(&t.albedo.view)),
            (34, R::TextureView(&t.material.view)),
            (35, R::TextureView(&t.emissive.view)),
            (36, R::TextureView(&t.light_irradiance.view)),
            (37, R::TextureView(&cone)),
            (38, R::TextureView(&near)),
            (39, R::TextureView(&t.ao.view)),
            (40, R::TextureView(&t.env_irradiance.view)),
            (41, R::TextureView(&t.indirect_irradiance.view)),
            (42, R::TextureView(&feedback_views[side])),
            (49, R::TextureView(&far)),
        ];
        res.extend(ctx.env.bindings());
        util::bind_group(device, "outputs", &outputs_layout, &res)
    };
    let pipeline = |entry: &str, layout: &wgpu::BindGroupLayout| {
        util::compute_pipeline(device, entry, &src, entry, layout)
    };
    let extras = |side: usize| {
        let mut e = vec![
            ("bent-cone", hist_cone[side].clone()),
            ("near-history", hist_near[side].clone()),
            ("far-history", hist_far[side].clone()),
            ("feedback", feedback[side].clone()),
        ];
        if let Some(r) = &reprojection {
            e.push(("reprojected", r.raw.clone()));
            e.push(("radiance-source", r.output_texture.clone()));
        }
        e
    };
    let technique = Horizon {
        name,
        hbil,
        size,
        source: settings.source,
        split_pipeline: pipeline("split", &split_layout),
        horizon_pipeline: pipeline("horizon", &horizon_layout),
        merge_pipeline: pipeline("merge", &merge_layout),
        accumulate_pipeline: pipeline("accumulate", &accumulate_layout),
        outputs_pipeline: pipeline("outputs", &outputs_layout),
        split,
        full_bg,
        accumulate_bg: [accumulate_bg(0), accumulate_bg(1)],
        outputs_bg: [outputs_bg(0), outputs_bg(1)],
        extras: [extras(0), extras(1)],
        reprojection,
        blur: blur.map(|(b, chains, tex)| {
            textures.extend(tex);
            (b, chains)
        }),
        _textures: {
            textures.extend([raw_cone, raw_near, raw_far]);
            textures.extend(hist_far);
            textures.extend(hist_cone);
            textures.extend(hist_near);
            textures.extend(hist_geo);
            textures.extend(feedback);
            textures
        },
        _params: params,
    };
    Ok(Box::new(technique))
}

impl Technique for Horizon {
    fn name(&self) -> &'static str {
        self.name
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        frame: FrameInfo,
    ) {
        let side = frame.side();
        let reproject = self.hbil && self.source == Source::Previous && frame.history;
        let source = if reproject { 2 } else { side };
        if reproject && let Some(r) = &self.reprojection {
            r.encode(encoder, profiler, side);
        }
        match &self.split {
            Some(s) => {
                let (gx, gy) = util::groups_8x8(s.layer_size);
                {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("split"),
                        timestamp_writes: profiler.compute("split"),
                    });
                    pass.set_pipeline(&self.split_pipeline);
                    pass.set_bind_group(0, &s.split_bg[source], &[]);
                    pass.dispatch_workgroups(gx, gy, 1);
                }
                {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some(self.name),
                        timestamp_writes: profiler.compute(self.name),
                    });
                    pass.set_pipeline(&self.horizon_pipeline);
                    pass.set_bind_group(0, &s.horizon_bg, &[]);
                    // The 16 layers stacked vertically (see horizon.wgsl).
                    pass.dispatch_workgroups(gx, gy * 16, 1);
                }
                super::dispatch_screen(
                    encoder,
                    profiler,
                    "merge",
                    &self.merge_pipeline,
                    &s.merge_bg,
                    self.size,
                );
            }
            None => super::dispatch_screen(
                encoder,
                profiler,
                self.name,
                &self.horizon_pipeline,
                &self.full_bg[source],
                self.size,
            ),
        }
        if let Some((blur, chains)) = &self.blur {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("blur"),
                timestamp_writes: profiler.compute("blur"),
            });
            for chain in chains {
                blur.dispatch(&mut pass, chain, self.size);
            }
        }
        let (gx, gy) = util::groups_8x8(self.size);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("temporal"),
            timestamp_writes: profiler.compute("temporal"),
        });
        pass.set_pipeline(&self.accumulate_pipeline);
        pass.set_bind_group(0, &self.accumulate_bg[side], &[]);
        pass.dispatch_workgroups(gx, gy, 1);
        pass.set_pipeline(&self.outputs_pipeline);
        pass.set_bind_group(0, &self.outputs_bg[side], &[]);
        pass.dispatch_workgroups(gx, gy, 1);
    }

    fn extras(&self, frame: FrameInfo) -> Vec<(&'static str, &wgpu::Texture)> {
        self.extras[frame.side()]
            .iter()
            .map(|(n, t)| (*n, t))
            .collect()
    }
}

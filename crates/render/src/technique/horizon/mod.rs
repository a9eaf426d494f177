//! `gtao` and `hbil`: horizon-based ambient occlusion (Jimenez et al. 2016) and horizon-based
//! indirect lighting (Mayaux 2018). The formulas, sources and deviations follow below;
//! each pass is one `.rs` + one `.wgsl` here: [`split`], [`search`], [`accumulate`]
//! (`params.wgsl` is shared).
//!
//! Frame (hbil; gtao skips the radiance steps):
//!   reproject (scatter or gather last frame's diffuse radiance) → push/pull (fill holes) →
//!   split (4×4 deinterleave, with interleaving) → horizon search (straight to full resolution) →
//!   bilateral blur → accumulate (temporal, disocclusion-rejected) and, in the same kernel, the
//!   outputs (ao, env-irradiance through the bent
//!   cone, indirect-irradiance, and the diffuse radiance the next frame gathers).
//! On the first frame and after a camera cut the source radiance is this frame's direct
//! radiance (DESIGN.md's L_o: one bounce); afterwards it is last frame's diffuse radiance, so
//! bounces add up over frames (HBIL Eq. 17).

//!
//! The derivations. Horizon-based techniques: `gtao` (Jimenez et al. 2016) and `hbil` (Mayaux
//! 2018, "Horizon-Based Indirect Lighting"). Entry points, in frame order:
//!   split     deinterleave depth, normal and source radiance into 4×4 quarter-resolution layers
//!             (HBIL Sec. 3.3; only with interleaving)
//!   horizon   the horizon search: AO, bent normal and near-field irradiance per pixel
//!   accumulate  temporal accumulation with disocclusion rejection (history ping-pong)
//!             and from it the AOVs: ao, env-irradiance (far field through the bent cone), indirect-irradiance and the
//!             diffuse radiance kept for the next frame (HBIL Eq. 17)
//!
//! Horizon search (HBIL Sec. 1.1–1.3, 2.1). At the surface point x (normal n) the local camera
//! frame is ω_o = normalize(eye − x), ω_x = normalize(Y × ω_o) with Y the camera's up vector,
//! ω_y = ω_o × ω_x. Slice φ has the tangent direction D(φ) = cos φ ω_x + sin φ ω_y; the plane
//! spanned by ω_o and D contains the eye, so it projects to a straight screen line through x,
//! which is marched both ways. A sample s on it lies in the slice (up to the snap to a texel
//! centre, removed by projecting s − x onto the slice plane), and its angle from ω_o is
//! exactly cos θ = (s − x)·ω_o / |s − x| — the local-camera horizon angle that Sec. 1.3 obtains
//! from the camera-space angle β by cos θ = (cos α z + sin α r)/√(r² + z²); computing it from the
//! vector in the local frame is the same correction without the intermediate angles.
//! Horizons are initialised from the normal (Sec. 2.1): with the projected normal
//! n′ = (n·D, n·ω_o) at slice angle γ = atan2(n′x, n′y), θ_front = γ + π/2 and θ_back = γ − π/2,
//! so they never fall below the tangent plane. Only samples within the near-field radius R count
//! (DESIGN.md's V_R); over the last `falloff`·R their rise fades out (GTAO's falloff).
//! Steps: t_j = r_px ((j + ξ)/steps)^power along the screen line, r_px the screen length of R at
//! the point (capped by `max_pixels`), ξ a per-pixel, per-frame jitter; with 4×4 interleaving the
//! march reads the pixel's own quarter-resolution layer, so offsets are multiples of 4 pixels.
//!
//! Slice integrals. For one slice with horizons θ0 ≤ 0 ≤ θ1 and n′ = (nx, ny) (unnormalised, so
//! that slices weigh by the projected normal's length as in GTAO), every quantity is an integral
//! ∫ f(θ) |sin θ| dθ over [θ0, θ1], and with
//!     G(θ) = ½ nx (θ − sin θ cos θ) + ½ ny sin² θ
//! (one antiderivative serves both sides because θ − sin θ cos θ is odd and sin² θ even):
//!   AO_i   = G(θ1) + G(θ0)                                            (HBIL Eq. 10–11)
//!   ñ′     = (Gx(θ1) + Gx(θ0), Gy(θ1) + Gy(θ0)),  Gx: n′ = (1, 0), Gy: n′ = (0, 1)   (Eq. 4–6)
//!   ΔE     = L_d(x′) (G(θ_old) − G(θ_new)) when a sample raises a horizon from θ_old to θ_new
//!                                                                       (Eq. 18, both sides)
//! Deviation: the paper prints Eq. 6 and Eq. 11 as ½ nx [θ1 − θ0 + sin θ0 cos θ0 − sin θ1 cos θ1];
//! with θ0 ≤ 0 that is not the integral of sin θ |sin θ| (it gives ñx = π/2 for the symmetric
//! horizons ±π/2, where the true value is 0); the G form above is the exact integral and agrees
//! with Jimenez et al.'s per-side â(h). AO = Σ_i AO_i / Σ_i U_i and E_near = Σ_i Σ ΔE / Σ_i U_i
//! (both carry the 1/π of DESIGN.md's AOVs), bent normal = normalize(Σ_i D ñx + ω_o ñy), where
//! U_i = G(θ_front,init) + G(θ_back,init) is slice i's value for an open hemisphere. The paper's
//! mean (1/S) Σ AO_i is unbiased only over uniformly spread φ — a single tilted slice of an open
//! plane gives |n′| (cos γ + γ sin γ) ≠ 1 — so with 2 slices per pixel a plane would read as
//! noise around 1; the ratio (same expectation, since E[U_i] = 1) is exactly 1 there.
//! Near field (Sec. 2.3, 3.4): L_d(x′) is read from the source radiance (this frame's direct
//! radiance on the first frame, else last frame's diffuse radiance reprojected); a sample whose
//! normal faces away from x is replaced by the last accepted one:
//! L ← mix(L, L(x′), smoothstep(a, b, −n′·ω)), ω = normalize(x′ − x). Eq. 19's (1 − F0) is the
//! receiver's, so it is applied once per pixel in `outputs`.
//! Slice angles: pixel cell c (its position in a 4×4 block, Bayer order) and slice k of S take
//! φ = π (k + frac(c/16 + ξ_frame)) / S: the 16 cells × S slices of a block cover [0, π) evenly
//! (32 directions for S = 2, the paper's setting), and ξ_frame (golden-ratio sequence) turns
//! them from frame to frame through the whole of [0, 1), so that every pixel's running mean
//! sees every direction. (Turning them by ξ_frame/16 only, within each cell's sixteenth, left
//! each pixel's mean converged to its own sixteenth of the integral: a fixed 4×4 pattern that
//! neither the running mean nor an edge-stopping filter removes.)

pub mod accumulate;
pub mod params;
pub mod search;
pub mod split;

use super::vbgi::{self, Bitmask};
use super::{FrameInfo, Technique, TechniqueContext, TechniqueDesc, TechniqueParams};
use crate::RenderError;
use crate::passes::bilateral_blur::{BilateralBlur, BlurChain, BlurSettings};
use crate::passes::denoise::{self, Denoise, SvgfConfig};
use crate::passes::layers::{LayerSettings, LayerStack};
use crate::passes::reproject::{History, ReprojectParams, Reprojection};
use crate::passes::{ComputeStep, PingPong};
use crate::profiler::GpuProfiler;
use crate::settings::Declared;
use crate::targets::HDR_FORMAT;
use crate::util;
use wgpu::util::DeviceExt;

pub use crate::settings::horizon::{Aperture, Far, PRESETS, ReprojectMode, Settings, Source};
pub use params::HorizonParams;

/// The history geometry and split geometry: world normal xyz, view depth w.
pub const GEOMETRY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

const GTAO_PRESETS: [crate::settings::Preset; 5] =
    crate::settings::fitted::with_fitted(PRESETS, crate::settings::fitted::GTAO);
const HBIL_PRESETS: [crate::settings::Preset; 5] =
    crate::settings::fitted::with_fitted(PRESETS, crate::settings::fitted::HBIL);

pub const GTAO: TechniqueDesc = TechniqueDesc {
    name: "gtao",
    summary: "ground-truth AO: horizon search in slices, cosine-weighted AO, bent normal; ao × SH irradiance",
    create: create_gtao,
    check,
    settings: <Settings as Declared>::TABLE,
    presets: &GTAO_PRESETS,
};

pub const HBIL: TechniqueDesc = TechniqueDesc {
    name: "hbil",
    summary: "horizon-based indirect lighting: bent cones, far field through the cone, near-field bounces from reprojected radiance",
    create: create_hbil,
    check,
    settings: <Settings as Declared>::TABLE,
    presets: &HBIL_PRESETS,
};

/// The 4×4 deinterleaved layers (with interleaving): split by radiance source (direct side 0,
/// side 1, reprojected) and search.
struct Split {
    split_bg: [wgpu::BindGroup; 3],
    search_bg: wgpu::BindGroup,
    layer_size: (u32, u32),
}

/// Which technique the horizon machinery runs as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Gtao,
    Hbil,
    Vbgi,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Gtao => "gtao",
            Kind::Hbil => "hbil",
            Kind::Vbgi => "vbgi",
        }
    }

    /// The settings of the machinery (and vbgi's bitmask part).
    fn parse(self, tp: &TechniqueParams) -> Result<(Settings, Option<Bitmask>), String> {
        match self {
            Kind::Vbgi => vbgi::parse(tp),
            _ => Ok((Settings::from_params(tp)?, None)),
        }
    }
}

/// vbgi's resources: the second depth layer and its deinterleave.
struct BitmaskParts {
    bitmask: Bitmask,
    params: wgpu::Buffer,
    layers: Option<LayerStack>,
    /// With `thickness=layer` and interleaving.
    back: Option<(ComputeStep, wgpu::BindGroup, (u32, u32))>,
}

struct Horizon {
    name: &'static str,
    kind: Kind,
    hbil: bool,
    size: (u32, u32),
    source: Source,
    split_step: ComputeStep,
    search_step: ComputeStep,
    accumulate_step: ComputeStep,
    /// With interleaving.
    split: Option<Split>,
    /// Without interleaving, the search's bind group by radiance source (direct side 0, side 1,
    /// reprojected).
    full_bg: Vec<wgpu::BindGroup>,
    reprojection: Option<Reprojection>,
    blur: Option<(BilateralBlur, Vec<BlurChain>)>,
    accumulate_bg: PingPong<wgpu::BindGroup>,
    extras: PingPong<Vec<(&'static str, wgpu::Texture)>>,
    _textures: Vec<wgpu::Texture>,
    /// `HorizonParams` of [`Self::settings`].
    params: wgpu::Buffer,
    settings: Settings,
    bitmask: Option<BitmaskParts>,
}

/// The settings parsed without a device (`TechniqueDesc::check`).
fn check(tp: &TechniqueParams) -> Result<(), String> {
    config(tp).map(|_| ())
}

/// gtao's and hbil's denoiser choice and svgf configuration.
fn config(tp: &TechniqueParams) -> Result<(Denoise, SvgfConfig), String> {
    Ok(svgf_config(&Settings::from_params(tp)?))
}

/// The denoiser choice and svgf's configuration of the machinery's settings: svgf keeps the
/// running mean under the technique's own `temporal`, `history` and history tests.
pub fn svgf_config(s: &Settings) -> (Denoise, SvgfConfig) {
    (
        s.denoise,
        SvgfConfig {
            temporal: s.temporal,
            history: s.history,
            reject_depth: s.reject_depth,
            reject_normal: s.reject_normal,
            svgf: s.svgf,
        },
    )
}

fn create_gtao(
    ctx: &TechniqueContext,
    tp: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    denoise::create_denoised(ctx, tp, "gtao", config, |ctx| build(ctx, Kind::Gtao, tp))
}

fn create_hbil(
    ctx: &TechniqueContext,
    tp: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    denoise::create_denoised(ctx, tp, "hbil", config, |ctx| build(ctx, Kind::Hbil, tp))
}

fn array_view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// Builds gtao, hbil or vbgi (without svgf: `denoise::create_denoised` wraps this).
pub fn build(
    ctx: &TechniqueContext,
    kind: Kind,
    tp: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    let name = kind.name();
    let hbil = kind != Kind::Gtao;
    let (settings, bitmask) = kind.parse(tp).map_err(RenderError::setting(name))?;
    let device = ctx.device;
    let frame = ctx.frame_group;
    let (i, o) = (ctx.inputs, ctx.outputs);
    let size = i.size;
    let p = settings.params(hbil, size);
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("horizon params"),
        contents: bytemuck::bytes_of(&p),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    let full = |label: &str, format| super::screen_texture(device, size, label, format);
    let raw_cone = full("horizon cone", HDR_FORMAT);
    let raw_near = full("horizon near", HDR_FORMAT);
    let raw_far = full("horizon far", HDR_FORMAT);
    let pair = |label: &str, format| {
        [
            full(&format!("{label} 0"), format),
            full(&format!("{label} 1"), format),
        ]
    };
    let hist_far = pair("far history", HDR_FORMAT);
    let hist_cone = pair("cone history", HDR_FORMAT);
    let hist_near = pair("near history", HDR_FORMAT);
    let hist_geo = pair("geometry history", GEOMETRY_FORMAT);
    let feedback = pair("diffuse radiance", HDR_FORMAT);
    let view = |t: &wgpu::Texture| t.create_view(&Default::default());
    let hist_geo_views = [view(&hist_geo[0]), view(&hist_geo[1])];
    let feedback_views = [view(&feedback[0]), view(&feedback[1])];

    let reprojection = (hbil && settings.source == Source::Previous).then(|| {
        Reprojection::new(
            device,
            frame,
            i,
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
            reproject_params(&settings),
        )
    });
    // Radiance sources by index: this frame's direct radiance (side 0, side 1), reprojected.
    let direct_views = i.direct_radiance;
    let reprojected_view = reprojection
        .as_ref()
        .map(|r| &r.output)
        .unwrap_or(direct_views[0]);
    let source_views = [direct_views[0], direct_views[1], reprojected_view];

    // vbgi: its uniforms, the second depth layer (thickness=layer) and what the march reads of
    // it (the deinterleaved layer with interleaving, the peeled layer without, else a stand-in).
    let vbgi_params = bitmask.map(|b| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("vbgi params"),
            contents: bytemuck::bytes_of(&b.params),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        })
    });
    let layers = match bitmask {
        Some(b) if b.layer => {
            let two = LayerSettings {
                layers: 2,
                ..Default::default()
            };
            let mut stack = LayerStack::new(device, i, ctx.scene, frame, two).map_err(|e| {
                RenderError::Setting {
                    technique: name.into(),
                    msg: format!(
                        "thickness=layer: {e}; thickness=adaptive or thickness=constant need no second layer"
                    ),
                }
            })?;
            stack.shade = false;
            Some(stack)
        }
        _ => None,
    };
    let split_back = (layers.is_some() && settings.interleaved).then(|| {
        super::layered_texture(
            device,
            (p.layer_width, p.layer_height),
            16,
            "split back depth",
            wgpu::TextureFormat::R32Float,
        )
    });
    let stand_in = super::screen_texture(
        device,
        (1, 1),
        "no back depth",
        wgpu::TextureFormat::R32Float,
    );
    let back_view = match (&split_back, &layers) {
        (Some(t), _) => array_view(t),
        (None, Some(l)) => l.resources().peel_depth.clone(),
        (None, None) => array_view(&stand_in),
    };
    let search_layout = match bitmask {
        Some(_) => vbgi::bitmask::BitmaskBindings::layout(device),
        None => search::SearchBindings::layout(device),
    };
    let search_bg = |depth: &wgpu::TextureView,
                     normal: &wgpu::TextureView,
                     radiance: &wgpu::TextureView,
                     out: [&wgpu::TextureView; 3]| {
        match &vbgi_params {
            Some(vbgi) => vbgi::bitmask::BitmaskBindings {
                params: &params,
                vbgi,
                in_depth: depth,
                in_normal: normal,
                in_radiance: radiance,
                in_back: &back_view,
                out_cone: out[0],
                out_near: out[1],
                out_far: out[2],
            }
            .bind_group(device, &search_layout),
            None => search::SearchBindings {
                params: &params,
                in_depth: depth,
                in_normal: normal,
                in_radiance: radiance,
                out_cone: out[0],
                out_near: out[1],
                out_far: out[2],
            }
            .bind_group(device, &search_layout),
        }
    };
    let mut textures = Vec::new();
    let split_layout = split::SplitBindings::layout(device);
    let mut full_bg = Vec::new();
    let split = if settings.interleaved {
        let layer_size = (p.layer_width, p.layer_height);
        let layered =
            |label: &str, format| super::layered_texture(device, layer_size, 16, label, format);
        let s_geometry = layered("split geometry", GEOMETRY_FORMAT);
        let s_radiance = layered("split radiance", HDR_FORMAT);
        let (vg, vr) = (array_view(&s_geometry), array_view(&s_radiance));
        let (vc, vnear, vfar) = (view(&raw_cone), view(&raw_near), view(&raw_far));
        let split_bg = |radiance: &wgpu::TextureView| {
            split::SplitBindings {
                params: &params,
                full_depth: i.view_depth,
                full_normal: i.normal,
                full_radiance: radiance,
                split_geometry: &vg,
                split_radiance: &vr,
            }
            .bind_group(device, &split_layout)
        };
        let s = Split {
            split_bg: [
                split_bg(source_views[0]),
                split_bg(source_views[1]),
                split_bg(source_views[2]),
            ],
            // Depth is read from the geometry's w; `in_depth` only has to be bound.
            search_bg: search_bg(&vg, &vg, &vr, [&vc, &vnear, &vfar]),
            layer_size,
        };
        textures.extend([s_geometry, s_radiance]);
        Some(s)
    } else {
        let as_array = |t: &wgpu::Texture| array_view(t);
        let (depth, normal) = (
            as_array(i.view_depth.texture()),
            as_array(i.normal.texture()),
        );
        let (cone, near, far) = (view(&raw_cone), view(&raw_near), view(&raw_far));
        let source_textures = [
            i.direct_radiance[0].texture(),
            i.direct_radiance[1].texture(),
            reprojection
                .as_ref()
                .map(|r| &r.output_texture)
                .unwrap_or(i.direct_radiance[0].texture()),
        ];
        for s in source_textures {
            let radiance = s.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                base_mip_level: 0,
                mip_level_count: Some(1),
                ..Default::default()
            });
            full_bg.push(search_bg(&depth, &normal, &radiance, [&cone, &near, &far]));
        }
        None
    };

    let blur = (settings.denoise == Denoise::Bilateral).then(|| {
        let b = BilateralBlur::new(device, frame, blur_settings(&settings));
        let scratch = full("horizon blur scratch", HDR_FORMAT);
        let cone_out = full("horizon cone blurred", HDR_FORMAT);
        let near_out = full("horizon near blurred", HDR_FORMAT);
        let far_out = full("horizon far blurred", HDR_FORMAT);
        let chain = |from: &wgpu::Texture, to: &wgpu::Texture| {
            b.chain(device, i, &view(from), &view(&scratch), &view(to))
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

    let accumulate_layout = accumulate::AccumulateBindings::layout(device);
    let accumulate_bg = PingPong::from_fn(|side| {
        let prev = 1 - side;
        accumulate::AccumulateBindings {
            params: &params,
            gb_normal: i.normal,
            gb_view_depth: i.view_depth,
            raw_cone: &cone_in,
            raw_near: &near_in,
            raw_far: &far_in,
            prev_cone: &view(&hist_cone[prev]),
            prev_near: &view(&hist_near[prev]),
            prev_far: &view(&hist_far[prev]),
            prev_geometry: &hist_geo_views[prev],
            acc_cone: &view(&hist_cone[side]),
            acc_near: &view(&hist_near[side]),
            acc_far: &view(&hist_far[side]),
            acc_geometry: &hist_geo_views[side],
            gb_albedo: i.albedo,
            gb_material: i.material,
            gb_emissive: i.emission,
            light_irradiance: o.light_irradiance,
            out_ao: o.ao,
            out_env: o.env_irradiance,
            out_indirect: o.indirect_irradiance,
            out_feedback: &feedback_views[side],
        }
        .bind_group(device, &accumulate_layout)
    });
    let extras = PingPong::from_fn(|side| {
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
    });
    let back_layout = vbgi::back::BackBindings::layout(device);
    let mut counts = vec![
        ("SLICES", settings.slices as f64),
        ("STEPS", settings.steps as f64),
    ];
    // What the kernels compute besides the cone (params.wgsl's NEAR and FAR).
    let work = [
        ("NEAR", f64::from(u8::from(hbil))),
        ("FAR", f64::from(u8::from(p.far == 3))),
    ];
    match bitmask {
        Some(b) => counts.push(("SECTORS", b.sectors as f64)),
        None => counts.extend(work),
    }
    let step = |label: &'static str, source: String, entry: &str, layout, constants: &[_]| {
        let module = crate::passes::shader_module(device, label, &source);
        ComputeStep::new(device, label, &module, entry, frame, layout, constants)
    };
    let back = match (&split_back, &layers) {
        (Some(t), Some(l)) => {
            let bg = vbgi::back::BackBindings {
                params: &params,
                full_back: l.resources().peel_depth,
                split_back: &array_view(t),
            }
            .bind_group(device, &back_layout);
            let s = step("vbgi back", vbgi::back::source(), "back", &back_layout, &[]);
            Some((s, bg, util::groups_8x8((p.layer_width, p.layer_height))))
        }
        _ => None,
    };
    let (search_source, search_entry) = match bitmask {
        Some(_) => (vbgi::bitmask::source(), "bitmask"),
        None => (search::source(), "horizon"),
    };
    let bitmask_parts = match (bitmask, vbgi_params) {
        (Some(bitmask), Some(params)) => Some(BitmaskParts {
            bitmask,
            params,
            layers,
            back,
        }),
        _ => None,
    };
    textures.push(stand_in);
    textures.extend(split_back);
    let technique = Horizon {
        name,
        kind,
        hbil,
        size,
        source: settings.source,
        split_step: step("split", split::source(), "split", &split_layout, &[]),
        search_step: step(name, search_source, search_entry, &search_layout, &counts),
        accumulate_step: step(
            "accumulate",
            accumulate::source(),
            "accumulate",
            &accumulate_layout,
            &work,
        ),
        split,
        full_bg,
        accumulate_bg,
        extras,
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
        params,
        settings,
        bitmask: bitmask_parts,
    };
    Ok(Box::new(technique))
}

fn blur_settings(settings: &Settings) -> BlurSettings {
    BlurSettings {
        enabled: true,
        radius: settings.blur_radius,
        depth_sigma: 0.01,
        normal_power: 8.0,
    }
}

fn reproject_params(settings: &Settings) -> ReprojectParams {
    ReprojectParams {
        reject_depth: settings.reject_depth,
        reject_normal: settings.reject_normal,
        _pad0: 0.0,
        _pad1: 0.0,
    }
}

/// What shapes the passes' pipelines and resources: a change of any of these rebuilds.
fn structure(s: &Settings) -> impl PartialEq + use<> {
    (
        s.slices,
        s.steps,
        s.interleaved,
        s.reprojection,
        s.source,
        s.denoise,
        s.far == Far::Slices,
    )
}

impl Technique for Horizon {
    fn name(&self) -> &'static str {
        self.name
    }

    fn prepare(&self, queue: &wgpu::Queue, camera: &nearfield_scene::Camera) {
        if let Some(l) = self.bitmask.as_ref().and_then(|b| b.layers.as_ref()) {
            l.prepare(queue, camera);
        }
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        frame: FrameInfo,
    ) {
        let side = frame.side();
        if let Some(l) = self.bitmask.as_ref().and_then(|b| b.layers.as_ref()) {
            l.encode(encoder, profiler);
        }
        let reproject = self.hbil && self.source == Source::Previous && frame.history;
        let source = if reproject { 2 } else { side };
        if reproject && let Some(r) = &self.reprojection {
            r.encode(encoder, profiler, frame.index);
        }
        match &self.split {
            Some(s) => {
                let (gx, gy) = util::groups_8x8(s.layer_size);
                {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("split"),
                        timestamp_writes: profiler.compute("split"),
                    });
                    self.split_step
                        .dispatch(&mut pass, &s.split_bg[source], (gx, gy, 1));
                    if let Some((step, bg, groups)) =
                        self.bitmask.as_ref().and_then(|b| b.back.as_ref())
                    {
                        step.dispatch(&mut pass, bg, (groups.0, groups.1, 1));
                    }
                }
                {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some(self.name),
                        timestamp_writes: profiler.compute(self.name),
                    });
                    // The 16 layers stacked vertically (see search.wgsl).
                    self.search_step
                        .dispatch(&mut pass, &s.search_bg, (gx, gy * 16, 1));
                }
            }
            None => self
                .search_step
                .encode(encoder, profiler, &self.full_bg[source], self.size),
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
        self.accumulate_step.dispatch(
            &mut pass,
            self.accumulate_bg.current(frame.index),
            (gx, gy, 1),
        );
    }

    fn update(&mut self, queue: &wgpu::Queue, tp: &TechniqueParams) -> Result<bool, RenderError> {
        let (settings, bitmask) = self
            .kind
            .parse(tp)
            .map_err(RenderError::setting(self.name))?;
        let shape = |b: Option<Bitmask>| b.map(|b| (b.sectors, b.layer));
        if structure(&settings) != structure(&self.settings)
            || shape(bitmask) != shape(self.bitmask.as_ref().map(|b| b.bitmask))
        {
            return Ok(false);
        }
        if let (Some(parts), Some(b)) = (&mut self.bitmask, bitmask) {
            queue.write_buffer(&parts.params, 0, bytemuck::bytes_of(&b.params));
            parts.bitmask = b;
        }
        let p = settings.params(self.hbil, self.size);
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        if let Some((blur, _)) = &self.blur {
            blur.write(queue, blur_settings(&settings));
        }
        if let Some(r) = &self.reprojection {
            queue.write_buffer(
                &r.params,
                0,
                bytemuck::bytes_of(&reproject_params(&settings)),
            );
        }
        self.source = settings.source;
        self.settings = settings;
        Ok(true)
    }

    fn extras(&self, frame: FrameInfo) -> Vec<(&'static str, &wgpu::Texture)> {
        self.extras
            .current(frame.index)
            .iter()
            .map(|(n, t)| (*n, t))
            .collect()
    }
}

//! The horizon machine's stages ([`super::machine::build`]): each takes the handles it reads and
//! returns what it makes: the compute steps, the search's, accumulate's and the upsample's bind
//! groups, the blur, and the images it shows.

use super::march::{March, MarchIo, work};
use super::params::HorizonParams;
use super::{GEOMETRY_FORMAT, Settings, accumulate, split, upsample};
use crate::RenderError;
use crate::contract::formats::HDR_FORMAT;
use crate::contract::io::{NearFieldOutputs, Output};
use crate::contract::technique::{TechniqueContext, layered_texture, screen_texture};
use crate::passes::bilateral_blur::{BilateralBlur, BlurChain, BlurSettings};
use crate::passes::reproject::{History, ReprojectParams, Reprojection};
use crate::passes::{ComputeStep, PingPong};
use crate::settings::{Declared, count_constants};
use crate::util::view;

/// The compute steps of the machine, each with its constants.
pub(super) struct Steps {
    pub split: ComputeStep,
    pub search: ComputeStep,
    pub accumulate: ComputeStep,
    pub upsample: Option<ComputeStep>,
}

/// Compiles the machine's steps: the split, the search (its march's kernel with the slice, step
/// and march counts), accumulate and, with `upsample`, the upsample.
pub(super) fn steps(
    ctx: &TechniqueContext,
    name: &'static str,
    (settings, p, march): (&Settings, &HorizonParams, &dyn March),
    (split_layout, accumulate_layout, upsample_layout): (
        &wgpu::BindGroupLayout,
        &wgpu::BindGroupLayout,
        &wgpu::BindGroupLayout,
    ),
    (half, blurred, upsample): (bool, bool, bool),
) -> Steps {
    let (device, frame) = (ctx.device, ctx.frame_group);
    let near = p.indirect != 0;
    let (search_source, search_entry, march_constants) = march.kernel();
    let far_field = frame.far_field_constant();
    // The counts the search kernel declares (`SLICES`, `STEPS`), the march's own, and the rest.
    let mut owned = count_constants(&search_source, &settings.counts());
    owned.extend(march_constants);
    let mut counts: Vec<(&str, f64)> = owned.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    if half {
        counts.push(("HALF", 1.0));
    }
    counts.push(far_field);
    let work = work(near, p);
    let step = |label: &'static str, source: String, entry: &str, layout, constants: &[_]| {
        let module = crate::pipeline_cache::shader_module(device, label, &source);
        ComputeStep::new(device, label, &module, entry, frame, layout, constants)
    };
    Steps {
        split: step("split", split::source(), "split", split_layout, &[]),
        search: step(name, search_source, search_entry, march.layout(), &counts),
        accumulate: step(
            "accumulate",
            accumulate::source(),
            "accumulate",
            accumulate_layout,
            &[
                work[0],
                work[1],
                ("HISTORY", f64::from(u8::from(keeps_history(near, p)))),
                far_field,
                ("HALF", f64::from(u8::from(half && !blurred))),
            ],
        ),
        upsample: upsample.then(|| {
            step(
                "upsample",
                upsample::source(),
                "upsample",
                upsample_layout,
                &work,
            )
        }),
    }
}

/// The search's bind groups, one per radiance source (this frame's direct radiance on either
/// side, or last frame's reprojected): over the 16 interleaved layers with the split pass that
/// fills them (and the layers' textures), or over the full-resolution images.
#[allow(clippy::too_many_arguments)]
pub(super) fn search_groups(
    device: &wgpu::Device,
    i: &crate::contract::io::NearFieldInputs,
    settings: &Settings,
    p: &HorizonParams,
    params: &wgpu::Buffer,
    split_layout: &wgpu::BindGroupLayout,
    [raw_cone, raw_near, raw_far]: [&wgpu::Texture; 3],
    (source_views, reprojected): ([&wgpu::TextureView; 3], Option<&wgpu::Texture>),
    march: &dyn March,
) -> (Option<Split>, Vec<wgpu::BindGroup>, Vec<wgpu::Texture>) {
    let search_bg = |depth: &wgpu::TextureView,
                     normal: &wgpu::TextureView,
                     radiance: &wgpu::TextureView,
                     out: [&wgpu::TextureView; 3]| {
        let io = MarchIo {
            params,
            depth,
            normal,
            radiance,
            albedo: i.albedo,
            material: i.material,
            out,
        };
        march.bind_group(device, io)
    };
    let view = |t: &wgpu::Texture| t.create_view(&Default::default());
    let mut textures = Vec::new();
    let mut full_bg = Vec::new();
    let split = if settings.march.interleaved {
        let layer_size = (p.layer_width, p.layer_height);
        let layered = |label: &str, format| layered_texture(device, layer_size, 16, label, format);
        let s_geometry = layered("split geometry", GEOMETRY_FORMAT);
        let s_radiance = layered("split radiance", HDR_FORMAT);
        let (vg, vr) = (array_view(&s_geometry), array_view(&s_radiance));
        let (vc, vnear, vfar) = (view(raw_cone), view(raw_near), view(raw_far));
        let split_bg = |radiance: &wgpu::TextureView| {
            split::SplitBindings {
                params,
                full_depth: i.view_depth,
                full_normal: i.normal,
                full_radiance: radiance,
                split_geometry: &vg,
                split_radiance: &vr,
            }
            .bind_group(device, split_layout)
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
        let (cone, near, far) = (view(raw_cone), view(raw_near), view(raw_far));
        let source_textures = [
            i.direct_radiance[0].texture(),
            i.direct_radiance[1].texture(),
            reprojected.unwrap_or(i.direct_radiance[0].texture()),
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
    (split, full_bg, textures)
}

/// The machine's own images.
pub(super) struct Images {
    /// The search's results (cone, near light, far light): at every pixel, or with
    /// `resolution=half` one texel per 2×2 block (half.wgsl), which accumulate upsamples on its
    /// way in.
    pub raw: [wgpu::Texture; 3],
    /// With `resolution=half` and the blur, which reads every pixel: the results upsampled to
    /// full resolution first.
    pub upsampled: Option<[wgpu::Texture; 3]>,
    /// The temporal images, each a pair (this frame's and last frame's, swapped by frame
    /// parity): the running means of the cone (bent normal, aperture), the near-field and the
    /// far-field light, the depth and normal they belong to (disocclusion test), and the diffuse
    /// radiance handed to the next frame's reprojection.
    cone: [wgpu::Texture; 2],
    near: [wgpu::Texture; 2],
    far: [wgpu::Texture; 2],
    geometry: [wgpu::Texture; 2],
    feedback: [wgpu::Texture; 2],
}

/// Views of the temporal images, by frame parity.
pub(super) struct Histories {
    pub cone: [wgpu::TextureView; 2],
    pub near: [wgpu::TextureView; 2],
    pub far: [wgpu::TextureView; 2],
    pub geometry: [wgpu::TextureView; 2],
    pub feedback: [wgpu::TextureView; 2],
}

impl Images {
    pub fn new(
        device: &wgpu::Device,
        size: (u32, u32),
        search_size: (u32, u32),
        upsampled: bool,
    ) -> Self {
        let full = |label: &str, format| screen_texture(device, size, label, format);
        let raw = |label: &str| screen_texture(device, search_size, label, HDR_FORMAT);
        let pair = |label: &str, format| [0, 1].map(|k| full(&format!("{label} {k}"), format));
        Images {
            raw: [raw("horizon cone"), raw("horizon near"), raw("horizon far")],
            upsampled: upsampled.then(|| {
                ["cone", "near", "far"].map(|n| full(&format!("horizon {n} upsampled"), HDR_FORMAT))
            }),
            cone: pair("cone history", HDR_FORMAT),
            near: pair("near history", HDR_FORMAT),
            far: pair("far history", HDR_FORMAT),
            geometry: pair("geometry history", GEOMETRY_FORMAT),
            feedback: pair("diffuse radiance", HDR_FORMAT),
        }
    }

    /// What the blur reads: the search's results, or with `resolution=half` their upsample.
    pub fn blur_from(&self) -> [&wgpu::Texture; 3] {
        self.upsampled.as_ref().unwrap_or(&self.raw).each_ref()
    }

    /// What accumulate reads: the blurred results where the blur ran on them (`blurred`: the
    /// blur's scratch, cone, near and far), else the raw.
    pub fn accumulate_from(
        &self,
        blurred: Option<&[wgpu::Texture; 4]>,
        near: bool,
        far_slices: bool,
    ) -> [wgpu::TextureView; 3] {
        let raw = &self.raw;
        match blurred {
            Some(b) => [
                view(&b[1]),
                view(if near { &b[2] } else { &raw[1] }),
                view(if far_slices { &b[3] } else { &raw[2] }),
            ],
            None => raw.each_ref().map(view),
        }
    }

    pub fn histories(&self) -> Histories {
        let views = |pair: &[wgpu::Texture; 2]| pair.each_ref().map(view);
        Histories {
            cone: views(&self.cone),
            near: views(&self.near),
            far: views(&self.far),
            geometry: views(&self.geometry),
            feedback: views(&self.feedback),
        }
    }

    /// The technique's own images by name, per frame parity (what `--aov` and the viewer show).
    pub fn extras(
        &self,
        reprojection: Option<&Reprojection>,
    ) -> PingPong<Vec<(&'static str, wgpu::Texture)>> {
        PingPong::from_fn(|side| {
            let mut e = vec![
                ("bent-cone", self.cone[side].clone()),
                ("near-history", self.near[side].clone()),
                ("far-history", self.far[side].clone()),
                ("feedback", self.feedback[side].clone()),
            ];
            if let Some(r) = reprojection {
                e.push(("reprojected", r.raw.clone()));
                e.push(("radiance-source", r.output_texture.clone()));
            }
            e
        })
    }

    pub fn into_textures(self) -> impl Iterator<Item = wgpu::Texture> {
        let pairs = [self.far, self.cone, self.near, self.geometry, self.feedback];
        self.raw
            .into_iter()
            .chain(self.upsampled.into_iter().flatten())
            .chain(pairs.into_iter().flatten())
    }
}

/// Accumulate's bind groups, one per frame parity: the blurred (or raw) results in, last frame's
/// means read, this frame's written, and the technique's outputs.
#[allow(clippy::too_many_arguments)]
pub(super) fn accumulate_groups(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    (i, o): (
        &crate::contract::io::NearFieldInputs,
        &crate::contract::io::NearFieldOutputs,
    ),
    [raw_cone, raw_near, raw_far]: [&wgpu::TextureView; 3],
    h: &Histories,
    (out_env, out_indirect, out_bent, light_irradiance): (
        &wgpu::TextureView,
        &wgpu::TextureView,
        &wgpu::TextureView,
        &wgpu::TextureView,
    ),
) -> PingPong<wgpu::BindGroup> {
    PingPong::from_fn(|side| {
        let prev = 1 - side;
        accumulate::AccumulateBindings {
            params,
            gb_normal: i.normal,
            gb_view_depth: i.view_depth,
            raw_cone,
            raw_near,
            raw_far,
            prev_cone: &h.cone[prev],
            prev_near: &h.near[prev],
            prev_far: &h.far[prev],
            prev_geometry: &h.geometry[prev],
            acc_cone: &h.cone[side],
            acc_near: &h.near[side],
            acc_far: &h.far[side],
            acc_geometry: &h.geometry[side],
            gb_albedo: i.albedo,
            gb_material: i.material,
            gb_emissive: i.emission,
            light_irradiance,
            out_ao: o.ao,
            out_env,
            out_indirect,
            out_feedback: &h.feedback[side],
            out_bent,
        }
        .bind_group(device, layout)
    })
}

/// The bilateral blur of the search's results (the cone always, the near light with `near`, the
/// far light with `far_slices`): the blur, its chains and its textures (scratch, then the
/// blurred cone, near and far).
pub(super) fn blur_stage(
    ctx: &TechniqueContext,
    settings: &Settings,
    near: bool,
    far_slices: bool,
    [cone, near_light, far]: [&wgpu::Texture; 3],
) -> (BilateralBlur, Vec<BlurChain>, [wgpu::Texture; 4]) {
    let (device, i) = (ctx.device, ctx.inputs);
    let full = |label: &str| screen_texture(device, i.size, label, HDR_FORMAT);
    let view = |t: &wgpu::Texture| t.create_view(&Default::default());
    let b = BilateralBlur::new(device, ctx.frame_group, blur_settings(settings));
    let scratch = full("horizon blur scratch");
    let cone_out = full("horizon cone blurred");
    let near_out = full("horizon near blurred");
    let far_out = full("horizon far blurred");
    let chain = |from: &wgpu::Texture, to: &wgpu::Texture| {
        b.chain(device, i, &view(from), &view(&scratch), &view(to))
    };
    let mut chains = vec![chain(cone, &cone_out)];
    if near {
        chains.push(chain(near_light, &near_out));
    }
    if far_slices {
        chains.push(chain(far, &far_out));
    }
    (b, chains, [scratch, cone_out, near_out, far_out])
}

/// The upsample's bind group where there is an upsample: the half-resolution results to full
/// resolution.
pub(super) fn upsample_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    i: &crate::contract::io::NearFieldInputs,
    images: &Images,
) -> Option<wgpu::BindGroup> {
    let [cone, near, far] = images.raw.each_ref().map(view);
    let [out_cone, out_near, out_far] = images.upsampled.as_ref()?.each_ref().map(view);
    let group = upsample::UpsampleBindings {
        params,
        gb_normal: i.normal,
        gb_view_depth: i.view_depth,
        half_cone: &cone,
        half_near: &near,
        half_far: &far,
        out_cone: &out_cone,
        out_near: &out_near,
        out_far: &out_far,
    }
    .bind_group(device, layout);
    Some(group)
}

/// The 4×4 deinterleaved layers (with interleaving): split by radiance source (direct side 0,
/// side 1, reprojected) and search.
pub(super) struct Split {
    pub split_bg: [wgpu::BindGroup; 3],
    pub search_bg: wgpu::BindGroup,
    pub layer_size: (u32, u32),
}

/// All layers of `t` as one array view.
pub(super) fn array_view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// The bilateral blur of the search's results.
pub(super) fn blur_settings(settings: &Settings) -> BlurSettings {
    BlurSettings {
        enabled: true,
        radius: settings.march.blur_radius,
        depth_sigma: 0.01,
        normal_power: 8.0,
    }
}

/// Whether the accumulation is kept for the next frame: always with near-field light (hbil's
/// reprojection reads its geometry), otherwise only under the running mean (`HISTORY` in
/// accumulate.wgsl; gtao with `temporal=off` or `denoise=svgf` keeps none).
pub(super) fn keeps_history(near: bool, p: &HorizonParams) -> bool {
    near || p.temporal == 1
}

/// 1×1 images bound where the host hands in no output: what the flavour does not write (gtao
/// writes ao and the bent normal; hbil and vbgi also env- and indirect-irradiance), and
/// light-irradiance (read for the next frame's radiance) where the host has none.
pub(super) struct StandIns {
    pub textures: [wgpu::Texture; 2],
    views: [wgpu::TextureView; 2],
}

impl StandIns {
    pub fn new(device: &wgpu::Device) -> Self {
        let textures = ["horizon stand-in output", "horizon stand-in light"]
            .map(|label| screen_texture(device, (1, 1), label, HDR_FORMAT));
        let views = textures.each_ref().map(view);
        StandIns { textures, views }
    }

    /// env-irradiance, indirect-irradiance and the bent normal to write, light-irradiance to
    /// read: the host's, or a stand-in.
    pub fn outputs<'a>(
        &'a self,
        o: &'a NearFieldOutputs,
        name: &str,
        near: bool,
    ) -> Result<[&'a wgpu::TextureView; 4], RenderError> {
        let [spare_out, spare_in] = &self.views;
        let (env, indirect) = if near {
            (
                o.require(name, Output::EnvIrradiance)?,
                o.require(name, Output::IndirectIrradiance)?,
            )
        } else {
            (spare_out, spare_out)
        };
        Ok([
            env,
            indirect,
            o.bent_normal.unwrap_or(spare_out),
            o.light_irradiance.unwrap_or(spare_in),
        ])
    }
}

/// hbil's and vbgi's reprojection of last frame's diffuse radiance (the histories' feedback,
/// with the geometry it belongs to) into this frame.
pub(super) fn reprojection_stage(
    ctx: &TechniqueContext,
    settings: &Settings,
    h: &Histories,
) -> Reprojection {
    let history = |side: usize| History {
        geometry: &h.geometry[side],
        radiance: &h.feedback[side],
    };
    Reprojection::new(
        ctx.device,
        ctx.frame_group,
        ctx.inputs,
        [history(0), history(1)],
        settings.march.reprojection,
        reproject_params(settings),
    )
}

pub(super) fn reproject_params(settings: &Settings) -> ReprojectParams {
    ReprojectParams {
        reject_depth: settings.march.reject_depth,
        reject_normal: settings.march.reject_normal,
        _pad0: 0.0,
        _pad1: 0.0,
    }
}

//! The horizon machinery that gtao, hbil and vbgi share: split (4×4 deinterleave), the
//! technique's [`March`], reprojection with push/pull, the bilateral blur and the running mean
//! with the outputs (accumulate). See the module above for the derivation.

use super::march::{Flavor, March, MarchContext, MarchIo};
use super::params::FAR_SLICES;
use super::settings::Far;
use super::stages::{
    Histories, Split, accumulate_groups, blur_settings, blur_stage, extra_images, search_groups,
    steps, upsample_group,
};
use super::{GEOMETRY_FORMAT, Resolution, Settings, Source, accumulate, split, upsample};
use crate::RenderError;
use crate::contract::formats::HDR_FORMAT;
use crate::contract::technique::{
    FrameInfo, Output, Technique, TechniqueContext, TechniqueParams, screen_texture,
};
use crate::passes::bilateral_blur::{BilateralBlur, BlurChain};
use crate::passes::denoise::Denoise;
use crate::passes::reproject::{History, ReprojectParams, Reprojection};
use crate::passes::{ComputeStep, PingPong};
use crate::profiler::GpuProfiler;
use crate::util;
use wgpu::util::DeviceExt;

struct Horizon {
    name: &'static str,
    flavor: Flavor,
    /// The march gathers near-field light (hbil, vbgi).
    near: bool,
    /// The host handed in a bent-normal output.
    bent_normal: bool,
    size: (u32, u32),
    /// The search's grid: `size`, or with `resolution=half` one texel per 2×2 block.
    search_size: (u32, u32),
    source: Source,
    split_step: ComputeStep,
    search_step: ComputeStep,
    accumulate_step: ComputeStep,
    /// With `resolution=half` and the blur: the pass that brings the search's results to every
    /// pixel (upsample.wgsl) and its bind group.
    upsample: Option<(ComputeStep, wgpu::BindGroup)>,
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
    march: Box<dyn March>,
}

/// Builds gtao, hbil or vbgi (without svgf: the registry wraps it in the denoiser).
pub fn build(
    ctx: &TechniqueContext,
    flavor: Flavor,
    tp: &TechniqueParams,
) -> Result<Box<dyn Technique>, RenderError> {
    let name = flavor.name;
    let near = flavor.near;
    let settings = (flavor.settings)(tp).map_err(RenderError::setting(name))?;
    let device = ctx.device;
    let frame = ctx.frame_group;
    let (i, o) = (ctx.inputs, ctx.outputs);
    let size = i.size;
    // What the flavour writes (TechniqueDesc::writes): gtao ao and the bent normal; hbil and
    // vbgi also env- and indirect-irradiance. Outputs it does not write, and light-irradiance
    // (read for the next frame's radiance) where the host has none, bind a 1×1 stand-in.
    let stand_in = |label: &str, format| {
        let t = screen_texture(device, (1, 1), label, format);
        let v = t.create_view(&Default::default());
        (t, v)
    };
    let (spare_hdr, spare_hdr_view) = stand_in("horizon stand-in output", HDR_FORMAT);
    let (spare_in, spare_in_view) = stand_in("horizon stand-in light", HDR_FORMAT);
    let (out_env, out_indirect) = if near {
        (
            o.require(name, Output::EnvIrradiance)?,
            o.require(name, Output::IndirectIrradiance)?,
        )
    } else {
        (&spare_hdr_view, &spare_hdr_view)
    };
    let out_bent = o.bent_normal.unwrap_or(&spare_hdr_view);
    let light_in = o.light_irradiance.unwrap_or(&spare_in_view);
    let mut p = settings.params(near, size);
    p.bent_normal = o.bent_normal.is_some() as u32;
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("horizon params"),
        contents: bytemuck::bytes_of(&p),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    let full = |label: &str, format| screen_texture(device, size, label, format);
    // The search's results: at every pixel, or with `resolution=half` one texel per 2×2 block
    // (half.wgsl), which accumulate upsamples on its way in. With the blur, which reads every
    // pixel, the upsample pass first writes them at full resolution (`upsampled`).
    let half = settings.march.resolution == Resolution::Half;
    let blurred = settings.denoise == Denoise::Bilateral;
    let search_size = search_size(half, size);
    let raw = |label: &str| screen_texture(device, search_size, label, HDR_FORMAT);
    let raw_cone = raw("horizon cone");
    let raw_near = raw("horizon near");
    let raw_far = raw("horizon far");
    let upsampled = (half && blurred).then(|| {
        [
            full("horizon cone upsampled", HDR_FORMAT),
            full("horizon near upsampled", HDR_FORMAT),
            full("horizon far upsampled", HDR_FORMAT),
        ]
    });
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

    let reprojection = (near && settings.march.source == Source::Previous).then(|| {
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
            settings.march.reprojection,
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

    let march = (flavor.march)(&MarchContext {
        ctx,
        tp,
        name,
        settings: &settings,
        params: &p,
        params_buffer: &params,
    })?;
    let search_bg = |depth: &wgpu::TextureView,
                     normal: &wgpu::TextureView,
                     radiance: &wgpu::TextureView,
                     out: [&wgpu::TextureView; 3]| {
        march.bind_group(
            device,
            MarchIo {
                params: &params,
                depth,
                normal,
                radiance,
                out,
            },
        )
    };
    let split_layout = split::SplitBindings::layout(device);
    let (split, full_bg, mut textures) = search_groups(
        device,
        i,
        &settings,
        &p,
        &params,
        &split_layout,
        [&raw_cone, &raw_near, &raw_far],
        (
            source_views,
            reprojection.as_ref().map(|r| &r.output_texture),
        ),
        &search_bg,
    );

    let raw = [&raw_cone, &raw_near, &raw_far];
    let upsample_layout = upsample::UpsampleBindings::layout(device);
    let upsample_bg = upsampled.as_ref().map(|u| {
        upsample_group(
            device,
            &upsample_layout,
            &params,
            i,
            raw,
            [&u[0], &u[1], &u[2]],
        )
    });
    // What the blur reads: the search's results, or with `resolution=half` their upsample.
    let blur_from = match &upsampled {
        Some(u) => [&u[0], &u[1], &u[2]],
        None => raw,
    };
    let blur = blurred.then(|| blur_stage(ctx, &settings, near, p.far == FAR_SLICES, blur_from));
    // What accumulate reads: the blurred results where the blur ran on them, else the raw.
    let [cone_in, near_in, far_in] = match &blur {
        Some((_, _, tex)) => [
            view(&tex[1]),
            view(if near { &tex[2] } else { &raw_near }),
            view(if p.far == FAR_SLICES {
                &tex[3]
            } else {
                &raw_far
            }),
        ],
        None => raw.map(view),
    };

    let accumulate_layout = accumulate::AccumulateBindings::layout(device);
    let accumulate_bg = accumulate_groups(
        device,
        &accumulate_layout,
        &params,
        (i, o),
        [&cone_in, &near_in, &far_in],
        &Histories {
            cone: &hist_cone,
            near: &hist_near,
            far: &hist_far,
            geometry: &hist_geo_views,
            feedback: &feedback_views,
        },
        (out_env, out_indirect, out_bent, light_in),
    );
    let extras = extra_images(
        [&hist_cone, &hist_near, &hist_far, &feedback],
        reprojection.as_ref(),
    );
    let steps = steps(
        ctx,
        name,
        (&settings, &p, march.as_ref()),
        (&split_layout, &accumulate_layout, &upsample_layout),
        (half, blurred, upsample_bg.is_some()),
    );
    let technique = Horizon {
        name,
        flavor,
        near,
        bent_normal: o.bent_normal.is_some(),
        size,
        search_size,
        source: settings.march.source,
        split_step: steps.split,
        search_step: steps.search,
        accumulate_step: steps.accumulate,
        upsample: steps.upsample.zip(upsample_bg),
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
            textures.extend([raw_cone, raw_near, raw_far, spare_hdr, spare_in]);
            textures.extend(upsampled.into_iter().flatten());
            textures.extend(hist_far);
            textures.extend(hist_cone);
            textures.extend(hist_near);
            textures.extend(hist_geo);
            textures.extend(feedback);
            textures
        },
        params,
        settings,
        march,
    };
    Ok(Box::new(technique))
}

/// The search's grid at image size `size`: one texel per 2×2 block with `resolution=half`
/// (half.wgsl's `half_size`).
fn search_size(half: bool, size: (u32, u32)) -> (u32, u32) {
    if half {
        (size.0.div_ceil(2), size.1.div_ceil(2))
    } else {
        size
    }
}

fn reproject_params(settings: &Settings) -> ReprojectParams {
    ReprojectParams {
        reject_depth: settings.march.reject_depth,
        reject_normal: settings.march.reject_normal,
        _pad0: 0.0,
        _pad1: 0.0,
    }
}

/// What shapes the passes' pipelines and resources: a change of any of these rebuilds.
fn structure(s: &Settings) -> impl PartialEq + use<> {
    (
        s.march.temporal,
        s.march.slices,
        s.march.steps,
        s.march.interleaved,
        s.march.resolution,
        s.march.reprojection,
        s.march.source,
        s.denoise,
        s.far == Far::Slices,
    )
}

impl Technique for Horizon {
    fn name(&self) -> &'static str {
        self.name
    }

    fn prepare(&self, queue: &wgpu::Queue, camera: &nearfield_scene::Camera) {
        self.march.prepare(queue, camera);
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        profiler: &mut GpuProfiler,
        frame: FrameInfo,
    ) {
        let side = frame.side();
        self.march.encode_before(encoder, profiler);
        let reproject = self.near && self.source == Source::Previous && frame.history;
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
                    self.march.dispatch_after_split(&mut pass);
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
            None => {
                self.search_step
                    .encode(encoder, profiler, &self.full_bg[source], self.search_size)
            }
        }
        if let Some((step, bg)) = &self.upsample {
            step.encode(encoder, profiler, bg, self.size);
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
        let settings = (self.flavor.settings)(tp).map_err(RenderError::setting(self.name))?;
        if structure(&settings) != structure(&self.settings)
            || !self
                .march
                .update(queue, tp)
                .map_err(RenderError::setting(self.name))?
        {
            return Ok(false);
        }
        let mut p = settings.params(self.near, self.size);
        p.bent_normal = self.bent_normal as u32;
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
        self.source = settings.march.source;
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

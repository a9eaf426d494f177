//! The horizon machinery that gtao, hbil and vbgi share: split (4×4 deinterleave), the
//! technique's [`March`], reprojection with push/pull, the bilateral blur and the running mean
//! with the outputs (accumulate). See the module above for the derivation.

use super::march::{Flavor, March, MarchContext};
use super::params::FAR_SLICES;
use super::stages::{
    Images, Split, StandIns, accumulate_groups, blur_settings, blur_stage, reproject_params,
    reprojection_stage, search_groups, steps, upsample_group,
};
use super::{Resolution, Settings, Source, accumulate, split, upsample};
use crate::RenderError;
use crate::contract::technique::{FrameInfo, Technique, TechniqueContext, TechniqueParams};
use crate::passes::bilateral_blur::{BilateralBlur, BlurChain};
use crate::passes::denoise::Denoise;
use crate::passes::reproject::Reprojection;
use crate::passes::{ComputeStep, PingPong};
use crate::profiler::GpuProfiler;
use crate::settings::Declared;
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
    let (i, o) = (ctx.inputs, ctx.outputs);
    let size = i.size;
    let stand_ins = StandIns::new(device);
    let [out_env, out_indirect, out_bent, light_in] = stand_ins.outputs(o, name, near)?;
    let mut p = settings.params(near, size);
    p.bent_normal = o.bent_normal.is_some() as u32;
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("horizon params"),
        contents: bytemuck::bytes_of(&p),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    let half = settings.march.resolution == Resolution::Half;
    let blurred = settings.denoise == Denoise::Bilateral;
    let search_size = search_size(half, size);
    let images = Images::new(device, size, search_size, half && blurred);
    let h = images.histories();
    let reprojection = (near && settings.march.source == Source::Previous)
        .then(|| reprojection_stage(ctx, &settings, &h));
    // Radiance sources by index: this frame's direct radiance (side 0, side 1), reprojected.
    let [direct_0, direct_1] = i.direct_radiance;
    let sources = [
        direct_0,
        direct_1,
        reprojection.as_ref().map_or(direct_0, |r| &r.output),
    ];
    let march = (flavor.march)(&MarchContext {
        ctx,
        tp,
        name,
        settings: &settings,
        params: &p,
        params_buffer: &params,
    })?;
    let split_layout = split::SplitBindings::layout(device);
    let (split, full_bg, mut textures) = search_groups(
        device,
        i,
        &settings,
        &p,
        &params,
        &split_layout,
        images.raw.each_ref(),
        (sources, reprojection.as_ref().map(|r| &r.output_texture)),
        march.as_ref(),
    );

    let upsample_layout = upsample::UpsampleBindings::layout(device);
    let upsample_bg = upsample_group(device, &upsample_layout, &params, i, &images);
    let far_slices = p.far == FAR_SLICES;
    let blur = blurred.then(|| blur_stage(ctx, &settings, near, far_slices, images.blur_from()));
    let [cone_in, near_in, far_in] =
        images.accumulate_from(blur.as_ref().map(|(_, _, tex)| tex), near, far_slices);
    let accumulate_layout = accumulate::AccumulateBindings::layout(device);
    let accumulate_bg = accumulate_groups(
        device,
        &accumulate_layout,
        &params,
        (i, o),
        [&cone_in, &near_in, &far_in],
        &h,
        (out_env, out_indirect, out_bent, light_in),
    );
    let extras = images.extras(reprojection.as_ref());
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
            textures.extend(stand_ins.textures);
            textures.extend(images.into_textures());
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
        if !settings.same_build(&self.settings)
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

//! vbgi's march for the horizon machinery ([`crate::technique::horizon::March`]): the bitmask
//! kernel ([`super::bitmask`]), its uniforms, and the second depth layer it reads the thickness
//! from (depth peeling, deinterleaved by [`super::back`] with interleaving).

use super::{Settings, back, bitmask};
use crate::RenderError;
use crate::contract::technique::{TechniqueParams, layered_texture, screen_texture};
use crate::passes::ComputeStep;
use crate::passes::layers::{LayerSettings, LayerStack};
use crate::profiler::GpuProfiler;
use crate::settings::march::Resolution;
use crate::settings::{Declared, count_constants};
use crate::technique::horizon::{March, MarchContext, MarchIo};
use crate::util;
use wgpu::util::DeviceExt;

/// The bitmask march and what it owns.
pub struct BitmaskMarch {
    layout: wgpu::BindGroupLayout,
    /// vbgi's settings it was made with.
    settings: Settings,
    /// `VbgiParams`.
    params: wgpu::Buffer,
    /// With `thickness=layer`: the second depth layer.
    layers: Option<LayerStack>,
    /// What the kernel reads of the second layer: the deinterleaved layer with interleaving,
    /// the peeled layer without, else a stand-in.
    back_view: wgpu::TextureView,
    /// The second layer's direct radiance, as `back_view`.
    back_radiance_view: wgpu::TextureView,
    /// With `thickness=layer` and interleaving: the deinterleave.
    back: Option<(ComputeStep, wgpu::BindGroup, (u32, u32))>,
    /// params.wgsl's `NEAR` and `FAR` of the kernel (the far field through the sectors).
    work: [(&'static str, f64); 2],
    _textures: Vec<wgpu::Texture>,
}

fn array_view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

/// Makes vbgi's march ([`crate::technique::horizon::Flavor::march`]).
pub fn create(m: &MarchContext) -> Result<Box<dyn March>, RenderError> {
    let ctx = m.ctx;
    let device = ctx.device;
    let settings = Settings::from_params(m.tp).map_err(RenderError::setting(m.name))?;
    let (_, b) = settings.split();
    let p = m.params;
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("vbgi params"),
        contents: bytemuck::bytes_of(&b.params),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    // The occluder's rear (the second layer's direct radiance) is shaded, deinterleaved and
    // read only with a probe volume (bitmask.wgsl's `sender_radiance`); under the open sky the
    // rear sends nothing and only the layer's depth is read.
    let rear = b.layer && ctx.frame_group.far_volume();
    let layers = if b.layer {
        let two = LayerSettings {
            layers: 2,
            ..Default::default()
        };
        let mut stack =
            LayerStack::new(device, ctx.inputs, ctx.scene, ctx.frame_group, two).map_err(|e| {
                RenderError::Setting {
                    technique: m.name.into(),
                    msg: format!(
                        "thickness=layer: {e}; thickness=adaptive or thickness=constant need no second layer"
                    ),
                }
            })?;
        stack.shade = rear;
        stack.back_faces_exit = m.settings.march.resolution == Resolution::Half;
        Some(stack)
    } else {
        None
    };
    // The second layer's depth and radiance: deinterleaved with interleaving, else read as the
    // peel leaves them; 1×1 stand-ins without a second layer.
    let split = |label, format| {
        (layers.is_some() && m.settings.march.interleaved)
            .then(|| layered_texture(device, (p.layer_width, p.layer_height), 16, label, format))
    };
    let split_back = split("split back depth", wgpu::TextureFormat::R32Float);
    let split_back_radiance =
        split("split back radiance", wgpu::TextureFormat::Rgba16Float).filter(|_| rear);
    let stand_in = screen_texture(
        device,
        (1, 1),
        "no back depth",
        wgpu::TextureFormat::R32Float,
    );
    let stand_in_radiance = screen_texture(
        device,
        (1, 1),
        "no back radiance",
        wgpu::TextureFormat::Rgba16Float,
    );
    let back_view = match (&split_back, &layers) {
        (Some(t), _) => array_view(t),
        (None, Some(l)) => l.resources().peel_depth.clone(),
        (None, None) => array_view(&stand_in),
    };
    let back_radiance_view = match (&split_back_radiance, &layers) {
        (Some(t), _) => array_view(t),
        (None, Some(l)) if rear => l.resources().peel_radiance.clone(),
        _ => array_view(&stand_in_radiance),
    };
    let back = match (&split_back, &layers) {
        (Some(t), Some(l)) => {
            let back_layout = back::BackBindings::layout(device);
            let bg = back::BackBindings {
                params: m.params_buffer,
                full_back: l.resources().peel_depth,
                split_back: &array_view(t),
                full_back_radiance: l.resources().peel_radiance,
                split_back_radiance: &back_radiance_view,
            }
            .bind_group(device, &back_layout);
            let module = crate::pipeline_cache::shader_module(device, "vbgi back", &back::source());
            let step = ComputeStep::new(
                device,
                "vbgi back",
                &module,
                "back",
                ctx.frame_group,
                &back_layout,
                &[("REAR", if rear { 1.0 } else { 0.0 })],
            );
            Some((step, bg, util::groups_8x8((p.layer_width, p.layer_height))))
        }
        _ => None,
    };
    let mut textures = vec![stand_in, stand_in_radiance];
    textures.extend(split_back);
    textures.extend(split_back_radiance);
    Ok(Box::new(BitmaskMarch {
        layout: bitmask::BitmaskBindings::layout(device),
        settings,
        params,
        layers,
        back_view,
        back_radiance_view,
        back,
        work: crate::technique::horizon::march::work(true, m.params),
        _textures: textures,
    }))
}

impl March for BitmaskMarch {
    fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    fn bind_group(&self, device: &wgpu::Device, io: MarchIo) -> wgpu::BindGroup {
        bitmask::BitmaskBindings {
            params: io.params,
            vbgi: &self.params,
            in_depth: io.depth,
            in_normal: io.normal,
            in_radiance: io.radiance,
            in_back: &self.back_view,
            in_back_radiance: &self.back_radiance_view,
            out_cone: io.out[0],
            out_near: io.out[1],
            out_far: io.out[2],
        }
        .bind_group(device, &self.layout)
    }

    fn kernel(&self) -> (String, &'static str, Vec<(String, f64)>) {
        let source = bitmask::source();
        // vbgi's own counts (`SECTORS`); the machinery specialises its shared ones.
        let shared = self.settings.march.counts();
        let own: Vec<_> = (self.settings.counts().into_iter())
            .filter(|c| !shared.contains(c))
            .collect();
        let mut constants = count_constants(&source, &own);
        constants.extend(self.work.iter().map(|&(k, v)| (k.to_string(), v)));
        (source, "bitmask", constants)
    }

    fn prepare(&self, queue: &wgpu::Queue, camera: &nearfield_scene::Camera) {
        if let Some(l) = &self.layers {
            l.prepare(queue, camera);
        }
    }

    fn encode_before(&self, encoder: &mut wgpu::CommandEncoder, profiler: &mut GpuProfiler) {
        if let Some(l) = &self.layers {
            l.encode(encoder, profiler);
        }
    }

    fn dispatch_after_split(&self, pass: &mut wgpu::ComputePass) {
        if let Some((step, bg, groups)) = &self.back {
            step.dispatch(pass, bg, (groups.0, groups.1, 1));
        }
    }

    fn update(&mut self, queue: &wgpu::Queue, tp: &TechniqueParams) -> Result<bool, String> {
        let settings = Settings::from_params(tp)?;
        if !settings.same_build(&self.settings) {
            return Ok(false);
        }
        let (_, b) = settings.split();
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&b.params));
        self.settings = settings;
        Ok(true)
    }
}

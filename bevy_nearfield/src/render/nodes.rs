//! The glue's passes in Bevy's `Core3d` schedule: after the prepasses and after the main pass,
//! and the readback of the images a test or a tool asked for. Each of the two is a time span of
//! Bevy's render diagnostics, `nearfield` and `nearfield add` (GPU and CPU time where Bevy's
//! `RenderDiagnosticsPlugin` is on, as Bevy's own `ssao`).

use super::pipelines::{AddBindings, AoBindings, CaptureBindings, GluePipelines, InputsBindings};
use super::prepare::NearFieldView;
use crate::ExtractedNearField;
use crate::readback::{ExtractedReadback, NearFieldImages, ReadbackBuffers};
use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::pbr::ScreenSpaceAmbientOcclusionResources;
use bevy::prelude::*;
use bevy::render::diagnostic::RecordDiagnostics;
use bevy::render::renderer::{RenderContext, RenderDevice, ViewQuery};
use bevy::render::sync_world::MainEntity;
use bevy::render::view::ViewTarget;
use nearfield_render::wgpu;

/// Full-screen pass of `pipeline` with the glue's group and `group` into `targets`.
fn fullscreen(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::RenderPipeline,
    glue: &wgpu::BindGroup,
    group: &wgpu::BindGroup,
    targets: &[&wgpu::TextureView],
    load: wgpu::LoadOp<wgpu::Color>,
) {
    let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = targets
        .iter()
        .map(|view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load,
                    store: wgpu::StoreOp::Store,
                },
            })
        })
        .collect();
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &attachments,
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, glue, &[]);
    pass.set_bind_group(1, group, &[]);
    pass.draw(0..3, 0..1);
}

/// After Bevy's prepasses: nearfield's inputs from them, the technique, its ao into Bevy's.
#[allow(clippy::type_complexity)]
pub(super) fn inputs_and_technique(
    view: ViewQuery<(
        &NearFieldView,
        &ViewPrepassTextures,
        Option<&ScreenSpaceAmbientOcclusionResources>,
        Option<&ExtractedReadback>,
    )>,
    pipelines: Res<GluePipelines>,
    device: Res<RenderDevice>,
    mut ctx: RenderContext,
) {
    let (nf, prepass, bevy_ao, readback) = view.into_inner();
    let (Some(depth), Some(normal)) = (prepass.depth_only_view(), prepass.normal.as_ref()) else {
        return;
    };
    let device = device.wgpu_device();
    let motion = prepass
        .motion_vectors
        .as_ref()
        .map(|m| &*m.texture.default_view)
        // Unbound motion reads a valid image the shader ignores (`has_motion` = 0).
        .unwrap_or(&nf.images.captured.view);
    let inputs_group = InputsBindings {
        bevy_depth: depth,
        bevy_normal: &normal.texture.default_view,
        bevy_motion: motion,
        captured: &nf.images.captured.view,
    }
    .bind_group(device, &pipelines.inputs_layout);
    let info = *nf.info.lock().unwrap();
    let diagnostics = ctx.diagnostic_recorder();
    let diagnostics = diagnostics.as_deref();
    let encoder = ctx.command_encoder();
    let span = diagnostics.time_span(encoder, "nearfield");
    encoder.push_debug_group("nearfield");
    fullscreen(
        encoder,
        "nearfield inputs",
        &pipelines.inputs,
        &nf.glue_group,
        &inputs_group,
        &[
            &nf.images.view_depth.view,
            &nf.images.normal.view,
            &nf.images.motion.view,
            &nf.images.gathered.view,
        ],
        wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
    );
    {
        let mut state = nf.state.lock().unwrap();
        state.profiler.begin_frame();
        nf.technique.encode(encoder, &mut state.profiler, info);
    }
    if let Some(bevy_ao) = bevy_ao {
        let target = &bevy_ao.screen_space_ambient_occlusion_texture;
        let ao_group = AoBindings {
            near_field_ao: &nf.images.ao.view,
            bevy_ao: &target.default_view,
            ao_view_depth: &nf.images.view_depth.view,
            ao_normal: &nf.images.normal.view,
            ao_env_irradiance: nf
                .images
                .env_irradiance
                .as_ref()
                .map_or(&nf.images.ao.view, |i| &i.view),
            ao_gbuffer: prepass
                .deferred
                .as_ref()
                .map_or(&pipelines.no_gbuffer.view, |g| &*g.texture.default_view),
        }
        .bind_group(device, &pipelines.ao_layout);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("nearfield ao into Bevy's"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipelines.ao);
        pass.set_bind_group(0, &nf.glue_group, &[]);
        pass.set_bind_group(1, &ao_group, &[]);
        pass.set_bind_group(2, &nf.far_group, &[]);
        pass.dispatch_workgroups(nf.size.x.div_ceil(8), nf.size.y.div_ceil(8), 1);
    }
    if readback.is_some() {
        let images = &nf.images;
        ReadbackBuffers::copy(
            &nf.readback,
            device,
            encoder,
            &images.ao.texture,
            [&images.indirect_irradiance, &images.env_irradiance]
                .map(|i| i.as_ref().map(|i| &i.texture)),
        );
    }
    encoder.pop_debug_group();
    span.end(encoder);
}

/// After Bevy's main pass: its colour is kept as the radiance the next frame gathers (before
/// anything is added), then the indirect light is added where Bevy's deferred G-buffer gives
/// the base colour.
pub(super) fn capture_and_add(
    view: ViewQuery<(
        &NearFieldView,
        &ViewTarget,
        &ViewPrepassTextures,
        &ExtractedNearField,
        Option<&ExtractedReadback>,
    )>,
    pipelines: Res<GluePipelines>,
    device: Res<RenderDevice>,
    mut ctx: RenderContext,
) {
    let (nf, target, prepass, near_field, readback) = view.into_inner();
    let device = device.wgpu_device();
    // The indirect light's pass, where there is one to draw (hbil and vbgi, a G-buffer, a main
    // texture whose format has a pipeline).
    let add = prepass
        .deferred
        .as_ref()
        .filter(|_| near_field.technique.has_indirect() && near_field.indirect_intensity != 0.0)
        .zip(nf.images.indirect_irradiance.as_ref())
        .zip(
            pipelines
                .add
                .iter()
                .find(|(f, _)| *f == target.main_texture_format()),
        )
        .map(|((gbuffer, indirect), (_, pipeline))| {
            let group = AddBindings {
                bevy_gbuffer: &gbuffer.texture.default_view,
                indirect_irradiance: &indirect.view,
            }
            .bind_group(device, &pipelines.add_layout);
            (pipeline, group)
        });
    // Bevy's colour of this frame is what the next frame gathers (reprojected by its inputs
    // pass), with this frame's view depth for that pass's same-surface test.
    let next = &nf.images.captured.view;
    let capture_group = CaptureBindings {
        bevy_colour: target.main_texture_view(),
        view_depth: &nf.images.view_depth.view,
    }
    .bind_group(device, &pipelines.capture_layout);
    let diagnostics = ctx.diagnostic_recorder();
    let diagnostics = diagnostics.as_deref();
    let encoder = ctx.command_encoder();
    let span = diagnostics.time_span(encoder, "nearfield add");
    fullscreen(
        encoder,
        "nearfield capture radiance",
        &pipelines.capture,
        &nf.glue_group,
        &capture_group,
        &[next],
        wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
    );
    if readback.is_some()
        && let Some(b) = nf.readback.lock().unwrap().as_ref()
    {
        b.copy_radiance(encoder, &nf.images.captured.texture);
    }
    if let Some((pipeline, group)) = &add {
        fullscreen(
            encoder,
            "nearfield add indirect",
            pipeline,
            &nf.glue_group,
            group,
            &[target.main_texture_view()],
            wgpu::LoadOp::Load,
        );
    }
    span.end(encoder);
}

/// After the frame is submitted: maps the copies and stores them by camera.
pub(super) fn collect(
    device: Res<RenderDevice>,
    images: Res<NearFieldImages>,
    views: Query<(&MainEntity, &NearFieldView), With<ExtractedReadback>>,
) {
    for (main, nf) in &views {
        let slot = nf.readback.lock().unwrap();
        let Some(b) = slot.as_ref() else { continue };
        images.insert(main.id(), b.read(device.wgpu_device(), nf.frames()));
    }
}

//! Each view's nearfield, made (or remade) and given this frame's uniforms before the graph runs.

use super::environment::ViewEnvironment;
use super::pipelines::{FarBindings, Glue, GlueBindings, GluePipelines};
use crate::far::NearFieldVolume;
use crate::readback::ReadbackBuffers;
use crate::{ExtractedNearField, NearFieldTechnique};
use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::log::error;
use bevy::pbr::SsaoPipelineId;
use bevy::prelude::*;
use bevy::render::camera::{ExtractedCamera, TemporalJitter};
use bevy::render::render_asset::RenderAssets;
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::sync_world::MainEntity;
use bevy::render::texture::GpuImage;
use bevy::render::view::ExtractedView;
use nearfield_render::contract::io::{NearFieldInputs, NearFieldOutputs};
use nearfield_render::far::GpuFarField;
use nearfield_render::frame::{CameraMatrices, FrameInputs, ViewUniforms};
use nearfield_render::gpu_env::GpuEnvironment;
use nearfield_render::passes::FrameGroup;
use nearfield_render::profiler::GpuProfiler;
use nearfield_render::technique::{
    self, FarRule, FrameInfo, Output, Technique, TechniqueContext, TechniqueParams,
};
use nearfield_render::wgpu;
use nearfield_scene::Environment;
use nearfield_scene::probes::ProbeVolume;
use std::sync::Arc;
use std::sync::Mutex;
use wgpu::util::DeviceExt;

/// A texture and its full view (nearfield's own).
pub use nearfield_render::targets::Target as Image;

/// nearfield's images of one view (NearFieldInputs and NearFieldOutputs).
pub struct Images {
    pub(super) view_depth: Image,
    pub(super) normal: Image,
    albedo: Image,
    material: Image,
    emission: Image,
    /// Bevy's lit colour, kept after its main pass (a = the view depth) for the next frame.
    pub(super) captured: Image,
    /// The radiance the technique gathers: the captured colour reprojected to this frame.
    pub(super) gathered: Image,
    pub(super) motion: Image,
    pub(super) ao: Image,
    /// The outputs the technique declares besides ao (`TechniqueDesc::writes`): gtao writes
    /// none of these three, hbil and vbgi env- and indirect-irradiance.
    pub(super) env_irradiance: Option<Image>,
    pub(super) indirect_irradiance: Option<Image>,
    light_irradiance: Option<Image>,
}

impl Images {
    fn new(device: &wgpu::Device, size: UVec2, writes: &[Output]) -> Self {
        use wgpu::TextureFormat as F;
        use wgpu::TextureUsages as U;
        let target = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
        let storage = U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC;
        let image =
            |label, format, usage| Image::new(device, label, (size.x, size.y), format, usage);
        Images {
            view_depth: image("nearfield view depth", F::R32Float, target),
            normal: image("nearfield normal", F::Rgba16Float, target),
            // Not written: zero albedo, material, emission (the techniques' bounce reads the
            // radiance, which is Bevy's lit colour).
            albedo: image("nearfield albedo", F::Rgba8Unorm, U::TEXTURE_BINDING),
            material: image("nearfield material", F::Rgba8Unorm, U::TEXTURE_BINDING),
            emission: image("nearfield emission", F::Rgba16Float, U::TEXTURE_BINDING),
            captured: image("nearfield captured colour", F::Rgba16Float, target),
            gathered: image("nearfield gathered radiance", F::Rgba16Float, target),
            motion: image("nearfield motion", F::Rg16Float, target),
            ao: image("nearfield ao", F::R32Float, storage),
            env_irradiance: writes
                .contains(&Output::EnvIrradiance)
                .then(|| image("nearfield env irradiance", F::Rgba16Float, storage)),
            indirect_irradiance: writes
                .contains(&Output::IndirectIrradiance)
                .then(|| image("nearfield indirect irradiance", F::Rgba16Float, storage)),
            light_irradiance: writes
                .contains(&Output::LightIrradiance)
                .then(|| image("nearfield light irradiance", F::Rgba16Float, storage)),
        }
    }
}

/// What one view keeps from frame to frame.
pub(super) struct State {
    frame_index: u32,
    previous: Option<CameraMatrices>,
    /// Last frame's Bevy clip_from_world (unjittered), for the camera's motion.
    previous_clip_from_world: Option<Mat4>,
    pub(super) profiler: GpuProfiler,
}

/// A view's nearfield: images, group 0, the technique (render world).
#[derive(Component)]
pub struct NearFieldView {
    pub(super) size: UVec2,
    pub(super) technique_name: NearFieldTechnique,
    pub(super) params: TechniqueParams,
    pub(super) images: Images,
    pub(super) view_buffer: wgpu::Buffer,
    pub(super) glue_buffer: wgpu::Buffer,
    pub(super) glue_group: wgpu::BindGroup,
    _frame_group: FrameGroup,
    pub(super) technique: Box<dyn Technique>,
    /// This frame's side of the radiance pair and whether last frame's may be read.
    pub(super) info: Mutex<FrameInfo>,
    pub(super) state: Mutex<State>,
    pub(super) ambient_occlusion: bool,
    pub(super) readback: Mutex<Option<ReadbackBuffers>>,
    /// The baked volume the technique reads as its far field (None: its sky, below).
    pub(super) far_volume: Option<Arc<ProbeVolume>>,
    /// Without a volume, the camera's environment map the view was made for (None: there was
    /// none, or its image was not yet on the GPU) and, where it could be read, the technique's
    /// sky read from it (None: a white sky).
    environment: Option<(ViewEnvironment, Option<Arc<Environment>>)>,
    /// glue.wgsl's `far_rule`: how the ao written into Bevy's meets Bevy's volume.
    far_rule: u32,
    /// Group 2 of the ao pass: nearfield's view and the technique's far field.
    pub(super) far_group: wgpu::BindGroup,
    _keep: (GpuEnvironment, GpuFarField),
}

/// What a view's technique reads beyond R: the baked volume, or without one the camera's
/// environment map (its key, and the sky read from it where it could be).
struct Far<'a> {
    volume: Option<&'a NearFieldVolume>,
    environment: Option<(ViewEnvironment, Option<Arc<Environment>>)>,
}

/// glue.wgsl's `far_rule` for a technique's rule, with a baked volume or without, and without
/// one with the view's environment map read as the technique's sky or not.
fn glue_far_rule(rule: FarRule, volume: bool, environment: bool) -> u32 {
    match (volume, environment, rule) {
        (true, _, FarRule::Occlusion) => 1,
        (true, _, FarRule::Replace) => 2,
        (false, true, FarRule::Replace) => 3,
        _ => 0,
    }
}

/// nearfield's camera of a Bevy view: eye, view direction, up and vertical field of view; near
/// and far from Bevy's projection (the far plane is Bevy's `far`).
fn camera_of(
    view: &ExtractedView,
    near: f32,
    far: f32,
) -> (nearfield_scene::Camera, CameraMatrices) {
    let t = view.world_from_view.compute_transform();
    let v3 = |v: Vec3| glam::Vec3::new(v.x, v.y, v.z);
    let eye = t.translation;
    let forward = t.rotation * Vec3::NEG_Z;
    let up = t.rotation * Vec3::Y;
    // Bevy's projection: clip_from_view[1][1] = 1 / tan(fov / 2).
    let yfov = 2.0 * (1.0 / view.clip_from_view.y_axis.y).atan();
    let camera = nearfield_scene::Camera {
        eye: v3(eye),
        target: v3(eye + forward),
        up: v3(up),
        yfov,
    };
    let aspect = view.clip_from_view.y_axis.y / view.clip_from_view.x_axis.x;
    let matrices = CameraMatrices {
        view_from_world: camera.view_from_world(),
        clip_from_view: camera.clip_from_view(aspect, near, far),
        near,
        far,
    };
    (camera, matrices)
}

/// Bevy's near plane (`clip_from_view[3][2]` of its infinite reverse-z projection) and a far
/// plane for nearfield's matrices (1000 × near, Bevy's default ratio).
fn near_far(view: &ExtractedView) -> (f32, f32) {
    let near = view.clip_from_view.w_axis.z.max(1e-4);
    (near, near * 1e5)
}

impl NearFieldView {
    /// Frames rendered so far.
    pub(crate) fn frames(&self) -> u32 {
        self.state.lock().unwrap().frame_index
    }

    fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        pipelines: &GluePipelines,
        size: UVec2,
        near_field: &ExtractedNearField,
        view: &ExtractedView,
        Far {
            volume,
            environment,
        }: Far,
    ) -> Result<Self, String> {
        let desc = technique::find(near_field.technique.name()).map_err(|e| e.to_string())?;
        let radius = technique::radius_of(near_field.technique.name(), &near_field.params)
            .map_err(|e| e.to_string())?
            .filter(|r| r.is_finite() && *r > 0.0)
            .unwrap_or(1.0);
        let images = Images::new(device, size, desc.writes);
        let (near, far) = near_far(view);
        let (camera, matrices) = camera_of(view, near, far);
        let size_t = (size.x, size.y);
        let uniforms = ViewUniforms::new(&FrameInputs {
            camera: &camera,
            current: matrices,
            previous: matrices,
            size: size_t,
            frame_index: 0,
            seed: 0,
            previous_tan_half_fov: (0.5 * camera.yfov).tan(),
            history: (false, 0),
        });
        let view_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("nearfield view"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        // With a baked volume the technique reads it beyond R; without one, its sky is the
        // camera's environment map where there is one (docs/src/bevy.md, "Counted once"). Else
        // a white sky: the technique's env-irradiance is then its unoccluded fraction, and
        // Bevy's own ambient light is darkened by the ao.
        let sky = environment.as_ref().and_then(|(_, e)| e.clone());
        let env = match &sky {
            Some(e) if volume.is_none() => (**e).clone(),
            _ => Environment::constant(glam::Vec3::ONE),
        };
        let gpu_env = GpuEnvironment::new(device, queue, &env);
        let far_field = match volume {
            Some(v) => GpuFarField::volume(device, queue, &v.0, radius),
            None => GpuFarField::sky(device, queue),
        };
        let far_group = FarBindings {
            ao_cam: &view_buffer,
            ao_far_probes: &far_field.probes_view,
            ao_far_visibility: &far_field.visibility_view,
            ao_far_atlas: &far_field.irradiance_view,
            ao_far_sampler: &gpu_env.sampler,
            ao_env: &gpu_env.uniform_buffer,
        }
        .bind_group(device, &pipelines.far_layout);
        // gtao, hbil and vbgi read nothing of nearfield's own frame: no `Frame` buffer.
        let frame_group = FrameGroup::new(device, &view_buffer, None, &gpu_env, &far_field);
        let inputs = NearFieldInputs {
            size: size_t,
            view_depth: &images.view_depth.view,
            normal: &images.normal.view,
            albedo: &images.albedo.view,
            material: &images.material.view,
            emission: &images.emission.view,
            // One image for both sides: the glue writes this frame's reprojected colour into it
            // before the technique reads it.
            direct_radiance: [&images.gathered.view, &images.gathered.view],
            motion: &images.motion.view,
            depth: None,
        };
        let outputs = NearFieldOutputs {
            ao: &images.ao.view,
            bent_normal: None,
            env_irradiance: images.env_irradiance.as_ref().map(|i| &i.view),
            indirect_irradiance: images.indirect_irradiance.as_ref().map(|i| &i.view),
            light_irradiance: images.light_irradiance.as_ref().map(|i| &i.view),
        };
        let technique = technique::create(
            desc,
            &TechniqueContext {
                device,
                queue,
                frame_group: &frame_group,
                inputs: &inputs,
                outputs: &outputs,
                env: &gpu_env,
                scene: None,
                pack_half: false,
            },
            &near_field.params,
        )
        .map_err(|e| e.to_string())?;
        let glue_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("nearfield glue"),
            size: std::mem::size_of::<Glue>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let glue_group =
            GlueBindings { glue: &glue_buffer }.bind_group(device, &pipelines.glue_layout);
        Ok(NearFieldView {
            size,
            technique_name: near_field.technique,
            params: near_field.params.clone(),
            images,
            view_buffer,
            glue_buffer,
            glue_group,
            _frame_group: frame_group,
            technique,
            info: Mutex::new(FrameInfo {
                index: 0,
                history: false,
            }),
            state: Mutex::new(State {
                frame_index: 0,
                previous: None,
                previous_clip_from_world: None,
                profiler: GpuProfiler::new(device, queue, false),
            }),
            ambient_occlusion: near_field.ambient_occlusion,
            readback: Mutex::new(None),
            far_volume: volume.map(|v| v.0.clone()),
            far_rule: glue_far_rule(desc.far_rule, volume.is_some(), sky.is_some()),
            environment,
            far_group,
            _keep: (gpu_env, far_field),
        })
    }

    /// This frame's uniforms: the view (this and last frame's camera), the glue's. Under TAA
    /// (`jitter`) Bevy rasterizes the prepass with a jittered projection: nearfield's matrices
    /// and the glue's reconstruction take the same jitter, so that every position the technique
    /// rebuilds lies on the surface the depth holds and every point it projects lands where that
    /// depth shows it.
    fn prepare(
        &self,
        queue: &wgpu::Queue,
        view: &ExtractedView,
        jitter: Option<&TemporalJitter>,
        has_motion: bool,
        has_gbuffer: bool,
        intensity: f32,
    ) {
        let (near, far) = near_far(view);
        let (camera, mut matrices) = camera_of(view, near, far);
        let mut clip_from_view = view.clip_from_view;
        if let Some(j) = jitter {
            let size = self.size.as_vec2();
            j.jitter_projection(&mut clip_from_view, size);
            let mut m = Mat4::from_cols_array(&matrices.clip_from_view.to_cols_array());
            j.jitter_projection(&mut m, size);
            matrices.clip_from_view = glam::Mat4::from_cols_array(&m.to_cols_array());
        }
        let world_from_view = view.world_from_view.to_matrix();
        let clip_from_world = view.clip_from_view * world_from_view.inverse();
        let mut state = self.state.lock().unwrap();
        let previous = state.previous.unwrap_or(matrices);
        let index = state.frame_index;
        // Frame 0 gathers no radiance (Bevy's colour is kept after its main pass), so the
        // accumulation starts again at frame 1, the first that sees Bevy's colour.
        let history = state.previous.is_some() && index >= 2;
        let uniforms = ViewUniforms::new(&FrameInputs {
            camera: &camera,
            current: matrices,
            previous,
            size: (self.size.x, self.size.y),
            frame_index: index,
            seed: 0,
            previous_tan_half_fov: (0.5 * camera.yfov).tan(),
            history: (history, index.saturating_sub(1)),
        });
        queue.write_buffer(&self.view_buffer, 0, bytemuck::bytes_of(&uniforms));
        let previous_clip_from_world = state.previous_clip_from_world.unwrap_or(clip_from_world);
        let glue = Glue {
            view_from_clip: clip_from_view.inverse().to_cols_array_2d(),
            previous_clip_from_view: (previous_clip_from_world * world_from_view)
                .to_cols_array_2d(),
            size: [self.size.x as f32, self.size.y as f32],
            has_motion: has_motion as u32,
            indirect_intensity: intensity,
            ambient_occlusion: self.ambient_occlusion as u32,
            far_rule: self.far_rule,
            has_gbuffer: has_gbuffer as u32,
            _pad: 0,
        };
        queue.write_buffer(&self.glue_buffer, 0, bytemuck::bytes_of(&glue));
        self.technique.prepare(queue, &camera);
        *self.info.lock().unwrap() = FrameInfo { index, history };
        state.previous = Some(matrices);
        state.previous_clip_from_world = Some(clip_from_world);
        state.frame_index = index.wrapping_add(1);
    }
}

/// Makes (or remakes, when the size or the settings change) each view's nearfield and writes
/// this frame's uniforms. A view whose technique cannot be made logs one line and goes without.
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
pub(super) fn prepare_views(
    mut commands: Commands,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    pipelines: Res<GluePipelines>,
    refusals: Res<crate::Refusals>,
    volume: Option<Res<NearFieldVolume>>,
    gpu_images: Res<RenderAssets<GpuImage>>,
    views: Query<(
        Entity,
        &MainEntity,
        &ExtractedCamera,
        &ExtractedView,
        &ExtractedNearField,
        Option<&ViewPrepassTextures>,
        Option<&TemporalJitter>,
        Option<&NearFieldView>,
    )>,
) {
    for (entity, main, camera, view, near_field, prepass, jitter, existing) in &views {
        if refusals.0.lock().unwrap().contains(&main.id()) {
            continue;
        }
        let Some(size) = camera.physical_viewport_size else {
            continue;
        };
        if size.x == 0 || size.y == 0 {
            continue;
        }
        let has_motion = prepass.is_some_and(|p| p.motion_vectors.is_some());
        let has_gbuffer = prepass.is_some_and(|p| p.deferred.is_some());
        let volume = volume.as_deref();
        // The environment map the view is made for: none beside a volume, and none until its
        // image is on the GPU.
        let wanted = near_field
            .environment
            .filter(|e| volume.is_none() && gpu_images.get(e.image).is_some());
        let current = existing.filter(|v| {
            v.size == size
                && v.technique_name == near_field.technique
                && v.params == near_field.params
                && v.ambient_occlusion == near_field.ambient_occlusion
                && match (&v.far_volume, volume) {
                    (None, None) => true,
                    (Some(a), Some(b)) => Arc::ptr_eq(a, &b.0),
                    _ => false,
                }
                && v.environment.as_ref().map(|e| e.0) == wanted
        });
        // A view made anew where the size or the settings changed (or the first frame).
        let fresh = match current {
            Some(_) => None,
            None => match NearFieldView::new(
                device.wgpu_device(),
                &queue,
                &pipelines,
                size,
                near_field,
                view,
                Far {
                    volume,
                    environment: wanted.map(|key| {
                        let e = environment_of(
                            &key,
                            existing,
                            &device,
                            &queue,
                            &pipelines,
                            &gpu_images,
                        );
                        (key, e)
                    }),
                },
            ) {
                Ok(v) => Some(v),
                Err(e) => {
                    error!(
                        "NearField ({}): {e}; the camera renders without it",
                        near_field.technique.name()
                    );
                    refusals.0.lock().unwrap().insert(main.id());
                    commands.entity(entity).remove::<NearFieldView>();
                    continue;
                }
            },
        };
        let Some(v) = fresh.as_ref().or(current) else {
            continue;
        };
        v.prepare(
            &queue,
            view,
            jitter,
            has_motion,
            has_gbuffer,
            near_field.indirect_intensity,
        );
        if let Some(v) = fresh {
            commands.entity(entity).insert(v);
        }
    }
}

/// The technique's sky read from the view's environment map `key`: the one `existing` holds
/// where it was made for the same map, else read from Bevy's image (None, with one logged line,
/// where it cannot be read: the technique then sees a white sky).
fn environment_of(
    key: &ViewEnvironment,
    existing: Option<&NearFieldView>,
    device: &RenderDevice,
    queue: &RenderQueue,
    pipelines: &GluePipelines,
    gpu_images: &RenderAssets<GpuImage>,
) -> Option<Arc<Environment>> {
    if let Some((k, e)) = existing.and_then(|v| v.environment.as_ref())
        && k == key
    {
        return e.clone();
    }
    let image = gpu_images.get(key.image)?;
    match key.read(device.wgpu_device(), queue, pipelines, image) {
        Ok(e) => Some(Arc::new(e)),
        Err(e) => {
            error!("NearField: {e}; the technique sees a white sky");
            None
        }
    }
}

/// Bevy's SSAO passes do not run for a view with nearfield (its ao image is written by
/// [`inputs_and_technique`] instead).
pub(super) fn skip_bevy_ssao(
    mut commands: Commands,
    views: Query<Entity, (With<ExtractedNearField>, With<SsaoPipelineId>)>,
) {
    for entity in &views {
        commands.entity(entity).remove::<SsaoPipelineId>();
    }
}

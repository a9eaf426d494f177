//! The render world: per view, nearfield's input and output images, its group 0 and the created
//! technique; each frame the glue passes around the technique's own passes.
//!
//! Order inside Bevy's `Core3d` schedule: after the prepasses, [`inputs_and_technique`] (Bevy's
//! depth, normal and motion → nearfield's inputs; the technique; its ao into Bevy's ao image);
//! after the main pass, [`capture_and_add`] (Bevy's lit colour kept as next frame's radiance;
//! the indirect light added where the camera has Bevy's deferred G-buffer).

use crate::readback::{self, ExtractedReadback, ReadbackBuffers};
use crate::{ExtractedNearField, NearFieldTechnique};
use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::log::error;
use bevy::pbr::{ScreenSpaceAmbientOcclusionResources, SsaoPipelineId};
use bevy::prelude::*;
use bevy::render::camera::ExtractedCamera;
use bevy::render::renderer::{RenderAdapter, RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::sync_world::MainEntity;
use bevy::render::view::{ExtractedView, ViewTarget};
use bevy::render::{Render, RenderSystems};
use nearfield_render::contract::io::{NearFieldInputs, NearFieldOutputs};
use nearfield_render::far::GpuFarField;
use nearfield_render::frame::{CameraMatrices, FrameInputs, ViewUniforms};
use nearfield_render::gpu_env::GpuEnvironment;
use nearfield_render::passes::FrameGroup;
use nearfield_render::profiler::GpuProfiler;
use nearfield_render::technique::{
    self, FrameInfo, Output, Technique, TechniqueContext, TechniqueParams,
};
use nearfield_render::wgpu;
use std::sync::Mutex;
use wgpu::util::DeviceExt;

const GLUE: &str = include_str!("glue.wgsl");

pub(crate) fn build(render_app: &mut bevy::app::SubApp) {
    render_app
        .init_resource::<GluePipelines>()
        .add_systems(
            Render,
            (
                prepare_views.in_set(RenderSystems::PrepareResources),
                skip_bevy_ssao.in_set(RenderSystems::PrepareBindGroups),
                readback::collect.in_set(RenderSystems::Cleanup),
            ),
        )
        .add_systems(
            Core3d,
            (
                inputs_and_technique
                    .after(Core3dSystems::Prepass)
                    .before(Core3dSystems::MainPass),
                capture_and_add
                    .after(Core3dSystems::MainPass)
                    .before(Core3dSystems::EarlyPostProcess),
            ),
        );
    readback::build_render(render_app);
}

/// The glue shader's header (the `Glue` uniform, the full-screen triangle) with one of its
/// sections (split at the lines that start with `// --- `).
fn glue_section(index: usize, ao_format: &str) -> String {
    let sections: Vec<&str> = GLUE.split("\n// --- ").collect();
    format!("{}\n// --- {}", sections[0], sections[index]).replace("AO_FORMAT", ao_format)
}

/// The glue's pipelines, made once on Bevy's device.
#[derive(Resource)]
pub(crate) struct GluePipelines {
    glue_layout: wgpu::BindGroupLayout,
    inputs_layout: wgpu::BindGroupLayout,
    inputs: wgpu::RenderPipeline,
    capture_layout: wgpu::BindGroupLayout,
    /// By the format of the image written (this frame's radiance: rgba16float).
    capture: wgpu::RenderPipeline,
    add_layout: wgpu::BindGroupLayout,
    /// The additive pass, by Bevy's main-texture format (hdr and not).
    add: Vec<(wgpu::TextureFormat, wgpu::RenderPipeline)>,
    ao_layout: wgpu::BindGroupLayout,
    ao: wgpu::ComputePipeline,
}

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

const FLOAT: wgpu::TextureSampleType = wgpu::TextureSampleType::Float { filterable: false };

impl FromWorld for GluePipelines {
    fn from_world(world: &mut World) -> Self {
        let device = world.resource::<RenderDevice>().wgpu_device().clone();
        let adapter = world.resource::<RenderAdapter>();
        // The format Bevy's SSAO gives its ao image (bevy_pbr's ssao: r16float where the adapter
        // can store to it, else r32float).
        let ao_format = if adapter
            .get_texture_format_features(wgpu::TextureFormat::R16Float)
            .allowed_usages
            .contains(wgpu::TextureUsages::STORAGE_BINDING)
        {
            wgpu::TextureFormat::R16Float
        } else {
            wgpu::TextureFormat::R32Float
        };
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let glue_layout = layout(
            "nearfield glue",
            &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        );
        let inputs_layout = layout(
            "nearfield glue inputs",
            &[
                texture_entry(0, FLOAT),
                texture_entry(1, FLOAT),
                texture_entry(2, FLOAT),
            ],
        );
        let capture_layout = layout("nearfield glue capture", &[texture_entry(0, FLOAT)]);
        let add_layout = layout(
            "nearfield glue add",
            &[
                texture_entry(0, wgpu::TextureSampleType::Uint),
                texture_entry(1, FLOAT),
            ],
        );
        let ao_layout = layout(
            "nearfield glue ao",
            &[
                texture_entry(0, FLOAT),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: ao_format,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                    count: None,
                },
            ],
        );
        let module = |label, index| {
            let format = match ao_format {
                wgpu::TextureFormat::R16Float => "r16float",
                _ => "r32float",
            };
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(glue_section(index, format).into()),
            })
        };
        let raster = |label,
                      index,
                      entry,
                      group: &wgpu::BindGroupLayout,
                      targets: &[Option<wgpu::ColorTargetState>]| {
            let m = module(label, index);
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[Some(&glue_layout), Some(group)],
                immediate_size: 0,
            });
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &m,
                    entry_point: Some("vs_fullscreen"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &m,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        use wgpu::TextureFormat as F;
        let inputs = raster(
            "nearfield glue inputs",
            1,
            "fs_inputs",
            &inputs_layout,
            &[
                Some(F::R32Float.into()),
                Some(F::Rgba16Float.into()),
                Some(F::Rg16Float.into()),
            ],
        );
        let capture = raster(
            "nearfield glue capture",
            2,
            "fs_capture",
            &capture_layout,
            &[Some(F::Rgba16Float.into())],
        );
        let additive = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Zero,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let add = [F::Rgba16Float, F::Rgba8UnormSrgb]
            .into_iter()
            .map(|format| {
                let p = raster(
                    "nearfield glue add indirect",
                    3,
                    "fs_add_indirect",
                    &add_layout,
                    &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(additive),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                );
                (format, p)
            })
            .collect();
        let ao_module = module("nearfield glue ao", 4);
        let ao_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("nearfield glue ao"),
            bind_group_layouts: &[Some(&glue_layout), Some(&ao_layout)],
            immediate_size: 0,
        });
        let ao = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("nearfield glue ao"),
            layout: Some(&ao_pipeline_layout),
            module: &ao_module,
            entry_point: Some("cs_ao"),
            compilation_options: Default::default(),
            cache: None,
        });
        GluePipelines {
            glue_layout,
            inputs_layout,
            inputs,
            capture_layout,
            capture,
            add_layout,
            add,
            ao_layout,
            ao,
        }
    }
}

/// The glue's uniform (`Glue` in glue.wgsl).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GlueUniform {
    view_from_clip: [[f32; 4]; 4],
    size: [f32; 2],
    has_motion: u32,
    indirect_intensity: f32,
    ambient_occlusion: u32,
    _pad: [u32; 3],
}

/// A texture and its full view (nearfield's own).
pub use nearfield_render::targets::Target as Image;

/// nearfield's images of one view (NearFieldInputs and NearFieldOutputs).
pub struct Images {
    view_depth: Image,
    normal: Image,
    albedo: Image,
    material: Image,
    emission: Image,
    direct: [Image; 2],
    motion: Image,
    pub(crate) ao: Image,
    /// The outputs the technique declares besides ao (`TechniqueDesc::writes`): gtao writes
    /// none of these three, hbil and vbgi env- and indirect-irradiance.
    env_irradiance: Option<Image>,
    pub(crate) indirect_irradiance: Option<Image>,
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
            direct: [
                image("nearfield radiance 0", F::Rgba16Float, target),
                image("nearfield radiance 1", F::Rgba16Float, target),
            ],
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
struct State {
    frame_index: u32,
    previous: Option<CameraMatrices>,
    profiler: GpuProfiler,
}

/// A view's nearfield: images, group 0, the technique (render world).
#[derive(Component)]
pub struct NearFieldView {
    size: UVec2,
    technique_name: NearFieldTechnique,
    params: TechniqueParams,
    pub(crate) images: Images,
    view_buffer: wgpu::Buffer,
    glue_buffer: wgpu::Buffer,
    glue_group: wgpu::BindGroup,
    _frame_group: FrameGroup,
    technique: Box<dyn Technique>,
    /// This frame's side of the radiance pair and whether last frame's may be read.
    info: Mutex<FrameInfo>,
    state: Mutex<State>,
    ambient_occlusion: bool,
    pub(crate) readback: Mutex<Option<ReadbackBuffers>>,
    _keep: (GpuEnvironment, GpuFarField),
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
    ) -> Result<Self, String> {
        let desc = technique::find(near_field.technique.name()).map_err(|e| e.to_string())?;
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
        // A white sky: the technique's env-irradiance is then its unoccluded fraction; Bevy's
        // own environment light is shaded by Bevy and darkened by the ao.
        let env = nearfield_scene::Environment::constant(glam::Vec3::ONE);
        let gpu_env = GpuEnvironment::new(device, queue, &env);
        let far_field = GpuFarField::sky(device, queue);
        // gtao, hbil and vbgi read nothing of nearfield's own frame: no `Frame` buffer.
        let frame_group = FrameGroup::new(device, &view_buffer, None, &gpu_env, &far_field);
        let inputs = NearFieldInputs {
            size: size_t,
            view_depth: &images.view_depth.view,
            normal: &images.normal.view,
            albedo: &images.albedo.view,
            material: &images.material.view,
            emission: &images.emission.view,
            direct_radiance: [&images.direct[0].view, &images.direct[1].view],
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
            size: std::mem::size_of::<GlueUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let glue_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("nearfield glue"),
            layout: &pipelines.glue_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: glue_buffer.as_entire_binding(),
            }],
        });
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
                profiler: GpuProfiler::new(device, queue, false),
            }),
            ambient_occlusion: near_field.ambient_occlusion,
            readback: Mutex::new(None),
            _keep: (gpu_env, far_field),
        })
    }

    /// This frame's uniforms: the view (this and last frame's camera), the glue's.
    fn prepare(&self, queue: &wgpu::Queue, view: &ExtractedView, has_motion: bool, intensity: f32) {
        let (near, far) = near_far(view);
        let (camera, matrices) = camera_of(view, near, far);
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
        let glue = GlueUniform {
            view_from_clip: view.clip_from_view.inverse().to_cols_array_2d(),
            size: [self.size.x as f32, self.size.y as f32],
            has_motion: has_motion as u32,
            indirect_intensity: intensity,
            ambient_occlusion: self.ambient_occlusion as u32,
            _pad: [0; 3],
        };
        queue.write_buffer(&self.glue_buffer, 0, bytemuck::bytes_of(&glue));
        self.technique.prepare(queue, &camera);
        *self.info.lock().unwrap() = FrameInfo { index, history };
        state.previous = Some(matrices);
        state.frame_index = index.wrapping_add(1);
    }
}

/// Makes (or remakes, when the size or the settings change) each view's nearfield and writes
/// this frame's uniforms. A view whose technique cannot be made logs one line and goes without.
#[allow(clippy::type_complexity)]
fn prepare_views(
    mut commands: Commands,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    pipelines: Res<GluePipelines>,
    refusals: Res<crate::Refusals>,
    views: Query<(
        Entity,
        &MainEntity,
        &ExtractedCamera,
        &ExtractedView,
        &ExtractedNearField,
        Option<&ViewPrepassTextures>,
        Option<&NearFieldView>,
    )>,
) {
    for (entity, main, camera, view, near_field, prepass, existing) in &views {
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
        let current = existing.filter(|v| {
            v.size == size
                && v.technique_name == near_field.technique
                && v.params == near_field.params
                && v.ambient_occlusion == near_field.ambient_occlusion
        });
        if let Some(v) = current {
            v.prepare(&queue, view, has_motion, near_field.indirect_intensity);
            continue;
        }
        match NearFieldView::new(
            device.wgpu_device(),
            &queue,
            &pipelines,
            size,
            near_field,
            view,
        ) {
            Ok(v) => {
                v.prepare(&queue, view, has_motion, near_field.indirect_intensity);
                commands.entity(entity).insert(v);
            }
            Err(e) => {
                error!(
                    "NearField ({}): {e}; the camera renders without it",
                    near_field.technique.name()
                );
                refusals.0.lock().unwrap().insert(main.id());
                commands.entity(entity).remove::<NearFieldView>();
            }
        }
    }
}

/// Bevy's SSAO passes do not run for a view with nearfield (its ao image is written by
/// [`inputs_and_technique`] instead).
fn skip_bevy_ssao(
    mut commands: Commands,
    views: Query<Entity, (With<ExtractedNearField>, With<SsaoPipelineId>)>,
) {
    for entity in &views {
        commands.entity(entity).remove::<SsaoPipelineId>();
    }
}

fn texture_of(view: &wgpu::TextureView) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::TextureView(view)
}

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
fn inputs_and_technique(
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
        .unwrap_or(&nf.images.direct[0].view);
    let inputs_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("nearfield glue inputs"),
        layout: &pipelines.inputs_layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: texture_of(depth),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: texture_of(&normal.texture.default_view),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: texture_of(motion),
            },
        ],
    });
    let info = *nf.info.lock().unwrap();
    let encoder = ctx.command_encoder();
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
        let ao_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("nearfield glue ao"),
            layout: &pipelines.ao_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: texture_of(&nf.images.ao.view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: texture_of(&target.default_view),
                },
            ],
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("nearfield ao into Bevy's"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipelines.ao);
        pass.set_bind_group(0, &nf.glue_group, &[]);
        pass.set_bind_group(1, &ao_group, &[]);
        pass.dispatch_workgroups(nf.size.x.div_ceil(8), nf.size.y.div_ceil(8), 1);
    }
    if readback.is_some() {
        readback::copy(device, encoder, nf);
    }
    encoder.pop_debug_group();
}

/// After Bevy's main pass: its colour is kept as the radiance the next frame gathers (before
/// anything is added), then the indirect light is added where Bevy's deferred G-buffer gives
/// the base colour.
fn capture_and_add(
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
    let info = *nf.info.lock().unwrap();
    // Frame i reads radiance[i % 2] as this frame's and the other as last frame's: Bevy's colour
    // of frame i is next frame's.
    let next = &nf.images.direct[(info.side() + 1) % 2].view;
    let capture_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("nearfield glue capture"),
        layout: &pipelines.capture_layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: texture_of(target.main_texture_view()),
        }],
    });
    let encoder = ctx.command_encoder();
    fullscreen(
        encoder,
        "nearfield capture radiance",
        &pipelines.capture,
        &nf.glue_group,
        &capture_group,
        &[next],
        wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
    );
    if readback.is_some() {
        readback::copy_radiance(
            encoder,
            nf,
            &nf.images.direct[(info.side() + 1) % 2].texture,
        );
    }
    if !near_field.technique.has_indirect() || near_field.indirect_intensity == 0.0 {
        return;
    }
    let Some(gbuffer) = prepass.deferred.as_ref() else {
        return;
    };
    let Some(indirect) = nf.images.indirect_irradiance.as_ref() else {
        return;
    };
    let Some((_, add)) = pipelines
        .add
        .iter()
        .find(|(f, _)| *f == target.main_texture_format())
    else {
        return;
    };
    let add_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("nearfield glue add"),
        layout: &pipelines.add_layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: texture_of(&gbuffer.texture.default_view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: texture_of(&indirect.view),
            },
        ],
    });
    fullscreen(
        encoder,
        "nearfield add indirect",
        add,
        &nf.glue_group,
        &add_group,
        &[target.main_texture_view()],
        wgpu::LoadOp::Load,
    );
}

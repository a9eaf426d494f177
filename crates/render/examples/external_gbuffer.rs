//! A wgpu program of its own that hands its G-buffer to nearfield's techniques.
//!
//! It rasterises a small scene (nearfield's built-in `boxes`, as plain triangles) with its own
//! shader into its own textures — not nearfield's `FrameTargets`, not nearfield's G-buffer pass —
//! shades a direct radiance of its own, and runs `ssdo`, `hbil` and `gtao` on those images through the
//! documented inputs (`nearfield_render::contract::io::NearFieldInputs`). It reads `ao` back and
//! prints its mean over the surface pixels. What it needs from nearfield besides the technique:
//! the narrow `View` uniform (camera matrices, size, frame index: `ViewUniforms`), the
//! environment (`GpuEnvironment`, whose own uniform holds its rotation and intensity) and the far
//! field, which together are group 0 of every pass. Nothing of nearfield's own frame (exposure,
//! tone mapping, lights, AOVs): `FrameGroup::new` takes `None` for it.
//!
//! ```text
//! cargo run --release -p nearfield-render --example external_gbuffer
//! ```
//! `tests/external_gbuffer.rs` runs the same scene and camera through nearfield's `Renderer` and
//! checks that both give the same ao.

use nearfield_render::contract::io::{NearFieldInputs, NearFieldOutputs};
use nearfield_render::frame::{CameraMatrices, FrameInputs, ViewUniforms};
use nearfield_render::gpu_env::GpuEnvironment;
use nearfield_render::passes::FrameGroup;
use nearfield_render::profiler::GpuProfiler;
use nearfield_render::technique::{self, FrameInfo, Output, TechniqueContext, TechniqueParams};
use nearfield_render::{GpuContext, wgpu};
use wgpu::util::DeviceExt;

/// The image size of the example.
pub const SIZE: (u32, u32) = (160, 90);
/// The techniques it runs.
pub const METHODS: [&str; 3] = ["ssdo", "hbil", "gtao"];

/// The engine's own G-buffer shader: world normal (flipped on back faces), view depth, albedo,
/// and a direct radiance of its own (albedo × a sky that is brighter above).
const SHADER: &str = r#"
struct Camera {
    clip_from_world: mat4x4<f32>,
    view_from_world: mat4x4<f32>,
}
@group(0) @binding(0) var<uniform> camera: Camera;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) albedo: vec3<f32>,
}

@vertex
fn vs(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>,
      @location(2) albedo: vec3<f32>) -> VertexOut {
    var o: VertexOut;
    o.clip = camera.clip_from_world * vec4<f32>(position, 1.0);
    o.world = position;
    o.normal = normal;
    o.albedo = albedo;
    return o;
}

struct GBuffer {
    @location(0) normal: vec4<f32>,
    @location(1) view_depth: vec4<f32>,
    @location(2) albedo: vec4<f32>,
    @location(3) direct: vec4<f32>,
}

@fragment
fn fs(in: VertexOut, @builtin(front_facing) front: bool) -> GBuffer {
    var n = normalize(in.normal);
    if !front {
        n = -n;
    }
    var o: GBuffer;
    o.normal = vec4<f32>(n, 1.0);
    o.view_depth = vec4<f32>(-(camera.view_from_world * vec4<f32>(in.world, 1.0)).z, 0.0, 0.0, 0.0);
    o.albedo = vec4<f32>(in.albedo, 1.0);
    o.direct = vec4<f32>(in.albedo * (0.6 + 0.4 * n.y), 1.0);
    return o;
}
"#;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Vertex {
    position: [f32; 3],
    normal: [f32; 3],
    albedo: [f32; 3],
}

/// One image of the engine's G-buffer.
fn image(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: SIZE.0,
            height: SIZE.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    (texture, view)
}

/// Renders `method` (e.g. `ssdo`, `hbil`) for one frame of the built-in `boxes` scene from its
/// default camera and returns the mean `ao` over the pixels the scene covers.
pub fn mean_ao(ctx: &GpuContext, method: &str) -> Result<f32, String> {
    let (ao, view_depth) = ao_image(ctx, method)?;
    // Surface pixels: where the engine's view depth is positive.
    let covered: Vec<f32> = ao
        .iter()
        .zip(&view_depth)
        .filter(|(_, d)| **d > 0.0)
        .map(|(a, _)| *a)
        .collect();
    if covered.is_empty() {
        return Err("no surface pixels".into());
    }
    Ok(covered.iter().sum::<f32>() / covered.len() as f32)
}

/// The `ao` image (r32float, row 0 at the top) of `method` on the engine's G-buffer, and the
/// engine's view depth (0 on background).
pub fn ao_image(ctx: &GpuContext, method: &str) -> Result<(Vec<f32>, Vec<f32>), String> {
    let images = engine_images(ctx, method, None)?;
    Ok((images.ao, images.view_depth))
}

/// What one frame of a technique leaves in the engine's images.
pub struct EngineImages {
    /// `ao` (row 0 at the top).
    pub ao: Vec<f32>,
    /// The engine's view depth (0 on background).
    pub view_depth: Vec<f32>,
    /// The bent normal (xyzw), where the technique declares it.
    pub bent_normal: Option<Vec<[f32; 4]>>,
}

/// One frame of `method` on the engine's G-buffer with the outputs it declares, less
/// `leave_out` (to see a missing output refused).
pub fn engine_images(
    ctx: &GpuContext,
    method: &str,
    leave_out: Option<Output>,
) -> Result<EngineImages, String> {
    let (device, queue) = (&ctx.device, &ctx.queue);
    let scene = nearfield_scene::builtin::scene("boxes").map_err(|e| e.to_string())?;
    let env = scene.default_env.load().map_err(|e| e.to_string())?;
    let camera = scene.default_camera();

    // The scene as plain triangles, single-sided ones culled as engines do.
    let mut vertices = Vec::new();
    let (mut one_sided, mut two_sided) = (Vec::new(), Vec::new());
    for mesh in &scene.meshes {
        let m = &scene.materials[mesh.material as usize];
        let base = vertices.len() as u32;
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            vertices.push(Vertex {
                position: p.to_array(),
                normal: n.to_array(),
                albedo: m.base_color.truncate().to_array(),
            });
        }
        let list = if m.double_sided {
            &mut two_sided
        } else {
            &mut one_sided
        };
        list.extend(mesh.indices.iter().flatten().map(|i| base + i));
    }
    let buffer = |label, bytes: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage,
        })
    };
    let vertex_buffer = buffer(
        "vertices",
        bytemuck::cast_slice(&vertices),
        wgpu::BufferUsages::VERTEX,
    );
    let index_lists = [(one_sided, true), (two_sided, false)];
    let index_buffers: Vec<(wgpu::Buffer, u32, bool)> = index_lists
        .iter()
        .filter(|(list, _)| !list.is_empty())
        .map(|(list, cull)| {
            let b = buffer(
                "indices",
                bytemuck::cast_slice(list),
                wgpu::BufferUsages::INDEX,
            );
            (b, list.len() as u32, *cull)
        })
        .collect();

    // The engine's camera uniform and G-buffer.
    let matrices = CameraMatrices::new(&camera, SIZE, scene.bounds());
    let mut camera_data = [[[0f32; 4]; 4]; 2];
    camera_data[0] = matrices.clip_from_world().to_cols_array_2d();
    camera_data[1] = matrices.view_from_world.to_cols_array_2d();
    let camera_buffer = buffer(
        "camera",
        bytemuck::cast_slice(&camera_data),
        wgpu::BufferUsages::UNIFORM,
    );
    use wgpu::TextureFormat as F;
    use wgpu::TextureUsages as U;
    let target = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING;
    let (_n, normal) = image(device, "engine normal", F::Rgba16Float, target);
    let (depth_texture, view_depth) = image(
        device,
        "engine view depth",
        F::R32Float,
        target | U::COPY_SRC,
    );
    let (_a, albedo) = image(device, "engine albedo", F::Rgba8Unorm, target);
    let (_r0, direct0) = image(device, "engine direct radiance", F::Rgba16Float, target);
    let (_r1, direct1) = image(device, "engine direct radiance", F::Rgba16Float, target);
    // Never written: wgpu's zero-initialised images stand for no metal, no emission, no motion.
    let (_m, material) = image(device, "engine material", F::Rgba8Unorm, U::TEXTURE_BINDING);
    let (_e, emission) = image(
        device,
        "engine emission",
        F::Rgba16Float,
        U::TEXTURE_BINDING,
    );
    let (_v, motion) = image(device, "engine motion", F::Rg16Float, U::TEXTURE_BINDING);
    let (_z, depth) = image(device, "engine depth", F::Depth32Float, target);
    let storage = U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC;
    // The outputs the technique declares it writes, and no others (gtao: ao and the bent
    // normal; ssdo: ao, env-, indirect- and light-irradiance).
    let desc = technique::find(method).map_err(|e| e.to_string())?;
    let (ao_texture, ao) = image(device, "engine ao", F::R32Float, storage);
    let declared = |o: Output, label| {
        (desc.writes.contains(&o) && leave_out != Some(o))
            .then(|| image(device, label, F::Rgba16Float, storage))
    };
    let bent = declared(Output::BentNormal, "engine bent normal");
    let env_irradiance = declared(Output::EnvIrradiance, "engine env");
    let indirect_irradiance = declared(Output::IndirectIrradiance, "engine indirect");
    let light_irradiance = declared(Output::LightIrradiance, "engine light");

    // The engine's raster pass.
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("engine gbuffer"),
        source: wgpu::ShaderSource::Wgsl(SHADER.into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("engine camera"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let camera_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("engine camera"),
        layout: &layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: camera_buffer.as_entire_binding(),
        }],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("engine gbuffer"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = |cull: Option<wgpu::Face>| {
        let formats = [F::Rgba16Float, F::R32Float, F::Rgba8Unorm, F::Rgba16Float];
        let targets: Vec<Option<wgpu::ColorTargetState>> =
            formats.iter().map(|&f| Some(f.into())).collect();
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("engine gbuffer"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3],
                })],
            },
            primitive: wgpu::PrimitiveState {
                cull_mode: cull,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: F::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    };
    let (culled, unculled) = (pipeline(Some(wgpu::Face::Back)), pipeline(None));

    // nearfield's group 0: the view, the environment and the far field.
    let gpu_env = GpuEnvironment::new(device, queue, &env);
    let view = ViewUniforms::new(&FrameInputs {
        camera: &camera,
        current: matrices,
        previous: matrices,
        size: SIZE,
        frame_index: 0,
        seed: 0,
        previous_tan_half_fov: (0.5 * camera.yfov).tan(),
        history: (false, 0),
    });
    let uniform = |label, bytes: &[u8]| buffer(label, bytes, wgpu::BufferUsages::UNIFORM);
    let view_buffer = uniform("view", bytemuck::bytes_of(&view));
    let far = nearfield_render::far::GpuFarField::sky(device, queue);
    let frame_group = FrameGroup::new(device, &view_buffer, None, &gpu_env, &far);

    // The technique, on the engine's images.
    let inputs = NearFieldInputs {
        size: SIZE,
        view_depth: &view_depth,
        normal: &normal,
        albedo: &albedo,
        material: &material,
        emission: &emission,
        direct_radiance: [&direct0, &direct1],
        motion: &motion,
        depth: Some(&depth),
    };
    let outputs = NearFieldOutputs {
        ao: &ao,
        bent_normal: bent.as_ref().map(|(_, v)| v),
        env_irradiance: env_irradiance.as_ref().map(|(_, v)| v),
        indirect_irradiance: indirect_irradiance.as_ref().map(|(_, v)| v),
        light_irradiance: light_irradiance.as_ref().map(|(_, v)| v),
    };
    let (_, params) = technique::resolve_params(method, &TechniqueParams::default())
        .map_err(|e| e.to_string())?;
    let t = technique::create(
        desc,
        &TechniqueContext {
            device,
            queue,
            frame_group: &frame_group,
            inputs: &inputs,
            outputs: &outputs,
            env: &gpu_env,
            scene: None,
            pack_half: ctx.pack_half,
        },
        &params,
    )
    .map_err(|e| e.to_string())?;
    t.prepare(queue, &camera);

    // One frame: the engine's G-buffer, then the technique.
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let color = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("engine gbuffer"),
            color_attachments: &[
                color(&normal),
                color(&view_depth),
                color(&albedo),
                color(&direct0),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &camera_group, &[]);
        pass.set_vertex_buffer(0, vertex_buffer.slice(..));
        for (indices, count, cull) in &index_buffers {
            pass.set_pipeline(if *cull { &culled } else { &unculled });
            pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..*count, 0, 0..1);
        }
    }
    let mut profiler = GpuProfiler::new(device, queue, false);
    profiler.begin_frame();
    t.encode(
        &mut encoder,
        &mut profiler,
        FrameInfo {
            index: 0,
            history: false,
        },
    );
    let bytes = nearfield_render::util::read_texture(device, queue, encoder, &ao_texture, 4);
    let read = |texture: &wgpu::Texture, texel_bytes| {
        let encoder = device.create_command_encoder(&Default::default());
        nearfield_render::util::read_texture(device, queue, encoder, texture, texel_bytes)
    };
    let depth_bytes = read(&depth_texture, 4);
    let bent_normal = bent.as_ref().map(|(texture, _)| {
        let halves: Vec<u16> = bytemuck::pod_collect_to_vec(&read(texture, 8));
        halves
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]].map(|h| half::f16::from_bits(h).to_f32()))
            .collect()
    });
    Ok(EngineImages {
        ao: bytemuck::pod_collect_to_vec(&bytes),
        view_depth: bytemuck::pod_collect_to_vec(&depth_bytes),
        bent_normal,
    })
}

#[allow(dead_code)]
fn main() {
    let ctx = match GpuContext::new(None) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("external_gbuffer: {e}");
            std::process::exit(2);
        }
    };
    for method in METHODS {
        match mean_ao(&ctx, method) {
            Ok(a) => println!("{method}: mean ao {a:.4} over the surface pixels"),
            Err(e) => {
                eprintln!("external_gbuffer: {method}: {e}");
                std::process::exit(1);
            }
        }
    }
}

//! Extra layers for the screen-space blocker test (SSDO paper Sec. 4): depth peeling of the main
//! view and additional cameras, each with normal, albedo, emission, view depth and the direct
//! radiance of what it sees (layers.wgsl).
//!
//! - Depth peeling: layers 2..=`layers` of the main camera, rasterized without culling; layer k
//!   keeps the nearest fragment farther than layer k − 1 (read from that layer's depth buffer,
//!   relative margin 1e-4). Odd layers (1, 3) are *entries* into a solid, even layers (2, 4)
//!   *exits*: entry normals face the camera, exit normals face away from it (the outward normal
//!   of a two-manifold solid's back face), whatever the triangle winding or double-sidedness.
//! - Additional cameras: up to four views at 1/`camera_scale` of the main resolution, looking
//!   at the main camera's target from `eye + spread · r · d`, where r is the radius of the
//!   scene's bounding sphere and d one of [`CAMERA_DIRECTIONS`] (normalised, in the main
//!   camera's right/up/back frame); same vertical field of view and aspect, one depth layer.
//! - Direct radiance of every texel of both: ρ × (unoccluded SH irradiance of the environment +
//!   (1/π) Σ E_l with shadow maps) + emission — the sender radiance of DESIGN.md's
//!   `indirect-irradiance`, for bounces from peeled and off-screen geometry.
//!
//! Views in `views` (one 256-byte [`LayerView`] each): 0..=2 the peeled layers 2..=4, 3..=6 the
//! cameras. The blocker test that reads them is `occlusion()` in shaders/screen_samples.wgsl.

use crate::gpu_env::GpuEnvironment;
use crate::gpu_scene::GpuScene;
use crate::passes::gbuffer;
use crate::passes::shadow::ShadowPass;
use crate::profiler::GpuProfiler;
use crate::targets::{self, FrameTargets};
use crate::technique::Setting;
use crate::util;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use nearfield_scene::{Aabb, Camera};
use wgpu::BindingResource as R;
use wgpu::util::DeviceExt;

pub const SHADER: &str = include_str!("layers.wgsl");

/// Most depth layers of the main view (the G-buffer is layer 1).
pub const MAX_LAYERS: u32 = 4;
/// Most additional cameras.
pub const MAX_CAMERAS: u32 = 4;
/// Index of the first camera in the views buffer.
const CAMERA_VIEW_BASE: u32 = 3;
const VIEW_STRIDE: u64 = 256;

/// Displacements of the additional cameras, in the main camera's (right, up, back) frame before
/// normalisation: to the right and up, to the left and up, straight up, and up behind the target.
pub const CAMERA_DIRECTIONS: [[f32; 3]; 4] = [
    [1.0, 0.4, 0.0],
    [-1.0, 0.4, 0.0],
    [0.0, 1.0, 0.2],
    [0.3, 0.6, -1.0],
];

/// What the extra layers hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerSettings {
    /// Depth layers of the main view, 1..=4 (1: the G-buffer only).
    pub layers: u32,
    /// Additional cameras, 0..=4.
    pub cameras: u32,
    /// Resolution divisor of the additional cameras, 1..=8.
    pub camera_scale: u32,
    /// Camera displacement as a fraction of the scene's bounding-sphere radius.
    pub camera_spread: f32,
}

impl Default for LayerSettings {
    fn default() -> Self {
        LayerSettings {
            layers: 1,
            cameras: 0,
            camera_scale: 2,
            camera_spread: 0.5,
        }
    }
}

impl LayerSettings {
    /// Whether anything beyond the G-buffer is drawn.
    pub fn active(&self) -> bool {
        self.layers > 1 || self.cameras > 0
    }
}

/// `LayerView` in shaders/common.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LayerView {
    pub clip_from_world: [[f32; 4]; 4],
    pub view_from_world: [[f32; 4]; 4],
    pub world_from_view: [[f32; 4]; 4],
    pub size: [f32; 4],
    pub projection: [f32; 4],
    pub flags: [u32; 4],
    pub pad: [f32; 4],
}

impl LayerView {
    fn new(camera: &Camera, size: (u32, u32), bounds: Aabb, flags: [u32; 4]) -> Self {
        let m = crate::frame::CameraMatrices::new(camera, size, bounds);
        LayerView {
            clip_from_world: m.clip_from_world().to_cols_array_2d(),
            view_from_world: m.view_from_world.to_cols_array_2d(),
            world_from_view: m.view_from_world.inverse().to_cols_array_2d(),
            size: [
                size.0 as f32,
                size.1 as f32,
                1.0 / size.0 as f32,
                1.0 / size.1 as f32,
            ],
            projection: [
                m.near,
                m.far,
                size.0 as f32 / size.1 as f32,
                (0.5 * camera.yfov).tan(),
            ],
            flags,
            pad: [0.0; 4],
        }
    }
}

/// The additional cameras of `main` (see the module documentation).
pub fn camera_views(main: &Camera, bounds: Aabb, settings: &LayerSettings) -> Vec<Camera> {
    let back = -main.forward();
    let right = main.up.cross(back).normalize_or(Vec3::X);
    let up = back.cross(right);
    let radius = if bounds.is_empty() {
        1.0
    } else {
        bounds.radius()
    };
    CAMERA_DIRECTIONS[..settings.cameras as usize]
        .iter()
        .map(|d| {
            let d = Vec3::from(*d).normalize();
            let offset = (right * d.x + up * d.y + back * d.z) * (settings.camera_spread * radius);
            let mut c = Camera {
                eye: main.eye + offset,
                ..*main
            };
            if c.forward().cross(c.up).length() < 1e-3 {
                c.up = right;
            }
            c
        })
        .collect()
}

/// One set of layer images (an array texture per attribute).
struct LayerImages {
    normal: wgpu::Texture,
    albedo: wgpu::Texture,
    emissive: wgpu::Texture,
    depth: wgpu::Texture,
    radiance: wgpu::Texture,
    /// Per layer: normal, albedo, emissive, view depth render views.
    attachments: Vec<[wgpu::TextureView; 4]>,
    size: (u32, u32),
    count: u32,
}

fn array_view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}

fn layer_view(t: &wgpu::Texture, layer: u32) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    })
}

impl LayerImages {
    fn new(device: &wgpu::Device, label: &str, size: (u32, u32), count: u32) -> Self {
        let make = |what: &str, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(&format!("{label} {what}")),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: count.max(1),
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        use wgpu::TextureUsages as U;
        let raster = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
        let normal = make("normal", targets::NORMAL_FORMAT, raster);
        let albedo = make("albedo", targets::ALBEDO_FORMAT, raster);
        let emissive = make("emissive", targets::EMISSIVE_FORMAT, raster);
        let depth = make("view depth", targets::VIEW_DEPTH_FORMAT, raster);
        let radiance = make(
            "radiance",
            targets::HDR_FORMAT,
            U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC,
        );
        let attachments = (0..count)
            .map(|k| {
                [
                    layer_view(&normal, k),
                    layer_view(&albedo, k),
                    layer_view(&emissive, k),
                    layer_view(&depth, k),
                ]
            })
            .collect();
        LayerImages {
            normal,
            albedo,
            emissive,
            depth,
            radiance,
            attachments,
            size,
            count,
        }
    }
}

/// `ShadeParams` in layers.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct ShadeParams {
    /// Index in the views buffer of this set's first layer.
    first_view: u32,
    count: u32,
    _pad: [u32; 2],
}

/// The peeled layers and additional cameras of one technique, with everything to draw them.
pub struct LayerStack {
    pub settings: LayerSettings,
    peel: LayerImages,
    cams: LayerImages,
    views: wgpu::Buffer,
    bounds: Aabb,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    main_size: (u32, u32),
    /// Depth buffers: two at the main size (peeling ping-pong), one at the camera size.
    _depth_textures: Vec<wgpu::Texture>,
    peel_depth: [wgpu::TextureView; 2],
    cam_depth: wgpu::TextureView,
    raster: wgpu::RenderPipeline,
    /// Per peeled layer (reading the depth of the layer before), then one for the cameras.
    raster_groups: Vec<wgpu::BindGroup>,
    shade: wgpu::ComputePipeline,
    shade_groups: [wgpu::BindGroup; 2],
    // Views the bindings hand out.
    peel_views: [wgpu::TextureView; 3],
    cam_views: [wgpu::TextureView; 3],
}

fn depth_texture(device: &wgpu::Device, size: (u32, u32), label: &str) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: targets::DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

/// Shader text of the shading pass.
pub fn source() -> String {
    util::compose(&[util::COMMON_WGSL, util::ENV_WGSL, util::LIGHTS_WGSL, SHADER])
}

/// The `--set` keys of [`LayerSettings`], for the tables of the techniques that take them.
pub const SETTINGS: [Setting; 4] = [
    Setting::choice(
        "layers",
        &["1", "2", "4"],
        "1",
        "depth layers in the blocker test (depth peeling)",
    ),
    Setting::integer(
        "cameras",
        0.0,
        4.0,
        "0",
        "additional cameras in the blocker test",
    ),
    Setting::integer(
        "camera_scale",
        1.0,
        8.0,
        "2",
        "resolution divisor of the additional cameras",
    ),
    Setting::number(
        "camera_spread",
        0.0,
        4.0,
        "0.5",
        "camera displacement (× scene bounding radius)",
    ),
];

/// Parses and checks the settings every technique with the shared blocker test takes
/// (`layers`, `cameras`, `camera_scale`, `camera_spread`); `Ok(false)` for other keys.
pub fn parse_setting(s: &mut LayerSettings, key: &str, v: &str) -> Result<bool, String> {
    use crate::technique::{parse_integer, parse_number};
    match key {
        "layers" => {
            let n = parse_integer(key, v, 1, MAX_LAYERS)?;
            if n == 3 {
                return Err(
                    "layers=3: expected 1, 2 or 4 (layers come in entry/exit pairs)".into(),
                );
            }
            s.layers = n;
        }
        "cameras" => s.cameras = parse_integer(key, v, 0, MAX_CAMERAS)?,
        "camera_scale" => s.camera_scale = parse_integer(key, v, 1, 8)?,
        "camera_spread" => s.camera_spread = parse_number(key, v, 0.0, 4.0)?,
        _ => return Ok(false),
    }
    Ok(true)
}

impl LayerStack {
    pub fn new(
        device: &wgpu::Device,
        targets: &FrameTargets,
        scene: &GpuScene,
        env: &GpuEnvironment,
        shadows: &ShadowPass,
        frame: &wgpu::Buffer,
        settings: LayerSettings,
    ) -> Self {
        let main_size = targets.size;
        let peel_count = settings.layers.saturating_sub(1);
        let peel_size = if peel_count > 0 { main_size } else { (1, 1) };
        let cam_size = if settings.cameras > 0 {
            (
                (main_size.0 / settings.camera_scale).max(1),
                (main_size.1 / settings.camera_scale).max(1),
            )
        } else {
            (1, 1)
        };
        let peel = LayerImages::new(device, "peeled layers", peel_size, peel_count);
        let cams = LayerImages::new(device, "camera layers", cam_size, settings.cameras);
        let depth_textures = vec![
            depth_texture(device, peel_size, "peel depth a"),
            depth_texture(device, peel_size, "peel depth b"),
            depth_texture(device, cam_size, "camera depth"),
        ];
        let dv = |t: &wgpu::Texture| t.create_view(&Default::default());
        let peel_depth = [dv(&depth_textures[0]), dv(&depth_textures[1])];
        let cam_depth = dv(&depth_textures[2]);
        let views = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("layer views"),
            contents: &vec![0u8; (VIEW_STRIDE * (CAMERA_VIEW_BASE + MAX_CAMERAS) as u64) as usize],
            usage: wgpu::BufferUsages::UNIFORM
                | wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST,
        });

        // Raster: vs_layer / fs_layer of gbuffer.wgsl, no culling.
        use wgpu::ShaderStages as S;
        let raster_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("layers raster"),
            entries: &[
                util::storage_buffer(1, S::FRAGMENT),
                util::texture_array(2, S::FRAGMENT),
                util::texture_array(3, S::FRAGMENT),
                util::sampler(4, S::FRAGMENT),
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: S::VERTEX | S::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: wgpu::BufferSize::new(VIEW_STRIDE),
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    visibility: S::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let raster_group = |prev: &wgpu::TextureView| {
            util::bind_group(
                device,
                "layers raster",
                &raster_layout,
                &[
                    (1, scene.materials.as_entire_binding()),
                    (2, R::TextureView(&scene.srgb_textures)),
                    (3, R::TextureView(&scene.linear_textures)),
                    (4, R::Sampler(&scene.material_sampler)),
                    (
                        5,
                        R::Buffer(wgpu::BufferBinding {
                            buffer: &views,
                            offset: 0,
                            size: wgpu::BufferSize::new(VIEW_STRIDE),
                        }),
                    ),
                    (6, R::TextureView(prev)),
                ],
            )
        };
        // Layer 2 reads the G-buffer's depth, layer 3 depth a, layer 4 depth b; cameras read
        // nothing (any depth view will do).
        let raster_groups = vec![
            raster_group(&targets.depth.view),
            raster_group(&peel_depth[0]),
            raster_group(&peel_depth[1]),
            raster_group(&targets.depth.view),
        ];
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("layers raster"),
            source: wgpu::ShaderSource::Wgsl(gbuffer::source().into()),
        });
        let raster = util::raster_pipeline(
            device,
            &util::RasterPipeline {
                label: "layers raster",
                layout: &raster_layout,
                module: &module,
                vertex: "vs_layer",
                fragment: "fs_layer",
                color_formats: &[
                    targets::NORMAL_FORMAT,
                    targets::ALBEDO_FORMAT,
                    targets::EMISSIVE_FORMAT,
                    targets::VIEW_DEPTH_FORMAT,
                ],
                cull: None,
                depth_bias: Default::default(),
            },
        );

        // Shading: direct radiance of every layer texel.
        let c = S::COMPUTE;
        let mut entries = vec![
            util::uniform(0, c),
            util::storage_buffer(40, c),
            util::uniform(50, c),
            util::texture_array(51, c),
            util::texture_array(52, c),
            util::texture_array(53, c),
            wgpu::BindGroupLayoutEntry {
                binding: 54,
                visibility: c,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 55,
                visibility: c,
                ty: wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: targets::HDR_FORMAT,
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                },
                count: None,
            },
        ];
        entries.extend(GpuEnvironment::layout_entries());
        entries.extend(ShadowPass::layout_entries());
        let shade_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("layers shade"),
            entries: &entries,
        });
        let peel_views = [
            array_view(&peel.normal),
            array_view(&peel.depth),
            array_view(&peel.radiance),
        ];
        let cam_views = [
            array_view(&cams.normal),
            array_view(&cams.depth),
            array_view(&cams.radiance),
        ];
        let shade_group = |images: &LayerImages, first_view: u32| {
            let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("layers shade params"),
                contents: bytemuck::bytes_of(&ShadeParams {
                    first_view,
                    count: images.count,
                    _pad: [0; 2],
                }),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let normal = array_view(&images.normal);
            let albedo = array_view(&images.albedo);
            let emissive = array_view(&images.emissive);
            let depth = array_view(&images.depth);
            let radiance = array_view(&images.radiance);
            let mut res = vec![
                (0, frame.as_entire_binding()),
                (40, views.as_entire_binding()),
                (50, params.as_entire_binding()),
                (51, R::TextureView(&normal)),
                (52, R::TextureView(&albedo)),
                (53, R::TextureView(&emissive)),
                (54, R::TextureView(&depth)),
                (55, R::TextureView(&radiance)),
            ];
            res.extend(env.bindings());
            res.extend(shadows.bindings(scene));
            util::bind_group(device, "layers shade", &shade_layout, &res)
        };
        let shade_groups = [shade_group(&peel, 0), shade_group(&cams, CAMERA_VIEW_BASE)];
        let shade =
            util::compute_pipeline(device, "layers shade", &source(), "shade", &shade_layout);
        LayerStack {
            settings,
            peel,
            cams,
            views,
            bounds: scene.bounds,
            vertices: scene.vertices.clone(),
            indices: scene.indices.clone(),
            index_count: scene.index_count,
            main_size,
            _depth_textures: depth_textures,
            peel_depth,
            cam_depth,
            raster,
            raster_groups,
            shade,
            shade_groups,
            peel_views,
            cam_views,
        }
    }

    /// Writes this frame's views (the main camera for peeling, the additional cameras).
    pub fn prepare(&self, queue: &wgpu::Queue, camera: &Camera) {
        if !self.settings.active() {
            return;
        }
        let mut data = vec![LayerView::zeroed(); (CAMERA_VIEW_BASE + MAX_CAMERAS) as usize];
        for k in 0..CAMERA_VIEW_BASE {
            // Layers 2 and 4 (k = 0, 2) are exits.
            let exit = (k % 2 == 0) as u32;
            data[k as usize] = LayerView::new(camera, self.main_size, self.bounds, [1, exit, 0, 0]);
        }
        for (c, view) in camera_views(camera, self.bounds, &self.settings)
            .iter()
            .enumerate()
        {
            data[CAMERA_VIEW_BASE as usize + c] =
                LayerView::new(view, self.cams.size, self.bounds, [0, 0, 0, 0]);
        }
        let mut bytes = Vec::with_capacity(data.len() * VIEW_STRIDE as usize);
        for v in &data {
            bytes.extend_from_slice(bytemuck::bytes_of(v));
        }
        queue.write_buffer(&self.views, 0, &bytes);
    }

    /// Records the peeling passes ("depth peeling"), the additional cameras ("extra cameras")
    /// and the shading of both ("layer shading"). Nothing when the settings ask for none.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, profiler: &mut GpuProfiler) {
        let draw = |encoder: &mut wgpu::CommandEncoder,
                    profiler: &mut GpuProfiler,
                    label: &'static str,
                    (first, last): (bool, bool),
                    attachments: &[wgpu::TextureView; 4],
                    depth: &wgpu::TextureView,
                    group: &wgpu::BindGroup,
                    view: u32| {
            let clear = |view| {
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
            let colors = [
                clear(&attachments[0]),
                clear(&attachments[1]),
                clear(&attachments[2]),
                clear(&attachments[3]),
            ];
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &colors,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: profiler.render_group(label, first, last),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.raster);
            pass.set_bind_group(0, group, &[(view as u64 * VIEW_STRIDE) as u32]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        };
        let n = self.peel.count;
        for k in 0..n {
            draw(
                encoder,
                profiler,
                "depth peeling",
                (k == 0, k + 1 == n),
                &self.peel.attachments[k as usize],
                &self.peel_depth[(k % 2) as usize],
                &self.raster_groups[k as usize],
                k,
            );
        }
        let m = self.cams.count;
        for c in 0..m {
            draw(
                encoder,
                profiler,
                "extra cameras",
                (c == 0, c + 1 == m),
                &self.cams.attachments[c as usize],
                &self.cam_depth,
                &self.raster_groups[3],
                CAMERA_VIEW_BASE + c,
            );
        }
        if n + m == 0 {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("layer shading"),
            timestamp_writes: profiler.compute("layer shading"),
        });
        pass.set_pipeline(&self.shade);
        for (images, group) in [
            (&self.peel, &self.shade_groups[0]),
            (&self.cams, &self.shade_groups[1]),
        ] {
            if images.count == 0 {
                continue;
            }
            let (gx, gy) = util::groups_8x8(images.size);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(gx, gy, images.count);
        }
    }

    /// Layout entries 40..=44 (views, peeled and camera normals and depths) of passes that
    /// include shaders/screen_samples.wgsl, and 45, 46 (peeled and camera radiance) where
    /// `radiance`.
    pub fn layout_entries(radiance: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
        let c = wgpu::ShaderStages::COMPUTE;
        let unfilterable = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: c,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2Array,
                multisampled: false,
            },
            count: None,
        };
        let mut e = vec![
            util::storage_buffer(40, c),
            util::texture_array(41, c),
            unfilterable(42),
            util::texture_array(43, c),
            unfilterable(44),
        ];
        if radiance {
            e.extend([util::texture_array(45, c), util::texture_array(46, c)]);
        }
        e
    }

    /// Bindings matching [`Self::layout_entries`].
    pub fn bindings(&self, radiance: bool) -> Vec<(u32, wgpu::BindingResource<'_>)> {
        let mut b = vec![
            (40, self.views.as_entire_binding()),
            (41, R::TextureView(&self.peel_views[0])),
            (42, R::TextureView(&self.peel_views[1])),
            (43, R::TextureView(&self.cam_views[0])),
            (44, R::TextureView(&self.cam_views[1])),
        ];
        if radiance {
            b.extend([
                (45, R::TextureView(&self.peel_views[2])),
                (46, R::TextureView(&self.cam_views[2])),
            ]);
        }
        b
    }
}

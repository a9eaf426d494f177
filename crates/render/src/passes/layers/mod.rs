//! Extra layers for the screen-space blocker test (SSDO paper Sec. 4): depth peeling of the main
//! view and additional cameras, each with normal, albedo, emission, view depth and the direct
//! radiance of what it sees (layers/shade.wgsl).
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
//!   (1/π) Σ E_l with shadow maps) + emission — the sender radiance of `indirect-irradiance`
//!   (docs/src/aovs.md), for bounces from peeled and off-screen geometry.
//!
//! Views in `views` (one 256-byte [`LayerView`] each): 0..=2 the peeled layers 2..=4, 3..=6 the
//! cameras. The blocker test that reads them is `occlusion()` in technique/samples.wgsl.

use super::FrameGroup;
use crate::bindings::PassLayout;
use crate::contract::io::{NearFieldInputs, SceneInputs};
use crate::profiler::GpuProfiler;
use crate::targets;
use crate::util;
use bytemuck::Zeroable;
use glam::Vec3;
use nearfield_scene::{Aabb, Camera};
use wgpu::util::DeviceExt;

pub mod draw;
pub mod peel;
pub mod shade;

use draw::LayerDrawing;
pub use peel::{PeelBindings, peel_source};
pub use shade::{ShadeBindings, ShadeParams, source};

pub use crate::settings::layers::{LayerSettings, MAX_CAMERAS, MAX_LAYERS};
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

crate::gpu_struct! {
    /// `LayerView` in shaders/common.wgsl.
    pub struct LayerView {
        pub clip_from_world: [[f32; 4]; 4],
        pub view_from_world: [[f32; 4]; 4],
        pub world_from_view: [[f32; 4]; 4],
        /// Width, height (pixels) and their inverses.
        pub size: [f32; 2],
        pub inv_size: [f32; 2],
        /// Near and far plane (m), aspect, tan(yfov/2).
        pub near: f32,
        pub far: f32,
        pub aspect: f32,
        pub tan_half_fov: f32,
        /// 1: peel against the layer before.
        pub peel: u32,
        /// 1: an exit layer (normal stored facing away from the camera).
        pub exit: u32,
        /// 1: keep a single-sided back face behind the G-buffer's layer however close it lies
        /// ([`LayerStack::back_faces_exit`]).
        pub after_front: u32,
        pub _pad1: u32,
        pub _pad2: [f32; 4],
    }
}

impl LayerView {
    /// The view of `camera` at `size`; `peel`: peel against the layer before; `exit`: an exit
    /// layer.
    fn new(camera: &Camera, size: (u32, u32), bounds: Aabb, peel: bool, exit: bool) -> Self {
        let m = crate::frame::CameraMatrices::new(camera, size, bounds);
        LayerView {
            clip_from_world: m.clip_from_world().to_cols_array_2d(),
            view_from_world: m.view_from_world.to_cols_array_2d(),
            world_from_view: m.view_from_world.inverse().to_cols_array_2d(),
            size: [size.0 as f32, size.1 as f32],
            inv_size: [1.0 / size.0 as f32, 1.0 / size.1 as f32],
            near: m.near,
            far: m.far,
            aspect: size.0 as f32 / size.1 as f32,
            tan_half_fov: (0.5 * camera.yfov).tan(),
            peel: peel as u32,
            exit: exit as u32,
            after_front: 0,
            _pad1: 0,
            _pad2: [0.0; 4],
        }
    }
}

/// Additional camera `c` of `main`.
pub fn camera_view(main: &Camera, bounds: Aabb, settings: &LayerSettings, c: u32) -> Camera {
    let back = -main.forward();
    let right = main.up.cross(back).normalize_or(Vec3::X);
    let up = back.cross(right);
    let radius = if bounds.is_empty() {
        1.0
    } else {
        bounds.radius()
    };
    let d = Vec3::from(CAMERA_DIRECTIONS[c as usize]).normalize();
    let offset = (right * d.x + up * d.y + back * d.z) * (settings.camera_spread * radius);
    let mut cam = Camera {
        eye: main.eye + offset,
        ..*main
    };
    if cam.forward().cross(cam.up).length() < 1e-3 {
        cam.up = right;
    }
    cam
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

/// What the blocker test binds of the extra layers, under these names (technique/samples.wgsl,
/// senders.wgsl).
#[derive(Clone, Copy)]
pub struct LayerResources<'a> {
    /// `array<LayerView>`: views 0..2 = peeled layers 2..4, 3..6 = additional cameras.
    pub layer_views: &'a wgpu::Buffer,
    /// Peeled layers' normals (rgba16float array, oriented).
    pub peel_normal: &'a wgpu::TextureView,
    /// Peeled layers' view depths (r32float array).
    pub peel_depth: &'a wgpu::TextureView,
    /// Additional cameras' normals (rgba16float array).
    pub cam_normal: &'a wgpu::TextureView,
    /// Additional cameras' view depths (r32float array).
    pub cam_depth: &'a wgpu::TextureView,
    /// Peeled layers' direct radiance (rgba16float array).
    pub peel_radiance: &'a wgpu::TextureView,
    /// Additional cameras' direct radiance (rgba16float array).
    pub cam_radiance: &'a wgpu::TextureView,
}

/// The peeled layers and additional cameras of one technique, with everything to draw them.
pub struct LayerStack {
    pub settings: LayerSettings,
    /// Shade the layers (their direct radiance, for bounces); off where only their depth is
    /// read (vbgi's thickness). On by default.
    pub shade: bool,
    /// Take a single-sided back face behind the G-buffer's layer as the second layer however
    /// close it lies (peel.wgsl): the exit through a solid's outermost pixel, which the
    /// re-rasterization tolerance drops where R spans few pixels. Off by default (vbgi's
    /// `resolution=half`; the book, vbgi, "Half resolution").
    pub back_faces_exit: bool,
    peel: LayerImages,
    cams: LayerImages,
    views: wgpu::Buffer,
    bounds: Aabb,
    main_size: (u32, u32),
    /// Depth buffers: two at the main size (peeling ping-pong), one at the camera size.
    _depth_textures: Vec<wgpu::Texture>,
    peel_depth: [wgpu::TextureView; 2],
    cam_depth: wgpu::TextureView,
    /// What draws and shades the layers; `None` when the settings ask for none.
    draw: Option<LayerDrawing>,
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

/// The binding declarations the reflection test checks.
pub fn pass_layouts() -> Vec<PassLayout> {
    let mut v = peel::pass_layouts();
    v.push(shade::pass_layout());
    v
}

impl LayerStack {
    pub fn new(
        device: &wgpu::Device,
        inputs: &NearFieldInputs,
        scene: Option<SceneInputs>,
        frame: &FrameGroup,
        settings: LayerSettings,
    ) -> Result<Self, String> {
        let main_size = inputs.size;
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
        let draw = if settings.active() {
            let need =
                "depth peeling and additional cameras need nearfield's scene and the depth buffer";
            let (Some(SceneInputs { scene, lights }), Some(gbuffer_depth)) = (scene, inputs.depth)
            else {
                return Err(need.into());
            };
            Some(LayerDrawing::new(
                device,
                frame,
                scene,
                lights,
                (&peel, &cams),
                &views,
                gbuffer_depth,
                &peel_depth,
            ))
        } else {
            None
        };
        Ok(LayerStack {
            settings,
            shade: true,
            back_faces_exit: false,
            peel,
            cams,
            views,
            bounds: scene.map_or(Aabb::EMPTY, |s| s.scene.bounds),
            main_size,
            _depth_textures: depth_textures,
            peel_depth,
            cam_depth,
            draw,
            peel_views,
            cam_views,
        })
    }

    /// Writes this frame's views (the main camera for peeling, the additional cameras).
    pub fn prepare(&self, queue: &wgpu::Queue, camera: &Camera) {
        if !self.settings.active() {
            return;
        }
        // One LayerView is one VIEW_STRIDE: the array is the buffer's contents as they are.
        const _: () = assert!(std::mem::size_of::<LayerView>() == VIEW_STRIDE as usize);
        let mut data = [LayerView::zeroed(); (CAMERA_VIEW_BASE + MAX_CAMERAS) as usize];
        for k in 0..CAMERA_VIEW_BASE {
            // Layers 2 and 4 (k = 0, 2) are exits.
            let exit = k % 2 == 0;
            data[k as usize] = LayerView {
                after_front: (k == 0 && self.back_faces_exit) as u32,
                ..LayerView::new(camera, self.main_size, self.bounds, true, exit)
            };
        }
        for c in 0..self.settings.cameras {
            let view = camera_view(camera, self.bounds, &self.settings, c);
            data[(CAMERA_VIEW_BASE + c) as usize] =
                LayerView::new(&view, self.cams.size, self.bounds, false, false);
        }
        queue.write_buffer(&self.views, 0, bytemuck::cast_slice(&data));
    }

    /// Records the peeling passes ("depth peeling"), the additional cameras ("extra cameras")
    /// and the shading of both ("layer shading"). Nothing when the settings ask for none.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, profiler: &mut GpuProfiler) {
        let Some(d) = &self.draw else { return };
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
            pass.set_pipeline(&d.raster);
            pass.set_bind_group(1, group, &[(view as u64 * VIEW_STRIDE) as u32]);
            pass.set_vertex_buffer(0, d.vertices.slice(..));
            pass.set_index_buffer(d.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..d.index_count, 0, 0..1);
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
                &d.raster_groups[k as usize],
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
                &d.raster_groups[3],
                CAMERA_VIEW_BASE + c,
            );
        }
        if n + m == 0 || !self.shade {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("layer shading"),
            timestamp_writes: profiler.compute("layer shading"),
        });
        for (images, group) in [
            (&self.peel, &d.shade_groups[0]),
            (&self.cams, &d.shade_groups[1]),
        ] {
            if images.count == 0 {
                continue;
            }
            let (gx, gy) = util::groups_8x8(images.size);
            d.shade.dispatch(&mut pass, group, (gx, gy, images.count));
        }
    }

    /// The layer images a pass that includes technique/samples.wgsl (and senders.wgsl) binds.
    pub fn resources(&self) -> LayerResources<'_> {
        LayerResources {
            layer_views: &self.views,
            peel_normal: &self.peel_views[0],
            peel_depth: &self.peel_views[1],
            cam_normal: &self.cam_views[0],
            cam_depth: &self.cam_views[1],
            peel_radiance: &self.peel_views[2],
            cam_radiance: &self.cam_views[2],
        }
    }
}

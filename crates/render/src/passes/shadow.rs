//! Shadow maps for every punctual light (raster, depth only), sampled with PCF in
//! direct_lighting.wgsl.
//!
//! Layout: one depth32float 2D array of `size`² layers. A directional light takes one layer
//! (orthographic, fitted to the scene's bounding sphere; a disc light — the environment's sun —
//! fitted each frame to the part of the view frustum inside that sphere, snapped to whole
//! texels so that shadows do not crawl as the camera moves), a spot light one (perspective over its
//! outer cone plus a margin, capped at 160°), a point light six (90° faces ±X, ±Y, ±Z). At most
//! [`ShadowSettings::max_layers`] layers are allocated; lights beyond get no shadow (logged).
//! A layer is drawn on the first frame and again only when its projection changed or an object
//! moved ([`ShadowPass::moved`]; docs/src/scenes.md, "Lighting details").
//!
//! Biases (documented, fixed):
//! - slope-scaled rasterizer bias: constant 2, slope 2.0 (in the depth format's units), against
//!   acne on surfaces at grazing angles to the light;
//! - receiver normal offset: the shaded point moves along its normal by
//!   [`ShadowSettings::normal_offset_texels`] shadow-map texels (world size of a texel at that
//!   point) before the lookup, against acne on curved and lit-at-grazing surfaces. Both shift
//!   shadows by about a texel: contact shadows start that much late.

use crate::bindings::{PassLayout, kind};
use crate::contract::formats::DEPTH_FORMAT;
pub use crate::contract::lights::{LightResources, NoLights};
use crate::gpu_scene::GpuScene;
use crate::profiler::GpuProfiler;
use crate::util;
use glam::{Mat4, Vec3};
use nearfield_scene::{Aabb, Camera, LightKind};
use std::sync::atomic::{AtomicBool, Ordering};
use wgpu::util::DeviceExt;

pub const SHADER: &str = include_str!("shadow.wgsl");

/// The shadow pass's WGSL as compiled.
pub fn source() -> String {
    util::compose(&[util::GPU_MATERIAL_WGSL, SHADER])
}

/// Shadow-map settings.
#[derive(Clone, Copy, Debug)]
pub struct ShadowSettings {
    /// Side of each shadow map (texels), 256..=8192. Default 2048.
    pub size: u32,
    /// Most layers (a point light uses six). Default 24.
    pub max_layers: u32,
    /// Receiver offset along the normal (shadow-map texels), 0..=8. Default 1.5.
    pub normal_offset_texels: f32,
}

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings {
            size: 2048,
            max_layers: 24,
            normal_offset_texels: 1.5,
        }
    }
}

/// Uniform stride of a layer's matrix (the dynamic-offset alignment every device accepts).
const VIEW_STRIDE: u64 = 256;

crate::bind_group! {
    /// Group 1 of the shadow pass (group 0 is not read).
    pub struct ShadowBindings: VERTEX | FRAGMENT {
        /// `ShadowView`: one layer's light_clip_from_world, at a dynamic offset per layer.
        view: buffer_range = kind::uniform_dynamic(64),
        /// The scene's materials (alpha-masked ones cast leaf-shaped shadows).
        materials: buffer = kind::STORAGE_READ,
        /// Base-colour textures (rgba8unorm-srgb array).
        srgb_textures: view = kind::TEXTURE_ARRAY,
        material_sampler: sampler = kind::SAMPLER,
    }
}

/// The binding declarations the reflection test checks (vertex and fragment stage).
pub fn pass_layouts() -> Vec<PassLayout> {
    PassLayout::entries(
        "shadow",
        source(),
        &["vs_main", "fs_main"],
        ShadowBindings::SLOTS,
    )
}

pub struct ShadowPass {
    /// The lights' kinds, in table order.
    kinds: Vec<LightKind>,
    bounds: Aabb,
    /// The last (camera, image size) a disc light's layer was fitted to.
    fitted_to: Option<(Camera, (u32, u32))>,
    /// Per layer: its projection, and whether the map holds what that projection sees. A layer
    /// is drawn again only when its projection changed (a disc light refitted to a moved
    /// camera, the sun turned) or an object moved.
    layer_matrices: Vec<Mat4>,
    drawn: Vec<AtomicBool>,
    view_buffer: wgpu::Buffer,
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    layer_views: Vec<wgpu::TextureView>,
    /// All layers as a D2Array view (for sampling).
    pub array_view: wgpu::TextureView,
    pub compare_sampler: wgpu::Sampler,
    /// light_clip_from_world per layer (storage buffer for the lighting pass).
    pub matrices: wgpu::Buffer,
    /// Per scene light: first layer (None = unshadowed) and texel size factor.
    pub light_layers: Vec<(Option<u32>, f32)>,
    pub settings: ShadowSettings,
    /// Profiler label of [`Self::encode`].
    label: &'static str,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
}

/// Shadow projections of one light, and its texel size factor (metres for orthographic,
/// metres per metre of distance for perspective layers). `view` (camera, image size): a disc
/// light's layer covers only what that camera sees ([`fit_square`]).
pub fn light_views(
    kind: &LightKind,
    bounds: Aabb,
    size: u32,
    view: Option<(&Camera, (u32, u32))>,
) -> (Vec<Mat4>, f32) {
    let center = bounds.center();
    let radius = bounds.radius().max(1e-3);
    let up_for = |d: Vec3| if d.y.abs() > 0.99 { Vec3::X } else { Vec3::Y };
    match *kind {
        LightKind::Directional {
            direction,
            angular_radius,
        } => {
            let eye = center - direction * (2.0 * radius);
            let light_view =
                glam::camera::rh::view::look_to_mat4(eye, direction, up_for(direction));
            let (cx, cy, half) = match view {
                Some((camera, image)) if angular_radius > 0.0 => {
                    fit_square(&light_view, camera, image, bounds, radius, size)
                }
                _ => (0.0, 0.0, radius),
            };
            let proj = glam::camera::rh::proj::directx::orthographic(
                cx - half,
                cx + half,
                cy - half,
                cy + half,
                0.5 * radius,
                3.5 * radius,
            );
            (vec![proj * light_view], 2.0 * half / size as f32)
        }
        LightKind::Spot {
            position,
            direction,
            outer_cone,
            ..
        } => {
            let fov = (2.0 * outer_cone + 4f32.to_radians()).min(160f32.to_radians());
            let far = (position - center).length() + radius;
            let view = glam::camera::rh::view::look_to_mat4(position, direction, up_for(direction));
            let proj = glam::camera::rh::proj::directx::perspective(fov, 1.0, far * 1e-4, far);
            (vec![proj * view], 2.0 * (0.5 * fov).tan() / size as f32)
        }
        LightKind::Point { position } => {
            let far = (position - center).length() + radius;
            let proj = glam::camera::rh::proj::directx::perspective(
                std::f32::consts::FRAC_PI_2,
                1.0,
                far * 1e-4,
                far,
            );
            let faces = [
                Vec3::X,
                Vec3::NEG_X,
                Vec3::Y,
                Vec3::NEG_Y,
                Vec3::Z,
                Vec3::NEG_Z,
            ];
            let views = faces
                .iter()
                .map(|&d| proj * glam::camera::rh::view::look_to_mat4(position, d, up_for(d)))
                .collect();
            (views, 2.0 / size as f32)
        }
    }
}

/// The square (centre x, y and half side, in light-view metres) of a directional light's map
/// that covers what `camera` sees of the scene: the view frustum from the camera's near to its
/// far plane around `bounds` (Camera::depth_range), projected along the light, intersected with
/// the scene's bounding sphere (radius `radius` about the light view's axis). The centre is
/// snapped to whole texels of a `size`-texel map.
fn fit_square(
    light_view: &Mat4,
    camera: &Camera,
    image: (u32, u32),
    bounds: Aabb,
    radius: f32,
    size: u32,
) -> (f32, f32, f32) {
    let (near, far) = camera.depth_range(bounds);
    let forward = camera.forward();
    let (w, h) = (image.0.max(1) as f32, image.1.max(1) as f32);
    let mut lo = glam::Vec2::splat(f32::INFINITY);
    let mut hi = glam::Vec2::splat(f32::NEG_INFINITY);
    for (px, py) in [(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)] {
        let ray = camera.ray_through(glam::Vec2::new(px, py), image);
        let along = ray.dot(forward).max(1e-6);
        for depth in [near, far] {
            let p = light_view.transform_point3(camera.eye + ray * (depth / along));
            lo = lo.min(p.truncate());
            hi = hi.max(p.truncate());
        }
    }
    let lo = lo.max(glam::Vec2::splat(-radius));
    let hi = hi.min(glam::Vec2::splat(radius));
    if !(lo.x < hi.x && lo.y < hi.y) {
        return (0.0, 0.0, radius);
    }
    let half = (0.5 * (hi - lo).max_element()).clamp(1e-3 * radius, radius);
    let texel = 2.0 * half / size as f32;
    let centre = (0.5 * (lo + hi) / texel).round() * texel;
    (centre.x, centre.y, half)
}

/// The shadow-map layers of each light (its first layer, `None` past `settings.max_layers`,
/// and its texel factor) and every layer's clip_from_world.
#[allow(clippy::type_complexity)]
fn allocate_layers(
    scene: &GpuScene,
    kinds: &[LightKind],
    settings: ShadowSettings,
) -> (Vec<Mat4>, Vec<(Option<u32>, f32)>) {
    let mut matrices: Vec<Mat4> = Vec::new();
    let mut light_layers = Vec::new();
    let mut dropped = 0;
    for kind in kinds {
        let (views, texel) = light_views(kind, scene.bounds, settings.size, None);
        if matrices.len() + views.len() > settings.max_layers as usize {
            light_layers.push((None, texel));
            dropped += 1;
            continue;
        }
        light_layers.push((Some(matrices.len() as u32), texel));
        matrices.extend(views);
    }
    if dropped > 0 {
        log::warn!(
            "{dropped} light(s) get no shadow map: more than {} shadow layers",
            settings.max_layers
        );
    }
    (matrices, light_layers)
}

/// The layers' matrices as a storage array (what lighting reads) and as uniforms at a
/// `VIEW_STRIDE` stride (what each layer's draw reads at its dynamic offset); one identity
/// matrix where there is no layer.
fn matrix_buffers(device: &wgpu::Device, matrices: &[Mat4]) -> (wgpu::Buffer, wgpu::Buffer) {
    let flat: Vec<[[f32; 4]; 4]> = if matrices.is_empty() {
        vec![Mat4::IDENTITY.to_cols_array_2d()]
    } else {
        matrices.iter().map(|m| m.to_cols_array_2d()).collect()
    };
    let matrix_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("shadow matrices"),
        contents: bytemuck::cast_slice(&flat),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    });
    let mut strided = vec![0u8; VIEW_STRIDE as usize * flat.len()];
    for (i, m) in flat.iter().enumerate() {
        let at = i * VIEW_STRIDE as usize;
        strided[at..at + 64].copy_from_slice(bytemuck::bytes_of(m));
    }
    let view_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("shadow views"),
        contents: &strided,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    (matrix_buffer, view_buffer)
}

impl ShadowPass {
    /// Shadow maps of the scene's lights.
    pub fn new(device: &wgpu::Device, scene: &GpuScene, settings: ShadowSettings) -> Self {
        let kinds: Vec<LightKind> = scene.scene_lights.iter().map(|l| l.kind).collect();
        Self::for_lights(device, scene, &kinds, settings, "shadows")
    }

    /// Shadow maps of any lights (e.g. virtual point lights) over `scene`, timed as `label`.
    pub fn for_lights(
        device: &wgpu::Device,
        scene: &GpuScene,
        kinds: &[LightKind],
        settings: ShadowSettings,
        label: &'static str,
    ) -> Self {
        let (matrices, light_layers) = allocate_layers(scene, kinds, settings);
        let layers = matrices.len().max(1) as u32;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow maps"),
            size: wgpu::Extent3d {
                width: settings.size,
                height: settings.size,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let layer_views = (0..matrices.len() as u32)
            .map(|l| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: l,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let (matrix_buffer, view_buffer) = matrix_buffers(device, &matrices);
        let layout = ShadowBindings::layout(device);
        let bind_group = ShadowBindings {
            view: wgpu::BufferBinding {
                buffer: &view_buffer,
                offset: 0,
                size: wgpu::BufferSize::new(64),
            },
            materials: &scene.materials,
            srgb_textures: &scene.srgb_textures,
            material_sampler: &scene.material_sampler,
        }
        .bind_group(device, &layout);
        let module = crate::pipeline_cache::shader_module(device, "shadow", &source());
        // No culling: single-sided walls (open boxes) must still cast shadows.
        let pipeline = util::raster_pipeline(
            device,
            &util::RasterPipeline {
                label: "shadow",
                frame: None,
                layout: &layout,
                module: &module,
                vertex: "vs_main",
                fragment: "fs_main",
                color_formats: &[],
                cull: None,
                depth_bias: wgpu::DepthBiasState {
                    constant: 2,
                    slope_scale: 2.0,
                    clamp: 0.0,
                },
                vertex_buffers: &[Some(crate::gpu_scene::Vertex::LAYOUT)],
            },
        );
        let compare_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow compare"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        ShadowPass {
            kinds: kinds.to_vec(),
            bounds: scene.bounds,
            fitted_to: None,
            drawn: matrices.iter().map(|_| AtomicBool::new(false)).collect(),
            layer_matrices: matrices,
            view_buffer,
            pipeline,
            bind_group,
            layer_views,
            array_view,
            compare_sampler,
            matrices: matrix_buffer,
            light_layers,
            settings,
            label,
            vertices: scene.vertices.clone(),
            indices: scene.indices.clone(),
            index_count: scene.index_count,
        }
    }

    /// Fits the layers of disc lights to what `camera` sees at `image` size (a no-op without
    /// disc lights or when neither changed). Returns whether any light's texel factor changed:
    /// the light table must then be rewritten (`GpuScene::write_lights`).
    pub fn fit_to_view(&mut self, queue: &wgpu::Queue, camera: &Camera, image: (u32, u32)) -> bool {
        let disc = |k: &LightKind| matches!(k, LightKind::Directional { angular_radius, .. } if *angular_radius > 0.0);
        if !self.kinds.iter().any(disc) || self.fitted_to == Some((*camera, image)) {
            return false;
        }
        self.fitted_to = Some((*camera, image));
        let mut changed = false;
        for (i, kind) in self.kinds.iter().enumerate() {
            let (Some(layer), true) = (self.light_layers[i].0, disc(kind)) else {
                continue;
            };
            let (views, texel) =
                light_views(kind, self.bounds, self.settings.size, Some((camera, image)));
            changed |= self.light_layers[i].1 != texel;
            self.light_layers[i].1 = texel;
            if self.layer_matrices[layer as usize] == views[0] {
                continue;
            }
            self.layer_matrices[layer as usize] = views[0];
            self.drawn[layer as usize].store(false, Ordering::Relaxed);
            let m = views[0].to_cols_array_2d();
            queue.write_buffer(&self.matrices, layer as u64 * 64, bytemuck::bytes_of(&m));
            queue.write_buffer(
                &self.view_buffer,
                layer as u64 * VIEW_STRIDE,
                bytemuck::bytes_of(&m),
            );
        }
        changed
    }

    /// Replaces light `index`'s kind by another with the same number of layers (the sun after
    /// the environment turned); the next [`Self::fit_to_view`] refits it.
    pub fn set_light_kind(&mut self, index: usize, kind: LightKind) {
        if let Some(k) = self.kinds.get_mut(index) {
            *k = kind;
            self.fitted_to = None;
        }
    }

    /// The light bindings of a pass that includes shaders/lights.wgsl, with `table` as its
    /// light table (the scene's lights, or virtual point lights shadowed by this pass).
    pub fn light_resources<'a>(&'a self, table: &'a wgpu::Buffer) -> LightResources<'a> {
        LightResources {
            lights: table,
            shadow_clip_from_world: &self.matrices,
            shadow_maps: &self.array_view,
            shadow_sampler: &self.compare_sampler,
            shadow_depths: &self.array_view,
        }
    }

    /// Marks every layer stale: an object moved, so every map it may fall in is drawn again.
    pub fn moved(&self) {
        for d in &self.drawn {
            d.store(false, Ordering::Relaxed);
        }
    }

    /// Renders the layers whose projection changed since they were last drawn (all of them on
    /// the first frame; none while the camera and the lights stand still), timed together under
    /// the pass's label. The commands must be submitted: the layers count as drawn.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, profiler: &mut GpuProfiler) {
        let stale: Vec<usize> = (0..self.layer_views.len())
            .filter(|&i| !self.drawn[i].swap(true, Ordering::Relaxed))
            .collect();
        let n = stale.len();
        for (k, &i) in stale.iter().enumerate() {
            let view = &self.layer_views[i];
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow layer"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: profiler.render_group(self.label, k == 0, k + 1 == n),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(1, &self.bind_group, &[(i as u64 * VIEW_STRIDE) as u32]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
    }
}

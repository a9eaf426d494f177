//! Reflective shadow maps (Dachsbacher & Stamminger 2005): the scene seen from each light, with
//! the position, normal and base colour of every texel, read back once so that Instant
//! Radiosity (crate::vpl::radiosity_lights) can draw its virtual point lights from them.
//!
//! A light's views are its shadow-map projections (passes/shadow.rs `light_views`): one
//! orthographic view for a directional light, one perspective view for a spot light, six cube
//! faces for a point light. A texel receives the flux that crosses it: for perspective views
//! Φ_in = I(ω) Ω_texel with I(ω) = E_⊥(p) d² (cone and range included) and
//! Ω_texel = a² / (1 + u² + v²)^{3/2} (a the texel's side on the image plane at distance 1, (u, v)
//! its centre there); for orthographic views Φ_in = E_⊥ a² (a the texel's side in metres). The
//! surface reflects ρ Φ_in (Lambertian). The depth test makes Φ_in the flux of the light's first
//! hit, i.e. shadowed exactly.

use crate::bindings::{PassLayout, kind};
use crate::gpu_scene::GpuScene;
use crate::passes::shadow::light_views;
use crate::util;
use glam::Vec3;
use nearfield_scene::{Light, LightKind};
use wgpu::util::DeviceExt;

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// One lit texel of a reflective shadow map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RsmTexel {
    pub position: Vec3,
    /// Unit normal on the light's side.
    pub normal: Vec3,
    /// Reflected flux ρ Φ_in (W, RGB).
    pub flux: Vec3,
}

crate::gpu_struct! {
    /// `RsmView` in gbuffer.wgsl.
    pub struct RsmView {
        pub clip_from_world: [[f32; 4]; 4],
        pub to_light: [f32; 4],
    }
}

/// Flux of one texel crossing the view of `light` (before the surface's albedo): see the module
/// documentation. `texel` is the view's texel factor from `light_views`, (x, y) the texel.
pub fn incoming_flux(light: &Light, p: Vec3, texel: f32, size: u32, x: u32, y: u32) -> Vec3 {
    let e = light.normal_irradiance(p);
    match light.kind {
        LightKind::Directional { .. } => e * (texel * texel),
        LightKind::Point { position } | LightKind::Spot { position, .. } => {
            let half = 0.5 * size as f32;
            let u = (x as f32 + 0.5 - half) * texel;
            let v = (y as f32 + 0.5 - half) * texel;
            let omega = texel * texel / (1.0 + u * u + v * v).powf(1.5);
            e * (p - position).length_squared() * omega
        }
    }
}

pub const SHADER: &str = include_str!("rsm.wgsl");

pub fn source() -> String {
    util::compose(&[
        util::COMMON_WGSL,
        util::ENV_WGSL,
        util::FRAME_BINDINGS_WGSL,
        util::GPU_MATERIAL_WGSL,
        util::MATERIALS_WGSL,
        SHADER,
    ])
}

crate::bind_group! {
    /// Group 1 of the reflective-shadow-map pass (group 0 is not read).
    pub struct RsmBindings: VERTEX | FRAGMENT {
        /// The scene's materials (shaders/materials.wgsl).
        materials: buffer = kind::STORAGE_READ,
        srgb_textures: view = kind::TEXTURE_ARRAY,
        linear_textures: view = kind::TEXTURE_ARRAY,
        material_sampler: sampler = kind::SAMPLER,
        /// `RsmView`: the light's clip_from_world and where the light is.
        rsm_view: buffer = kind::UNIFORM,
    }
}

/// The binding declarations the reflection test checks (vertex and fragment stage).
pub fn pass_layouts() -> Vec<PassLayout> {
    PassLayout::entries("rsm", source(), &["vs_rsm", "fs_rsm"], RsmBindings::SLOTS)
}

/// Renders the reflective shadow maps (`size`² per view) of `lights` and returns their lit
/// texels (those with flux > 0).
pub fn render(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &GpuScene,
    lights: &[Light],
    size: u32,
) -> Vec<RsmTexel> {
    let maps = Maps::new(device, size);
    let mut texels = Vec::new();
    for light in lights {
        let (views, texel) = light_views(&light.kind, scene.bounds, size, None);
        let to_light = match light.kind {
            LightKind::Directional { direction, .. } => (-direction).extend(0.0),
            LightKind::Point { position } | LightKind::Spot { position, .. } => {
                position.extend(1.0)
            }
        };
        for clip_from_world in views {
            let view = RsmView {
                clip_from_world: clip_from_world.to_cols_array_2d(),
                to_light: to_light.to_array(),
            };
            let [positions, normals, albedos] = maps.draw(device, queue, scene, &view);
            for (i, ((p, n), a)) in positions.iter().zip(&normals).zip(&albedos).enumerate() {
                if p[3] == 0.0 {
                    continue;
                }
                let position = Vec3::from_slice(&p[..3]);
                let (x, y) = (i as u32 % size, i as u32 / size);
                let flux =
                    Vec3::from_slice(&a[..3]) * incoming_flux(light, position, texel, size, x, y);
                if flux.max_element() > 0.0 {
                    texels.push(RsmTexel {
                        position,
                        normal: Vec3::from_slice(&n[..3]).normalize_or_zero(),
                        flux,
                    });
                }
            }
        }
    }
    texels
}

/// The pipeline and the maps one view is drawn into: position, normal and albedo (and depth).
struct Maps {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    targets: [wgpu::Texture; 3],
    target_views: [wgpu::TextureView; 3],
    depth_view: wgpu::TextureView,
    _depth: wgpu::Texture,
}

impl Maps {
    fn new(device: &wgpu::Device, size: u32) -> Self {
        let layout = RsmBindings::layout(device);
        let module = crate::pipeline_cache::shader_module(device, "rsm", &source());
        let pipeline = util::raster_pipeline(
            device,
            &util::RasterPipeline {
                label: "rsm",
                frame: None,
                layout: &layout,
                module: &module,
                vertex: "vs_rsm",
                fragment: "fs_rsm",
                color_formats: &[FORMAT, FORMAT, FORMAT],
                cull: None,
                depth_bias: Default::default(),
                vertex_buffers: &[Some(crate::gpu_scene::Vertex::LAYOUT)],
            },
        );
        let texture = |label: &str, format: wgpu::TextureFormat, usage: wgpu::TextureUsages| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: size,
                    height: size,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let readable = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let targets = ["rsm position", "rsm normal", "rsm albedo"]
            .map(|label| texture(label, FORMAT, readable));
        let depth = texture(
            "rsm depth",
            crate::targets::DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        Maps {
            target_views: targets
                .each_ref()
                .map(|t| t.create_view(&Default::default())),
            depth_view: depth.create_view(&Default::default()),
            _depth: depth,
            targets,
            layout,
            pipeline,
        }
    }

    /// Draws the scene from `view` and reads the three maps back.
    fn draw(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        view: &RsmView,
    ) -> [Vec<[f32; 4]>; 3] {
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("rsm view"),
            contents: bytemuck::bytes_of(view),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let m = scene.material_bindings();
        let group = RsmBindings {
            materials: m.materials,
            srgb_textures: m.srgb_textures,
            linear_textures: m.linear_textures,
            material_sampler: m.material_sampler,
            rsm_view: &uniform,
        }
        .bind_group(device, &self.layout);
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let clear = wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                store: wgpu::StoreOp::Store,
            };
            let attachments = self.target_views.each_ref().map(|v| {
                Some(wgpu::RenderPassColorAttachment {
                    view: v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: clear,
                })
            });
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("rsm"),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(1, &group, &[]);
            pass.set_vertex_buffer(0, scene.vertices.slice(..));
            pass.set_index_buffer(scene.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..scene.index_count, 0, 0..1);
        }
        let read = |t: &wgpu::Texture, encoder| -> Vec<[f32; 4]> {
            let bytes = util::read_texture(device, queue, encoder, t, 16);
            bytemuck::pod_collect_to_vec(&bytes)
        };
        let empty = || device.create_command_encoder(&Default::default());
        [
            read(&self.targets[0], encoder),
            read(&self.targets[1], empty()),
            read(&self.targets[2], empty()),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The six cube faces of a point light of intensity I pass its whole flux 4π I.
    #[test]
    fn cube_faces_pass_a_point_lights_flux() {
        let light = Light {
            kind: LightKind::Point {
                position: Vec3::ZERO,
            },
            color: Vec3::ONE,
            intensity: 2.0,
            range: None,
        };
        let size = 64;
        let texel = 2.0 / size as f32;
        let mut face = 0.0f64;
        for y in 0..size {
            for x in 0..size {
                let p = Vec3::new(0.3, -0.2, 1.0);
                face += incoming_flux(&light, p, texel, size, x, y).x as f64;
            }
        }
        let truth = 4.0 * std::f64::consts::PI * 2.0;
        assert!((6.0 * face / truth - 1.0).abs() < 1e-3, "{}", 6.0 * face);
    }

    /// A directional light of E lux passes E a² through each texel of side a.
    #[test]
    fn orthographic_texels_pass_irradiance_times_area() {
        let light = Light {
            kind: LightKind::Directional {
                direction: Vec3::NEG_Y,
                angular_radius: 0.0,
            },
            color: Vec3::new(1.0, 0.5, 0.25),
            intensity: 4.0,
            range: None,
        };
        let f = incoming_flux(&light, Vec3::ZERO, 0.01, 256, 3, 200);
        assert!((f - light.color * 4.0 * 1e-4).abs().max_element() < 1e-9);
    }
}

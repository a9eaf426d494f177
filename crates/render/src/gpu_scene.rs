//! The scene on the GPU: one vertex and one index buffer for all meshes, the material table,
//! material textures as two 2D arrays, and the light table.

use crate::RenderError;
use glam::Vec3;
use nearfield_scene::{Aabb, AlphaMode, LightKind, Scene, TextureColorSpace};
use wgpu::util::DeviceExt;

pub use crate::vertex::Vertex;

crate::gpu_struct! {
    /// `GpuMaterial` in gbuffer.wgsl.
    pub struct GpuMaterial {
        pub base_color: [f32; 4],
        /// Emissive factor (strength applied).
        pub emissive: [f32; 3],
        /// Alpha cutoff (< 0: opaque).
        pub alpha_cutoff: f32,
        pub metallic: f32,
        pub roughness: f32,
        /// 1 on the meshes the far field's bake never saw (dynamic: the book, "Near and far"),
        /// 0 on the rest; the G-buffer's material target carries it.
        pub dynamic: f32,
        pub _pad1: f32,
        /// Layers of the base colour (sRGB array), metallic-roughness (linear array) and emissive
        /// (sRGB array) textures; [`NO_TEXTURE`] = none.
        pub base_color_texture: u32,
        pub metallic_roughness_texture: u32,
        pub emissive_texture: u32,
        pub _pad2: u32,
    }
}

crate::gpu_struct! {
    /// `GpuLight` in direct_lighting.wgsl.
    pub struct GpuLight {
        /// Position, or direction of travel (directional).
        pub position: [f32; 3],
        /// 0 directional, 1 point, 2 spot.
        pub kind: f32,
        /// Spot axis.
        pub direction: [f32; 3],
        /// Range (m), 0 = unlimited.
        pub range: f32,
        /// Colour × intensity.
        pub color: [f32; 3],
        /// tan of a directional disc light's angular radius (0: punctual): sizes its PCF.
        pub tan_radius: f32,
        /// cos of a spot's inner and outer cone angle.
        pub cos_inner: f32,
        pub cos_outer: f32,
        /// First shadow layer (−1: none) and the shadow texel size factor.
        pub shadow_layer: f32,
        pub shadow_texel: f32,
    }
}

pub const NO_TEXTURE: u32 = u32::MAX;

/// Largest material texture side kept on the GPU; larger textures are downsampled.
pub const MAX_TEXTURE_SIZE: u32 = 2048;

/// The scene's GPU buffers and textures.
pub struct GpuScene {
    pub vertices: wgpu::Buffer,
    /// The previous frame's vertex positions (the G-buffer's motion vectors): its own buffer
    /// where objects move, else `vertices` itself.
    pub previous: wgpu::Buffer,
    /// The moving objects and the scene's clock (`None`: nothing moves).
    pub moving: Option<crate::moving::MovingObjects>,
    pub indices: wgpu::Buffer,
    /// Index count of culled (single-sided) geometry; double-sided geometry follows it.
    pub single_sided_indices: u32,
    pub index_count: u32,
    pub materials: wgpu::Buffer,
    pub srgb_textures: wgpu::TextureView,
    pub linear_textures: wgpu::TextureView,
    pub material_sampler: wgpu::Sampler,
    pub lights: wgpu::Buffer,
    pub light_count: u32,
    /// The lights, in the order of `lights`: the scene's, then the environment's sun.
    pub scene_lights: Vec<nearfield_scene::Light>,
    /// How many lights `lights` holds at most.
    pub light_capacity: usize,
    pub bounds: Aabb,
    pub triangle_count: u32,
    /// Whether some mesh is dynamic (the far field's bake never saw it): its surfaces carry
    /// `GpuMaterial::dynamic`.
    pub has_dynamic: bool,
}

impl GpuScene {
    /// Uploads `scene` lit by `lights` (its own lights, and the environment's sun if split out;
    /// the table has room for one more light than `scene.lights`, for a sun that arrives with a
    /// later environment).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        lights: &[nearfield_scene::Light],
    ) -> Result<Self, RenderError> {
        // Geometry: single-sided meshes first, then double-sided ones.
        let mut vertices: Vec<Vertex> = Vec::new();
        let mut single: Vec<u32> = Vec::new();
        let mut double: Vec<u32> = Vec::new();
        let mut first = Vec::with_capacity(scene.meshes.len());
        // A dynamic mesh reads the second copy of the material table, whose `dynamic` is 1.
        let has_dynamic = scene.has_dynamic();
        let dynamic_base = if has_dynamic {
            scene.materials.len() as u32
        } else {
            0
        };
        for mesh in &scene.meshes {
            let base = vertices.len() as u32;
            first.push(base);
            for i in 0..mesh.positions.len() {
                vertices.push(Vertex {
                    position: mesh.positions[i].into(),
                    normal: mesh.normals[i].into(),
                    uv: mesh.uvs[i].into(),
                    material: mesh.material + if mesh.dynamic { dynamic_base } else { 0 },
                });
            }
            let target = if scene.materials[mesh.material as usize].double_sided {
                &mut double
            } else {
                &mut single
            };
            target.extend(mesh.indices.iter().flatten().map(|i| base + i));
        }
        let single_sided_indices = single.len() as u32;
        single.extend(double);
        let index_count = single.len() as u32;
        let moving = crate::moving::MovingObjects::new(scene, &vertices, &first);
        let vertex_buffer = |label| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&vertices),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            })
        };
        let (vertex_buffer, previous) = match moving {
            Some(_) => (
                vertex_buffer("scene vertices"),
                vertex_buffer("previous vertices"),
            ),
            None => {
                let v = vertex_buffer("scene vertices");
                (v.clone(), v)
            }
        };
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene indices"),
            contents: bytemuck::cast_slice(&single),
            usage: wgpu::BufferUsages::INDEX,
        });

        // Textures: one array per colour space, all layers resized to the largest size present.
        let mut layer_of = vec![NO_TEXTURE; scene.textures.len()];
        let mut arrays = Vec::new();
        for space in [TextureColorSpace::Srgb, TextureColorSpace::Linear] {
            let members: Vec<usize> = (0..scene.textures.len())
                .filter(|&i| scene.textures[i].color_space == space)
                .collect();
            for (layer, &i) in members.iter().enumerate() {
                layer_of[i] = layer as u32;
            }
            arrays.push(texture_array(device, queue, scene, &members, space)?);
        }
        let linear_textures = arrays.pop().unwrap();
        let srgb_textures = arrays.pop().unwrap();
        let layer = |t: Option<usize>| t.map(|i| layer_of[i]).unwrap_or(NO_TEXTURE);
        let copies = if has_dynamic { 2 } else { 1 };
        let materials: Vec<GpuMaterial> = (0..copies)
            .flat_map(|copy| scene.materials.iter().map(move |m| (copy, m)))
            .map(|(copy, m)| GpuMaterial {
                base_color: m.base_color.into(),
                emissive: m.emissive.into(),
                alpha_cutoff: match m.alpha_mode {
                    AlphaMode::Mask { cutoff } => cutoff,
                    _ => -1.0,
                },
                metallic: m.metallic,
                roughness: m.roughness,
                dynamic: copy as f32,
                _pad1: 0.0,
                base_color_texture: layer(m.base_color_texture),
                metallic_roughness_texture: layer(m.metallic_roughness_texture),
                emissive_texture: layer(m.emissive_texture),
                _pad2: NO_TEXTURE,
            })
            .collect();
        let material_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("materials"),
            contents: bytemuck::cast_slice(&materials),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let material_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("material sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let light_count = lights.len() as u32;
        let scene_lights = lights.to_vec();
        let capacity = (scene.lights.len() + 1).max(lights.len());
        let lights = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lights"),
            size: (std::mem::size_of::<GpuLight>() * capacity) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(GpuScene {
            vertices: vertex_buffer,
            previous,
            moving,
            indices: index_buffer,
            single_sided_indices,
            index_count,
            materials: material_buffer,
            srgb_textures,
            linear_textures,
            material_sampler,
            lights,
            light_count,
            scene_lights,
            light_capacity: capacity,
            bounds: scene.bounds_in_motion(),
            triangle_count: index_count / 3,
            has_dynamic,
        })
    }

    /// Poses the moving objects for the next frame ([`crate::moving::MovingObjects::advance`]):
    /// whether they moved.
    pub fn advance(&mut self, queue: &wgpu::Queue) -> bool {
        match &mut self.moving {
            Some(m) => m.advance(queue, &self.vertices, &self.previous),
            None => false,
        }
    }

    /// Writes the light table; `shadow` gives each light's first shadow layer and texel factor.
    pub fn write_lights(&self, queue: &wgpu::Queue, shadow: &[(Option<u32>, f32)]) {
        self.write_lights_masked(queue, shadow, &[]);
    }

    /// [`Self::write_lights`] with the lights whose `off` entry is true given no radiance.
    pub fn write_lights_masked(
        &self,
        queue: &wgpu::Queue,
        shadow: &[(Option<u32>, f32)],
        off: &[bool],
    ) {
        let lights: Vec<GpuLight> = self
            .scene_lights
            .iter()
            .zip(shadow)
            .enumerate()
            .map(|(i, (l, &(layer, texel)))| {
                let mut g = gpu_light(l, layer, texel);
                if off.get(i).copied().unwrap_or(false) {
                    g.color = [0.0; 3];
                }
                g
            })
            .collect();
        if !lights.is_empty() {
            queue.write_buffer(&self.lights, 0, bytemuck::cast_slice(&lights));
        }
    }
}

pub(crate) fn gpu_light(l: &nearfield_scene::Light, layer: Option<u32>, texel: f32) -> GpuLight {
    let c = l.color * l.intensity;
    let mut tan_radius = 0.0;
    let (pos, kind, dir, cones) = match l.kind {
        LightKind::Directional {
            direction,
            angular_radius,
        } => {
            tan_radius = angular_radius.clamp(0.0, 1.0).tan();
            (direction, 0.0, Vec3::ZERO, (1.0, 1.0))
        }
        LightKind::Point { position } => (position, 1.0, Vec3::ZERO, (1.0, 1.0)),
        LightKind::Spot {
            position,
            direction,
            inner_cone,
            outer_cone,
        } => (
            position,
            2.0,
            direction,
            (inner_cone.cos(), outer_cone.cos()),
        ),
    };
    GpuLight {
        position: pos.into(),
        kind,
        direction: dir.into(),
        range: l.range.unwrap_or(0.0),
        color: c.into(),
        tan_radius,
        cos_inner: cones.0,
        cos_outer: cones.1,
        shadow_layer: layer.map(|l| l as f32).unwrap_or(-1.0),
        shadow_texel: texel,
    }
}

/// Uploads the listed textures as layers of one 2D array with a full mip chain. Layers are
/// resized (bilinear) to the largest width and height among them, capped at
/// [`MAX_TEXTURE_SIZE`]. Mips are box-filtered in the stored encoding (for sRGB textures that is
/// a slight darkening of high-contrast detail, the usual shortcut). No members: one white texel.
fn texture_array(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    members: &[usize],
    space: TextureColorSpace,
) -> Result<wgpu::TextureView, RenderError> {
    let (w, h) = members.iter().fold((1u32, 1u32), |(w, h), &i| {
        (
            w.max(scene.textures[i].width),
            h.max(scene.textures[i].height),
        )
    });
    let (w, h) = (w.min(MAX_TEXTURE_SIZE), h.min(MAX_TEXTURE_SIZE));
    let layers = members.len().max(1) as u32;
    let max_layers = device.limits().max_texture_array_layers;
    if layers > max_layers {
        return Err(RenderError::Scene(format!(
            "the scene has {layers} textures of one kind; this GPU allows {max_layers} array layers"
        )));
    }
    let mips = 32 - w.max(h).leading_zeros();
    let format = match space {
        TextureColorSpace::Srgb => wgpu::TextureFormat::Rgba8UnormSrgb,
        TextureColorSpace::Linear => wgpu::TextureFormat::Rgba8Unorm,
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(match space {
            TextureColorSpace::Srgb => "sRGB material textures",
            TextureColorSpace::Linear => "linear material textures",
        }),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: layers,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for layer in 0..layers {
        let mut img = match members.get(layer as usize) {
            Some(&i) => {
                let t = &scene.textures[i];
                let img = image::RgbaImage::from_raw(t.width, t.height, t.rgba8.clone())
                    .ok_or_else(|| {
                        RenderError::Scene(format!("texture {i} has a wrong byte count"))
                    })?;
                if (t.width, t.height) != (w, h) {
                    image::imageops::resize(&img, w, h, image::imageops::FilterType::Triangle)
                } else {
                    img
                }
            }
            None => image::RgbaImage::from_pixel(w, h, image::Rgba([255; 4])),
        };
        for mip in 0..mips {
            let (mw, mh) = ((w >> mip).max(1), (h >> mip).max(1));
            if mip > 0 {
                img = image::imageops::resize(&img, mw, mh, image::imageops::FilterType::Triangle);
            }
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: mip,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                img.as_raw(),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * mw),
                    rows_per_image: Some(mh),
                },
                wgpu::Extent3d {
                    width: mw,
                    height: mh,
                    depth_or_array_layers: 1,
                },
            );
        }
    }
    Ok(texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    }))
}

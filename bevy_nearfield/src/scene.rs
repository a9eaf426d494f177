//! nearfield's scenes in Bevy: a scene loaded by `nearfield_scene` (a glTF file, or one written
//! by `nearfield export`) spawned as Bevy meshes with `StandardMaterial`s, and nearfield's camera
//! as a Bevy transform and projection — so that Bevy and `nearfield render` see the same thing.

use bevy::asset::RenderAssetUsages;
use bevy::camera::{PerspectiveProjection, Projection};
use bevy::image::{ImageAddressMode, ImageSampler, ImageSamplerDescriptor};
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};
use nearfield_scene::{AlphaMode, Scene, TextureColorSpace};

/// How the spawned materials are shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shading {
    /// Bevy's PBR with the scene's base colour, metallic, roughness and emission.
    Lit,
    /// Unlit: each surface shows its base colour times this factor (what a constant sky of
    /// radiance `factor` gives a diffuse surface before occlusion).
    Unlit(f32),
}

fn v3(v: glam::Vec3) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// Spawns every mesh of `scene` with its material.
pub fn spawn_scene(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    images: &mut Assets<Image>,
    scene: &Scene,
    shading: Shading,
) {
    let textures: Vec<Handle<Image>> = scene
        .textures
        .iter()
        .map(|t| {
            let format = match t.color_space {
                TextureColorSpace::Srgb => TextureFormat::Rgba8UnormSrgb,
                _ => TextureFormat::Rgba8Unorm,
            };
            let mut image = Image::new(
                Extent3d {
                    width: t.width,
                    height: t.height,
                    depth_or_array_layers: 1,
                },
                TextureDimension::D2,
                t.rgba8.clone(),
                format,
                RenderAssetUsages::RENDER_WORLD,
            );
            image.sampler = ImageSampler::Descriptor(ImageSamplerDescriptor {
                address_mode_u: ImageAddressMode::Repeat,
                address_mode_v: ImageAddressMode::Repeat,
                ..ImageSamplerDescriptor::linear()
            });
            images.add(image)
        })
        .collect();
    let handles: Vec<Handle<StandardMaterial>> = scene
        .materials
        .iter()
        .map(|m| {
            let c = m.base_color;
            let texture_of = |i: Option<usize>| i.and_then(|i| textures.get(i).cloned());
            let texture = texture_of(m.base_color_texture);
            let (unlit, base_color) = match shading {
                Shading::Lit => (false, Color::linear_rgba(c.x, c.y, c.z, c.w)),
                Shading::Unlit(f) => (true, Color::linear_rgba(f * c.x, f * c.y, f * c.z, c.w)),
            };
            materials.add(StandardMaterial {
                base_color,
                base_color_texture: texture,
                // glTF's metallic-roughness texture (G roughness, B metallic), which Bevy reads
                // the same way; without it Sponza's materials (metallicFactor 1 by default) are
                // all metal, and diffuse light such as an irradiance volume's is lost.
                metallic_roughness_texture: texture_of(m.metallic_roughness_texture),
                metallic: m.metallic,
                perceptual_roughness: m.roughness,
                emissive_texture: texture_of(m.emissive_texture),
                emissive: LinearRgba::rgb(m.emissive.x, m.emissive.y, m.emissive.z),
                double_sided: m.double_sided,
                cull_mode: (!m.double_sided).then_some(bevy::render::render_resource::Face::Back),
                alpha_mode: match m.alpha_mode {
                    AlphaMode::Opaque => bevy::prelude::AlphaMode::Opaque,
                    AlphaMode::Mask { cutoff } => bevy::prelude::AlphaMode::Mask(cutoff),
                    AlphaMode::Blend => bevy::prelude::AlphaMode::Blend,
                },
                unlit,
                ..default()
            })
        })
        .collect();
    for mesh in &scene.meshes {
        let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
        let normals: Vec<[f32; 3]> = mesh.normals.iter().map(|n| n.to_array()).collect();
        let mut m = Mesh::new(
            PrimitiveTopology::TriangleList,
            RenderAssetUsages::RENDER_WORLD,
        )
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
        .with_inserted_indices(Indices::U32(
            mesh.indices.iter().flatten().copied().collect(),
        ));
        if mesh.uvs.len() == mesh.positions.len() {
            let uvs: Vec<[f32; 2]> = mesh.uvs.iter().map(|u| u.to_array()).collect();
            m.insert_attribute(Mesh::ATTRIBUTE_UV_0, uvs);
        }
        let material = handles
            .get(mesh.material as usize)
            .cloned()
            .unwrap_or_default();
        commands.spawn((Mesh3d(meshes.add(m)), MeshMaterial3d(material)));
    }
}

/// nearfield's camera as a Bevy transform and perspective projection of `size` pixels, with the
/// near plane `near` (metres).
pub fn camera(
    camera: &nearfield_scene::Camera,
    size: (u32, u32),
    near: f32,
) -> (Transform, Projection) {
    let eye = v3(camera.eye);
    let transform = Transform::from_translation(eye).looking_at(v3(camera.target), v3(camera.up));
    let projection = Projection::Perspective(PerspectiveProjection {
        fov: camera.yfov,
        aspect_ratio: size.0 as f32 / size.1 as f32,
        near,
        ..default()
    });
    (transform, projection)
}

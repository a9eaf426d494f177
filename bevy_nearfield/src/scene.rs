//! nearfield's scenes in Bevy: a scene loaded by `nearfield_scene` (a glTF file, or one written
//! by `nearfield export`) spawned as Bevy meshes with `StandardMaterial`s, its lights (and the
//! environment's sun) as Bevy's lights in Bevy's units, nearfield's camera as a Bevy transform
//! and projection, and nearfield's exposure as Bevy's — so that Bevy and `nearfield render`
//! see the same thing at the same exposure (docs/src/bevy.md, "Units").

use bevy::asset::RenderAssetUsages;
use bevy::camera::{Exposure, PerspectiveProjection, Projection};
use bevy::image::{ImageAddressMode, ImageSampler, ImageSamplerDescriptor};
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};
use nearfield_scene::{AlphaMode, Animation, Environment, LightKind, Scene, TextureColorSpace};
use std::sync::Arc;

/// How the spawned materials are shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shading {
    /// Bevy's PBR with the scene's base colour, metallic, roughness and emission.
    Lit,
    /// As `Lit` without the specular lobe (reflectance 0, so F0 = 0): the diffuse part alone,
    /// the quantity of nearfield's `lambertian` AOV and of its path tracer.
    Diffuse,
    /// Unlit: each surface shows its base colour times this factor (what a constant sky of
    /// radiance `factor` gives a diffuse surface before occlusion).
    Unlit(f32),
}

fn v3(v: glam::Vec3) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// A mesh of the scene that follows an animated node (glTF node animation, a `*-moving`
/// built-in): spawned at rest, its `Transform` is the node's motion from the rest pose
/// ([`SceneMotion::transform_at`]), which [`play_scene_motion`] sets from Bevy's clock.
#[derive(Component, Clone)]
pub struct SceneMotion {
    /// Index into the animation's nodes.
    pub node: u32,
    pub animation: Arc<Animation>,
}

impl SceneMotion {
    /// The mesh's transform at time `t` (s): world from its rest pose, as `nearfield render`
    /// poses it at the same time.
    pub fn transform_at(&self, t: f32) -> Transform {
        let m = self.animation.motion_at(self.node, t);
        Transform::from_matrix(Mat4::from_cols_array(&m.to_cols_array()))
    }
}

/// Plays the scene's animation in a loop on Bevy's clock (`Time`'s elapsed seconds, modulo the
/// animation's duration): add it to `Update` to see a moving scene move.
pub fn play_scene_motion(time: Res<Time>, mut moving: Query<(&SceneMotion, &mut Transform)>) {
    for (m, mut transform) in &mut moving {
        let period = m.animation.duration();
        let t = if period > 0.0 {
            time.elapsed_secs() % period
        } else {
            0.0
        };
        *transform = m.transform_at(t);
    }
}

/// Spawns every mesh of `scene` with its material; a moving mesh at rest with its
/// [`SceneMotion`], posed at time 0.
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
                Shading::Lit | Shading::Diffuse => (false, Color::linear_rgba(c.x, c.y, c.z, c.w)),
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
                // No culling, as nearfield's shadow maps: Bevy's shadow pass culls with the
                // material's mode, so a single-sided wall lit from behind (the Cornell box's
                // walls, Sponza's) would cast no shadow. From inside a scene the back faces are
                // behind front ones; one seen from outside is shaded with its front normal.
                cull_mode: None,
                alpha_mode: match m.alpha_mode {
                    AlphaMode::Opaque => bevy::prelude::AlphaMode::Opaque,
                    AlphaMode::Mask { cutoff } => bevy::prelude::AlphaMode::Mask(cutoff),
                    AlphaMode::Blend => bevy::prelude::AlphaMode::Blend,
                },
                unlit,
                reflectance: if shading == Shading::Diffuse {
                    0.0
                } else {
                    0.5
                },
                ..default()
            })
        })
        .collect();
    let animation = Arc::new(scene.animation.clone());
    for mesh in &scene.meshes {
        let (rest_positions, rest_normals) = match &mesh.motion {
            Some(mm) => (&mm.rest_positions, &mm.rest_normals),
            None => (&mesh.positions, &mesh.normals),
        };
        let positions: Vec<[f32; 3]> = rest_positions.iter().map(|p| p.to_array()).collect();
        let normals: Vec<[f32; 3]> = rest_normals.iter().map(|n| n.to_array()).collect();
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
        let mut entity = commands.spawn((Mesh3d(meshes.add(m)), MeshMaterial3d(material)));
        if let Some(mm) = &mesh.motion {
            let motion = SceneMotion {
                node: mm.node,
                animation: animation.clone(),
            };
            entity.insert((motion.transform_at(0.0), motion));
        }
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

/// Bevy's luminous power (lm) of a point or spot light of `candela` (Bevy reads 4π lm as 1 cd).
pub fn lumens(candela: f32) -> f32 {
    4.0 * std::f32::consts::PI * candela
}

/// Spawns the scene's lights and the environment's sun (its disc as a parallel light) with
/// shadows, in Bevy's units: a directional light's lux is its `illuminance`, a point or spot
/// light's candela [`lumens`]. A light without a range gets ten times the scene's diagonal
/// (Bevy windows every point and spot light by its range). Returns the lights spawned.
pub fn spawn_lights(commands: &mut Commands, scene: &Scene, env: &Environment) -> Vec<Entity> {
    let b = scene.bounds();
    let reach = 10.0 * (b.max - b.min).length().max(1.0);
    let colour = |c: glam::Vec3| Color::linear_rgb(c.x, c.y, c.z);
    scene
        .lights
        .iter()
        .chain(env.sun_light().as_ref())
        .map(|l| {
            let range = l.range.unwrap_or(reach);
            match l.kind {
                LightKind::Directional { direction, .. } => commands.spawn((
                    DirectionalLight {
                        color: colour(l.color),
                        illuminance: l.intensity,
                        shadow_maps_enabled: true,
                        ..default()
                    },
                    Transform::default().looking_to(v3(direction), up_for(v3(direction))),
                )),
                LightKind::Point { position } => commands.spawn((
                    PointLight {
                        color: colour(l.color),
                        intensity: lumens(l.intensity),
                        range,
                        shadow_maps_enabled: true,
                        ..default()
                    },
                    Transform::from_translation(v3(position)),
                )),
                LightKind::Spot {
                    position,
                    direction,
                    inner_cone,
                    outer_cone,
                } => commands.spawn((
                    SpotLight {
                        color: colour(l.color),
                        intensity: lumens(l.intensity),
                        range,
                        // Bevy's cone must stay below π/2.
                        inner_angle: inner_cone.min(MAX_CONE),
                        outer_angle: outer_cone.min(MAX_CONE),
                        shadow_maps_enabled: true,
                        ..default()
                    },
                    Transform::from_translation(v3(position))
                        .looking_to(v3(direction), up_for(v3(direction))),
                )),
            }
            .id()
        })
        .collect()
}

/// The widest spot cone Bevy takes (its `outer_angle` must be below π/2).
const MAX_CONE: f32 = std::f32::consts::FRAC_PI_2 - 1e-3;

/// An up vector not parallel to `d`.
fn up_for(d: Vec3) -> Vec3 {
    if d.normalize_or_zero().y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

/// Side of the radiance cube [`environment_map_light`] makes (0.35° texels at the faces'
/// centres), and of its diffuse cube.
pub const ENVIRONMENT_SIZE: u32 = 256;
const DIFFUSE_SIZE: u32 = 32;

/// The environment as Bevy's `EnvironmentMapLight` in Bevy's units (docs/src/bevy.md, "The far
/// field"): the specular map holds the radiance (level 0: the map itself, 2 × 2 bilinear taps
/// a texel; each level below the 2 × 2 mean of the one above, a box chain and not Bevy's GGX
/// prefiltering, so rough reflections are sharper than Bevy's own filtering would draw them),
/// the diffuse map E/π from the map's SH (bands 0–2, nearfield's `env_irradiance_sh`); the
/// intensity is the environment's, so that radiance × intensity is cd/m². The map's sun, where
/// it was split out, is not in it: [`spawn_lights`] spawns it.
pub fn environment_map_light(images: &mut Assets<Image>, env: &Environment) -> EnvironmentMapLight {
    let raw = Environment {
        intensity: 1.0,
        ..env.clone()
    };
    let n = ENVIRONMENT_SIZE;
    let radiance = cube_faces(n, 2, |d| raw.radiance(d));
    let levels = n.ilog2() + 1;
    let specular = cube_image(n, levels, |face| {
        let mut chain = vec![radiance[face].clone()];
        for level in 1..levels {
            let (above, side) = (chain.last().unwrap(), n >> (level - 1));
            let half = side / 2;
            let at = |x: u32, y: u32| above[(y * side + x) as usize];
            chain.push(
                (0..half * half)
                    .map(|k| {
                        let (x, y) = (2 * (k % half), 2 * (k / half));
                        0.25 * (at(x, y) + at(x + 1, y) + at(x, y + 1) + at(x + 1, y + 1))
                    })
                    .collect(),
            );
        }
        chain
    });
    let sh = nearfield_scene::sh::project_environment(&raw, 9);
    let diffuse_faces = cube_faces(DIFFUSE_SIZE, 1, |d| {
        nearfield_scene::sh::irradiance_over_pi(&sh, d).max(glam::Vec3::ZERO)
    });
    let diffuse = cube_image(DIFFUSE_SIZE, 1, |face| vec![diffuse_faces[face].clone()]);
    EnvironmentMapLight {
        diffuse_map: images.add(diffuse),
        specular_map: images.add(specular),
        intensity: env.intensity,
        ..default()
    }
}

/// The world direction of texel (x, y) of cube face `face` (wgpu's face order +X, −X, +Y, −Y,
/// +Z, −Z and texel orientation), as Bevy reads its environment maps: the cube's z negated.
fn cube_direction(face: usize, n: u32, x: f32, y: f32) -> glam::Vec3 {
    let s = 2.0 * x / n as f32 - 1.0;
    let t = 2.0 * y / n as f32 - 1.0;
    let c = match face {
        0 => glam::Vec3::new(1.0, -t, -s),
        1 => glam::Vec3::new(-1.0, -t, s),
        2 => glam::Vec3::new(s, 1.0, t),
        3 => glam::Vec3::new(s, -1.0, -t),
        4 => glam::Vec3::new(s, -t, 1.0),
        _ => glam::Vec3::new(-s, -t, -1.0),
    };
    glam::Vec3::new(c.x, c.y, -c.z).normalize()
}

/// Each face's n × n texels of `f` (the mean of `taps` × `taps` directions in each texel).
fn cube_faces(n: u32, taps: u32, f: impl Fn(glam::Vec3) -> glam::Vec3) -> Vec<Vec<glam::Vec3>> {
    (0..6)
        .map(|face| {
            (0..n * n)
                .map(|k| {
                    let (x, y) = ((k % n) as f32, (k / n) as f32);
                    let mut sum = glam::Vec3::ZERO;
                    for j in 0..taps {
                        for i in 0..taps {
                            let (dx, dy) = (
                                (i as f32 + 0.5) / taps as f32,
                                (j as f32 + 0.5) / taps as f32,
                            );
                            sum += f(cube_direction(face, n, x + dx, y + dy));
                        }
                    }
                    sum / (taps * taps) as f32
                })
                .collect()
        })
        .collect()
}

/// A cube image (rgba16float) of side `n` with `levels` mip levels, `chain(face)` each face's
/// levels (layer-major, as Bevy uploads an image's data).
fn cube_image(n: u32, levels: u32, chain: impl Fn(usize) -> Vec<Vec<glam::Vec3>>) -> Image {
    let mut data = Vec::new();
    for face in 0..6 {
        for level in chain(face) {
            for t in level {
                for c in [t.x, t.y, t.z, 1.0] {
                    data.extend_from_slice(
                        &half::f16::from_f32(c.min(nearfield_render::gpu_env::F16_MAX))
                            .to_le_bytes(),
                    );
                }
            }
        }
    }
    let mut image = Image::new_uninit(
        Extent3d {
            width: n,
            height: n,
            depth_or_array_layers: 6,
        },
        TextureDimension::D2,
        TextureFormat::Rgba16Float,
        RenderAssetUsages::RENDER_WORLD,
    );
    image.data = Some(data);
    image.texture_descriptor.mip_level_count = levels;
    image.texture_view_descriptor = Some(bevy::render::render_resource::TextureViewDescriptor {
        dimension: Some(bevy::render::render_resource::TextureViewDimension::Cube),
        ..default()
    });
    image
}

/// Bevy's camera exposure for nearfield's `--exposure` (stops): nearfield shows radiance ×
/// 2^stops, Bevy radiance × 2^−ev100 / 1.2, so ev100 = −log2(1.2) − stops. At nearfield's
/// default (0) a radiance of 1 cd/m² is 1 in both images before tone mapping.
pub fn exposure(stops: f32) -> Exposure {
    Exposure {
        ev100: -(1.2f32).log2() - stops,
    }
}

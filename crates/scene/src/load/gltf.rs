//! glTF 2.0 (`.gltf` and `.glb`) through the `gltf` crate.
//!
//! Supported: the node hierarchy and transforms (flattened to world space), indexed and
//! non-indexed triangle primitives, missing normals (generated: smooth, area-weighted), base
//! colour factor and texture (sRGB), metallic-roughness factor and texture, emissive factor and
//! texture with `KHR_materials_emissive_strength`, alpha mask, double-sided, `KHR_lights_punctual`
//! (point, spot, directional) and perspective cameras. A *required* extension outside this list is
//! an error; an optional one is ignored with one warning. `KHR_materials_transmission` materials
//! render opaque with a warning. Normal maps and texture transforms are ignored.

use super::{finish_mesh, io_error};
use crate::{
    AlphaMode, Camera, Light, LightKind, Material, Mesh, Scene, SceneError, Texture,
    TextureColorSpace,
};
use glam::{Mat4, Vec2, Vec3, Vec4};
use std::collections::HashMap;
use std::path::Path;

/// Extensions whose presence we handle (fully, or by documented fallback).
const SUPPORTED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
];

pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let err = |msg: String| SceneError::Gltf {
        path: path.to_path_buf(),
        msg,
    };
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    let unvalidated =
        ::gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| err(e.to_string()))?;
    for ext in unvalidated.document.extensions_required() {
        if !SUPPORTED.contains(&ext) {
            return Err(SceneError::UnsupportedExtension {
                path: path.to_path_buf(),
                extension: ext.to_string(),
            });
        }
    }
    for ext in unvalidated.document.extensions_used() {
        if !SUPPORTED.contains(&ext) {
            log::warn!("{}: ignoring optional glTF extension {ext}", path.display());
        }
    }
    drop(unvalidated);
    let gltf = ::gltf::Gltf::from_slice(&bytes).map_err(|e| err(e.to_string()))?;
    let base = path.parent();
    let buffers = ::gltf::import_buffers(&gltf.document, base, gltf.blob.clone())
        .map_err(|e| err(format!("buffer: {e}")))?;
    let images = ::gltf::import_images(&gltf.document, base, &buffers)
        .map_err(|e| err(format!("image: {e}")))?;
    let doc = &gltf.document;

    let mut scene = Scene {
        name: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        ..Default::default()
    };

    // Textures are decoded per (image, colour space): the same image may serve two roles.
    let mut texture_of: HashMap<(usize, bool), usize> = HashMap::new();
    let mut texture =
        |scene: &mut Scene, tex: ::gltf::Texture, srgb: bool| -> Result<usize, SceneError> {
            let image = tex.source().index();
            if let Some(&i) = texture_of.get(&(image, srgb)) {
                return Ok(i);
            }
            let data = &images[image];
            let rgba8 = to_rgba8(data).ok_or_else(|| {
                err(format!(
                    "image {image} has an unsupported pixel format {:?}",
                    data.format
                ))
            })?;
            scene.textures.push(Texture {
                width: data.width,
                height: data.height,
                rgba8,
                color_space: if srgb {
                    TextureColorSpace::Srgb
                } else {
                    TextureColorSpace::Linear
                },
            });
            texture_of.insert((image, srgb), scene.textures.len() - 1);
            Ok(scene.textures.len() - 1)
        };

    let mut warned_transmission = false;
    let mut warned_blend = false;
    for m in doc.materials() {
        let pbr = m.pbr_metallic_roughness();
        let mut mat = Material {
            name: m.name().unwrap_or("").to_string(),
            base_color: Vec4::from(pbr.base_color_factor()),
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            emissive: Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
            double_sided: m.double_sided(),
            alpha_mode: match m.alpha_mode() {
                ::gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
                ::gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                    cutoff: m.alpha_cutoff().unwrap_or(0.5),
                },
                ::gltf::material::AlphaMode::Blend => {
                    if !warned_blend {
                        log::warn!("{}: alpha-blended materials render opaque", path.display());
                        warned_blend = true;
                    }
                    AlphaMode::Blend
                }
            },
            ..Default::default()
        };
        if m.transmission().is_some() && !warned_transmission {
            log::warn!("{}: transmissive materials render opaque", path.display());
            warned_transmission = true;
        }
        if let Some(t) = pbr.base_color_texture() {
            mat.base_color_texture = Some(texture(&mut scene, t.texture(), true)?);
        }
        if let Some(t) = pbr.metallic_roughness_texture() {
            mat.metallic_roughness_texture = Some(texture(&mut scene, t.texture(), false)?);
        }
        if let Some(t) = m.emissive_texture() {
            mat.emissive_texture = Some(texture(&mut scene, t.texture(), true)?);
        }
        scene.materials.push(mat);
    }
    // Primitives without a material get glTF's default material (white, metallic 1, roughness 1);
    // we use a rough white dielectric instead, which is what every viewer shows.
    let default_material = scene.materials.len() as u32;
    scene.materials.push(Material {
        base_color: Vec4::ONE,
        ..Default::default()
    });

    let gscene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| err("the file has no scene".into()))?;
    let mut cameras: Vec<(usize, Camera)> = Vec::new();
    let mut stack: Vec<(::gltf::Node, Mat4)> =
        gscene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
    let mut warned_mode = false;
    while let Some((node, parent)) = stack.pop() {
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        for child in node.children() {
            stack.push((child, world));
        }
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                if prim.mode() != ::gltf::mesh::Mode::Triangles {
                    if !warned_mode {
                        log::warn!("{}: skipping non-triangle primitives", path.display());
                        warned_mode = true;
                    }
                    continue;
                }
                let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
                let positions: Vec<Vec3> = reader
                    .read_positions()
                    .ok_or_else(|| {
                        err(format!(
                            "mesh '{}' has a primitive without positions",
                            mesh.name().unwrap_or("")
                        ))
                    })?
                    .map(Vec3::from)
                    .collect();
                let normals: Vec<Vec3> = reader
                    .read_normals()
                    .map(|it| it.map(Vec3::from).collect())
                    .unwrap_or_default();
                let uvs: Vec<Vec2> = reader
                    .read_tex_coords(0)
                    .map(|it| it.into_f32().map(Vec2::from).collect())
                    .unwrap_or_default();
                let flat: Vec<u32> = match reader.read_indices() {
                    Some(it) => it.into_u32().collect(),
                    None => (0..positions.len() as u32).collect(),
                };
                let mut m = Mesh {
                    name: mesh.name().unwrap_or("").to_string(),
                    positions,
                    normals,
                    uvs,
                    indices: flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
                    material: prim
                        .material()
                        .index()
                        .map(|i| i as u32)
                        .unwrap_or(default_material),
                };
                let n = m.positions.len() as u32;
                if m.indices.iter().flatten().any(|&i| i >= n) {
                    return Err(err(format!("mesh '{}' has an index out of range", m.name)));
                }
                if m.indices.is_empty() {
                    continue;
                }
                finish_mesh(&mut m, path);
                m.transform(world);
                scene.meshes.push(m);
            }
        }
        if let Some(light) = node.light() {
            let position = world.transform_point3(Vec3::ZERO);
            let direction = world
                .transform_vector3(Vec3::NEG_Z)
                .try_normalize()
                .unwrap_or(Vec3::NEG_Z);
            let kind = match light.kind() {
                ::gltf::khr_lights_punctual::Kind::Directional => LightKind::Directional {
                    direction,
                    angular_radius: 0.0,
                },
                ::gltf::khr_lights_punctual::Kind::Point => LightKind::Point { position },
                ::gltf::khr_lights_punctual::Kind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                } => LightKind::Spot {
                    position,
                    direction,
                    inner_cone: inner_cone_angle,
                    outer_cone: outer_cone_angle,
                },
            };
            scene.lights.push(Light {
                kind,
                color: Vec3::from(light.color()),
                intensity: light.intensity(),
                range: light.range(),
            });
        }
        if let Some(cam) = node.camera() {
            match cam.projection() {
                ::gltf::camera::Projection::Perspective(p) => {
                    let eye = world.transform_point3(Vec3::ZERO);
                    let fwd = world.transform_vector3(Vec3::NEG_Z).normalize();
                    let up = world.transform_vector3(Vec3::Y).normalize();
                    if !cameras.iter().any(|(i, _)| *i == cam.index()) {
                        cameras.push((
                            cam.index(),
                            Camera {
                                eye,
                                target: eye + fwd,
                                up,
                                yfov: p.yfov(),
                            },
                        ));
                    }
                }
                ::gltf::camera::Projection::Orthographic(_) => {
                    log::warn!(
                        "{}: ignoring orthographic camera {}",
                        path.display(),
                        cam.index()
                    );
                }
            }
        }
    }
    cameras.sort_by_key(|(i, _)| *i);
    scene.cameras = cameras.into_iter().map(|(_, c)| c).collect();
    Ok(scene)
}

fn to_rgba8(data: &::gltf::image::Data) -> Option<Vec<u8>> {
    use ::gltf::image::Format as F;
    let p = &data.pixels;
    let n = (data.width * data.height) as usize;
    let out: Vec<u8> = match data.format {
        F::R8G8B8A8 => p.clone(),
        F::R8G8B8 => p
            .chunks_exact(3)
            .flat_map(|c| [c[0], c[1], c[2], 255])
            .collect(),
        F::R8G8 => p
            .chunks_exact(2)
            .flat_map(|c| [c[0], c[1], 0, 255])
            .collect(),
        F::R8 => p.iter().flat_map(|&c| [c, c, c, 255]).collect(),
        F::R16G16B16A16 => p.chunks_exact(2).map(|c| c[1]).collect(),
        F::R16G16B16 => p
            .chunks_exact(6)
            .flat_map(|c| [c[1], c[3], c[5], 255])
            .collect(),
        F::R16G16 => p
            .chunks_exact(4)
            .flat_map(|c| [c[1], c[3], 0, 255])
            .collect(),
        F::R16 => p
            .chunks_exact(2)
            .flat_map(|c| [c[1], c[1], c[1], 255])
            .collect(),
        _ => return None,
    };
    (out.len() == 4 * n).then_some(out)
}

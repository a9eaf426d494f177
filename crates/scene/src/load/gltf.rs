//! glTF 2.0 (`.gltf` and `.glb`) through the `gltf` crate.
//!
//! Supported: the node hierarchy and transforms (flattened to world space), indexed and
//! non-indexed triangle primitives, missing normals (generated: smooth, area-weighted), base
//! colour factor and texture (sRGB), metallic-roughness factor and texture, emissive factor and
//! texture with `KHR_materials_emissive_strength`, alpha mask, double-sided, `KHR_lights_punctual`
//! (point, spot, directional) and perspective cameras. A *required* extension outside this list is
//! an error; an optional one is ignored with one warning. `KHR_materials_transmission` materials
//! render opaque with a warning. Normal maps and texture transforms are ignored. Node animation
//! (translation, rotation and scale channels, every animation of the file played at once) moves
//! the meshes under the animated nodes ([`animation`]); morph targets, skins and animated
//! cameras and lights are not played.
//!
//! Before anything is built, the file's structure is checked ([`check`]): the node graph is a
//! tree, every accessor lies inside its buffer view and every view inside its buffer, URIs name
//! regular files, image headers are within [`crate::limits`]; while it is built, transforms,
//! cameras, lights and counts are.

mod animation;
mod check;

use super::{finish_mesh, io_error};
use crate::limits;
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
    let (gltf, buffers) = open(path)?;
    let doc = &gltf.document;
    let mut scene = Scene {
        name: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        ..Default::default()
    };
    let default_material = materials(path, doc, &buffers, &mut scene)?;
    let gscene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| err("the file has no scene".into()))?;
    let mut cameras: Vec<(usize, Camera)> = Vec::new();
    // Each node with its parent's world transform, the names of its ancestors and whether an
    // ancestor is dynamic (its extras' "nearfield": {"dynamic": true}).
    let mut stack: Vec<(::gltf::Node, Mat4, Vec<String>, bool)> = gscene
        .nodes()
        .map(|n| (n, Mat4::IDENTITY, Vec::new(), false))
        .collect();
    let mut counts = Counts::default();
    // Each node's parent, and the node each mesh hangs from (what an animation moves).
    let mut parents: HashMap<usize, usize> = HashMap::new();
    let mut mesh_nodes: Vec<usize> = Vec::new();
    while let Some((node, parent, mut nodes, parent_dynamic)) = stack.pop() {
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let world = parent * local;
        let carries = node.mesh().is_some() || node.camera().is_some() || node.light().is_some();
        check::transform(&node, &local, &world, carries).map_err(err)?;
        let dynamic = parent_dynamic || check::dynamic_extra(&node).map_err(err)?;
        if let Some(name) = node.name().filter(|n| !n.is_empty()) {
            nodes.push(name.to_string());
        }
        for child in node.children() {
            parents.insert(child.index(), node.index());
            stack.push((child, world, nodes.clone(), dynamic));
        }
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                let Some(mut m) = primitive(path, &mesh, &prim, &buffers, &mut counts)? else {
                    continue;
                };
                m.material = prim
                    .material()
                    .index()
                    .map(|i| i as u32)
                    .unwrap_or(default_material);
                m.nodes = nodes.clone();
                m.dynamic = dynamic;
                finish_mesh(&mut m, path);
                m.transform(world);
                scene.meshes.push(m);
                mesh_nodes.push(node.index());
            }
        }
        if let Some(light) = node.light() {
            let light = light_of(&light, &world);
            check::light(&light).map_err(|e| err(format!("{}: {e}", check::node_name(&node))))?;
            scene.lights.push(light);
        }
        if let Some(cam) = node.camera()
            && let Some(camera) = camera_of(path, &node, &cam, &world)?
            && !cameras.iter().any(|(i, _)| *i == cam.index())
        {
            cameras.push((cam.index(), camera));
        }
    }
    cameras.sort_by_key(|(i, _)| *i);
    scene.cameras = cameras.into_iter().map(|(_, c)| c).collect();
    scene.animation = animation::read(doc, &buffers, &parents).map_err(err)?;
    for (m, node) in scene.meshes.iter_mut().zip(mesh_nodes) {
        if scene.animation.moves(node as u32) {
            m.follow(node as u32);
        }
    }
    scene.pose(0.0);
    Ok(scene)
}

/// Reads and checks the file: its header, its required extensions, its structure, the node
/// tree, its buffers and accessors. The document and its buffers.
fn open(path: &Path) -> Result<(::gltf::Gltf, Vec<Vec<u8>>), SceneError> {
    let err = |msg: String| SceneError::Gltf {
        path: path.to_path_buf(),
        msg,
    };
    limits::check_regular_file(path)?;
    let bytes = std::fs::read(path).map_err(|e| io_error(path, e))?;
    check::glb_header(&bytes).map_err(err)?;
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
    // The crate's own validation indexes some arrays before checking the indices.
    check::before_validation(unvalidated.document.as_json()).map_err(err)?;
    drop(unvalidated);
    let gltf = ::gltf::Gltf::from_slice(&bytes).map_err(|e| {
        let msg = e.to_string();
        err(msg
            .strip_prefix("invalid glTF: ")
            .unwrap_or(&msg)
            .to_string())
    })?;
    drop(bytes);
    let doc = &gltf.document;
    check::node_tree(doc).map_err(err)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let buffers = check::import_buffers(doc, base, gltf.blob.as_deref()).map_err(err)?;
    check::accessors(doc, &buffers).map_err(err)?;
    Ok((gltf, buffers))
}

/// The materials with their textures, then a default material for primitives without one (glTF's
/// is white, metallic 1, roughness 1; a rough white dielectric is what every viewer shows). The
/// default's index.
fn materials(
    path: &Path,
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    scene: &mut Scene,
) -> Result<u32, SceneError> {
    let err = |msg: String| SceneError::Gltf {
        path: path.to_path_buf(),
        msg,
    };
    let base = path.parent().unwrap_or(Path::new("."));
    // Textures are decoded per (image, colour space): the same image may serve two roles.
    let mut texture_of: HashMap<(usize, bool), usize> = HashMap::new();
    let mut texture =
        |scene: &mut Scene, tex: ::gltf::Texture, srgb: bool| -> Result<usize, SceneError> {
            let image = tex.source().index();
            if let Some(&i) = texture_of.get(&(image, srgb)) {
                return Ok(i);
            }
            let source = doc.images().nth(image).expect("validated index");
            let rgba = check::image_bytes(&source, base, buffers)
                .and_then(|b| {
                    limits::decode_image(
                        &b,
                        limits::MAX_TEXTURE_SIDE,
                        limits::MAX_TEXTURE_PIXELS,
                        &format!("image {image}"),
                    )
                })
                .map_err(|e| err(format!("image {image}: {e}")))?
                .into_rgba8();
            let (width, height) = rgba.dimensions();
            let rgba8 = rgba.into_raw();
            scene.textures.push(Texture {
                width,
                height,
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
            mat.base_color_texture = Some(texture(scene, t.texture(), true)?);
        }
        if let Some(t) = pbr.metallic_roughness_texture() {
            mat.metallic_roughness_texture = Some(texture(scene, t.texture(), false)?);
        }
        if let Some(t) = m.emissive_texture() {
            mat.emissive_texture = Some(texture(scene, t.texture(), true)?);
        }
        scene.materials.push(mat);
    }
    let default_material = scene.materials.len() as u32;
    scene.materials.push(Material {
        base_color: Vec4::ONE,
        ..Default::default()
    });
    Ok(default_material)
}

/// Triangles and vertices read so far (instances included), against the limits; whether a
/// non-triangle primitive was skipped (said once).
#[derive(Default)]
struct Counts {
    triangles: usize,
    vertices: usize,
    warned_mode: bool,
}

/// One primitive's mesh in its node's space, or `None` for a primitive without triangles (its
/// material, nodes and dynamic flag are the caller's to set).
fn primitive(
    path: &Path,
    mesh: &::gltf::Mesh,
    prim: &::gltf::Primitive,
    buffers: &[Vec<u8>],
    counts: &mut Counts,
) -> Result<Option<Mesh>, SceneError> {
    let err = |msg: String| SceneError::Gltf {
        path: path.to_path_buf(),
        msg,
    };
    if prim.mode() != ::gltf::mesh::Mode::Triangles {
        if !counts.warned_mode {
            log::warn!("{}: skipping non-triangle primitives", path.display());
            counts.warned_mode = true;
        }
        return Ok(None);
    }
    check::attribute_types(prim).map_err(|e| {
        err(format!(
            "mesh {} primitive {}: {e}",
            mesh.index(),
            prim.index()
        ))
    })?;
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
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
    let m = Mesh {
        name: mesh.name().unwrap_or("").to_string(),
        positions,
        normals,
        uvs,
        indices: flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
        material: 0,
        nodes: Vec::new(),
        dynamic: false,
        motion: None,
    };
    let n = m.positions.len() as u32;
    if let Some(bad) = m.indices.iter().flatten().find(|&&i| i >= n) {
        return Err(err(format!(
            "mesh {} ('{}') references vertex {bad} of {n}",
            mesh.index(),
            m.name
        )));
    }
    counts.triangles += m.indices.len();
    counts.vertices += m.positions.len();
    if counts.triangles > limits::MAX_TRIANGLES || counts.vertices > limits::MAX_VERTICES {
        return Err(err(format!(
            "more than {} triangles or vertices (instances included), the limit",
            limits::MAX_TRIANGLES
        )));
    }
    Ok((!m.indices.is_empty()).then_some(m))
}

/// A `KHR_lights_punctual` light at its node's world transform.
fn light_of(light: &::gltf::khr_lights_punctual::Light, world: &Mat4) -> Light {
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
    Light {
        kind,
        color: Vec3::from(light.color()),
        intensity: light.intensity(),
        range: light.range(),
    }
}

/// A perspective camera at its node's world transform, checked; `None` (with a warning) for an
/// orthographic one.
fn camera_of(
    path: &Path,
    node: &::gltf::Node,
    cam: &::gltf::Camera,
    world: &Mat4,
) -> Result<Option<Camera>, SceneError> {
    match cam.projection() {
        ::gltf::camera::Projection::Perspective(p) => {
            let eye = world.transform_point3(Vec3::ZERO);
            let fwd = world.transform_vector3(Vec3::NEG_Z).normalize();
            let up = world.transform_vector3(Vec3::Y).normalize();
            let camera = Camera {
                eye,
                target: eye + fwd,
                up,
                yfov: p.yfov(),
            };
            camera.validate().map_err(|e| SceneError::Gltf {
                path: path.to_path_buf(),
                msg: format!("camera {} at {}: {e}", cam.index(), check::node_name(node)),
            })?;
            Ok(Some(camera))
        }
        ::gltf::camera::Projection::Orthographic(_) => {
            log::warn!(
                "{}: ignoring orthographic camera {}",
                path.display(),
                cam.index()
            );
            Ok(None)
        }
    }
}

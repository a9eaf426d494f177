//! glTF 2.0 export of a loaded scene (`nearfield export`): meshes, metallic-roughness materials
//! with their textures (PNG), punctual lights (`KHR_lights_punctual`), node animation (a moving
//! mesh hangs from its animated node, in that node's space) and one camera, as `.glb`
//! (binary) or `.gltf` (JSON with the buffer embedded as a data URI). What [`crate::load`]
//! reads back is the same scene: a test loads an exported built-in and compares.
//!
//! Other engines get our built-in scenes this way (the Bevy peer harness in `peers/bevy_ssao`
//! renders the exported Cornell box from the exported camera).

use crate::{AlphaMode, Camera, LightKind, Scene, SceneError, Texture};
use base64::Engine;
use glam::{Quat, Vec3};
use serde_json::{Value, json};
use std::path::Path;

/// Binary buffer and the JSON that indexes it.
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    /// A mesh's positions (with their bounds), normals and texture coordinates where it has them
    /// at every vertex, and indices, as accessors; the glTF mesh of one primitive.
    fn mesh(&mut self, m: &crate::Mesh) -> Value {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in &m.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let pv = self.view(
            &floats(m.positions.iter().flat_map(|p| p.to_array())),
            Some(ARRAY_BUFFER),
        );
        let bounds = json!({ "min": lo.to_array(), "max": hi.to_array() });
        let pos = self.accessor(pv, FLOAT, m.positions.len(), "VEC3", bounds);
        let mut attributes = json!({ "POSITION": pos });
        if m.normals.len() == m.positions.len() {
            let nv = self.view(
                &floats(m.normals.iter().flat_map(|n| n.to_array())),
                Some(ARRAY_BUFFER),
            );
            let normals = self.accessor(nv, FLOAT, m.normals.len(), "VEC3", json!({}));
            attributes["NORMAL"] = json!(normals);
        }
        if m.uvs.len() == m.positions.len() {
            let uv = self.view(
                &floats(m.uvs.iter().flat_map(|t| t.to_array())),
                Some(ARRAY_BUFFER),
            );
            let uvs = self.accessor(uv, FLOAT, m.uvs.len(), "VEC2", json!({}));
            attributes["TEXCOORD_0"] = json!(uvs);
        }
        let index_bytes: Vec<u8> = m
            .indices
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let iv = self.view(&index_bytes, Some(ELEMENT_ARRAY_BUFFER));
        let indices = self.accessor(iv, UNSIGNED_INT, m.indices.len() * 3, "SCALAR", json!({}));
        json!({
            "name": m.name,
            "primitives": [{ "attributes": attributes, "indices": indices, "material": m.material }],
        })
    }

    /// Appends `bytes` (4-byte aligned) as a buffer view; returns its index.
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    /// An accessor of `n` elements of `kind` (VEC3, VEC2, SCALAR) and component type `ctype`.
    fn accessor(&mut self, view: usize, ctype: u32, n: usize, kind: &str, extra: Value) -> usize {
        let mut a = json!({ "bufferView": view, "componentType": ctype, "count": n, "type": kind });
        if let (Value::Object(a), Value::Object(e)) = (&mut a, extra) {
            a.extend(e);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }
}

const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

fn floats(values: impl Iterator<Item = f32>) -> Vec<u8> {
    values.flat_map(f32::to_le_bytes).collect()
}

fn png(t: &Texture) -> Result<Vec<u8>, String> {
    let mut out = std::io::Cursor::new(Vec::new());
    image::RgbaImage::from_raw(t.width, t.height, t.rgba8.clone())
        .ok_or("texture data does not match its size")?
        .write_to(&mut out, image::ImageFormat::Png)
        .map_err(|e| format!("texture: {e}"))?;
    Ok(out.into_inner())
}

/// The node transform (column-major) that places a glTF camera or light (which look along
/// their local −Z, +Y up) at `eye`, looking at `target`.
fn look(camera: &Camera) -> Vec<f32> {
    camera.view_from_world().inverse().to_cols_array().to_vec()
}

/// The rotation taking −Z to `direction` (unit).
fn towards(direction: Vec3) -> Quat {
    Quat::from_rotation_arc(Vec3::NEG_Z, direction.normalize())
}

/// A material as glTF JSON: glTF's emissive factor is at most 1, the rest goes into
/// `KHR_materials_emissive_strength`.
fn material(m: &crate::Material) -> Value {
    let mut pbr = json!({
        "baseColorFactor": m.base_color.to_array(),
        "metallicFactor": m.metallic,
        "roughnessFactor": m.roughness,
    });
    if let Some(t) = m.base_color_texture {
        pbr["baseColorTexture"] = json!({ "index": t });
    }
    if let Some(t) = m.metallic_roughness_texture {
        pbr["metallicRoughnessTexture"] = json!({ "index": t });
    }
    let mut v =
        json!({ "name": m.name, "pbrMetallicRoughness": pbr, "doubleSided": m.double_sided });
    let peak = m.emissive.max_element();
    if peak > 0.0 {
        let strength = peak.max(1.0);
        v["emissiveFactor"] = json!((m.emissive / strength).to_array());
        if strength > 1.0 {
            v["extensions"] =
                json!({ "KHR_materials_emissive_strength": { "emissiveStrength": strength } });
        }
    }
    if let Some(t) = m.emissive_texture {
        v["emissiveTexture"] = json!({ "index": t });
    }
    match m.alpha_mode {
        AlphaMode::Opaque => {}
        AlphaMode::Mask { cutoff } => {
            v["alphaMode"] = json!("MASK");
            v["alphaCutoff"] = json!(cutoff);
        }
        AlphaMode::Blend => v["alphaMode"] = json!("BLEND"),
    }
    v
}

/// A light as `KHR_lights_punctual` JSON, with its node's translation and rotation.
fn light(l: &crate::Light) -> (Value, Vec3, Quat) {
    let mut light = json!({ "color": l.color.to_array(), "intensity": l.intensity });
    if let Some(r) = l.range {
        light["range"] = json!(r);
    }
    let (kind, translation, rotation) = match l.kind {
        LightKind::Directional { direction, .. } => ("directional", Vec3::ZERO, towards(direction)),
        LightKind::Point { position } => ("point", position, Quat::IDENTITY),
        LightKind::Spot {
            position,
            direction,
            inner_cone,
            outer_cone,
        } => {
            light["spot"] = json!({ "innerConeAngle": inner_cone, "outerConeAngle": outer_cone });
            ("spot", position, towards(direction))
        }
    };
    light["type"] = json!(kind);
    (light, translation, rotation)
}

/// The scene as glTF JSON and its binary buffer. `camera` becomes camera 0 with the aspect
/// ratio `aspect` (width / height).
fn build(scene: &Scene, camera: &Camera, aspect: f32) -> Result<(Value, Vec<u8>), String> {
    let mut b = Builder {
        bin: Vec::new(),
        views: Vec::new(),
        accessors: Vec::new(),
    };
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    // The scene's root nodes, and the moving meshes' nodes under each animated node.
    let mut roots = Vec::new();
    let mut hanging: Vec<Vec<usize>> = vec![Vec::new(); scene.animation.nodes.len()];
    for m in scene.meshes.iter().filter(|m| !m.indices.is_empty()) {
        match &m.motion {
            Some(mm) => {
                meshes.push(b.mesh(&at_rest_in_node(scene, m, mm)));
                hanging[mm.node as usize].push(nodes.len());
            }
            None => {
                meshes.push(b.mesh(m));
                roots.push(nodes.len());
            }
        }
        nodes.push(json!({ "name": m.name, "mesh": meshes.len() - 1 }));
    }
    let animations = animate(&mut b, scene, &mut nodes, (&mut roots, hanging));

    let mut images = Vec::new();
    for t in &scene.textures {
        let view = b.view(&png(t)?, None);
        images.push(json!({ "bufferView": view, "mimeType": "image/png" }));
    }
    let textures: Vec<Value> = (0..images.len())
        .map(|i| json!({ "source": i, "sampler": 0 }))
        .collect();
    let materials: Vec<Value> = scene.materials.iter().map(material).collect();
    let emissive_strength = scene
        .materials
        .iter()
        .any(|m| m.emissive.max_element() > 1.0);

    let mut lights = Vec::new();
    for l in &scene.lights {
        let (light, translation, rotation) = light(l);
        lights.push(light);
        roots.push(nodes.len());
        nodes.push(json!({
            "name": format!("light {}", lights.len() - 1),
            "translation": translation.to_array(),
            "rotation": rotation.to_array(),
            "extensions": { "KHR_lights_punctual": { "light": lights.len() - 1 } },
        }));
    }
    roots.push(nodes.len());
    nodes.push(json!({
        "name": "camera",
        "camera": 0,
        "matrix": look(camera),
    }));

    let mut used = Vec::new();
    if !lights.is_empty() {
        used.push("KHR_lights_punctual");
    }
    if emissive_strength {
        used.push("KHR_materials_emissive_strength");
    }
    let mut doc = json!({
        "asset": { "version": "2.0", "generator": concat!("nearfield ", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [{ "name": scene.name, "nodes": roots }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{
            "type": "perspective",
            "perspective": { "yfov": camera.yfov, "aspectRatio": aspect, "znear": 0.01 },
        }],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{ "byteLength": b.bin.len() }],
    });
    if !images.is_empty() {
        doc["images"] = json!(images);
        doc["textures"] = json!(textures);
        // Linear filtering with mipmaps, repeat (the loader's and the renderer's assumption).
        doc["samplers"] = json!([{ "magFilter": 9729, "minFilter": 9987 }]);
    }
    if let Some(a) = animations {
        doc["animations"] = json!([a]);
    }
    if !lights.is_empty() {
        doc["extensions"] = json!({ "KHR_lights_punctual": { "lights": lights } });
    }
    if !used.is_empty() {
        doc["extensionsUsed"] = json!(used);
    }
    Ok((doc, b.bin))
}

/// A moving mesh at rest in the space of the node it follows.
fn at_rest_in_node(
    scene: &Scene,
    m: &crate::Mesh,
    mm: &crate::animation::MeshMotion,
) -> crate::Mesh {
    let mut local = crate::Mesh {
        positions: mm.rest_positions.clone(),
        normals: mm.rest_normals.clone(),
        motion: None,
        ..m.clone()
    };
    local.transform(scene.animation.world(mm.node, None).inverse());
    local
}

/// The animated nodes as glTF nodes (appended to `nodes`, the roots to `roots`, each with the
/// moving meshes' nodes in `hanging` and its child nodes as children) and one animation of all
/// their channels; `None` when nothing moves.
fn animate(
    b: &mut Builder,
    scene: &Scene,
    nodes: &mut Vec<Value>,
    (roots, hanging): (&mut Vec<usize>, Vec<Vec<usize>>),
) -> Option<Value> {
    if scene.animation.is_empty() {
        return None;
    }
    let base = nodes.len();
    let (mut samplers, mut channels) = (Vec::new(), Vec::new());
    for (i, n) in scene.animation.nodes.iter().enumerate() {
        let mut children = hanging[i].clone();
        children.extend(
            (0..scene.animation.nodes.len())
                .filter(|&c| scene.animation.nodes[c].parent == Some(i as u32))
                .map(|c| base + c),
        );
        if n.parent.is_none() {
            roots.push(base + i);
        }
        let mut node = json!({
            "name": n.name,
            "translation": n.translation.to_array(),
            "rotation": n.rotation.to_array(),
            "scale": n.scale.to_array(),
        });
        if !children.is_empty() {
            node["children"] = json!(children);
        }
        nodes.push(node);
        let tracks: [(&str, Option<Flat>); 3] = [
            (
                "translation",
                n.translations
                    .as_ref()
                    .map(|t| track(t, |v: Vec3| v.to_array())),
            ),
            (
                "rotation",
                n.rotations
                    .as_ref()
                    .map(|t| track(t, |q: Quat| q.to_array())),
            ),
            (
                "scale",
                n.scales.as_ref().map(|t| track(t, |v: Vec3| v.to_array())),
            ),
        ];
        for (path, t) in tracks {
            let Some((times, values, kind, interpolation)) = t else {
                continue;
            };
            let tv = b.view(&floats(times.iter().copied()), None);
            let (lo, hi) = (times[0], times[times.len() - 1]);
            let input = b.accessor(
                tv,
                FLOAT,
                times.len(),
                "SCALAR",
                json!({ "min": [lo], "max": [hi] }),
            );
            let width = if kind == "VEC4" { 4 } else { 3 };
            let vv = b.view(&floats(values.iter().copied()), None);
            let output = b.accessor(vv, FLOAT, values.len() / width, kind, json!({}));
            let interpolation = match interpolation {
                crate::Interpolation::Step => "STEP",
                crate::Interpolation::Linear => "LINEAR",
                crate::Interpolation::CubicSpline => "CUBICSPLINE",
            };
            channels.push(
                json!({ "sampler": samplers.len(), "target": { "node": base + i, "path": path } }),
            );
            samplers
                .push(json!({ "input": input, "output": output, "interpolation": interpolation }));
        }
    }
    Some(json!({ "name": "motion", "samplers": samplers, "channels": channels }))
}

/// A track's times, its values flattened, their glTF type and its interpolation.
type Flat<'a> = (&'a [f32], Vec<f32>, &'static str, crate::Interpolation);

/// A track as glTF stores it ([`Flat`]).
fn track<T: Copy, const N: usize>(t: &crate::Track<T>, flat: fn(T) -> [f32; N]) -> Flat<'_> {
    let kind = if N == 4 { "VEC4" } else { "VEC3" };
    let values = t.values.iter().flat_map(|v| flat(*v)).collect();
    (&t.times, values, kind, t.interpolation)
}

/// Writes `scene` seen from `camera` (aspect = width / height) to `path`: binary glTF when the
/// name ends in `.glb`, else JSON glTF with an embedded buffer. Written atomically.
pub fn write_gltf(
    scene: &Scene,
    camera: &Camera,
    aspect: f32,
    path: &Path,
) -> Result<(), SceneError> {
    let invalid = |what: String| SceneError::Invalid {
        path: path.to_path_buf(),
        what,
    };
    let (mut doc, bin) = build(scene, camera, aspect).map_err(invalid)?;
    let glb = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let bytes = if glb {
        let mut text = serde_json::to_vec(&doc).map_err(|e| invalid(e.to_string()))?;
        while !text.len().is_multiple_of(4) {
            text.push(b' ');
        }
        let mut bin = bin;
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + text.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&text);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    } else {
        let data = base64::engine::general_purpose::STANDARD.encode(&bin);
        doc["buffers"][0]["uri"] = json!(format!("data:application/octet-stream;base64,{data}"));
        serde_json::to_vec_pretty(&doc).map_err(|e| invalid(e.to_string()))?
    };
    crate::atomic::write_bytes(path, &bytes).map_err(invalid)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An exported built-in loads back as the same scene: geometry, materials, camera.
    #[test]
    fn an_exported_builtin_loads_back_as_the_same_scene() {
        let dir = std::env::temp_dir().join(format!("nearfield-export-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for name in ["cornell", "boxes", "columns-moving"] {
            let scene = crate::builtin::scene(name).unwrap();
            let camera = scene.cameras[0];
            for ext in ["glb", "gltf"] {
                let path = dir.join(format!("{name}.{ext}"));
                write_gltf(&scene, &camera, 16.0 / 9.0, &path).unwrap();
                let back = crate::load_scene(&path).unwrap();
                assert_eq!(
                    back.triangle_count(),
                    scene.triangle_count(),
                    "{name}.{ext}"
                );
                let (a, b) = (scene.bounds(), back.bounds());
                assert!((a.min - b.min).abs().max_element() < 1e-5, "{name}.{ext}");
                assert!((a.max - b.max).abs().max_element() < 1e-5, "{name}.{ext}");
                for (m, n) in scene.materials.iter().zip(&back.materials) {
                    assert!((m.base_color - n.base_color).abs().max_element() < 1e-6);
                    assert!(
                        (m.emissive - n.emissive).abs().max_element()
                            < 1e-4 * (1.0 + m.emissive.max_element())
                    );
                    assert!((m.roughness - n.roughness).abs() < 1e-6);
                }
                let c = back.cameras[0];
                assert!((c.eye - camera.eye).length() < 1e-4, "{name}.{ext}");
                assert!((c.yfov - camera.yfov).abs() < 1e-6);
                let (d0, d1) = (
                    (camera.target - camera.eye).normalize(),
                    (c.target - c.eye).normalize(),
                );
                assert!(d0.dot(d1) > 1.0 - 1e-6, "{name}.{ext}: view direction");
                // A moving object moves the same: its bounds at each time agree.
                assert_eq!(back.moves(), scene.moves(), "{name}.{ext}");
                for t in [0.3, 1.1, 2.5, 9.0] {
                    let (mut a, mut b) = (scene.clone(), back.clone());
                    a.pose(t);
                    b.pose(t);
                    let (a, b) = (a.dynamic_bounds(), b.dynamic_bounds());
                    let d = (a.min - b.min).abs().max(a.max - b.max).max_element();
                    assert!(
                        a.is_empty() || d < 1e-4,
                        "{name}.{ext} at {t} s: {a:?} {b:?}"
                    );
                }
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

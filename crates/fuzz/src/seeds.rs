//! Seeds per target: small generated files that reach every feature a loader has (node
//! hierarchies, cameras, lights, textures, sparse and indexed accessors; ascii and binary PLY;
//! HDR and EXR), and real files from `../shared/assets` where they are present.

use crate::Target;
use std::path::{Path, PathBuf};

/// The OBJ that the `mtl` target's cases are the material library of.
pub const OBJ_USING_FUZZ_MTL: &str = "mtllib fuzz.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
                                      usemtl red\nf 1 2 3\nusemtl light\nf 2 4 3\n";

/// `../shared/assets` beside the repository, when it is there.
pub fn assets() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets");
    dir.is_dir().then_some(dir)
}

/// Real seed files per target (relative to the assets folder), small enough to load many
/// times a second.
fn real(target: Target) -> &'static [&'static str] {
    match target {
        Target::GltfJson => &["scenes/suzanne/Suzanne.gltf"],
        Target::Glb => &["scenes/cornell_box_suzanne_gltf/cornell-box.glb"],
        Target::Obj => &["scenes/cornell_box_mcguire/CornellBox-Original.obj"],
        Target::Mtl => &["scenes/cornell_box_mcguire/CornellBox-Original.mtl"],
        Target::Hdr => &["env/debevec_pisa_latlong_256x128.hdr"],
        _ => &[],
    }
}

/// Files real seeds refer to, linked into the worker's scratch directory.
pub const COMPANIONS: &[&str] = &[
    "scenes/suzanne/Suzanne.bin",
    "scenes/suzanne/Suzanne_BaseColor.png",
    "scenes/suzanne/Suzanne_MetallicRoughness.png",
    "scenes/cornell_box_mcguire/CornellBox-Original.mtl",
];

/// Links [`COMPANIONS`] into `dir` (when the assets are present).
pub fn prepare(dir: &Path) {
    let Some(assets) = assets() else { return };
    for c in COMPANIONS {
        let src = assets.join(c);
        let dst = dir.join(src.file_name().unwrap());
        if !dst.exists() {
            #[cfg(unix)]
            let _ = std::os::unix::fs::symlink(&src, &dst);
            #[cfg(not(unix))]
            let _ = std::fs::copy(&src, &dst);
        }
    }
}

/// Every seed of `target`: generated ones first, then the real ones that exist.
pub fn seeds(target: Target) -> Vec<Vec<u8>> {
    let mut out = generated(target);
    if let Some(assets) = assets() {
        for f in real(target) {
            if let Ok(b) = std::fs::read(assets.join(f)) {
                out.push(b);
            }
        }
    }
    out
}

fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for i in 0..4 {
            s.push(if i <= c.len() {
                A[(n >> (18 - 6 * i) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    s
}

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|f| f.to_le_bytes()).collect()
}

fn png(w: u32, h: u32) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(w, h, |x, y| {
        image::Rgba([(x * 60) as u8, (y * 60) as u8, 128, 255])
    });
    let mut out = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
        .unwrap();
    out
}

/// A quad (two indexed triangles) with normals and uvs, a child node, a camera, a light, a
/// textured material and a sparse accessor: the binary buffer and the JSON that uses it.
fn gltf_parts() -> (Vec<u8>, serde_json::Value) {
    let positions = f32s(&[0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.]);
    let normals = f32s(&[0., 0., 1., 0., 0., 1., 0., 0., 1., 0., 0., 1.]);
    let uvs = f32s(&[0., 1., 1., 1., 1., 0., 0., 0.]);
    let indices: Vec<u8> = [0u16, 1, 2, 0, 2, 3]
        .iter()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    let sparse_idx: Vec<u8> = 2u32.to_le_bytes().to_vec();
    let sparse_val = f32s(&[1.0, 1.0, 0.5]);
    let mut bin = Vec::new();
    let mut views = Vec::new();
    for part in [
        &positions,
        &normals,
        &uvs,
        &indices,
        &sparse_idx,
        &sparse_val,
    ] {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        views.push(
            serde_json::json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": part.len()}),
        );
        bin.extend(part.iter());
    }
    let json = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "intensity": 10, "color": [1, 0.9, 0.8]},
            {"type": "spot", "intensity": 5, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
            {"type": "directional", "intensity": 2}
        ]}},
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0.5],
             "sparse": {"count": 1, "indices": {"bufferView": 4, "componentType": 5125},
                        "values": {"bufferView": 5}}}
        ],
        "images": [{"uri": format!("data:image/png;base64,{}", base64(&png(4, 4)))}],
        "textures": [{"source": 0}],
        "materials": [
            {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0},
             "emissiveFactor": [0.1, 0, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}},
            {"alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true}
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 4}, "material": 1}]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5}}],
        "nodes": [
            {"mesh": 0, "children": [1, 2], "translation": [0, 0, -1]},
            {"mesh": 1, "scale": [2, 2, 2], "rotation": [0, 0.6, 0, 0.8]},
            {"camera": 0, "translation": [0.5, 0.5, 3], "children": [3]},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,1,0,1]},
            {"extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"extensions": {"KHR_lights_punctual": {"light": 2}}}
        ],
        "scenes": [{"nodes": [0, 4, 5]}],
        "scene": 0
    });
    (bin, json)
}

/// The generated glTF with its buffer inline (a data URI).
pub fn gltf_json() -> Vec<u8> {
    let (bin, mut json) = gltf_parts();
    json["buffers"][0]["uri"] =
        format!("data:application/octet-stream;base64,{}", base64(&bin)).into();
    serde_json::to_vec_pretty(&json).unwrap()
}

/// A GLB of `json` with `bin` as its binary chunk.
pub fn glb(json: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).unwrap();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(b);
    out
}

/// Splits a GLB into its JSON and binary chunk (None when it is not one).
pub fn split_glb(data: &[u8]) -> Option<(serde_json::Value, Vec<u8>)> {
    if data.len() < 20 || &data[0..4] != b"glTF" {
        return None;
    }
    let jlen = u32::from_le_bytes(data[12..16].try_into().ok()?) as usize;
    let json = serde_json::from_slice(data.get(20..20 + jlen)?).ok()?;
    let rest = data.get(20 + jlen..)?;
    let bin = if rest.len() >= 8 {
        let blen = u32::from_le_bytes(rest[0..4].try_into().ok()?) as usize;
        rest.get(8..8 + blen)?.to_vec()
    } else {
        Vec::new()
    };
    Some((json, bin))
}

fn generated(target: Target) -> Vec<Vec<u8>> {
    match target {
        Target::GltfJson => vec![gltf_json()],
        Target::Glb => {
            let (bin, json) = gltf_parts();
            vec![glb(&json, &bin)]
        }
        Target::Obj => vec![
            b"mtllib CornellBox-Original.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nvt 1 0\n\
              vt 1 1\nvt 0 1\nusemtl leftWall\nf 1/1/1 2/2/1 3/3/1 4/4/1\ng second\nv 0 0 1\nf 1 2 5\nf -1 -2 -3\n"
                .to_vec(),
        ],
        Target::Mtl => vec![
            b"newmtl red\nKd 0.8 0.1 0.1\nKs 0 0 0\nNs 10\nnewmtl light\nKd 0.5 0.5 0.5\nKe 10 10 8\nd 1\nillum 2\n"
                .to_vec(),
        ],
        Target::PlyAscii => vec![
            b"ply\nformat ascii 1.0\ncomment a square and a triangle\nelement vertex 5\nproperty float x\n\
              property float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
              element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n\
              1 1 0 0 0 1\n0 1 0 0 0 1\n0 0 1 0 1 0\n4 0 1 2 3\n3 0 1 4\n"
                .to_vec(),
        ],
        Target::PlyBinary => [false, true]
            .into_iter()
            .map(|big| {
                let fmt = if big { "binary_big_endian" } else { "binary_little_endian" };
                let mut out = format!(
                    "ply\nformat {fmt} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                     property float z\nelement face 2\nproperty list uchar uint vertex_indices\nend_header\n"
                )
                .into_bytes();
                let f = |x: f32| if big { x.to_be_bytes() } else { x.to_le_bytes() };
                let u = |x: u32| if big { x.to_be_bytes() } else { x.to_le_bytes() };
                for p in [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]] {
                    for c in p {
                        out.extend(f(c));
                    }
                }
                for face in [[0u32, 1, 2], [0, 2, 3]] {
                    out.push(3);
                    for i in face {
                        out.extend(u(i));
                    }
                }
                out
            })
            .collect(),
        Target::Hdr | Target::Exr => {
            let img = image::Rgb32FImage::from_fn(16, 8, |x, y| {
                image::Rgb([x as f32 * 0.1, y as f32 * 0.2, if x == 3 && y == 1 { 50.0 } else { 0.5 }])
            });
            let mut out = Vec::new();
            let format = if target == Target::Hdr {
                image::ImageFormat::Hdr
            } else {
                image::ImageFormat::OpenExr
            };
            image::DynamicImage::ImageRgb32F(img)
                .write_to(&mut std::io::Cursor::new(&mut out), format)
                .unwrap();
            vec![out]
        }
        Target::CameraJson => vec![
            br#"{"eye":[0,1,5],"target":[0,1,0],"up":[0,1,0],"yfov_deg":45}"#.to_vec(),
            br#"{"eye":[2.5,0.3,-1e3],"target":[0,0,0],"yfov_deg":90.5}"#.to_vec(),
        ],
        Target::ViewScript => vec![
            b"# a session\nmethod b ssdo:samples=8\nset radius 1\nquality b high\naov ao\nsize 640x360\n\
              scene builtin:boxes\nenv sky\nenv-intensity 2\nenv-rotation 90\nexposure -1\ntonemap neutral\n\
              light 0 off\nsplit 0.3\nsplit off\ncamera c.json\nsave-camera d.json\norbit 5\nframe\nwait 3\n\
              screenshot s.png\nreport\nquit\n"
                .to_vec(),
        ],
        Target::MethodSpec => nearfield_render::technique::REGISTRY
            .iter()
            .map(|t| {
                let kv: Vec<String> = t
                    .settings
                    .iter()
                    .take(6)
                    .map(|s| format!("{}={}", s.key, s.default))
                    .collect();
                if kv.is_empty() {
                    t.name.to_string().into_bytes()
                } else {
                    format!("{}:{},{}", t.name, kv.join("+"), t.name).into_bytes()
                }
            })
            .collect(),
        Target::SetValues => nearfield_render::technique::REGISTRY
            .iter()
            .filter(|t| !t.settings.is_empty())
            .map(|t| {
                let mut s = t.name.to_string();
                for set in t.settings {
                    s.push_str(&format!("\n{}={}", set.key, set.default));
                }
                s.into_bytes()
            })
            .collect(),
    }
}

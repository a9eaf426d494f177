//! Wavefront OBJ (+ MTL diffuse colour `Kd`, emission `Ke`) through `tobj`. Polygons are
//! triangulated; missing normals are generated. A missing MTL file is a warning, and the
//! affected meshes get the default material.

use super::{finish_mesh, io_error};
use crate::{Material, Mesh, Scene, SceneError};
use glam::{Vec2, Vec3};
use std::path::Path;

pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    crate::limits::check_regular_file(path)?;
    let text = std::fs::read(path).map_err(|e| io_error(path, e))?;
    check_indices(&text).map_err(|msg| SceneError::Obj {
        path: path.to_path_buf(),
        msg,
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    // Material libraries are read only when they are regular files within the size limit (a
    // `mtllib /dev/zero` would never end).
    let mtl_loader = |mtl: &Path| {
        let full = base.join(mtl);
        if crate::limits::check_regular_file(&full).is_err() {
            return Err(tobj::LoadError::OpenFileFailed);
        }
        let text = std::fs::read(&full).map_err(|_| tobj::LoadError::OpenFileFailed)?;
        check_mtl(&text)?;
        tobj::load_mtl_buf(&mut &text[..])
    };
    let (models, materials) =
        tobj::load_obj_buf(&mut &text[..], &opts, mtl_loader).map_err(|e| SceneError::Obj {
            path: path.to_path_buf(),
            msg: e.to_string(),
        })?;
    let mtl = materials.unwrap_or_else(|e| {
        log::warn!(
            "{}: material library not loaded ({e}); using the default material",
            path.display()
        );
        Vec::new()
    });
    let mut scene = Scene {
        name: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        ..Default::default()
    };
    scene.materials.push(Material::default());
    for m in &mtl {
        let mut mat = Material {
            name: m.name.clone(),
            ..Default::default()
        };
        if let Some(kd) = m.diffuse {
            mat.base_color = Vec3::from(kd).extend(1.0);
        }
        if let Some(ke) = m.unknown_param.get("Ke") {
            let v: Vec<f32> = ke
                .split_whitespace()
                .filter_map(|s| s.parse().ok())
                .collect();
            if v.len() == 3 {
                mat.emissive = Vec3::new(v[0], v[1], v[2]);
            }
        }
        scene.materials.push(mat);
    }
    for model in models {
        let m = &model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let n = m.positions.len() / 3;
        let mut mesh = Mesh {
            name: model.name.clone(),
            positions: m
                .positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2]))
                .collect(),
            normals: m
                .normals
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2]))
                .collect(),
            // OBJ's v points up; glTF's (and our textures') v points down.
            uvs: m
                .texcoords
                .chunks_exact(2)
                .map(|t| Vec2::new(t[0], 1.0 - t[1]))
                .collect(),
            indices: m
                .indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect(),
            material: m.material_id.map(|i| i as u32 + 1).unwrap_or(0),
            ..Default::default()
        };
        if mesh.indices.iter().flatten().any(|&i| i as usize >= n) {
            return Err(SceneError::Obj {
                path: path.to_path_buf(),
                msg: format!("object '{}' has a face index out of range", model.name),
            });
        }
        if mesh.material as usize >= scene.materials.len() {
            mesh.material = 0;
        }
        finish_mesh(&mut mesh, path);
        scene.meshes.push(mesh);
    }
    Ok(scene)
}

/// Refuses colour lines (`Ka`, `Kd`, `Ks`, `Ke`) with fewer than three values, which `tobj`
/// would not survive.
fn check_mtl(text: &[u8]) -> Result<(), tobj::LoadError> {
    for line in String::from_utf8_lossy(text).lines() {
        let mut words = line.split_whitespace();
        if matches!(words.next(), Some("Ka" | "Kd" | "Ks" | "Ke")) && words.count() < 3 {
            return Err(tobj::LoadError::MaterialParseError);
        }
    }
    Ok(())
}

/// Every index of a face, line or point names an existing `v`, `vt` or `vn` (counted over the
/// whole file, negative indices from the end), so that `tobj` never computes with one that
/// does not exist.
fn check_indices(text: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(text);
    let (mut v, mut vt, mut vn) = (0i64, 0i64, 0i64);
    for line in text.lines() {
        match line.split_whitespace().next() {
            Some("v") => v += 1,
            Some("vt") => vt += 1,
            Some("vn") => vn += 1,
            _ => {}
        }
    }
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if !matches!(words.next(), Some("f" | "l" | "p")) {
            continue;
        }
        for vertex in words {
            for (part, count, what) in vertex
                .split('/')
                .zip([(v, "v"), (vt, "vt"), (vn, "vn")])
                .map(|(p, (c, w))| (p, c, w))
            {
                if part.is_empty() {
                    continue;
                }
                let i: i64 = part
                    .parse()
                    .map_err(|_| format!("line {}: '{part}' is not an index", n + 1))?;
                if i == 0 || i.unsigned_abs() > count as u64 {
                    return Err(format!(
                        "line {}: index {i} names no {what} (the file has {count})",
                        n + 1
                    ));
                }
            }
        }
    }
    Ok(())
}

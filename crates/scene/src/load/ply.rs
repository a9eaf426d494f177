//! Stanford PLY (ascii and binary little/big-endian) through `ply-rs-bw`: vertex `x y z`, optional
//! `nx ny nz`, faces as `vertex_indices` (or `vertex_index`) lists, fan-triangulated. One mesh with
//! the default material.

use super::{finish_mesh, io_error};
use crate::{Material, Mesh, Scene, SceneError};
use glam::{Vec2, Vec3};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};
use std::path::Path;

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => v as f64,
        Property::UChar(v) => v as f64,
        Property::Short(v) => v as f64,
        Property::UShort(v) => v as f64,
        Property::Int(v) => v as f64,
        Property::UInt(v) => v as f64,
        Property::Float(v) => v as f64,
        Property::Double(v) => v,
        _ => return None,
    })
}

fn list(p: &Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListInt(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUInt(v) => v.iter().map(|&x| x as i64).collect(),
        _ => return None,
    })
}

pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let err = |msg: String| SceneError::Ply {
        path: path.to_path_buf(),
        msg,
    };
    let size = crate::limits::check_regular_file(path)?;
    check_header(path, size).map_err(err)?;
    let file = std::fs::File::open(path).map_err(|e| io_error(path, e))?;
    let mut reader = std::io::BufReader::new(file);
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut reader)
        // The parser's message continues with the offending line and a debug dump.
        .map_err(|e| {
            err(e
                .to_string()
                .lines()
                .next()
                .unwrap_or("")
                .trim()
                .to_string())
        })?;
    let vertices = ply
        .payload
        .get("vertex")
        .ok_or_else(|| err("no 'vertex' element".into()))?;
    let faces = ply
        .payload
        .get("face")
        .ok_or_else(|| err("no 'face' element".into()))?;
    let mut mesh = Mesh {
        name: "ply".into(),
        ..Default::default()
    };
    let has_normals = vertices
        .first()
        .is_some_and(|v| v.contains_key("nx") && v.contains_key("ny") && v.contains_key("nz"));
    for (i, v) in vertices.iter().enumerate() {
        let get = |k: &str| {
            v.get(k)
                .and_then(scalar)
                .ok_or_else(|| err(format!("vertex {i} has no numeric '{k}'")))
        };
        mesh.positions.push(Vec3::new(
            get("x")? as f32,
            get("y")? as f32,
            get("z")? as f32,
        ));
        if has_normals {
            mesh.normals.push(Vec3::new(
                get("nx")? as f32,
                get("ny")? as f32,
                get("nz")? as f32,
            ));
        }
    }
    let n = mesh.positions.len() as i64;
    for (i, f) in faces.iter().enumerate() {
        let idx = f
            .get("vertex_indices")
            .or_else(|| f.get("vertex_index"))
            .and_then(list)
            .ok_or_else(|| err(format!("face {i} has no vertex_indices list")))?;
        if let Some(bad) = idx.iter().find(|&&k| k < 0 || k >= n) {
            return Err(err(format!("face {i} references vertex {bad} of {n}")));
        }
        for k in 1..idx.len().saturating_sub(1) {
            mesh.indices
                .push([idx[0] as u32, idx[k] as u32, idx[k + 1] as u32]);
        }
    }
    mesh.uvs = vec![Vec2::ZERO; mesh.positions.len()];
    finish_mesh(&mut mesh, path);
    Ok(Scene {
        name: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        meshes: vec![mesh],
        materials: vec![Material::default()],
        ..Default::default()
    })
}

/// Reads the header alone and checks its element counts against [`crate::limits`] and against
/// what the file's size can hold (every element takes at least one byte per property in binary
/// and two characters in ascii), so that a header claiming billions of elements is refused
/// before the parser allocates for them.
fn check_header(path: &Path, file_size: u64) -> Result<(), String> {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path)
        .map_err(|e| e.to_string())?
        .take(1 << 16)
        .read_to_end(&mut head)
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&head);
    let Some(end) = text.find("end_header") else {
        return Err("no end_header in the first 64 KiB".into());
    };
    let binary = text[..end].contains("binary_");
    let mut elements: Vec<(String, u64, u64, u64)> = Vec::new();
    for line in text[..end].lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["element", name, count] => {
                let n: u64 = count
                    .parse()
                    .map_err(|_| format!("element {name}: count '{count}' is not a number"))?;
                elements.push((name.to_string(), n, 0, 0));
            }
            ["property", "list", count_ty, _, _] => {
                let b = scalar_bytes(count_ty).unwrap_or(1);
                if let Some(e) = elements.last_mut() {
                    e.2 += b;
                    e.3 += 1;
                }
            }
            ["property", ty, _] => {
                let b = scalar_bytes(ty).unwrap_or(1);
                if let Some(e) = elements.last_mut() {
                    e.2 += b;
                    e.3 += 1;
                }
            }
            _ => {}
        }
    }
    let mut least = 0u64;
    for (name, n, bytes, props) in &elements {
        let limit = match name.as_str() {
            "vertex" => crate::limits::MAX_VERTICES as u64,
            "face" => crate::limits::MAX_TRIANGLES as u64,
            _ => (crate::limits::MAX_VERTICES as u64) * 4,
        };
        if *n > limit {
            return Err(format!("{n} {name} elements, beyond the limit of {limit}"));
        }
        let per = if binary { *bytes } else { 2 * props };
        least = least.saturating_add(n.saturating_mul(per));
    }
    if least > file_size {
        return Err(format!(
            "the header declares {} elements, more than a {file_size}-byte file can hold",
            elements.iter().map(|e| e.1).sum::<u64>()
        ));
    }
    Ok(())
}

fn scalar_bytes(ty: &str) -> Option<u64> {
    Some(match ty {
        "char" | "uchar" | "int8" | "uint8" => 1,
        "short" | "ushort" | "int16" | "uint16" => 2,
        "int" | "uint" | "float" | "int32" | "uint32" | "float32" => 4,
        "double" | "float64" => 8,
        _ => return None,
    })
}

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
    let file = std::fs::File::open(path).map_err(|e| io_error(path, e))?;
    let mut reader = std::io::BufReader::new(file);
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut reader)
        .map_err(|e| err(e.to_string()))?;
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

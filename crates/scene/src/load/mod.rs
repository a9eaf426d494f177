//! Scene file loaders. Each returns a world-space [`crate::Scene`] or a [`crate::SceneError`]
//! naming the file and the problem.

pub mod gltf;
pub mod obj;
pub mod ply;

use crate::{Mesh, SceneError};
use std::path::Path;

/// Fills missing or degenerate normals with smooth area-weighted ones (and normalises stored
/// ones), and missing uvs with 0.
pub(crate) fn finish_mesh(mesh: &mut Mesh, path: &Path) {
    if mesh.normals_need_generating() {
        if !mesh.normals.is_empty() {
            log::warn!(
                "{}: mesh '{}' has zero or invalid normals; regenerating smooth normals",
                path.display(),
                mesh.name
            );
        }
        mesh.generate_smooth_normals();
    } else {
        // Files may store unnormalised normals; shading needs unit ones.
        for n in &mut mesh.normals {
            *n = n.normalize();
        }
    }
    if mesh.uvs.len() != mesh.positions.len() {
        mesh.uvs = vec![glam::Vec2::ZERO; mesh.positions.len()];
    }
}

pub(crate) fn io_error(path: &Path, e: std::io::Error) -> SceneError {
    if e.kind() == std::io::ErrorKind::NotFound {
        SceneError::Missing {
            path: path.to_path_buf(),
        }
    } else {
        SceneError::Io {
            path: path.to_path_buf(),
            source: e,
        }
    }
}

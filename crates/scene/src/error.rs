//! Errors raised while reading scenes, environments and cameras. Each one names the file and what
//! was wrong with it, so that the command line can print it as one line.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{path}: no such file")]
    Missing { path: PathBuf },
    #[error("{path}: unknown scene format (expected .gltf, .glb, .obj or .ply)")]
    UnknownFormat { path: PathBuf },
    #[error("{path}: cannot read: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: invalid glTF: {msg}")]
    Gltf { path: PathBuf, msg: String },
    #[error("{path}: requires glTF extension {extension}, which nearfield does not support")]
    UnsupportedExtension { path: PathBuf, extension: String },
    #[error("{path}: invalid OBJ: {msg}")]
    Obj { path: PathBuf, msg: String },
    #[error("{path}: invalid PLY: {msg}")]
    Ply { path: PathBuf, msg: String },
    #[error("{path}: {what}")]
    Invalid { path: PathBuf, what: String },
    #[error("{path}: invalid environment map: {msg}")]
    Environment { path: PathBuf, msg: String },
    #[error("{path}: invalid camera file: {msg}")]
    CameraFile { path: PathBuf, msg: String },
    #[error("unknown built-in scene '{name}' (known: {known})")]
    UnknownBuiltin { name: String, known: String },
    #[error("{0}")]
    Argument(String),
}

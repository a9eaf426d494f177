//! Errors raised while reading scenes, environments and cameras. Each one names the file and what
//! was wrong with it, so that the command line can print it as one line.

use std::path::PathBuf;

/// `s` on one line: line breaks written as `\n`, other control characters escaped. Messages
/// that echo what a user typed or a file held go through it, so that an error is always one
/// line.
pub fn one_line(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push(' '),
            c if c.is_control() => out.extend(c.escape_default()),
            c => out.push(c),
        }
    }
    out
}

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
    #[error("{}: invalid glTF: {}", one_line(&path.display().to_string()), one_line(msg))]
    Gltf { path: PathBuf, msg: String },
    #[error("{path}: requires glTF extension {extension}, which nearfield does not support")]
    UnsupportedExtension { path: PathBuf, extension: String },
    #[error("{}: invalid OBJ: {}", one_line(&path.display().to_string()), one_line(msg))]
    Obj { path: PathBuf, msg: String },
    #[error("{}: invalid PLY: {}", one_line(&path.display().to_string()), one_line(msg))]
    Ply { path: PathBuf, msg: String },
    #[error("{}: {}", one_line(&path.display().to_string()), one_line(what))]
    Invalid { path: PathBuf, what: String },
    #[error("{}: invalid environment map: {}", one_line(&path.display().to_string()), one_line(msg))]
    Environment { path: PathBuf, msg: String },
    #[error("{}: invalid camera file: {}", one_line(&path.display().to_string()), one_line(msg))]
    CameraFile { path: PathBuf, msg: String },
    #[error("{}: invalid camera path: {}", one_line(&path.display().to_string()), one_line(msg))]
    PathFile { path: PathBuf, msg: String },
    #[error("unknown built-in scene '{}' (known: {known})", one_line(name))]
    UnknownBuiltin { name: String, known: String },
    #[error("{}", one_line(.0))]
    Argument(String),
}

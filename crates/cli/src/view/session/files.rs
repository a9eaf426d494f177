//! What the session reads and writes in words and files: environment names, camera files.

use nearfield_scene::{Camera, CameraFile, EnvSource};
use std::path::Path;

/// How an environment source is typed after `--env`.
pub fn env_name(source: &EnvSource) -> String {
    match source {
        EnvSource::Sky => "sky".into(),
        EnvSource::File(p) => p.display().to_string(),
        EnvSource::Constant(c) => format!("constant:{},{},{}", c.x, c.y, c.z),
    }
}

/// Writes the camera JSON of docs/src/conventions.md (what `render --camera` and
/// `reference --camera` read).
pub fn save_camera(camera: &Camera, path: &Path) -> Result<(), String> {
    crate::output::check_parent_dir(path).map_err(|e| e.to_string())?;
    let text = serde_json::to_string_pretty(&CameraFile::from_camera(camera))
        .map_err(|e| e.to_string())?;
    crate::output::save_atomically(path, |tmp| {
        std::fs::write(tmp, format!("{text}\n")).map_err(anyhow::Error::from)
    })
    .map_err(|e| format!("{e:#}"))
}

//! Recording the viewer's camera as a camera path (docs/src/conventions.md, "Camera paths"): one
//! keyframe per rendered frame at [`FPS`] frames per second, so that `render --path` and
//! `compare --path` play the frames the viewer showed, camera for camera.

use nearfield_scene::Camera;
use nearfield_scene::path::{CameraPath, Keyframe};
use std::path::{Path, PathBuf};

/// The frame rate a recording is written at.
pub const FPS: f32 = 30.0;

/// A recording under way: where it goes and the camera of every frame since it started.
pub struct Recording {
    pub path: PathBuf,
    cameras: Vec<Camera>,
}

impl Recording {
    /// Starts a recording into `path` (checked now, written by [`Self::finish`]).
    pub fn start(path: &Path) -> Result<Self, String> {
        if path.extension().and_then(|e| e.to_str()) != Some("json") {
            return Err(format!(
                "record-path {}: must be a .json file",
                path.display()
            ));
        }
        crate::output::check_parent_dir(path).map_err(|e| e.to_string())?;
        Ok(Recording {
            path: path.to_path_buf(),
            cameras: Vec::new(),
        })
    }

    /// The camera of a rendered frame.
    pub fn frame(&mut self, camera: Camera) {
        self.cameras.push(camera);
    }

    /// Frames recorded so far.
    pub fn frames(&self) -> usize {
        self.cameras.len()
    }

    /// Writes the path: a keyframe per frame (the first frame at t = 0), or the camera `now`
    /// alone when no frame was rendered since the start.
    pub fn finish(self, now: Camera) -> Result<PathBuf, String> {
        let cameras = if self.cameras.is_empty() {
            vec![now]
        } else {
            self.cameras
        };
        let keys = cameras
            .iter()
            .enumerate()
            .map(|(i, c)| Keyframe::from((i as f32 / FPS, *c)));
        let path = CameraPath::new(FPS, keys).map_err(|e| format!("record-path: {e}"))?;
        let text = serde_json::to_string_pretty(&path.file()).map_err(|e| e.to_string())?;
        crate::output::save_atomically(&self.path, |tmp| {
            std::fs::write(tmp, format!("{text}\n")).map_err(anyhow::Error::from)
        })
        .map_err(|e| format!("{e:#}"))?;
        Ok(self.path)
    }
}

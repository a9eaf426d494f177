//! Writing results: checks made before anything is rendered (the extension, the directory) and
//! atomic writes (a failed write never leaves a truncated file).

use crate::BadInput;
use anyhow::{Context, Result};
use nearfield_render::Aov;
use std::path::Path;

/// Checks that `path` can take `aov` before anything is rendered.
pub fn check_output(aov: Aov, path: &Path) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let want = if aov == Aov::Final { "png" } else { "exr" };
    if ext != want {
        return Err(BadInput(format!(
            "{}: the {} AOV is written as .{want}",
            path.display(),
            aov.name()
        ))
        .into());
    }
    check_parent_dir(path)
}

/// Fails (exit 2) when the directory that would hold `path` does not exist.
pub fn check_parent_dir(path: &Path) -> Result<()> {
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(dir) = parent
        && !dir.is_dir()
    {
        return Err(BadInput(format!(
            "{}: directory {} does not exist",
            path.display(),
            dir.display()
        ))
        .into());
    }
    Ok(())
}

/// Writes a float AOV as an RGBA float EXR (alpha 0 on background).
pub fn write_exr(img: &nearfield_render::AovImage, path: &Path) -> Result<()> {
    let flat: Vec<f32> = img.pixels.iter().flatten().copied().collect();
    let buf = image::Rgba32FImage::from_raw(img.width, img.height, flat)
        .context("AOV image has a wrong size")?;
    save_atomically(path, |tmp| {
        buf.save_with_format(tmp, image::ImageFormat::OpenExr)
            .map_err(anyhow::Error::from)
    })
}

/// Writes via a temporary file in the same directory, then renames: a failed write never leaves
/// a truncated file behind ([`nearfield_scene::atomic`]).
pub fn save_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    nearfield_scene::atomic::write_atomically(path, |tmp| write(tmp).map_err(|e| format!("{e:#}")))
        .map_err(anyhow::Error::msg)
}

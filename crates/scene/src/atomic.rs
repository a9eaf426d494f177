//! Writing files so that a reader never sees half of one: every output of nearfield (images,
//! AOVs, the reference cache, compare's report, bench JSON, the viewer's screenshots and camera
//! files) is written to a temporary file beside its destination and renamed over it, so a
//! failed or interrupted write (a full disk, a lost device, a kill) leaves either the old file
//! or none, never a truncated one.

use std::path::{Path, PathBuf};

/// The temporary name `path` is written under: hidden, beside it, unique to this process.
pub fn temporary_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.partial", std::process::id()))
}

/// Calls `write` with a temporary path beside `path`, then renames it to `path`. On an error
/// the temporary file is removed and `path` is untouched.
pub fn write_atomically<E: std::fmt::Display>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), String> {
    let tmp = temporary_path(path);
    let result = write(&tmp)
        .map_err(|e| e.to_string())
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| e.to_string()));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// [`write_atomically`] of bytes.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), String> {
    write_atomically(path, |tmp| std::fs::write(tmp, bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let dir = std::env::temp_dir().join(format!("nearfield-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("out.txt");
        write_bytes(&p, b"first").unwrap();
        let e = write_atomically(&p, |tmp| {
            std::fs::write(tmp, b"half").unwrap();
            Err("the device was lost")
        })
        .unwrap_err();
        assert!(e.contains("device was lost"), "{e}");
        assert_eq!(std::fs::read(&p).unwrap(), b"first");
        assert!(!temporary_path(&p).exists());
        write_bytes(&p, b"second").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

//! The reference cache: the same scene, camera, size, AOV, radius, spp, seed (and environment,
//! max depth) reuse the stored EXR. The key is an FNV-1a hash of a canonical description that
//! includes each input file's path, size and modification time, so an edited file misses.

use std::path::{Path, PathBuf};

/// 64-bit FNV-1a (stable across builds and platforms, unlike `std`'s hasher).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// "path:size:mtime" of a file, or the text itself when it names no file (built-ins, `sky`).
pub fn describe_input(s: &str) -> String {
    let p = Path::new(s);
    match std::fs::metadata(p) {
        Ok(m) => {
            let mtime = m
                .modified()
                .ok()
                .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
                .map(|d| d.as_nanos())
                .unwrap_or(0);
            let canonical = std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
            format!("{}:{}:{}", canonical.display(), m.len(), mtime)
        }
        Err(_) => s.to_string(),
    }
}

/// The cache folder: `$NEARFIELD_CACHE`, else `$XDG_CACHE_HOME/nearfield`, else
/// `~/.cache/nearfield`, else the system temp folder.
pub fn cache_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("NEARFIELD_CACHE") {
        return PathBuf::from(d);
    }
    if let Some(d) = std::env::var_os("XDG_CACHE_HOME") {
        return PathBuf::from(d).join("nearfield");
    }
    if let Some(h) = std::env::var_os("HOME") {
        return PathBuf::from(h).join(".cache/nearfield");
    }
    std::env::temp_dir().join("nearfield-cache")
}

/// Path of the cached reference for a key description.
pub fn path_for(description: &str) -> PathBuf {
    cache_dir()
        .join("reference")
        .join(format!("{:016x}.exr", fnv1a(description.as_bytes())))
}

#[cfg(test)]
mod tests {
    #[test]
    fn fnv1a_known_values() {
        assert_eq!(super::fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(super::fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
    }
}

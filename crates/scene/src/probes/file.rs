//! The probe-volume file (`.nfv`, written by `nearfield bake --out`, and the bake cache): one
//! little-endian binary layout, read and written here only.
//!
//! ```text
//! "NFPROBES"                      8 bytes
//! version                         u32 (VERSION)
//! key                             u64 (what it was baked from; 0 = unknown)
//! origin xyz, spacing xyz         6 × f32
//! counts xyz                      3 × u32
//! vis_res, rays, bounces          3 × u32
//! max_distance                    f32
//! per probe:  offset xyz, active (u32 0/1), 9 × rgb SH     4 × 4 + 27 × 4 bytes
//! per probe:  vis_res² × (mean, mean²) / max_distance^k    vis_res² × 8 bytes
//! ```
//! The header is checked against the probe budget before anything is allocated, the file's length
//! must be exactly what the header implies, and every number must be finite: a truncated,
//! hostile or older file is one error line, never a panic or a huge allocation.

use super::{MAX_PROBES, Probe, ProbeGrid, ProbeVolume, SH_COEFFS, VIS_RES, VIS_TILE};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// The layout version this build reads and writes.
pub const VERSION: u32 = 1;
const MAGIC: &[u8; 8] = b"NFPROBES";
const HEADER_BYTES: usize = 8 + 4 + 8 + 6 * 4 + 3 * 4 + 3 * 4 + 4;
const PROBE_BYTES: usize = 4 * 4 + SH_COEFFS * 3 * 4;
const VIS_BYTES: usize = (VIS_RES * VIS_RES) as usize * 8;

#[derive(Debug, thiserror::Error)]
pub enum ProbeFileError {
    #[error("{path}: cannot read the probe volume: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: not a nearfield probe volume (no NFPROBES header)")]
    NotAVolume { path: PathBuf },
    #[error(
        "{path}: probe volume version {found}; this nearfield reads version {VERSION} (bake it again)"
    )]
    Version { path: PathBuf, found: u32 },
    #[error(
        "{path}: truncated or padded probe volume: {found} bytes, the header implies {expected}"
    )]
    Length {
        path: PathBuf,
        found: u64,
        expected: u64,
    },
    #[error("{path}: invalid probe volume: {what}")]
    Invalid { path: PathBuf, what: String },
}

impl ProbeVolume {
    /// The file's bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut b =
            Vec::with_capacity(HEADER_BYTES + self.probes.len() * (PROBE_BYTES + VIS_BYTES));
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&VERSION.to_le_bytes());
        b.extend_from_slice(&self.key.to_le_bytes());
        let g = &self.grid;
        for f in g.origin.to_array().into_iter().chain(g.spacing.to_array()) {
            b.extend_from_slice(&f.to_le_bytes());
        }
        for u in g
            .counts
            .into_iter()
            .chain([VIS_RES, self.rays, self.bounces])
        {
            b.extend_from_slice(&u.to_le_bytes());
        }
        b.extend_from_slice(&self.max_distance.to_le_bytes());
        for p in &self.probes {
            for f in p.offset.to_array() {
                b.extend_from_slice(&f.to_le_bytes());
            }
            b.extend_from_slice(&u32::from(p.active).to_le_bytes());
            for c in &p.sh {
                for f in c.to_array() {
                    b.extend_from_slice(&f.to_le_bytes());
                }
            }
        }
        let tile = (VIS_TILE * VIS_TILE) as usize;
        for i in 0..self.probes.len() {
            let t = &self.visibility[i * tile..(i + 1) * tile];
            for y in 0..VIS_RES {
                for x in 0..VIS_RES {
                    let m = t[((y + 1) * VIS_TILE + x + 1) as usize];
                    b.extend_from_slice(&m[0].to_le_bytes());
                    b.extend_from_slice(&m[1].to_le_bytes());
                }
            }
        }
        b
    }

    /// Writes the volume to `path` atomically.
    pub fn write(&self, path: &Path) -> Result<(), String> {
        crate::atomic::write_bytes(path, &self.to_bytes())
    }

    /// Reads a volume written by [`Self::write`].
    pub fn read(path: &Path) -> Result<Self, ProbeFileError> {
        let io = |source| ProbeFileError::Io {
            path: path.to_path_buf(),
            source,
        };
        let meta = std::fs::metadata(path).map_err(io)?;
        if !meta.is_file() {
            return Err(ProbeFileError::Invalid {
                path: path.to_path_buf(),
                what: "not a regular file".into(),
            });
        }
        let max_len = (HEADER_BYTES + MAX_PROBES * (PROBE_BYTES + VIS_BYTES)) as u64;
        if meta.len() > max_len {
            return Err(ProbeFileError::Invalid {
                path: path.to_path_buf(),
                what: format!(
                    "{} bytes, more than any volume within the probe budget",
                    meta.len()
                ),
            });
        }
        let bytes = std::fs::read(path).map_err(io)?;
        Self::from_bytes(&bytes, path)
    }

    /// Parses the file's bytes (`path` names it in errors).
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, ProbeFileError> {
        let path_buf = || path.to_path_buf();
        let invalid = |what: String| ProbeFileError::Invalid {
            path: path_buf(),
            what,
        };
        if bytes.len() < 12 || &bytes[..8] != MAGIC {
            return Err(ProbeFileError::NotAVolume { path: path_buf() });
        }
        let mut r = Reader { bytes, at: 8 };
        let version = r.u32();
        if version != VERSION {
            return Err(ProbeFileError::Version {
                path: path_buf(),
                found: version,
            });
        }
        if bytes.len() < HEADER_BYTES {
            return Err(ProbeFileError::Length {
                path: path_buf(),
                found: bytes.len() as u64,
                expected: HEADER_BYTES as u64,
            });
        }
        let key = r.u64();
        let origin = r.vec3();
        let spacing = r.vec3();
        let counts = [r.u32(), r.u32(), r.u32()];
        let (vis_res, rays, bounces) = (r.u32(), r.u32(), r.u32());
        let max_distance = r.f32();
        if !(origin.is_finite() && spacing.is_finite() && spacing.min_element() > 0.0) {
            return Err(invalid(
                "the grid's origin or spacing is not finite and positive".into(),
            ));
        }
        let count = counts.iter().map(|&c| c as u64).product::<u64>();
        if counts.contains(&0) || count > MAX_PROBES as u64 {
            return Err(invalid(format!(
                "{}×{}×{} probes: each count must be ≥ 1 and the total within the budget of {MAX_PROBES}",
                counts[0], counts[1], counts[2]
            )));
        }
        if vis_res != VIS_RES {
            return Err(invalid(format!(
                "visibility maps of {vis_res}² texels; this nearfield reads {VIS_RES}²"
            )));
        }
        if !(max_distance.is_finite() && max_distance > 0.0) {
            return Err(invalid(format!("max distance {max_distance}")));
        }
        let n = count as usize;
        let expected = (HEADER_BYTES + n * (PROBE_BYTES + VIS_BYTES)) as u64;
        if bytes.len() as u64 != expected {
            return Err(ProbeFileError::Length {
                path: path_buf(),
                found: bytes.len() as u64,
                expected,
            });
        }
        let mut probes = Vec::with_capacity(n);
        for i in 0..n {
            let offset = r.vec3();
            let active = match r.u32() {
                0 => false,
                1 => true,
                other => return Err(invalid(format!("probe {i}: state {other}"))),
            };
            let sh: [Vec3; SH_COEFFS] = std::array::from_fn(|_| r.vec3());
            if !offset.is_finite() || sh.iter().any(|c| !c.is_finite()) {
                return Err(invalid(format!("probe {i}: a number is not finite")));
            }
            probes.push(Probe { offset, active, sh });
        }
        let tile = (VIS_TILE * VIS_TILE) as usize;
        let mut visibility = Vec::with_capacity(n * tile);
        let mut interior = vec![[0f32; 2]; (VIS_RES * VIS_RES) as usize];
        for i in 0..n {
            for m in interior.iter_mut() {
                *m = [r.f32(), r.f32()];
                if !(m[0].is_finite() && m[1].is_finite() && m[0] >= 0.0 && m[1] >= 0.0) {
                    return Err(invalid(format!("probe {i}: visibility moments {m:?}")));
                }
            }
            visibility.extend(super::bordered_tile(&interior));
        }
        Ok(ProbeVolume {
            grid: ProbeGrid {
                origin,
                spacing,
                counts,
            },
            max_distance,
            probes,
            visibility,
            rays,
            bounces,
            key,
        })
    }
}

/// Little-endian reads from a slice whose length was checked.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let v = self.bytes[self.at..self.at + N]
            .try_into()
            .expect("checked length");
        self.at += N;
        v
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.take())
    }
    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.take())
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.take())
    }
    fn vec3(&mut self) -> Vec3 {
        Vec3::new(self.f32(), self.f32(), self.f32())
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::constant_volume;
    use super::*;

    fn sample() -> ProbeVolume {
        let mut v = constant_volume(Vec3::new(0.2, 0.4, 0.6), [3, 2, 2]);
        v.probes[3].active = false;
        v.probes[5].offset = Vec3::new(0.01, -0.02, 0.03);
        v.probes[7].sh[4] = Vec3::new(-0.5, 0.25, 3.0);
        let tile = (VIS_TILE * VIS_TILE) as usize;
        let mut interior = vec![[0f32; 2]; (VIS_RES * VIS_RES) as usize];
        for i in 0..v.probes.len() {
            for (k, m) in interior.iter_mut().enumerate() {
                let d = (i * 7 + k) as f32 / 1000.0;
                *m = [d, d * d];
            }
            v.visibility[i * tile..(i + 1) * tile]
                .copy_from_slice(&super::super::bordered_tile(&interior));
        }
        v.key = 0x1234_5678_9abc_def0;
        v
    }

    #[test]
    fn round_trip() {
        let v = sample();
        let back = ProbeVolume::from_bytes(&v.to_bytes(), Path::new("t.nfv")).unwrap();
        assert_eq!(back, v);
    }

    #[test]
    fn bad_files_are_one_error() {
        let p = Path::new("t.nfv");
        let bytes = sample().to_bytes();
        let e = ProbeVolume::from_bytes(&bytes[..bytes.len() - 1], p).unwrap_err();
        assert!(matches!(e, ProbeFileError::Length { .. }), "{e}");
        let e = ProbeVolume::from_bytes(&bytes[..30], p).unwrap_err();
        assert!(matches!(e, ProbeFileError::Length { .. }), "{e}");
        let e = ProbeVolume::from_bytes(b"hello world, not a volume", p).unwrap_err();
        assert!(matches!(e, ProbeFileError::NotAVolume { .. }), "{e}");
        let mut old = bytes.clone();
        old[8..12].copy_from_slice(&0u32.to_le_bytes());
        let e = ProbeVolume::from_bytes(&old, p).unwrap_err();
        assert!(matches!(e, ProbeFileError::Version { found: 0, .. }), "{e}");
        // Counts beyond the budget are refused before the length is even looked at.
        let mut huge = bytes.clone();
        huge[44..48].copy_from_slice(&u32::MAX.to_le_bytes());
        let e = ProbeVolume::from_bytes(&huge, p).unwrap_err();
        assert!(matches!(e, ProbeFileError::Invalid { .. }), "{e}");
        let mut nan = bytes.clone();
        let first_sh = HEADER_BYTES + 16;
        nan[first_sh..first_sh + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = ProbeVolume::from_bytes(&nan, p).unwrap_err();
        assert!(matches!(e, ProbeFileError::Invalid { .. }), "{e}");
        for e in [
            ProbeVolume::from_bytes(&bytes[..bytes.len() - 1], p).unwrap_err(),
            ProbeVolume::from_bytes(&old, p).unwrap_err(),
        ] {
            assert!(!e.to_string().contains('\n'));
        }
    }
}

//! The probe volume as Bevy's irradiance volume (`nearfield bake --format bevy`): the ambient
//! cube texture that `bevy_pbr`'s `IrradianceVolume` reads, in a KTX2 file.
//!
//! Bevy's volume of resolution (Rx, Ry, Rz) is a 3D texture of (Rx, 2Ry, 3Rz) texels: per
//! voxel (x, y, z) and side S of the cube, texel (x, y + o_S, z + a_S·Rz), where a_S is 0, 1, 2
//! for the X, Y and Z sides and o_S is 0 for the positive side and Ry for the negative one (what
//! Bevy 0.20's `irradiance_volume.wesl` samples: the negative half of each slab is the one it
//! reads where the normal's component is below 0). It blends the three sides the normal faces
//! by the squares of the normal's components (Valve's ambient cube) and multiplies the result
//! by the diffuse colour: a texel holds E(±axis)/π, the outgoing radiance of a white Lambertian
//! surface facing that way — [`ProbeVolume::irradiance`]'s quantity, so the value on each axis
//! is exactly ours.
//!
//! Bevy stretches the voxels over a unit cube centred on its `Transform`; probe (i, j, k) of a
//! grid stands at the centre of its cell, so the transform is the grid's box: translation
//! [`BevyVolume::translation`], scale [`BevyVolume::scale`] (counts × spacing), no rotation.
//! Switched-off probes (inside geometry) take the mean of their active neighbours, repeated
//! until every probe has a value, because Bevy filters trilinearly and knows no visibility.
//!
//! The texels are RGBA16F (alpha 1), the format Bevy filters on every backend. Where a value
//! exceeds half precision's largest (65504) the whole texture is scaled by a power of two and
//! [`BevyVolume::intensity`] (the `IrradianceVolume::intensity` to set) undoes it.

use super::ProbeVolume;
use crate::sh;
use glam::Vec3;

/// The six sides in Bevy's slab order: X, Y, Z, positive then negative.
pub const SIDES: [(usize, f32); 6] = [
    (0, 1.0),
    (0, -1.0),
    (1, 1.0),
    (1, -1.0),
    (2, 1.0),
    (2, -1.0),
];

/// Vulkan's `VK_FORMAT_R16G16B16A16_SFLOAT`, the KTX2 header's format.
pub const VK_FORMAT_R16G16B16A16_SFLOAT: u32 = 97;
/// The largest finite half-precision value.
pub const HALF_MAX: f32 = 65504.0;

/// A probe volume in Bevy's layout.
#[derive(Clone, Debug, PartialEq)]
pub struct BevyVolume {
    /// Texture size (Rx, 2Ry, 3Rz).
    pub size: [u32; 3],
    /// RGB per texel, x fastest, then y, then z; already multiplied by `1 / intensity`.
    pub texels: Vec<Vec3>,
    /// The `IrradianceVolume::intensity` that restores nearfield's units (1 unless scaled).
    pub intensity: f32,
    /// The volume's `Transform`: translation (m).
    pub translation: Vec3,
    /// The volume's `Transform`: scale (m), the grid's box.
    pub scale: Vec3,
}

/// Texel index of voxel `v` on side `side` (an index into [`SIDES`]) in a texture of voxel
/// resolution `r`.
pub fn texel_index(r: [u32; 3], v: [u32; 3], side: usize) -> usize {
    let (axis, sign) = SIDES[side];
    let t = v[1] + if sign < 0.0 { r[1] } else { 0 };
    let p = v[2] + axis as u32 * r[2];
    ((p * 2 * r[1] + t) * r[0] + v[0]) as usize
}

impl BevyVolume {
    /// Converts a baked volume.
    pub fn from_volume(volume: &ProbeVolume) -> Self {
        let g = &volume.grid;
        let r = g.counts;
        let filled = fill_inactive(volume);
        let mut texels = vec![Vec3::ZERO; (r[0] * 2 * r[1] * 3 * r[2]) as usize];
        for (index, sh) in filled.iter().enumerate() {
            let v = g.coords(index);
            for (side, &(axis, sign)) in SIDES.iter().enumerate() {
                let mut n = Vec3::ZERO;
                n[axis] = sign;
                texels[texel_index(r, v, side)] = sh::irradiance_over_pi(sh, n).max(Vec3::ZERO);
            }
        }
        let largest = texels
            .iter()
            .map(|t| t.max_element())
            .fold(0.0f32, f32::max);
        let mut scale = 1.0f32;
        while largest * scale > HALF_MAX {
            scale *= 0.5;
        }
        if scale != 1.0 {
            for t in &mut texels {
                *t *= scale;
            }
        }
        let size = g.spacing * Vec3::new(r[0] as f32, r[1] as f32, r[2] as f32);
        BevyVolume {
            size: [r[0], 2 * r[1], 3 * r[2]],
            texels,
            intensity: 1.0 / scale,
            translation: g.origin - 0.5 * g.spacing + 0.5 * size,
            scale: size,
        }
    }

    /// The KTX2 file: one level, one layer, one face, RGBA16F, a basic data format descriptor,
    /// and key/value data `nearfield.transform` (translation, scale and intensity as JSON).
    pub fn to_ktx2(&self) -> Vec<u8> {
        let mut data = Vec::with_capacity(self.texels.len() * 8);
        for t in &self.texels {
            for c in [t.x, t.y, t.z, 1.0] {
                data.extend_from_slice(&half::f16::from_f32(c).to_le_bytes());
            }
        }
        let kv_value = format!(
            "{{\"translation\":[{},{},{}],\"scale\":[{},{},{}],\"intensity\":{}}}",
            self.translation.x,
            self.translation.y,
            self.translation.z,
            self.scale.x,
            self.scale.y,
            self.scale.z,
            self.intensity
        );
        let mut kvd = Vec::new();
        for (k, v) in [
            ("KTXwriter", "nearfield"),
            ("nearfield.transform", kv_value.as_str()),
        ] {
            let len = k.len() + 1 + v.len() + 1;
            kvd.extend_from_slice(&(len as u32).to_le_bytes());
            kvd.extend_from_slice(k.as_bytes());
            kvd.push(0);
            kvd.extend_from_slice(v.as_bytes());
            kvd.push(0);
            while kvd.len() % 4 != 0 {
                kvd.push(0);
            }
        }
        let dfd = dfd_rgba16f();

        // identifier, header (9 × u32), index (4 × u32 + 2 × u64), one level (3 × u64)
        let header_len = 12 + 9 * 4 + 4 * 4 + 2 * 8 + 3 * 8;
        let dfd_offset = header_len;
        let kvd_offset = dfd_offset + dfd.len();
        let mut data_offset = kvd_offset + kvd.len();
        // level data is aligned to lcm(texel block size 8, 4)
        let padding = (8 - data_offset % 8) % 8;
        data_offset += padding;

        let mut b = Vec::with_capacity(data_offset + data.len());
        b.extend_from_slice(&[
            0xAB, b'K', b'T', b'X', b' ', b'2', b'0', 0xBB, b'\r', b'\n', 0x1A, b'\n',
        ]);
        for v in [
            VK_FORMAT_R16G16B16A16_SFLOAT,
            2, // typeSize
            self.size[0],
            self.size[1],
            self.size[2],
            0, // layerCount: not an array
            1, // faceCount
            1, // levelCount
            0, // no supercompression
        ] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        for v in [
            dfd_offset as u32,
            dfd.len() as u32,
            kvd_offset as u32,
            kvd.len() as u32,
        ] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&0u64.to_le_bytes()); // sgdByteOffset
        b.extend_from_slice(&0u64.to_le_bytes()); // sgdByteLength
        for v in [data_offset as u64, data.len() as u64, data.len() as u64] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        debug_assert_eq!(b.len(), header_len);
        b.extend_from_slice(&dfd);
        b.extend_from_slice(&kvd);
        b.resize(data_offset, 0);
        b.extend_from_slice(&data);
        b
    }
}

/// The data format descriptor of linear RGBA16F (Khronos Data Format 1.3, one basic block).
fn dfd_rgba16f() -> Vec<u8> {
    const SAMPLES: u32 = 4;
    let block_size = 24 + 16 * SAMPLES;
    let mut d = Vec::new();
    d.extend_from_slice(&(4 + block_size).to_le_bytes()); // dfdTotalSize
    d.extend_from_slice(&0u32.to_le_bytes()); // vendor 0 (Khronos), descriptor type 0 (basic)
    d.extend_from_slice(&(2 | (block_size << 16)).to_le_bytes()); // version 2, block size
    d.extend_from_slice(&[1, 1, 1, 0]); // model RGBSDA, primaries BT.709, transfer linear, flags
    d.extend_from_slice(&[0, 0, 0, 0]); // texel block 1×1×1×1
    d.extend_from_slice(&[8, 0, 0, 0, 0, 0, 0, 0]); // 8 bytes in plane 0
    for (i, channel) in [0u8, 1, 2, 15].into_iter().enumerate() {
        let bit_offset = (16 * i) as u16;
        d.extend_from_slice(&bit_offset.to_le_bytes());
        d.push(15); // bit length − 1
        d.push(channel | 0x80 | 0x40); // FLOAT | SIGNED
        d.extend_from_slice(&[0, 0, 0, 0]); // sample position
        d.extend_from_slice(&(-1.0f32).to_bits().to_le_bytes()); // sampleLower
        d.extend_from_slice(&1.0f32.to_bits().to_le_bytes()); // sampleUpper
    }
    d
}

/// Every probe's SH, switched-off probes replaced by the mean of their active (or already
/// filled) face neighbours, sweep after sweep until all have one (all zero when none is active).
fn fill_inactive(volume: &ProbeVolume) -> Vec<[Vec3; super::SH_COEFFS]> {
    let g = &volume.grid;
    let mut sh: Vec<_> = volume.probes.iter().map(|p| p.sh).collect();
    let mut known: Vec<bool> = volume.probes.iter().map(|p| p.active).collect();
    if !known.iter().any(|&k| k) {
        return vec![[Vec3::ZERO; super::SH_COEFFS]; sh.len()];
    }
    while known.iter().any(|&k| !k) {
        let mut next = known.clone();
        for i in 0..sh.len() {
            if known[i] {
                continue;
            }
            let c = g.coords(i);
            let mut sum = [Vec3::ZERO; super::SH_COEFFS];
            let mut n = 0;
            for axis in 0..3 {
                for d in [-1i64, 1] {
                    let q = c[axis] as i64 + d;
                    if q < 0 || q >= g.counts[axis] as i64 {
                        continue;
                    }
                    let mut cc = c;
                    cc[axis] = q as u32;
                    let j = g.index(cc);
                    if known[j] {
                        for (s, t) in sum.iter_mut().zip(&sh[j]) {
                            *s += *t;
                        }
                        n += 1;
                    }
                }
            }
            if n > 0 {
                for s in &mut sum {
                    *s /= n as f32;
                }
                sh[i] = sum;
                next[i] = true;
            }
        }
        known = next;
    }
    sh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::probes::{Probe, ProbeGrid};

    fn volume(active: impl Fn(usize) -> bool) -> ProbeVolume {
        let grid = ProbeGrid {
            origin: Vec3::new(-1.0, 0.5, 2.0),
            spacing: Vec3::new(1.0, 0.5, 2.0),
            counts: [3, 2, 4],
        };
        let probes = (0..grid.count())
            .map(|i| {
                let mut sh = [Vec3::ZERO; super::super::SH_COEFFS];
                sh[0] = Vec3::splat(1.0 + i as f32);
                sh[1] = Vec3::new(0.3, 0.0, 0.1);
                sh[3] = Vec3::new(-0.2, 0.1, 0.0);
                Probe {
                    offset: Vec3::ZERO,
                    active: active(i),
                    sh,
                }
            })
            .collect();
        ProbeVolume {
            grid,
            max_distance: 1.0,
            probes,
            visibility: Vec::new(),
            rays: 1,
            bounces: 1,
            key: 0,
        }
    }

    #[test]
    fn the_transform_is_the_grid_box() {
        let b = BevyVolume::from_volume(&volume(|_| true));
        assert_eq!(b.size, [3, 4, 12]);
        // cells from origin − spacing/2 to that + counts·spacing
        assert_eq!(b.scale, Vec3::new(3.0, 1.0, 8.0));
        assert_eq!(b.translation, Vec3::new(0.0, 0.75, 5.0));
        assert_eq!(b.intensity, 1.0);
    }

    #[test]
    fn every_texel_is_written_once() {
        let r = [3, 2, 4];
        let mut seen = vec![0; 3 * 4 * 12];
        for z in 0..r[2] {
            for y in 0..r[1] {
                for x in 0..r[0] {
                    for side in 0..6 {
                        seen[texel_index(r, [x, y, z], side)] += 1;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
    }

    #[test]
    fn switched_off_probes_take_their_neighbours_mean() {
        let v = volume(|i| i != 0);
        let b = BevyVolume::from_volume(&v);
        let g = &v.grid;
        // probe 0's neighbours: (1,0,0), (0,1,0), (0,0,1)
        let neighbours = [g.index([1, 0, 0]), g.index([0, 1, 0]), g.index([0, 0, 1])];
        let mut mean = [Vec3::ZERO; super::super::SH_COEFFS];
        for &j in &neighbours {
            for (m, s) in mean.iter_mut().zip(&v.probes[j].sh) {
                *m += *s / 3.0;
            }
        }
        let want = sh::irradiance_over_pi(&mean, Vec3::X).max(Vec3::ZERO);
        let got = b.texels[texel_index(g.counts, [0, 0, 0], 0)];
        assert!((got - want).abs().max_element() < 1e-5, "{got} {want}");
    }

    #[test]
    fn values_beyond_half_precision_are_scaled_and_the_intensity_undoes_it() {
        let mut v = volume(|_| true);
        for p in &mut v.probes {
            for s in &mut p.sh {
                *s *= 1e5;
            }
        }
        let b = BevyVolume::from_volume(&v);
        assert!(b.intensity > 1.0 && b.intensity.log2().fract() == 0.0);
        let largest = b
            .texels
            .iter()
            .map(|t| t.max_element())
            .fold(0.0f32, f32::max);
        assert!(largest <= HALF_MAX && largest > HALF_MAX / 2.0, "{largest}");
    }
}

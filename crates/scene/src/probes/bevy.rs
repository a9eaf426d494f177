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
//! Bevy interpolates its voxels trilinearly and knows no visibility: a surface between a probe
//! in a lit room and one behind the wall reads half of each (a dark band along every wall that
//! the grid straddles), where nearfield's own lookup ([`ProbeVolume::weights`]: the normal and
//! view offset, Chebyshev's visibility) leaves the probe behind the wall out. So the texture is
//! not the probes themselves but nearfield's lookup resampled: [`SUBDIVISION`] voxels per probe
//! spacing and axis, each side S of a voxel holding [`ProbeVolume::irradiance`] at the voxel's
//! centre for a surface facing S seen from the front (n = v = S). A side is read by Bevy only
//! for normals that face it, and the lookup's offset along S moves its point off a wall the
//! voxel may lie behind, so that a wall's surface is lit by the side of it it faces. Where no
//! probe around a voxel is active the nearest probe's light stands in (switched-off probes
//! filled with their active neighbours' mean).
//!
//! Bevy stretches the voxels over a unit cube centred on its `Transform` and weights a light
//! probe by a ramp that is 0 on its box's faces, so a surface on the grid's box (a floor on the
//! scene's bounds, where the default grid ends) would get no light from a box of exactly the
//! grid's cells: the texture has [`PAD`] more voxel on each side of every axis. The transform is
//! then the grid's box (from the first probe's cell to the last's) grown by a voxel on each side:
//! translation [`BevyVolume::translation`], scale [`BevyVolume::scale`], no rotation.
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
/// Voxels added on each side of every axis, beyond the grid's box.
pub const PAD: u32 = 1;
/// Voxels per probe spacing and axis of [`BevyVolume::from_volume`] (measured in
/// docs/src/bevy.md, "The far field").
pub const SUBDIVISION: u32 = 4;

/// A probe volume in Bevy's layout.
#[derive(Clone, Debug, PartialEq)]
pub struct BevyVolume {
    /// Texture size (Rx, 2Ry, 3Rz), R = the grid's counts + 2 [`PAD`].
    pub size: [u32; 3],
    /// RGB per texel, x fastest, then y, then z; already multiplied by `1 / intensity`.
    pub texels: Vec<Vec3>,
    /// The `IrradianceVolume::intensity` that restores nearfield's units (1 unless scaled).
    pub intensity: f32,
    /// The volume's `Transform`: translation (m).
    pub translation: Vec3,
    /// The volume's `Transform`: scale (m), the grid's box.
    pub scale: Vec3,
    /// The baked volume itself (`.nfv` bytes, [`ProbeVolume::to_bytes`]), carried in the file
    /// as `nearfield.volume` for the near-field techniques that read it as their far field.
    pub volume: Vec<u8>,
}

/// The KTX2 key of the transform's JSON.
pub const KEY_TRANSFORM: &str = "nearfield.transform";
/// The KTX2 key of the baked volume's bytes.
pub const KEY_VOLUME: &str = "nearfield.volume";

/// Texel index of voxel `v` on side `side` (an index into [`SIDES`]) in a texture of voxel
/// resolution `r`.
pub fn texel_index(r: [u32; 3], v: [u32; 3], side: usize) -> usize {
    let (axis, sign) = SIDES[side];
    let t = v[1] + if sign < 0.0 { r[1] } else { 0 };
    let p = v[2] + axis as u32 * r[2];
    ((p * 2 * r[1] + t) * r[0] + v[0]) as usize
}

impl BevyVolume {
    /// Converts a baked volume at [`SUBDIVISION`] voxels per probe spacing.
    pub fn from_volume(volume: &ProbeVolume) -> Self {
        Self::resampled(volume, SUBDIVISION)
    }

    /// Converts a baked volume at `k` ≥ 1 voxels per probe spacing and axis (module docs): each
    /// voxel side holds [`ProbeVolume::irradiance`] for a surface at the voxel's centre facing
    /// that side, seen from the front; where no probe around it is active, the nearest probe's
    /// (inactive ones filled with their neighbours' mean).
    pub fn resampled(volume: &ProbeVolume, k: u32) -> Self {
        let k = k.max(1);
        let g = &volume.grid;
        let r = g.counts.map(|c| c * k + 2 * PAD);
        let step = g.spacing / k as f32;
        let cells = |c: [u32; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
        // The grid's box (from the first probe's cell), and the texture's: a voxel more each side.
        let centre = g.origin - 0.5 * g.spacing + 0.5 * g.spacing * cells(g.counts);
        let size = step * cells(r);
        let first = centre - 0.5 * size + 0.5 * step;
        let filled = fill_inactive(volume);
        let max_index = g.counts.map(|c| c as f32 - 1.0);
        let mut texels = vec![Vec3::ZERO; (r[0] * 2 * r[1] * 3 * r[2]) as usize];
        for z in 0..r[2] {
            for y in 0..r[1] {
                for x in 0..r[0] {
                    let p = first + step * cells([x, y, z]);
                    let nearest = {
                        let rel = ((p - g.origin) / g.spacing).round();
                        let c = [0, 1, 2].map(|a| rel[a].clamp(0.0, max_index[a]) as u32);
                        &filled[g.index(c)]
                    };
                    for (side, &(axis, sign)) in SIDES.iter().enumerate() {
                        let mut n = Vec3::ZERO;
                        n[axis] = sign;
                        // ProbeVolume::irradiance, its weights computed once.
                        let w = volume.weights(p, n, n);
                        let sh = if w.weights.iter().any(|w| *w > 0.0) {
                            &volume.sh_with(&w)
                        } else {
                            nearest
                        };
                        texels[texel_index(r, [x, y, z], side)] =
                            sh::irradiance_over_pi(sh, n).max(Vec3::ZERO);
                    }
                }
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
        BevyVolume {
            size: [r[0], 2 * r[1], 3 * r[2]],
            texels,
            intensity: 1.0 / scale,
            translation: centre,
            scale: size,
            volume: volume.to_bytes(),
        }
    }

    /// The KTX2 file: one level, one layer, one face, RGBA16F, a basic data format descriptor,
    /// and key/value data [`KEY_TRANSFORM`] (translation, scale and intensity as JSON) and
    /// [`KEY_VOLUME`] (the `.nfv` bytes, NUL-terminated).
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
        // Sorted by key, as KTX2 asks; each value ends with a NUL (the volume's bytes too, so
        // that a reader that drops a trailing NUL gets them back whole).
        let mut kvd = Vec::new();
        for (k, v) in [
            ("KTXwriter", b"nearfield".as_slice()),
            (KEY_TRANSFORM, kv_value.as_bytes()),
            (KEY_VOLUME, self.volume.as_slice()),
        ] {
            let len = k.len() + 1 + v.len() + 1;
            kvd.extend_from_slice(&(len as u32).to_le_bytes());
            kvd.extend_from_slice(k.as_bytes());
            kvd.push(0);
            kvd.extend_from_slice(v);
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
    use crate::probes::tests::constant_volume;

    /// A 3 × 2 × 4 grid over the 2 m cube whose probes differ (probe i's light grows with i and
    /// leans towards +X and −Y), every probe seeing nothing within its range.
    fn volume(active: impl Fn(usize) -> bool) -> ProbeVolume {
        let mut v = constant_volume(Vec3::ONE, [3, 2, 4]);
        for (i, p) in v.probes.iter_mut().enumerate() {
            p.sh[0] = Vec3::splat(1.0 + i as f32);
            p.sh[1] = Vec3::new(0.3, 0.0, 0.1);
            p.sh[3] = Vec3::new(-0.2, 0.1, 0.0);
            p.active = active(i);
        }
        v
    }

    /// The centre of voxel `v` of the texture (`k` voxels per spacing).
    fn centre(vol: &ProbeVolume, b: &BevyVolume, k: u32, v: [u32; 3]) -> Vec3 {
        let step = vol.grid.spacing / k as f32;
        b.translation - 0.5 * b.scale
            + step * (Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32) + 0.5)
    }

    #[test]
    fn the_transform_is_the_grid_box_grown_by_a_voxel() {
        let v = volume(|_| true);
        let b = BevyVolume::from_volume(&v);
        let r = v.grid.counts.map(|c| c * SUBDIVISION + 2 * PAD);
        assert_eq!(b.size, [r[0], 2 * r[1], 3 * r[2]]);
        let g = &v.grid;
        let cells = Vec3::new(g.counts[0] as f32, g.counts[1] as f32, g.counts[2] as f32);
        let step = g.spacing / SUBDIVISION as f32;
        assert!(
            (b.scale - (g.spacing * cells + 2.0 * step))
                .abs()
                .max_element()
                < 1e-5
        );
        // The grid's box (cells around the probes) has the same centre.
        let box_min = g.origin - 0.5 * g.spacing;
        assert!(
            (b.translation - (box_min + 0.5 * g.spacing * cells))
                .abs()
                .max_element()
                < 1e-5
        );
        assert_eq!(b.intensity, 1.0);
        // The probes stand at voxel centres: probe (0, 0, 0) at voxel (PAD + k/2) − ½ … for
        // even k between two voxels, for k = 1 on voxel PAD.
        let b1 = BevyVolume::resampled(&v, 1);
        let c = centre(&v, &b1, 1, [PAD; 3]);
        assert!(
            (c - g.origin).abs().max_element() < 1e-5,
            "{c} {}",
            g.origin
        );
    }

    #[test]
    fn every_side_is_nearfields_lookup_for_a_surface_facing_it() {
        let v = volume(|i| i != 5);
        for k in [1, 2, 4] {
            let b = BevyVolume::resampled(&v, k);
            let r = v.grid.counts.map(|c| c * k + 2 * PAD);
            for voxel in [
                [0, 0, 0],
                [PAD, PAD, PAD],
                [r[0] / 2, 1, r[2] - 1],
                [2, r[1] - 1, 3],
            ] {
                let p = centre(&v, &b, k, voxel);
                for (side, &(axis, sign)) in SIDES.iter().enumerate() {
                    let mut n = Vec3::ZERO;
                    n[axis] = sign;
                    let want = v.irradiance(p, n, n);
                    let got = b.texels[texel_index(r, voxel, side)];
                    assert!(
                        (got - want).abs().max_element() <= 1e-5 * want.max_element().max(1.0),
                        "k {k} voxel {voxel:?} side {side}: {got} {want}"
                    );
                }
            }
        }
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
    fn where_no_probe_is_active_the_nearest_filled_one_stands_in() {
        // Only probe (2, 1, 3) is on: the far corner's voxels read no active probe, and take
        // the filled mean (the only active probe's light, spread to every probe).
        let g = volume(|_| true).grid;
        let on = g.index([2, 1, 3]);
        let v = volume(|i| i == on);
        let b = BevyVolume::resampled(&v, 1);
        let r = g.counts.map(|c| c + 2 * PAD);
        let want = sh::irradiance_over_pi(&v.probes[on].sh, Vec3::X).max(Vec3::ZERO);
        let got = b.texels[texel_index(r, [PAD; 3], 0)];
        assert!((got - want).abs().max_element() < 1e-5, "{got} {want}");
        assert!(got.max_element() > 0.0);
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

//! The far field as a probe volume (the book, "The far field"): a regular grid of probes, each
//! holding the radiance that arrives at it from every direction and every distance as order-2
//! spherical harmonics (9 RGB coefficients, `crate::sh`'s basis), and its visibility: the mean
//! and mean square distance to the nearest surface per direction, in an octahedral map of
//! [`VIS_RES`]² texels (McGuire et al. 2019, "Dynamic Diffuse Global Illumination with
//! Ray-Traced Irradiance Fields", DDGI).
//!
//! A point P with normal n (seen from v) reads the volume the way DDGI does: the eight probes of
//! its cell, each weighted by
//! - trilinear weight of the point P' = P + bias · (0.3 n + 0.7 v) (`bias` = [`BIAS_FRACTION`]
//!   of the smallest spacing), which keeps P' off its own surface;
//! - a wrap-around backface term ((dir·n + 1)/2)² + 0.2, dir the unit vector from P to the probe;
//! - Chebyshev's bound on the probe seeing P' (visibility), cubed: where P' lies beyond the mean
//!   distance μ the probe records in P's direction, weight σ²/(σ² + (d − μ)²), so that light does
//!   not leak through walls;
//! - weights below 0.2 are crushed (w³/0.04), and switched-off probes weigh nothing.
//!
//! The weights are normalised, and the weighted SH coefficients are the radiance at P. The
//! renderer's `shaders/far.wgsl` evaluates the same weights on the GPU; bakes
//! (`nearfield_reference::bake`) use [`ProbeVolume::irradiance`] to light their hits with the
//! previous bounce.

pub mod bevy;
mod file;
mod grid;
mod oct;

pub use file::{ProbeFileError, VERSION};
pub use grid::{DEFAULT_PROBES, DEFAULT_SPACING, GridError, MAX_PROBES, ProbeGrid};
pub use oct::{
    border_source, bordered_tile, oct_border_source, oct_decode, oct_encode, oct_texel_direction,
    oct_texel_solid_angle, texel_direction,
};

use crate::sh;
use glam::{Vec2, Vec3};

/// SH coefficients per probe (bands 0..2).
pub const SH_COEFFS: usize = 9;
/// Side of each probe's octahedral visibility map (texels).
pub const VIS_RES: u32 = 16;
/// Side of a visibility tile with its one-texel border (for bilinear filtering across the
/// octahedron's edges).
pub const VIS_TILE: u32 = VIS_RES + 2;
/// Side of each probe's octahedral irradiance map ([`ProbeVolume::irradiance_tile`]), which a
/// renderer samples with one bilinear fetch where it needs only E(n) (texels).
pub const IRR_RES: u32 = 12;
/// Side of an irradiance tile with its one-texel border.
pub const IRR_TILE: u32 = IRR_RES + 2;
/// Largest error of a bilinearly filtered irradiance tile against its SH, relative to the
/// largest E(n) of the probe, over random SH radiance (a unit test measures it: 0.088 at 12²,
/// where the octahedron's creases bend; 0.14 at 8², 0.063 at 16²).
pub const IRRADIANCE_TILE_ERROR: f32 = 0.10;
/// Mean of that error over directions and draws (0.0096 at 12²).
pub const IRRADIANCE_TILE_MEAN_ERROR: f32 = 0.012;
/// The lookup's offset along the normal and the view, as a fraction of the smallest spacing.
pub const BIAS_FRACTION: f32 = 0.2;
/// Mean distances are recorded up to this multiple of the spacing's length (rays that go farther
/// or escape count as this far).
pub const MAX_DISTANCE_FACTOR: f32 = 1.5;

/// One probe: where it stands, whether it takes part, and the radiance it receives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    /// Offset from its grid position (m) after relocation out of geometry.
    pub offset: Vec3,
    /// False for a probe the bake switched off (inside geometry it could not leave).
    pub active: bool,
    /// Incident radiance, order-2 SH (the renderer's intensity already applied).
    pub sh: [Vec3; SH_COEFFS],
}

/// A baked probe volume.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeVolume {
    pub grid: ProbeGrid,
    /// Distances are stored divided by this (m).
    pub max_distance: f32,
    pub probes: Vec<Probe>,
    /// Per probe a [`VIS_TILE`]² tile, row-major, of (mean, mean²) of the distance over
    /// `max_distance`; the border repeats the octahedron's opposite edge.
    pub visibility: Vec<[f32; 2]>,
    /// How it was baked: rays per probe and bounces.
    pub rays: u32,
    pub bounces: u32,
    /// The fingerprint of what it was baked from (the cache key), 0 when not known.
    pub key: u64,
}

/// The eight weights of a lookup: probe indices and normalised weights (0 for probes that do
/// not take part).
#[derive(Clone, Copy, Debug)]
pub struct Weights {
    pub probes: [usize; 8],
    pub weights: [f32; 8],
}

impl ProbeVolume {
    /// The lookup's bias (m).
    pub fn bias(&self) -> f32 {
        BIAS_FRACTION * self.grid.spacing.min_element()
    }

    /// Where probe `index` stands (grid position + relocation offset).
    pub fn probe_position(&self, index: usize) -> Vec3 {
        self.grid.position(index) + self.probes[index].offset
    }

    /// Bilinear (mean, mean²) of probe `index`'s visibility in unit direction `d`, in units of
    /// `max_distance`; the same filtering as a GPU sampler over the bordered tile.
    pub fn moments(&self, index: usize, d: Vec3) -> Vec2 {
        let e = oct_encode(d);
        // Continuous texel position inside the bordered tile (centres at +0.5).
        let r = VIS_RES as f32;
        let t = (e * 0.5 + 0.5) * r + 1.0 - 0.5;
        let t0 = t.floor();
        let f = t - t0;
        let last = (VIS_TILE - 1) as f32;
        let tile = &self.visibility[index * (VIS_TILE * VIS_TILE) as usize..];
        let at = |x: f32, y: f32| {
            let (x, y) = (x.clamp(0.0, last) as u32, y.clamp(0.0, last) as u32);
            Vec2::from(tile[(y * VIS_TILE + x) as usize])
        };
        let top = at(t0.x, t0.y).lerp(at(t0.x + 1.0, t0.y), f.x);
        let bottom = at(t0.x, t0.y + 1.0).lerp(at(t0.x + 1.0, t0.y + 1.0), f.x);
        top.lerp(bottom, f.y)
    }

    /// Each probe's visibility within `radius` metres as order-2 SH (9 coefficients of the
    /// scalar function V(ω) = 1 where its rays meet nothing closer than `radius`): from the
    /// visibility map's distance moments per texel, Chebyshev's bound where the texel's mean
    /// distance is below the radius (as the lookup's weights), 1 where its rays went past the
    /// recorded maximum. What a technique's own visibility within R is measured against (the
    /// book, "Near and far").
    pub fn visibility_sh(&self, radius: f32) -> Vec<[f32; SH_COEFFS]> {
        let res = VIS_RES;
        let maxd = self.max_distance;
        // Per interior texel: its direction's SH basis times its solid angle.
        let texels: Vec<([f32; SH_COEFFS], f32)> = (0..res * res)
            .map(|i| {
                let (x, y) = (i % res, i / res);
                let solid = oct_texel_solid_angle(x, y, res);
                let b = sh::basis16(texel_direction(x, y));
                (std::array::from_fn(|k| b[k]), solid)
            })
            .collect();
        let tile = (VIS_TILE * VIS_TILE) as usize;
        (0..self.probes.len())
            .map(|p| {
                let mut c = [0f32; SH_COEFFS];
                if !self.probes[p].active {
                    return c;
                }
                let t = &self.visibility[p * tile..(p + 1) * tile];
                for (i, (b, solid)) in texels.iter().enumerate() {
                    let (x, y) = (i as u32 % res, i as u32 / res);
                    let m = t[((y + 1) * VIS_TILE + x + 1) as usize];
                    let mean = m[0] * maxd;
                    let v = if mean >= 0.999 * maxd || radius <= mean {
                        1.0
                    } else {
                        let var = (m[1] - m[0] * m[0]).abs().max(1e-6) * maxd * maxd;
                        var / (var + (radius - mean) * (radius - mean))
                    };
                    for (ck, bk) in c.iter_mut().zip(b) {
                        *ck += v * bk * solid;
                    }
                }
                c
            })
            .collect()
    }

    /// The probes and weights a point `p` with unit normal `n`, seen from unit direction `v`
    /// (towards the viewer), reads (module docs).
    pub fn weights(&self, p: Vec3, n: Vec3, v: Vec3) -> Weights {
        let g = &self.grid;
        let biased = p + self.bias() * (0.3 * n + 0.7 * v);
        let max_index = Vec3::new(
            (g.counts[0] - 1) as f32,
            (g.counts[1] - 1) as f32,
            (g.counts[2] - 1) as f32,
        );
        let rel = ((biased - g.origin) / g.spacing).clamp(Vec3::ZERO, max_index);
        let base = rel.floor().min((max_index - 1.0).max(Vec3::ZERO));
        let alpha = (rel - base).clamp(Vec3::ZERO, Vec3::ONE);
        let mut out = Weights {
            probes: [0; 8],
            weights: [0.0; 8],
        };
        let mut total = 0.0;
        for c in 0..8u32 {
            let o = [c & 1, (c >> 1) & 1, (c >> 2) & 1];
            let coords = [
                (base.x as u32 + o[0]).min(g.counts[0] - 1),
                (base.y as u32 + o[1]).min(g.counts[1] - 1),
                (base.z as u32 + o[2]).min(g.counts[2] - 1),
            ];
            let index = g.index(coords);
            out.probes[c as usize] = index;
            let probe = &self.probes[index];
            if !probe.active {
                continue;
            }
            let trilinear = (0..3)
                .map(|a| if o[a] == 1 { alpha[a] } else { 1.0 - alpha[a] })
                .product::<f32>();
            let pos = self.probe_position(index);
            let to_probe = (pos - p).normalize_or_zero();
            let wrap = 0.5 * (to_probe.dot(n) + 1.0);
            let mut w = wrap * wrap + 0.2;
            let from_probe = biased - pos;
            let dist = from_probe.length();
            let m = self.moments(index, from_probe / dist.max(1e-12)) * self.max_distance;
            let mean_sq = m.y * self.max_distance;
            if dist > m.x {
                let variance = (mean_sq - m.x * m.x).abs().max(1e-6 * self.max_distance);
                let cheb = variance / (variance + (dist - m.x) * (dist - m.x));
                w *= cheb * cheb * cheb;
            }
            w = w.max(1e-6);
            if w < 0.2 {
                w *= w * w / (0.2 * 0.2);
            }
            w *= trilinear;
            out.weights[c as usize] = w;
            total += w;
        }
        if total > 0.0 {
            for w in &mut out.weights {
                *w /= total;
            }
        }
        out
    }

    /// The interpolated radiance SH at `p` (normal `n`, seen from `v`).
    pub fn sh_at(&self, p: Vec3, n: Vec3, v: Vec3) -> [Vec3; SH_COEFFS] {
        self.sh_with(&self.weights(p, n, v))
    }

    /// The radiance SH of the probes and weights `w` ([`Self::weights`]).
    pub fn sh_with(&self, w: &Weights) -> [Vec3; SH_COEFFS] {
        let mut sh = [Vec3::ZERO; SH_COEFFS];
        for (&i, &wi) in w.probes.iter().zip(&w.weights) {
            if wi > 0.0 {
                for (c, s) in sh.iter_mut().zip(&self.probes[i].sh) {
                    *c += *s * wi;
                }
            }
        }
        sh
    }

    /// E(n)/π at `p` from the volume: the irradiance every direction brings (docs/src/aovs.md's
    /// `far-irradiance` at R = 0), clamped at 0.
    pub fn irradiance(&self, p: Vec3, n: Vec3, v: Vec3) -> Vec3 {
        sh::irradiance_over_pi(&self.sh_at(p, n, v), n).max(Vec3::ZERO)
    }

    /// Probe `index`'s E(n)/π (unclamped, so that sums of probes clamp once) at the texel
    /// centres of a [`IRR_RES`]² octahedral map with its one-texel border, row-major
    /// ([`IRR_TILE`]² texels). Bilinear filtering of the tile reproduces the SH's E(n) to within
    /// [`IRRADIANCE_TILE_ERROR`] of its largest value (a unit test measures it).
    pub fn irradiance_tile(&self, index: usize) -> Vec<Vec3> {
        let sh = &self.probes[index].sh;
        let mut tile = Vec::with_capacity((IRR_TILE * IRR_TILE) as usize);
        for y in 0..IRR_TILE {
            for x in 0..IRR_TILE {
                let (sx, sy) = oct_border_source(x, y, IRR_RES);
                tile.push(sh::irradiance_over_pi(
                    sh,
                    oct_texel_direction(sx, sy, IRR_RES),
                ));
            }
        }
        tile
    }

    /// Probes that take part.
    pub fn active_count(&self) -> usize {
        self.probes.iter().filter(|p| p.active).count()
    }

    /// Bytes the volume occupies in memory.
    pub fn memory_bytes(&self) -> usize {
        self.probes.len() * std::mem::size_of::<Probe>() + self.visibility.len() * 8
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Aabb;

    /// Bilinear filtering of a bordered irradiance tile, as a GPU sampler does.
    fn sample_tile(tile: &[Vec3], d: Vec3) -> Vec3 {
        let t = (oct_encode(d) * 0.5 + 0.5) * IRR_RES as f32 + 1.0 - 0.5;
        let t0 = t.floor();
        let f = t - t0;
        let last = (IRR_TILE - 1) as f32;
        let at = |x: f32, y: f32| {
            let (x, y) = (x.clamp(0.0, last) as u32, y.clamp(0.0, last) as u32);
            tile[(y * IRR_TILE + x) as usize]
        };
        let top = at(t0.x, t0.y).lerp(at(t0.x + 1.0, t0.y), f.x);
        let bottom = at(t0.x, t0.y + 1.0).lerp(at(t0.x + 1.0, t0.y + 1.0), f.x);
        top.lerp(bottom, f.y)
    }

    #[test]
    fn irradiance_tiles_reproduce_the_sh_irradiance() {
        // SH of radiance made of a few bright directions (the most a probe's L2 rings), over
        // many random draws; the worst error relative to the probe's largest E(n).
        let mut state = 0x2545_f491_u32;
        let mut next = move || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let mut volume = constant_volume(Vec3::ONE, [2, 2, 2]);
        let mut worst = 0.0f32;
        let mut mean = 0.0f32;
        for _ in 0..64 {
            let mut coeffs = [Vec3::ZERO; SH_COEFFS];
            for _ in 0..1 + (next() * 4.0) as usize {
                let d = oct_decode(Vec2::new(next() * 2.0 - 1.0, next() * 2.0 - 1.0));
                let l = Vec3::new(next(), next(), next()) * 10.0;
                let b = sh::basis16(d);
                for (c, bk) in coeffs.iter_mut().zip(b) {
                    *c += l * bk;
                }
            }
            volume.probes[0].sh = coeffs;
            let tile = volume.irradiance_tile(0);
            let mut errors = Vec::new();
            let mut largest = 0.0f32;
            for _ in 0..2000 {
                let d = oct_decode(Vec2::new(next() * 2.0 - 1.0, next() * 2.0 - 1.0));
                let exact = sh::irradiance_over_pi(&coeffs, d);
                largest = largest.max(exact.max_element());
                errors.push((sample_tile(&tile, d) - exact).abs().max_element());
            }
            let e = errors.iter().fold(0.0f32, |a, &b| a.max(b)) / largest;
            worst = worst.max(e);
            mean += errors.iter().sum::<f32>() / errors.len() as f32 / largest / 64.0;
        }
        eprintln!("irradiance tile: worst error {worst:.4}, mean {mean:.4} of the largest E(n)");
        assert!(
            worst <= IRRADIANCE_TILE_ERROR && mean <= IRRADIANCE_TILE_MEAN_ERROR,
            "bilinear error of the largest E(n): worst {worst:.4} (bound \
             {IRRADIANCE_TILE_ERROR}), mean {mean:.4} (bound {IRRADIANCE_TILE_MEAN_ERROR})"
        );
    }

    /// A volume whose probes all see constant radiance `l` and open space up to max distance.
    pub(crate) fn constant_volume(l: Vec3, counts: [u32; 3]) -> ProbeVolume {
        let bounds = Aabb {
            min: Vec3::ZERO,
            max: Vec3::splat(2.0),
        };
        let grid = ProbeGrid::with_counts(bounds, counts).unwrap();
        let mut sh = [Vec3::ZERO; SH_COEFFS];
        // L_00 of a constant radiance l: l · √(4π).
        sh[0] = l * (4.0 * std::f32::consts::PI).sqrt();
        let n = grid.count();
        ProbeVolume {
            grid,
            max_distance: 3.0,
            probes: vec![
                Probe {
                    offset: Vec3::ZERO,
                    active: true,
                    sh,
                };
                n
            ],
            visibility: vec![[1.0, 1.0]; n * (VIS_TILE * VIS_TILE) as usize],
            rays: 0,
            bounces: 0,
            key: 0,
        }
    }

    #[test]
    fn octahedral_round_trip() {
        for i in 0..500 {
            let t = i as f32 * 0.731;
            let d = Vec3::new(t.sin() * (3.1 * t).cos(), t.cos(), (1.7 * t).sin()).normalize();
            let back = oct_decode(oct_encode(d));
            assert!((back - d).length() < 1e-5, "{d} {back}");
        }
        assert!((oct_decode(Vec2::ZERO) - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn border_texels_continue_the_sphere() {
        // A border texel's direction is close to the interior texel it copies.
        let r = VIS_RES as f32;
        for y in 0..VIS_TILE {
            for x in 0..VIS_TILE {
                if (1..=VIS_RES).contains(&x) && (1..=VIS_RES).contains(&y) {
                    continue;
                }
                let e = Vec2::new(
                    (x as f32 - 0.5) / r * 2.0 - 1.0,
                    (y as f32 - 0.5) / r * 2.0 - 1.0,
                );
                // Fold the outside position back onto the octahedron.
                let folded = Vec2::new(
                    if e.x.abs() > 1.0 {
                        e.x.signum() * 2.0 - e.x
                    } else {
                        e.x
                    },
                    if e.y.abs() > 1.0 {
                        e.y.signum() * 2.0 - e.y
                    } else {
                        e.y
                    },
                );
                let flip = |v: f32, outside: bool| if outside { -v } else { v };
                let folded = Vec2::new(
                    flip(folded.x, e.y.abs() > 1.0),
                    flip(folded.y, e.x.abs() > 1.0),
                );
                let (sx, sy) = border_source(x, y);
                let a = oct_decode(folded);
                let b = texel_direction(sx, sy);
                assert!(a.dot(b) > 0.99, "({x},{y}) → ({sx},{sy}): {a} vs {b}");
            }
        }
    }

    #[test]
    fn octahedral_texels_cover_the_sphere() {
        let total: f32 = (0..VIS_RES * VIS_RES)
            .map(|i| oct_texel_solid_angle(i % VIS_RES, i / VIS_RES, VIS_RES))
            .sum();
        assert!((total - 4.0 * std::f32::consts::PI).abs() < 1e-3, "{total}");
    }

    /// The cosine-weighted visibility of the SH, as far.wgsl's far_ao_at reads it.
    fn ao_of(c: &[f32; SH_COEFFS], n: Vec3) -> f32 {
        let coeffs: Vec<Vec3> = c.iter().map(|&x| Vec3::splat(x)).collect();
        sh::irradiance_over_pi(&coeffs, n).x
    }

    #[test]
    fn a_probe_sees_its_open_space_and_its_wall_within_r() {
        // Open space up to the recorded maximum: visible in every direction at any radius.
        let mut v = constant_volume(Vec3::ONE, [2, 2, 2]);
        let open = v.visibility_sh(0.5)[0];
        for n in [Vec3::X, Vec3::NEG_Y, Vec3::new(0.3, 0.4, -0.87).normalize()] {
            assert!((ao_of(&open, n) - 1.0).abs() < 0.01, "{}", ao_of(&open, n));
        }
        // A wall 0.4 m below probe 0 (−Y half space at 0.4 / cos θ): hidden within R = 1
        // below, open above.
        let tile = (VIS_TILE * VIS_TILE) as usize;
        let mut interior = Vec::new();
        for y in 0..VIS_RES {
            for x in 0..VIS_RES {
                let d = texel_direction(x, y);
                let t = if d.y < -0.05 {
                    (0.4 / -d.y).min(v.max_distance)
                } else {
                    v.max_distance
                } / v.max_distance;
                interior.push([t, t * t]);
            }
        }
        v.visibility[..tile].copy_from_slice(&bordered_tile(&interior));
        let wall = v.visibility_sh(1.0)[0];
        let down = ao_of(&wall, Vec3::NEG_Y);
        let up = ao_of(&wall, Vec3::Y);
        // Facing the wall only the directions within acos(0.4) of its plane reach past 1 m:
        // their cosine-weighted share is 0.4² = 0.16 (order-2 SH rings a little).
        assert!((down - 0.16).abs() < 0.03, "facing the wall: {down}");
        assert!(up > 0.95, "facing away: {up}");
        // Within 0.3 m the wall is out of reach.
        assert!(ao_of(&v.visibility_sh(0.3)[0], Vec3::NEG_Y) > 0.95);
    }

    #[test]
    fn constant_radiance_gives_its_irradiance_everywhere() {
        let v = constant_volume(Vec3::new(0.5, 1.0, 2.0), [3, 2, 4]);
        for p in [Vec3::splat(0.1), Vec3::new(1.3, 0.7, 1.9), Vec3::splat(5.0)] {
            let n = Vec3::new(0.3, 0.9, -0.2).normalize();
            let e = v.irradiance(p, n, Vec3::Y);
            assert!(
                (e - Vec3::new(0.5, 1.0, 2.0)).abs().max_element() < 1e-5,
                "{e}"
            );
            let w = v.weights(p, n, Vec3::Y);
            assert!((w.weights.iter().sum::<f32>() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn a_probe_behind_a_wall_weighs_nothing() {
        // Two probes in x; the second records a wall 0.3 m away in every direction, so a point
        // right beside the first probe is beyond what the second sees.
        let mut v = constant_volume(Vec3::ONE, [2, 1, 1]);
        let tile = (VIS_TILE * VIS_TILE) as usize;
        let wall = 0.3 / v.max_distance;
        for m in &mut v.visibility[tile..2 * tile] {
            *m = [wall, wall * wall];
        }
        v.probes[1].sh[0] = Vec3::splat(1000.0);
        let p = v.probe_position(0) + Vec3::new(0.2, 0.0, 0.0);
        let w = v.weights(p, Vec3::Y, Vec3::Y);
        let second = w
            .probes
            .iter()
            .zip(&w.weights)
            .filter(|(i, _)| **i == 1)
            .map(|(_, w)| *w)
            .sum::<f32>();
        assert!(second < 1e-4, "{second}");
    }

    #[test]
    fn switched_off_probes_weigh_nothing() {
        let mut v = constant_volume(Vec3::ONE, [2, 2, 2]);
        v.probes[0].active = false;
        let w = v.weights(Vec3::splat(0.6), Vec3::Y, Vec3::Y);
        for (i, wi) in w.probes.iter().zip(&w.weights) {
            if *i == 0 {
                assert_eq!(*wi, 0.0);
            }
        }
        assert!((w.weights.iter().sum::<f32>() - 1.0).abs() < 1e-5);
    }
}

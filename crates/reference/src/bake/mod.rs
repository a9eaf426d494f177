//! The probe bake (`nearfield bake`): the far field as a probe volume (`nearfield_scene::probes`),
//! traced on the CPU with the reference's BVH.
//!
//! For every probe of the grid:
//! 1. **Rays.** `rays` directions on a spherical Fibonacci lattice, turned by a rotation drawn
//!    from the probe's index (deterministic; neighbouring probes do not share their gaps). Each
//!    ray finds its closest surface with no culling.
//! 2. **Inside geometry.** A probe whose rays meet the back faces of single-sided surfaces more
//!    than [`INSIDE_FRACTION`] of the time stands inside a solid (DDGI's classification). It moves
//!    through the nearest such back face to [`EXIT_FRACTION`] of the smallest spacing beyond it,
//!    when that stays within [`MAX_OFFSET_FRACTION`] of a cell per axis and the new place passes
//!    the same test; otherwise it is switched off (weight 0 in every lookup).
//! 3. **What each ray brings.** A ray that escapes brings the environment in its direction,
//!    box-filtered to about the solid angle one ray stands for (so that a sun left in the map
//!    does not become one probe's spike). A ray that meets a surface x′ (shading normal n′
//!    facing the probe, albedo ρ′) brings its outgoing diffuse radiance
//!    `L = Le(x′) + ρ′ (E_lights(x′) + E_far(x′)) / π`: emission, every light with its shadow ray
//!    (the split sun as a disc, one direction per ray over it) and the incident light of the
//!    volume itself. Bounce k lights x′ with bounce k − 1's volume ([`ProbeVolume::irradiance`],
//!    the lookup the renderer makes); bounce 0 has no E_far. `bounces` K iterations follow the
//!    first: light that has bounced up to K times between surfaces is in the volume.
//! 4. **Projection.** Radiance onto order-2 SH, c_lm = (4π/N) Σ L(ωᵢ) Y_lm(ωᵢ); distances into
//!    the octahedral visibility map, each texel the mean and mean square of the distances of the
//!    rays around it, weighted max(0, ω·ω_texel)^[`DEPTH_SHARPNESS`] (DDGI), clamped to the
//!    volume's `max_distance` (escaped rays count as that far).
//!
//! The result depends on the scene, environment, grid, rays and bounces only (not on threads).

mod rays;

use crate::lights::Lights;
use crate::sampling::{hash, r2, r2_offset};
use crate::tracer::{Hit, Tracer};
use glam::Vec3;
use nearfield_scene::probes::{
    self, MAX_DISTANCE_FACTOR, Probe, ProbeGrid, ProbeVolume, SH_COEFFS, VIS_RES, VIS_TILE,
};
use nearfield_scene::{Environment, Scene, sh};
use rayon::prelude::*;
use rays::{directions, pack_normal, unpack_normal};
use std::f32::consts::PI;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Rays per probe by default ([`default_rays`]).
pub const DEFAULT_RAYS: u32 = 512;
/// Bounces by default.
pub const DEFAULT_BOUNCES: u32 = 4;
/// Most rays per probe.
pub const MAX_RAYS: u32 = 16384;
/// Most bounces.
pub const MAX_BOUNCES: u32 = 64;
/// Rays per probe that bounces light again (every k-th of its rays, k = ⌈rays / BOUNCE_RAYS⌉):
/// the bounce light is smoother than what the rays bring directly, and each bounce ray keeps its
/// hit's lookup into the volume (44 bytes) across the bounces, so that the probe budget's 65536
/// probes hold at most 704 MiB of them.
pub const BOUNCE_RAYS: u32 = 256;
/// Share of back-face hits above which a probe stands inside geometry.
pub const INSIDE_FRACTION: f32 = 0.25;
/// How far beyond the back face a relocated probe goes (× smallest spacing).
pub const EXIT_FRACTION: f32 = 0.1;
/// How far a probe may move from its grid position per axis (× that axis's spacing).
pub const MAX_OFFSET_FRACTION: f32 = 0.45;
/// Exponent of the visibility texels' cosine kernel (DDGI's depth sharpness).
pub const DEPTH_SHARPNESS: i32 = 50;

/// Triangles per doubling (squared) of the default grid's probe count: a scene of t triangles
/// gets `probes::DEFAULT_PROBES` × clamp(√(t / DETAIL_TRIANGLES), 1, 8) probes over its bounds.
/// Detailed geometry (an interior with columns, arches and galleries) needs probes closer than
/// a box of a few quads does. Measured on Crytek Sponza's view of the book (262 267 triangles,
/// 160×90, R = 1): the volume alone through the exact visibility is 0.19 off the path-traced
/// `far-irradiance` with 4096 probes (1.15 m apart), 0.14 with 33 000 (0.6 m); the built-in
/// scenes (at most a few hundred triangles) keep 4096 and bake in about a second.
pub const DETAIL_TRIANGLES: f32 = 5000.0;

/// How much finer than the plain default a scene's grid is: clamp(√(t / [`DETAIL_TRIANGLES`]),
/// 1, 8) for t triangles.
fn detail(scene: &Scene) -> f32 {
    (scene.triangle_count() as f32 / DETAIL_TRIANGLES)
        .sqrt()
        .clamp(1.0, 8.0)
}

/// The default grid of a scene: a probe every [`probes::DEFAULT_SPACING`] metres over its
/// bounds, coarser where that would take more than [`probes::DEFAULT_PROBES`] probes (cells of
/// about equal sides, a flat axis one layer). What an application keeps: measured in the book's
/// "Near and far", where the near field's radius follows the spacing (`--radius auto`).
pub fn default_grid(scene: &Scene) -> Result<ProbeGrid, probes::GridError> {
    let bounds = scene.bounds();
    if bounds.is_empty() {
        return Err(probes::GridError::Empty);
    }
    let spacing =
        ProbeGrid::default_spacing(bounds, probes::DEFAULT_PROBES).max(probes::DEFAULT_SPACING);
    ProbeGrid::with_spacing(bounds, spacing)
}

/// The default rays per probe: [`DEFAULT_RAYS`], twice that for detailed scenes (detail ≥ 4,
/// over 80 000 triangles), whose small openings to the sky need them. Measured on Crytek
/// Sponza (the book's view, R = 1, a 5120-spp truth of relative noise 0.05): the volume alone is
/// 0.151 off the path-traced `far-irradiance` with 512 rays, 0.135 with 1024 (bakes of 13 s and
/// 21 s on 2 cores).
pub fn default_rays(scene: &Scene) -> u32 {
    if detail(scene) >= 4.0 {
        2 * DEFAULT_RAYS
    } else {
        DEFAULT_RAYS
    }
}

/// What to bake.
#[derive(Clone, Copy, Debug)]
pub struct BakeSettings {
    pub grid: ProbeGrid,
    pub rays: u32,
    pub bounces: u32,
}

/// Why a bake's settings are refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BakeError {
    #[error("--rays {0}: must be in 1..={MAX_RAYS}")]
    Rays(u32),
    #[error("--bounces {0}: must be in 0..={MAX_BOUNCES}")]
    Bounces(u32),
    #[error("the bake was cancelled")]
    Cancelled,
}

impl BakeSettings {
    pub fn check(&self) -> Result<(), BakeError> {
        if self.rays == 0 || self.rays > MAX_RAYS {
            return Err(BakeError::Rays(self.rays));
        }
        if self.bounces > MAX_BOUNCES {
            return Err(BakeError::Bounces(self.bounces));
        }
        Ok(())
    }
}

/// Where a bake stands, for a caller on another thread (the viewer): stages done of `total`
/// (one per probe traced, one per probe per bounce), and a flag that stops it.
#[derive(Default)]
pub struct Monitor {
    pub done: AtomicU64,
    pub total: AtomicU64,
    pub cancel: AtomicBool,
}

impl Monitor {
    /// The fraction done, 0..=1.
    pub fn fraction(&self) -> f32 {
        let t = self.total.load(Ordering::Relaxed).max(1);
        (self.done.load(Ordering::Relaxed) as f64 / t as f64).min(1.0) as f32
    }
}

/// A hit of one of a probe's bounce rays: lit again by every bounce from the previous volume.
#[derive(Clone, Copy)]
struct BounceHit {
    /// Index of the ray.
    ray: u16,
    p: Vec3,
    /// Octahedral shading normal, facing the probe (16-bit per axis).
    normal: [u16; 2],
    /// Albedo ρ′ (8-bit, linear).
    albedo: [u8; 4],
}

/// A bounce hit's lookup into the volume (its weights do not change between bounces: they
/// depend on the geometry and the visibility only).
struct HitLookup {
    ray: u16,
    probes: [u16; 8],
    /// Weights × 65535.
    weights: [u16; 8],
    normal: [u16; 2],
    albedo: [u8; 4],
}

struct Baker<'a> {
    scene: &'a Scene,
    tracer: Tracer<'a>,
    lights: Lights,
    scene_radius: f32,
    /// The environment box-filtered to about one ray's solid angle.
    sky: Environment,
    settings: BakeSettings,
    max_distance: f32,
}

/// A probe after tracing: where it stands, whether it takes part, what its rays bring before
/// any bounce (SH), its visibility tile, and its bounce rays' hits.
struct Traced {
    offset: Vec3,
    active: bool,
    direct: [Vec3; SH_COEFFS],
    tile: Vec<[f32; 2]>,
    hits: Vec<BounceHit>,
}

impl Traced {
    fn off(offset: Vec3) -> Self {
        Traced {
            offset,
            active: false,
            direct: [Vec3::ZERO; SH_COEFFS],
            tile: probes::bordered_tile(&[[0.0, 0.0]; (VIS_RES * VIS_RES) as usize]),
            hits: Vec::new(),
        }
    }
}

impl<'a> Baker<'a> {
    fn new(scene: &'a Scene, env: &Environment, settings: BakeSettings) -> Self {
        let footprint = (PI * settings.rays as f32).sqrt();
        let width = (footprint as u32).next_power_of_two().clamp(16, 1024);
        let (w, h, texels) = env.box_downsampled(width);
        let sky = Environment {
            name: env.name.clone(),
            width: w,
            height: h,
            texels,
            rotation: env.rotation,
            intensity: env.intensity,
            sun: None,
        };
        Baker {
            scene,
            tracer: Tracer::new(scene),
            lights: Lights::new(scene, env),
            scene_radius: scene.bounds().radius(),
            sky,
            settings,
            max_distance: MAX_DISTANCE_FACTOR * settings.grid.spacing.length(),
        }
    }

    fn single_sided(&self, hit: &Hit) -> bool {
        !self.scene.materials[hit.material as usize].double_sided
    }

    /// Closest hits from `origin` along `dirs`, and the nearest back face of a single-sided
    /// surface with the share of rays that met one.
    fn probe_rays(
        &self,
        origin: Vec3,
        dirs: &[Vec3],
    ) -> (Vec<Option<Hit>>, Option<(Vec3, f32)>, f32) {
        let mut nearest_back: Option<(Vec3, f32)> = None;
        let mut back = 0usize;
        let hits: Vec<Option<Hit>> = dirs
            .iter()
            .map(|&d| {
                let hit = self.tracer.closest(origin, d, f32::INFINITY, false);
                if let Some(h) = &hit
                    && !h.front
                    && self.single_sided(h)
                {
                    back += 1;
                    if nearest_back.is_none_or(|(_, t)| h.t < t) {
                        nearest_back = Some((d, h.t));
                    }
                }
                hit
            })
            .collect();
        (hits, nearest_back, back as f32 / dirs.len().max(1) as f32)
    }

    /// Every `bounce_stride()`-th ray of a probe is a bounce ray.
    fn bounce_stride(&self) -> u32 {
        self.settings.rays.div_ceil(BOUNCE_RAYS).max(1)
    }

    fn trace(&self, index: usize) -> Traced {
        let g = &self.settings.grid;
        let home = g.position(index);
        let dirs = directions(index, self.settings.rays);
        let (mut hits, nearest_back, inside) = self.probe_rays(home, &dirs);
        let mut offset = Vec3::ZERO;
        if inside > INSIDE_FRACTION {
            let moved = nearest_back.and_then(|(d, t)| {
                let o = d * (t + EXIT_FRACTION * g.spacing.min_element());
                let fits = (o.abs() / g.spacing).max_element() <= MAX_OFFSET_FRACTION;
                fits.then_some(o)
            });
            let Some(o) = moved else {
                return Traced::off(offset);
            };
            let (again, _, still) = self.probe_rays(home + o, &dirs);
            if still > INSIDE_FRACTION {
                return Traced::off(o);
            }
            hits = again;
            offset = o;
        }
        let origin = home + offset;
        let u_offset = r2_offset(hash(index as u32) ^ 0xbb67_ae85);
        let stride = self.bounce_stride();
        let mut rays = 0u64;
        let mut direct = [glam::DVec3::ZERO; SH_COEFFS];
        let mut bounce_hits = Vec::new();
        let mut dist = Vec::with_capacity(dirs.len());
        for (j, (hit, &d)) in hits.iter().zip(&dirs).enumerate() {
            let l = match hit {
                None => {
                    dist.push(1.0);
                    self.sky.radiance(d)
                }
                Some(h) => {
                    dist.push(h.t.min(self.max_distance) / self.max_distance);
                    let rho = self.scene.base_color(h.material, h.uv).truncate();
                    let q = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
                    let rho8 = [q(rho.x), q(rho.y), q(rho.z), 0];
                    let mut l = self.scene.emission(h.material, h.uv);
                    if rho.max_element() > 0.0 {
                        l += rho
                            * self.lights.irradiance(
                                &self.tracer,
                                self.scene_radius,
                                h,
                                origin,
                                r2(j as u32, u_offset),
                                &mut rays,
                            );
                        if (j as u32).is_multiple_of(stride) && rho8[..3].iter().any(|&a| a > 0) {
                            bounce_hits.push(BounceHit {
                                ray: j as u16,
                                p: h.p,
                                normal: pack_normal(h.ns),
                                albedo: rho8,
                            });
                        }
                    }
                    l
                }
            };
            let b = sh::basis16(d);
            for (a, bi) in direct.iter_mut().zip(b) {
                *a += l.as_dvec3() * bi as f64;
            }
        }
        let w = 4.0 * std::f64::consts::PI / self.settings.rays as f64;
        Traced {
            offset,
            active: true,
            direct: direct.map(|c| (c * w).as_vec3()),
            tile: self.visibility(&dirs, &dist),
            hits: bounce_hits,
        }
    }

    /// The visibility tile from a probe's ray directions and distances (/ max distance).
    fn visibility(&self, dirs: &[Vec3], dist: &[f32]) -> Vec<[f32; 2]> {
        let n = (VIS_RES * VIS_RES) as usize;
        // Structure of arrays: the texel loop below runs over every ray.
        let (xs, ys, zs): (Vec<f32>, Vec<f32>, Vec<f32>) =
            dirs.iter().map(|d| (d.x, d.y, d.z)).collect();
        let mut interior = Vec::with_capacity(n);
        for y in 0..VIS_RES {
            for x in 0..VIS_RES {
                let t = probes::texel_direction(x, y);
                let (mut sum, mut sum_sq, mut weight) = (0f64, 0f64, 0f64);
                let mut nearest = (f32::MIN, 1.0f32);
                for j in 0..xs.len() {
                    let c = xs[j] * t.x + ys[j] * t.y + zs[j] * t.z;
                    if c > nearest.0 {
                        nearest = (c, dist[j]);
                    }
                    if c > 0.9 {
                        // Beyond, 0.9^50 < 0.6 %: the kernel's tail.
                        let w = c.powi(DEPTH_SHARPNESS) as f64;
                        let d = dist[j] as f64;
                        sum += w * d;
                        sum_sq += w * d * d;
                        weight += w;
                    }
                }
                interior.push(if weight > 1e-12 {
                    [(sum / weight) as f32, (sum_sq / weight) as f32]
                } else {
                    [nearest.1, nearest.1 * nearest.1]
                });
            }
        }
        probes::bordered_tile(&interior)
    }

    /// The lookups of a probe's bounce hits into `volume`.
    fn hit_lookups(
        &self,
        hits: &[BounceHit],
        index: usize,
        volume: &ProbeVolume,
    ) -> Vec<HitLookup> {
        let dirs = directions(index, self.settings.rays);
        hits.iter()
            .map(|h| {
                let w = volume.weights(h.p, unpack_normal(h.normal), -dirs[h.ray as usize]);
                HitLookup {
                    ray: h.ray,
                    probes: w.probes.map(|p| p as u16),
                    weights: w
                        .weights
                        .map(|w| (w.clamp(0.0, 1.0) * 65535.0).round() as u16),
                    normal: h.normal,
                    albedo: h.albedo,
                }
            })
            .collect()
    }

    /// Order-2 SH of the light a probe's bounce rays bring from their hits, lit by the previous
    /// bounce's probes: (4π/M) Σ ρ′ E_far(x′) Y(ωᵢ) over its M bounce rays.
    fn bounce(&self, index: usize, probes: &[Probe], lookups: &[HitLookup]) -> [Vec3; SH_COEFFS] {
        let dirs = directions(index, self.settings.rays);
        let mut acc = [glam::DVec3::ZERO; SH_COEFFS];
        for h in lookups {
            let n = unpack_normal(h.normal);
            let bn = sh::basis16(n);
            let mut e = Vec3::ZERO;
            for (&p, &w) in h.probes.iter().zip(&h.weights) {
                if w > 0 {
                    let sh = &probes[p as usize].sh;
                    let mut irr = Vec3::ZERO;
                    for (k, c) in sh.iter().enumerate() {
                        irr += *c * (bn[k] * sh::COSINE_LOBE_OVER_PI[sh::band(k)]);
                    }
                    e += irr * (w as f32 / 65535.0);
                }
            }
            let rho = Vec3::new(h.albedo[0] as f32, h.albedo[1] as f32, h.albedo[2] as f32) / 255.0;
            let l = rho * e.max(Vec3::ZERO);
            let b = sh::basis16(dirs[h.ray as usize]);
            for (a, bi) in acc.iter_mut().zip(b) {
                *a += l.as_dvec3() * bi as f64;
            }
        }
        let m = self.settings.rays.div_ceil(self.bounce_stride());
        let w = 4.0 * std::f64::consts::PI / m as f64;
        acc.map(|c| (c * w).as_vec3())
    }
}

/// Bakes the volume. `progress` prints a bar (or plain lines) on stderr; `monitor`, when given,
/// follows the bake from another thread and can cancel it.
pub fn bake(
    scene: &Scene,
    env: &Environment,
    settings: BakeSettings,
    progress: bool,
    monitor: Option<&Monitor>,
) -> Result<ProbeVolume, BakeError> {
    settings.check()?;
    let baker = Baker::new(scene, env, settings);
    let n = settings.grid.count();
    let stages = n as u64 * (2 + settings.bounces as u64);
    if let Some(m) = monitor {
        m.total.store(stages, Ordering::Relaxed);
        m.done.store(0, Ordering::Relaxed);
    }
    let cancelled = || monitor.is_some_and(|m| m.cancel.load(Ordering::Relaxed));
    let step = |k: u64| {
        if let Some(m) = monitor {
            m.done.fetch_add(k, Ordering::Relaxed);
        }
    };
    let bar = nearfield_scene::progress::Progress::new("bake", stages, "probe passes", progress);
    let traced: Vec<Traced> = (0..n)
        .into_par_iter()
        .map(|i| {
            if cancelled() {
                return Traced::off(Vec3::ZERO);
            }
            let t = baker.trace(i);
            bar.inc(1);
            step(1);
            t
        })
        .collect();
    if cancelled() {
        return Err(BakeError::Cancelled);
    }
    let mut volume = ProbeVolume {
        grid: settings.grid,
        max_distance: baker.max_distance,
        probes: traced
            .iter()
            .map(|t| Probe {
                offset: t.offset,
                active: t.active,
                sh: t.direct,
            })
            .collect(),
        visibility: traced.iter().flat_map(|t| t.tile.iter().copied()).collect(),
        rays: settings.rays,
        bounces: settings.bounces,
        key: 0,
    };
    debug_assert_eq!(volume.visibility.len(), n * (VIS_TILE * VIS_TILE) as usize);
    bar.inc(n as u64);
    step(n as u64);
    if settings.bounces == 0 {
        bar.finish();
        return Ok(volume);
    }
    let lookups: Vec<Vec<HitLookup>> = traced
        .into_par_iter()
        .enumerate()
        .map(|(i, t)| baker.hit_lookups(&t.hits, i, &volume))
        .collect();
    let direct: Vec<[Vec3; SH_COEFFS]> = volume.probes.iter().map(|p| p.sh).collect();
    for _ in 0..settings.bounces {
        if cancelled() {
            return Err(BakeError::Cancelled);
        }
        let previous = volume.probes.clone();
        let sh: Vec<[Vec3; SH_COEFFS]> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut c = direct[i];
                if previous[i].active {
                    for (a, b) in c.iter_mut().zip(baker.bounce(i, &previous, &lookups[i])) {
                        *a += b;
                    }
                }
                bar.inc(1);
                step(1);
                c
            })
            .collect();
        for (p, c) in volume.probes.iter_mut().zip(sh) {
            p.sh = c;
        }
    }
    bar.finish();
    Ok(volume)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fibonacci_directions_cover_the_sphere_evenly() {
        let n = 512;
        let dirs = directions(7, n);
        let mean: Vec3 = dirs.iter().copied().sum::<Vec3>() / n as f32;
        assert!(mean.length() < 1e-3, "{mean}");
        // The SH projection of a constant radiance: exact to 0.1 % in band 0, ~0 above.
        let mut c = [0f32; 16];
        for d in &dirs {
            for (ci, b) in c.iter_mut().zip(sh::basis16(*d)) {
                *ci += b * 4.0 * PI / n as f32;
            }
        }
        // ∫ Y_00 dω = 0.2820948 · 4π = √(4π).
        assert!((c[0] - (4.0 * PI).sqrt()).abs() < 1e-3 * c[0], "{}", c[0]);
        assert!(c[1..].iter().all(|x| x.abs() < 2e-2), "{c:?}");
    }

    #[test]
    fn normals_pack_to_within_a_thousandth() {
        for i in 0..200 {
            let t = i as f32 * 0.37;
            let n = Vec3::new(t.cos(), (2.3 * t).sin(), (0.7 * t).cos()).normalize();
            assert!((unpack_normal(pack_normal(n)) - n).length() < 1e-3);
        }
    }

    #[test]
    fn settings_are_checked() {
        let grid = ProbeGrid::with_counts(
            nearfield_scene::Aabb {
                min: Vec3::ZERO,
                max: Vec3::ONE,
            },
            [2, 2, 2],
        )
        .unwrap();
        let s = |rays, bounces| BakeSettings {
            grid,
            rays,
            bounces,
        };
        assert_eq!(s(0, 1).check(), Err(BakeError::Rays(0)));
        assert_eq!(s(64, 65).check(), Err(BakeError::Bounces(65)));
        assert!(s(64, 4).check().is_ok());
    }
}

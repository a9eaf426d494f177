//! The lights a surface point receives with shadow rays: the scene's punctual lights and the
//! environment's sun as a disc light (`nearfield_scene::sun`). Shared by the per-pixel estimators
//! (`integrate`) and the probe bake (`bake`).

use crate::tracer::{Hit, Tracer, offset_origin};
use glam::{Vec2, Vec3};
use nearfield_scene::{Environment, Light, LightKind, Scene};
use std::f32::consts::PI;

/// The scene's lights followed by the environment's sun, if split out.
pub struct Lights {
    pub lights: Vec<Light>,
    /// Some light is a disc (needs sampling).
    pub has_disc: bool,
}

impl Lights {
    pub fn new(scene: &Scene, env: &Environment) -> Self {
        let lights: Vec<Light> = scene
            .lights
            .iter()
            .copied()
            .chain(env.sun_light())
            .collect();
        let has_disc = lights.iter().any(|l| disc_radius(l) > 0.0);
        Lights { lights, has_disc }
    }

    /// (1/π) Σ_l E_l at `hit` with shadow rays whose origins are pushed towards `from` (the
    /// camera, or the previous path vertex): exact for punctual lights; a disc light gives one
    /// unbiased sample from `u`, a direction uniform over the disc's solid angle Ω, weighted
    /// L·(ω·n)·Ω = E_n (ω·n) · 2/(1 + cos r) (E_n its normal irradiance, r its radius).
    pub fn irradiance(
        &self,
        tracer: &Tracer,
        scene_radius: f32,
        hit: &Hit,
        from: Vec3,
        u: Vec2,
        rays: &mut u64,
    ) -> Vec3 {
        let mut e = Vec3::ZERO;
        for light in &self.lights {
            let radius = disc_radius(light);
            if radius > 0.0 {
                let (centre, _) = light.direction_from(hit.p);
                let l = uniform_cone(centre, radius.cos(), u);
                let cos = l.dot(hit.ns);
                if cos <= 0.0 || l.dot(hit.ng) <= 0.0 {
                    continue;
                }
                *rays += 1;
                let o = offset_origin(hit, l, from, scene_radius);
                if !tracer.occluded(o, l, f32::INFINITY) {
                    e += light.normal_irradiance(hit.p) * (cos * 2.0 / (1.0 + radius.cos()));
                }
                continue;
            }
            let (l, dist) = light.direction_from(hit.p);
            if l.dot(hit.ns) <= 0.0 || l.dot(hit.ng) <= 0.0 {
                continue;
            }
            let irr = light.irradiance(hit.p, hit.ns);
            if irr.max_element() <= 0.0 {
                continue;
            }
            let o = offset_origin(hit, l, from, scene_radius);
            let tmax = if dist.is_finite() {
                (hit.p + l * dist - o).length() * (1.0 - 1e-4)
            } else {
                f32::INFINITY
            };
            *rays += 1;
            if !tracer.occluded(o, l, tmax) {
                e += irr;
            }
        }
        e / PI
    }
}

/// Angular radius of a disc light (0 for punctual lights).
fn disc_radius(l: &Light) -> f32 {
    match l.kind {
        LightKind::Directional { angular_radius, .. } => angular_radius.max(0.0),
        _ => 0.0,
    }
}

/// A direction uniform over the cone of half-angle acos(`cos_max`) about the unit `axis`.
fn uniform_cone(axis: Vec3, cos_max: f32, u: Vec2) -> Vec3 {
    let cos = 1.0 - u.x * (1.0 - cos_max);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let (t, b) = crate::sampling::orthonormal_basis(axis);
    (t * (sin * phi.cos()) + b * (sin * phi.sin()) + axis * cos).normalize()
}
